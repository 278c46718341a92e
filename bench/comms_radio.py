"""Benchmark: end-to-end neighbour-message latency through the Zenoh radio emulator, and the emulator's CPU.

Three processes on loopback, as in a mission:
* this process: the Zenoh hub, the simulator's truth at 20 Hz, and N drones' states at 20 Hz each
  (one load generator instead of N agent processes, so the machine measures the radio, not N interpreters);
* ``python -m comms.radio`` (the thing measured: its CPU from /proc/<pid>/stat);
* a receiver process subscribed to everything the emulator delivers (one wildcard subscriber: per-receiver or
  per-group bundles), counting every delivery and recording ``rx time - source time`` for a sample of receivers
  (both ``time.monotonic()``: one clock on one machine).

Drones sit on a square grid with ``--spacing-m`` (default 10 m, d in the paper) and radio range 25 m, so an interior
drone has ~20 neighbours in range. The emulator's CPU per 1000 deliveries is taken between two of its own
``radio/stats`` reports (its delivered count) and the CPU read as each arrives; the JSON line after each row also
splits the emulator's CPU by thread (``radio_thread_cpu_pct``: the Python thread, Zenoh's ``app`` and ``tx``
runtimes). ``--tree LABEL=PATH`` runs the
emulator of another checkout (e.g. ``git archive main | tar -x -C /tmp/before``) in the same run, alternating
with this one per drone count, so a before/after comparison shares the machine's load; with two trees the last
line gives the ratio of their CPU per 1000 deliveries for each pair and the median. Each row also counts what the
emulator says it delivered against what the receiver got, and the emulator's ``input gaps`` (states it never
took), so nothing is lost silently. Run:

    .venv/bin/python bench/comms_radio.py --drones 13 100 300 --duration-s 10
    .venv/bin/python bench/comms_radio.py --drones 300 300 300 300 300 --tree before=/tmp/before --tree after=.
"""

from __future__ import annotations

import argparse
import json
import os
import signal
import subprocess
import sys
import threading
import time
from collections.abc import Sequence
from pathlib import Path

REPO = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(REPO))

import msgspec  # noqa: E402
import numpy as np  # noqa: E402

from comms.keys import MissionKeys  # noqa: E402
from comms.latest_buffer import LatestValueBuffer  # noqa: E402
from comms.messages import GroundTruth, NeighbourState, RadioBundle, RadioGroupBundle, RadioLinkStats, decode, encode  # noqa: E402
from comms.radio_model import RadioModel  # noqa: E402
from comms.zenoh_session import ZenohConfig, ZenohSession  # noqa: E402
from mission_plan.roles import Role  # noqa: E402

RATE_HZ = 20.0


