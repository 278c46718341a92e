"""Benchmark: the radio emulator's logic alone (``comms.radio_relay.RadioRelay``, no sockets), CPU per delivery.

300 drones on the 10 m grid of ``bench/comms_radio.py`` (range 25 m, ~17.5 neighbours each), states with 8 edge
points, queued 30 per batch (one 5 ms delivery cycle at 20 Hz), a new truth (every drone moved) after each drone's
state, as the simulator's 20 Hz truth, each batch decided and handed out as the emulator does in one delivery
cycle: one encoded ``RadioGroupBundle`` per group of receivers (``pop_due_group_bundles``), or in an older
checkout one ``RadioBundle`` per receiver (``pop_due_bundles``, or ``pop_due`` and the codec). ``--tree PATH`` measures another checkout's relay (e.g. ``git archive main |
tar -x -C /tmp/before``), so before and after run on the same load. Run:

    .venv/bin/python bench/radio_relay.py
    .venv/bin/python bench/radio_relay.py --tree /tmp/before
"""

from __future__ import annotations

import argparse
import sys
import time
from collections.abc import Sequence
from pathlib import Path


def measure(drones: int, messages: int, batch: int) -> tuple[float, float, int]:
    """(µs of CPU per state for deciding, µs per delivery in all: validate, decide, bundle; deliveries)."""
    from comms.messages import GroundTruth, NeighbourState, RadioBundle, encode
    from comms.radio_model import RadioModel

    try:
        from comms.radio_relay import RadioRelay
    except ImportError:  # a checkout from before the relay had its own module
        from comms.radio_emulator import RadioRelay  # type: ignore[attr-defined,no-redef]
    side = int(drones ** 0.5 + 0.999)
    positions = [(float(i % side) * 10.0, float(i // side) * 10.0, 10.0) for i in range(drones)]
    relay = RadioRelay(RadioModel(25.0))
    relay.on_truth(GroundTruth(t_s=0.0, vehicle_ids=list(range(drones)), positions_enu_m=positions))
    payloads = [encode(NeighbourState(sender_id=i % drones, role="boundary", seq=i // drones + 1, t_s=0.05 * (i // drones),
                                      position_en_m=(1.0, 2.0), altitude_m=10.0, edge_points_en_m=[(1.0, 2.0)] * 8))
                for i in range(messages)]
    def bundles(now_s: float) -> list[tuple[int, bytes]]:
        if hasattr(relay, "pop_due_group_bundles"):
            return relay.pop_due_group_bundles(now_s, now_s)
        if hasattr(relay, "pop_due_bundles"):
            return relay.pop_due_bundles(now_s, now_s)
        return [(r, encode(RadioBundle(t_s=now_s, entries=e))) for r, e in relay.pop_due(now_s).items()]

    deciding = 0.0
    start = time.process_time()
    for i, payload in enumerate(payloads):
        if i % drones == 0 and i:  # a new truth each round of states (20 Hz at 20 Hz states), every drone moved
            step = 0.05 * (i // drones)
            relay.on_truth(GroundTruth(t_s=step, vehicle_ids=list(range(drones)),
                                       positions_enu_m=[(x + 0.1 * step, y, z) for x, y, z in positions]))
        relay.on_state(i % drones, payload, 0.0)
        if i % batch == batch - 1:
            c0 = time.process_time()
            relay.flush()
            deciding += time.process_time() - c0
            bundles(1e9)
    bundles(1e9)
    done = time.process_time()
    delivered = relay.counters.delivered
    return 1e6 * deciding / messages, 1e6 * (done - start) / delivered, delivered


def main(argv: Sequence[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description="Radio relay (emulator logic) CPU per delivery, no sockets.")
    parser.add_argument("--tree", type=Path, default=Path(__file__).resolve().parents[1], help="checkout to measure")
    parser.add_argument("--drones", type=int, default=300)
    parser.add_argument("--messages", type=int, default=30000)
    parser.add_argument("--batch", type=int, default=30)
    args = parser.parse_args(argv)
    sys.path.insert(0, str(args.tree.resolve()))
    per_state, per_delivery, delivered = measure(args.drones, args.messages, args.batch)
    print(f"{args.tree}: {per_state:.1f} us per state (decide), {per_delivery:.2f} us per delivery in all, "
          f"{delivered} deliveries")
    return 0


if __name__ == "__main__":
    sys.exit(main())
