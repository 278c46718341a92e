"""Benchmark: what the authentication tag costs per message, beside encoding and decoding it.

Run: .venv/bin/python bench/signing_cost.py [--repeat 20000]
Prints a Markdown table of CPU µs per operation (best of 5 loops, ``time.process_time``): encode, decode, sign
(HMAC-SHA256 over the encoded message and the signature block) and verify (tag, sender, replay and window checks,
as every receiver runs them), the bytes on the wire with the 31-byte block, and what a receiver pays per control
tick to verify 13 and 200 neighbour states (the circle and the largest fleets).
"""

from __future__ import annotations

import argparse
import sys
import time
from collections.abc import Callable, Sequence
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

import numpy as np  # noqa: E402

from comms.messages import MissionCommand, NeighbourState, decode, encode  # noqa: E402
from comms.signing import MissionKey, Signer, Verifier  # noqa: E402

NOW_US = 1_800_000_000_000_000


def _samples() -> list[tuple[str, NeighbourState | MissionCommand, int]]:
    rng = np.random.default_rng(0)
    minimal = NeighbourState(sender_id=3, role="follower", seq=1234, t_s=12.5, position_en_m=(3.2, -7.9), altitude_m=10.0,
                             velocity_en_mps=(0.4, 0.1))
    boundary = NeighbourState(sender_id=3, role="boundary", seq=1234, t_s=12.5, position_en_m=(13.2, -2.9),
                              altitude_m=10.0, velocity_en_mps=(0.4, 0.9), lat_deg=47.39, lon_deg=8.54, flags=0b1111,
                              battery_fraction=0.9, group="A",
                              edge_points_en_m=[tuple(p) for p in rng.uniform(-20, 20, (32, 2)).tolist()])
    command = MissionCommand(seq=1, t_s=1.0, command="start", phase="caging", flood_clock_start_t_s=1.0)
    return [("NeighbourState (minimal)", minimal, 3), ("NeighbourState (boundary, 32 edge points)", boundary, 3),
            ("MissionCommand", command, 0xFFFF_FFFF)]


def _best_cpu_us(run: Callable[[], None], n: int) -> float:
    best = float("inf")
    for _ in range(5):
        t0 = time.process_time()
        run()
        best = min(best, (time.process_time() - t0) / n)
    return best * 1e6


def main(argv: Sequence[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__)
    parser.add_argument("--repeat", type=int, default=20000)
    args = parser.parse_args(argv)
    n = args.repeat
    key = MissionKey(bytes(range(32)))
    print("| message | bytes signed | encode µs | decode µs | sign µs | verify µs | verify 13 / 200 per tick µs |")
    print("|---|---:|---:|---:|---:|---:|---:|")
    for name, msg, sender in _samples():
        body = encode(msg)
        kind = type(msg)
        signer = Signer(key, sender)
        signed = [signer.sign(body, NOW_US) for _ in range(n)]  # distinct, increasing timestamps
        assert decode(kind, body) == msg

        def encode_all() -> None:
            for _ in range(n):
                encode(msg)

        def decode_all() -> None:
            for _ in range(n):
                decode(kind, body)

        def sign_all() -> None:
            for _ in range(n):
                signer.sign(body, NOW_US)

        def verify_all() -> None:
            verifier = Verifier(key)
            check = verifier.check
            for payload in signed:
                check(payload, sender, NOW_US)
            assert verifier.accepted == n

        enc, dec = _best_cpu_us(encode_all, n), _best_cpu_us(decode_all, n)
        sig, ver = _best_cpu_us(sign_all, n), _best_cpu_us(verify_all, n)
        print(f"| {name} | {len(signed[0])} ({len(body)} + 31) | {enc:.2f} | {dec:.2f} | {sig:.2f} | {ver:.2f} | "
              f"{13 * ver:.0f} / {200 * ver:.0f} |")
    return 0


if __name__ == "__main__":
    sys.exit(main())