def grid_positions(n: int, spacing_m: float) -> np.ndarray:
    side = int(np.ceil(np.sqrt(n)))
    ij = np.array([(i % side, i // side) for i in range(n)], dtype=float)
    p = np.zeros((n, 3))
    p[:, :2] = (ij - (side - 1) / 2) * spacing_m
    p[:, 2] = 10.0
    return p


def cpu_seconds(pid: int) -> float:
    fields = Path(f"/proc/{pid}/stat").read_text().rsplit(")", 1)[1].split()
    return (int(fields[11]) + int(fields[12])) / os.sysconf("SC_CLK_TCK")


def thread_cpu_seconds(pid: int) -> dict[str, float]:
    """CPU seconds [user + system] of each of a process's threads so far, summed by thread name (Zenoh's runtimes
    name their threads, e.g. ``app-0``, ``tx-0``; the main Python thread carries the command's name)."""
    by_name: dict[str, float] = {}
    for task in Path(f"/proc/{pid}/task").iterdir():
        try:
            text = (task / "stat").read_text()
        except OSError:  # the thread ended between the listing and the read
            continue
        name = text[text.index("(") + 1: text.rindex(")")]
        fields = text.rsplit(")", 1)[1].split()
        group = name.rstrip("0123456789").rstrip("-") or name
        by_name[group] = by_name.get(group, 0.0) + (int(fields[11]) + int(fields[12])) / os.sysconf("SC_CLK_TCK")
    return by_name


class _SourceTime(msgspec.Struct):
    """Just the source time of a NeighbourState (msgspec skips the other fields): keeps the probe cheap."""

    t_s: float


def receiver(hub: str, mission: str, duration_s: float, sample_every: int) -> int:
    """Subscribe to everything the radio emulator delivers (one wildcard subscriber: per-receiver ``RadioBundle``s
    on ``radio/<id>/inbox`` or ``RadioGroupBundle``s on ``radio/group/<g>``, whichever the emulator under test
    puts); count every delivery, and time those of every ``sample_every``-th receiver (only their source time is
    decoded, so the probe does not become the bottleneck); print JSON with latencies [s] and counts when done."""
    keys = MissionKeys(mission)
    bundle_decoder = msgspec.msgpack.Decoder(RadioBundle | RadioGroupBundle)
    time_decoder = msgspec.msgpack.Decoder(_SourceTime)
    latencies: list[float] = []
    counts = {"bundles": 0, "messages": 0, "deliveries": 0}
    lock = threading.Lock()

    def unpack(key: str, payload: bytes) -> list[tuple[str, bytes]]:
        now = time.monotonic()
        if key == keys.radio_stats:
            return []
        bundle = bundle_decoder.decode(payload)
        if isinstance(bundle, RadioGroupBundle):
            runs = np.cumsum([0, *bundle.counts]).tolist()
            selections = [(r, [bundle.entries[i] for i in bundle.indices[a:b]])
                          for r, a, b in zip(bundle.receivers, runs[:-1], runs[1:])]
        else:
            selections = [(keys.vehicle_id_of(key) or 0, bundle.entries)]
        lat = [now - time_decoder.decode(data).t_s for r, entries in selections if r % sample_every == 0
               for _, data in entries]
        with lock:
            latencies.extend(lat)
            counts["bundles"] += 1
            counts["messages"] += len(lat)
            counts["deliveries"] += sum(len(entries) for _, entries in selections)
        return []

    with ZenohSession(ZenohConfig.member(hub)) as session:
        session.subscribe(f"{keys.prefix}/radio/**", unpack=unpack)
        print("READY", flush=True)
        stop = threading.Event()
        signal.signal(signal.SIGTERM, lambda *_: stop.set())
        stop.wait(duration_s)
        while True:  # asked to stop: first take what is still on its way (a loaded host delivers late)
            with lock:
                before = counts["bundles"]
            time.sleep(1.0)
            with lock:
                if counts["bundles"] == before:
                    break
    with lock:
        print(json.dumps({"latencies": latencies, **counts}), flush=True)
    return 0


def delivered_so_far(stats: LatestValueBuffer) -> int | None:
    """The emulator's delivered count from its newest ``radio/stats`` report since the last call (None: none yet)."""
    delivered = None
    for item in stats.drain():
        report = decode(RadioLinkStats, item.payload)
        if report is not None:
            delivered = report.delivered
    return delivered


def wait_until_idle(stats: LatestValueBuffer, timeout_s: float = 30.0) -> float:
    """After the load stops: wait until two of the emulator's stats reports in a row show the same delivered count
    (it has worked off its backlog), so the receiver is not stopped while deliveries are still on their way; returns
    the seconds waited."""
    start = time.monotonic()
    last = None
    while time.monotonic() - start < timeout_s:
        stats.wait(1.5)
        delivered = delivered_so_far(stats)
        if delivered is not None:
            if delivered == last:
                break
            last = delivered
    return time.monotonic() - start


def run_one(n: int, duration_s: float, warmup_s: float, spacing_m: float, latency_s: float, tick_s: float | None,
            hub: str, tree: Path = REPO) -> dict:
    mission = f"bench{n}"
    load_before = os.getloadavg()[0]
    keys = MissionKeys(mission)
    positions = grid_positions(n, spacing_m)
    neighbours = RadioModel(25.0).in_range(positions).sum(axis=1)
    env = dict(os.environ, PYTHONPATH=str(tree))
    with ZenohSession(ZenohConfig.hub(hub)) as session:
        stats = session.subscribe(keys.radio_stats)
        tick = [] if tick_s is None else ["--tick-s", str(tick_s)]
        radio = subprocess.Popen([sys.executable, "-m", "comms.radio", "--mission", mission, "--range-m", "25",
                                  "--latency-s", str(latency_s), *tick, "--connect", hub], cwd=tree, env=env,
                                 stderr=subprocess.PIPE, text=True)
        rx = subprocess.Popen([sys.executable, __file__, "--role", "receiver", "--hub", hub, "--mission", mission,
                               "--duration-s", str(duration_s + warmup_s + 30),
                               "--sample-every", str(max(1, n // 20))], cwd=REPO, env=env,
                              stdout=subprocess.PIPE, text=True)
        try:
            assert rx.stdout is not None and rx.stdout.readline().strip() == "READY"
            time.sleep(1.0)
            ids = list(range(n))
            truth_payload = lambda t: encode(GroundTruth(t_s=t, vehicle_ids=ids, positions_enu_m=[tuple(p) for p in positions.tolist()]))  # noqa: E731
            state_keys = [keys.state(i) for i in ids]
            period = 1.0 / RATE_HZ
            phase = np.arange(n) * period / n  # drones spread over the period, as unsynchronised radios are
            start = time.monotonic()
            next_send = start + phase
            next_truth = start
            seq = np.zeros(n, dtype=np.int64)
            cpu0 = None
            t_measure = 0.0
            window: list[tuple[int, float, float]] = []  # (delivered, radio CPU s, time) at each stats report in the window
            sent_measured = 0
            end = start + warmup_s + duration_s
            while True:
                now = time.monotonic()
                if now >= end:
                    break
                if cpu0 is None and now >= start + warmup_s:
                    cpu0, t_measure = cpu_seconds(radio.pid), now
                    threads0 = thread_cpu_seconds(radio.pid)
                    sent_at_measure = int(seq.sum())
                    delivered_so_far(stats)
                if cpu0 is not None:
                    delivered = delivered_so_far(stats)
                    if delivered is not None:
                        window.append((delivered, cpu_seconds(radio.pid), now))
                if now >= next_truth:
                    session.put(keys.truth, truth_payload(now))
                    next_truth += period
                for i in np.flatnonzero(next_send <= now).tolist():
                    t = time.monotonic()
                    session.put(state_keys[i], encode(NeighbourState(
                        sender_id=i, role=Role.BOUNDARY, seq=int(seq[i]), t_s=t, position_en_m=(float(positions[i, 0]), float(positions[i, 1])),
                        altitude_m=10.0, velocity_en_mps=(0.0, 0.0))))
                    seq[i] += 1
                    next_send[i] += period
                time.sleep(max(0.0, min(float(next_send.min()), next_truth) - time.monotonic()))
            cpu1, t_end = cpu_seconds(radio.pid), time.monotonic()
            threads1 = thread_cpu_seconds(radio.pid)
            sent_measured = int(seq.sum()) - sent_at_measure
            lag = float(max(0.0, time.monotonic() - next_send.min()))
            settle_s = wait_until_idle(stats)
            time.sleep(0.5)
        finally:
            rx.send_signal(signal.SIGTERM)
            out, _ = rx.communicate(timeout=60)
            radio.send_signal(signal.SIGTERM)
            _, radio_err = radio.communicate(timeout=60)
    result = json.loads(out.strip().splitlines()[-1])
    lat = np.array(result["latencies"])
    # discard the warm-up share of the samples (first warmup/(warmup+duration) of the run)
    lat = lat[int(len(lat) * warmup_s / (warmup_s + duration_s)):]
    summary = radio_err.strip().splitlines()[-1] if radio_err.strip() else ""
    delivered, input_gaps = _summary_count(summary, "delivered"), _summary_count(summary, "input gaps")
    if input_gaps < 0:  # an emulator that took its states through callbacks counts them as superseded
        input_gaps = _summary_count(summary, "superseded")
    window_deliveries = window[-1][0] - window[0][0] if len(window) >= 2 else 0
    return {
        "tree": str(tree),
        "drones": n,
        "radio_cpu_ms_per_1000": 1e6 * (window[-1][1] - window[0][1]) / window_deliveries if window_deliveries else float("nan"),
        "window_deliveries_per_s": window_deliveries / (window[-1][2] - window[0][2]) if window_deliveries else 0.0,
        "deliveries_per_s": delivered / (duration_s + warmup_s),
        "emulator_delivered": delivered,
        "received_deliveries": result["deliveries"],
        "input_gaps": input_gaps,
        "load_average": [load_before, os.getloadavg()[0]],
        "mean_neighbours": float(neighbours.mean()),
        "states_per_s": sent_measured / (t_end - t_measure),
        "sampled_deliveries_per_s": result["messages"] / (duration_s + warmup_s),
        "bundles_per_s": result["bundles"] / (duration_s + warmup_s),
        "radio_cpu_pct": 100.0 * (cpu1 - cpu0) / (t_end - t_measure),
        "p50_ms": float(np.percentile(lat, 50) * 1e3) if lat.size else float("nan"),
        "p99_ms": float(np.percentile(lat, 99) * 1e3) if lat.size else float("nan"),
        "samples": int(lat.size),
        "generator_lag_s": lag,
        "settle_s": settle_s,
        "radio_thread_cpu_pct": {name: round(100.0 * (cpu - threads0.get(name, 0.0)) / (t_end - t_measure), 1)
                                 for name, cpu in sorted(threads1.items()) if cpu - threads0.get(name, 0.0) > 0},
        "radio_summary": summary,
    }


def _summary_count(summary: str, name: str) -> int:
    """A count from the emulator's exit line (``..., delivered 123, ...``); -1 when the line has none."""
    if f"{name} " not in summary:
        return -1
    return int(summary.split(f"{name} ")[1].split(",")[0])


def tree_option(text: str, tick_s: float | None) -> tuple[str, Path, float | None]:
    """``LABEL=PATH[@TICK_S]`` -> (label, checkout, its emulator's --tick-s, else ``tick_s``)."""
    label, _, rest = text.partition("=")
    path, _, tick = rest.partition("@")
    return label, Path(path).resolve(), float(tick) if tick else tick_s


def main(argv: Sequence[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description="Radio emulator latency and CPU benchmark.")
    parser.add_argument("--role", choices=("driver", "receiver"), default="driver")
    parser.add_argument("--drones", type=int, nargs="+", default=[13, 100, 300])
    parser.add_argument("--duration-s", type=float, default=10.0)
    parser.add_argument("--warmup-s", type=float, default=2.0)
    parser.add_argument("--spacing-m", type=float, default=10.0)
    parser.add_argument("--latency-s", type=float, default=0.0, help="radio model latency (0 = pure pipeline cost)")
    parser.add_argument("--tick-s", type=float, default=None,
                        help="radio delivery cycle (comms.radio --tick-s; default: each emulator's own default)")
    parser.add_argument("--hub", default="tcp/127.0.0.1:24447")
    parser.add_argument("--mission", default="bench")
    parser.add_argument("--sample-every", type=int, default=1, help="receiver role: time every k-th receiver")
    parser.add_argument("--tree", action="append", default=[], metavar="LABEL=PATH[@TICK_S]",
                        help="run the emulator of this checkout, with its own --tick-s after '@' (repeatable: alternated "
                             "per drone count, ratios against the first; default: this one)")
    args = parser.parse_args(argv)
    if args.role == "receiver":
        return receiver(args.hub, args.mission, args.duration_s, args.sample_every)
    trees = [tree_option(t, args.tick_s) for t in args.tree] or [("this", REPO, args.tick_s)]
    print("| emulator | drones | load | mean neighbours | states in /s | deliveries /s | delivered / received | input gaps "
          "| bundles /s | radio CPU % of one core | radio CPU ms per 1000 deliveries | latency p50 ms | p99 ms |")
    print("|---|---:|---|---:|---:|---:|---|---:|---:|---:|---:|---:|---:|")
    ratios: dict[str, list[float]] = {label: [] for label, _, _ in trees[1:]}
    for n in args.drones:
        per_tree = []
        for label, tree, tick_s in trees:
            r = run_one(n, args.duration_s, args.warmup_s, args.spacing_m, args.latency_s, tick_s, args.hub, tree)
            per_tree.append(r["radio_cpu_ms_per_1000"])
            load = "{:.1f} → {:.1f}".format(*r["load_average"])
            print(f"| {label} | {r['drones']} | {load} | {r['mean_neighbours']:.1f} | {r['states_per_s']:.0f} | "
                  f"{r['deliveries_per_s']:.0f} | {r['emulator_delivered']} / {r['received_deliveries']} | {r['input_gaps']} | "
                  f"{r['bundles_per_s']:.0f} | {r['radio_cpu_pct']:.0f} | {r['radio_cpu_ms_per_1000']:.2f} | {r['p50_ms']:.2f} | "
                  f"{r['p99_ms']:.2f} |", flush=True)
            print(f"<!-- {json.dumps({k: v for k, v in r.items()})} -->", flush=True)
        for (label, _, _), cpu in zip(trees[1:], per_tree[1:]):
            ratios[label].append(cpu / per_tree[0])
    for label, values in ratios.items():
        print(f"CPU per 1000 deliveries, {label} / {trees[0][0]} per pair: {', '.join(f'{x:.2f}' for x in values)}; "
              f"median {float(np.median(values)):.2f}; <= 0.5 in {sum(x <= 0.5 for x in values)} of {len(values)}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
