"""``python -m comms.radio``: run the central radio emulator for one mission until Ctrl-C / SIGTERM.

Example (the mission hub listening on the default tcp/127.0.0.1:7447)::

    python -m comms.radio --mission circle --range-m 25 --loss 0.05 --latency-s 0.02 --jitter-s 0.01 --seed 1
"""

from __future__ import annotations

import argparse
import signal
import sys
import threading
import time
from collections.abc import Sequence
from pathlib import Path

from comms.cli_args import add_zenoh_arguments, zenoh_config_from_args
from comms.keys import KeyNameError, validate_mission
from comms.key_file import read_key_file
from comms.radio_emulator import RadioEmulator, RadioEmulatorConfig
from comms.radio_model import BurstLoss, RadioModel
from comms.zenoh_session import ZenohOpenError


def parse_args(argv: Sequence[str] | None) -> argparse.Namespace:
    parser = argparse.ArgumentParser(prog="python -m comms.radio", description="Range-limited radio emulator fed by simulator ground truth.")
    parser.add_argument("--mission", default="circle", help="mission name (key prefix floodwatch/<mission>)")
    parser.add_argument("--range-m", type=float, default=25.0, help="radio range [m] (SPEC §4: 25)")
    parser.add_argument("--loss", type=float, default=0.0, help="packet loss probability per link and message")
    parser.add_argument("--latency-s", type=float, default=0.0, help="minimum one-way delay [s, sim time]")
    parser.add_argument("--jitter-s", type=float, default=0.0, help="extra uniform delay width [s, sim time]")
    parser.add_argument("--burst-loss", type=float, default=1.0, help="loss probability in a burst (bad state)")
    parser.add_argument("--burst-mean-s", type=float, default=0.0, help="mean burst length [mission s]; 0: no bursts")
    parser.add_argument("--burst-gap-s", type=float, default=0.0, help="mean time between bursts [mission s]")
    parser.add_argument("--edge-loss", type=float, default=0.0, help="extra loss at the range limit from distance")
    parser.add_argument("--edge-loss-exponent", type=float, default=2.0, help="growth of the distance loss with d / range")
    parser.add_argument("--bandwidth-bytes-per-s", type=float, default=0.0, help="each drone's budget; 0: unlimited")
    parser.add_argument("--ground-node", type=float, nargs=3, metavar=("E", "N", "U"), default=None,
                        help="the ground station's antenna [m; mission ENU] as a receiver (inbox radio/0/inbox)")
    parser.add_argument("--seed", type=int, default=0)
    parser.add_argument("--speed", type=float, default=1.0, help="simulation seconds per wall second")
    parser.add_argument("--clock", choices=("free", "paced"), default="free",
                        help="paced: delays in mission time on the truth's clock, each truth acknowledged once "
                             "everything due by then is delivered; free: delays on the wall clock / --speed")
    parser.add_argument("--stats-period-s", type=float, default=1.0, help="how often per-link counters are published")
    parser.add_argument("--tick-s", type=float, default=0.005, help="delivery cycle: batches messages (adds up to this much latency)")
    parser.add_argument("--key-file", type=Path, default=None, metavar="FILE",
                        help="the mission key: relay only states with a valid tag (default: relay unchecked)")
    parser.add_argument("--duration-s", type=float, default=None, help="stop after this many wall seconds")
    add_zenoh_arguments(parser)
    return parser.parse_args(argv)


def main(argv: Sequence[str] | None = None) -> int:
    args = parse_args(argv)
    try:
        validate_mission(args.mission)
        if args.speed <= 0 or args.stats_period_s <= 0 or args.tick_s < 0:
            raise ValueError("--speed and --stats-period-s must be > 0, --tick-s >= 0")
        config = RadioEmulatorConfig(
            mission=args.mission,
            zenoh=zenoh_config_from_args(args),
            radio=RadioModel(
                args.range_m, args.loss, args.latency_s, args.jitter_s, args.seed,
                burst=BurstLoss(args.burst_mean_s, args.burst_gap_s) if args.burst_mean_s > 0 else None,
                burst_loss_probability=args.burst_loss, edge_loss_probability=args.edge_loss,
                edge_loss_exponent=args.edge_loss_exponent, bandwidth_bytes_per_s=args.bandwidth_bytes_per_s,
            ),
            speed=args.speed,
            stats_period_s=args.stats_period_s,
            tick_s=args.tick_s,
            paced=args.clock == "paced",
            ground_node_enu_m=None if args.ground_node is None else tuple(args.ground_node),
            key=None if args.key_file is None else read_key_file(args.key_file),
        )
    except (ValueError, KeyNameError) as error:
        print(f"comms.radio: {error}", file=sys.stderr)
        return 2
    stop = threading.Event()
    for sig in (signal.SIGINT, signal.SIGTERM):
        signal.signal(sig, lambda *_: stop.set())
    try:
        emulator = RadioEmulator(config)
    except ZenohOpenError as error:
        print(f"comms.radio: {error}", file=sys.stderr)
        return 1
    if args.duration_s is not None:
        timer = threading.Timer(args.duration_s, stop.set)
        timer.daemon = True
        timer.start()
    started = time.monotonic()
    try:
        emulator.run_until(stop)
    finally:
        emulator.stop()
    c = emulator.relay.counters
    print(f"comms.radio: {time.monotonic() - started:.1f} s, in {c.messages_in}, delivered {c.delivered}, lost {c.lost}, "
          f"out of range {c.out_of_range}, over budget {c.over_budget}, rejected {c.rejected}, no truth {c.no_truth}, input gaps {emulator.input_gaps}", file=sys.stderr)
    return 0


if __name__ == "__main__":
    sys.exit(main())
