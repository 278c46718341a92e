"""Command line of the mock fleet: ``python -m mock_autopilot --vehicles N ...``; parsing only, then ``main``."""

from __future__ import annotations

import argparse
import logging
import signal
import sys
import threading
from dataclasses import dataclass, field
from typing import Sequence

from comms.frames import GeodeticHome
from mock_autopilot.faults import FaultSpec, FaultSpecError, parse_fault
from mock_autopilot.fleet import Fleet
from mock_autopilot.mavlink_codec import parse_signing_key
from mock_autopilot.ports import onboard_port_range
from mock_autopilot.px4_params import ParamError, ParamStore
from mock_autopilot.px4_streams import DEFAULT_PROFILE, STREAM_PROFILES
from mock_autopilot.vehicle import VehicleConfig

log = logging.getLogger("mock_autopilot")


class UsageError(ValueError):
    """A command-line value that cannot be used; printed as one line, exit code 2."""


@dataclass(frozen=True)
class FleetOptions:
    """Everything the CLI can set, already checked."""

    vehicles: int
    base_port: int = 14540
    gcs_port: int = 14550
    speed: float = 1.0
    no_gps: frozenset[int] = frozenset()
    params: dict[str, float] = field(default_factory=dict)
    signing_key: bytes | None = None
    faults: tuple[FaultSpec, ...] = ()
    pad_spacing_m: float = 2.0
    stream_profile: str = DEFAULT_PROFILE
    px4_local_ports: bool = False
    home: GeodeticHome = field(default_factory=GeodeticHome)
    duration_s: float | None = None


def parse_id_list(text: str) -> frozenset[int]:
    """``"0,2,5-7"`` -> {0, 2, 5, 6, 7} (instance numbers, 0-based)."""
    ids: set[int] = set()
    for part in filter(None, (p.strip() for p in text.split(","))):
        lo, sep, hi = part.partition("-")
        try:
            if sep:
                ids.update(range(int(lo), int(hi) + 1))
            else:
                ids.add(int(part))
        except ValueError as exc:
            raise UsageError(f"--no-gps-for: {part!r} is not an instance number or range") from exc
    return frozenset(ids)


def build_parser() -> argparse.ArgumentParser:
    p = argparse.ArgumentParser(
        prog="python -m mock_autopilot",
        description="N simulated PX4 vehicles in one process (MAVLink 2 over UDP, PX4 SITL port conventions).",
    )
    p.add_argument("--vehicles", type=int, required=True, help="number of vehicles; instance i is system id i+1")
    p.add_argument("--base-port", type=int, default=14540, help="onboard/API link of instance i sends to this + i")
    p.add_argument("--gcs-port", type=int, default=14550, help="GCS link of every vehicle sends here")
    p.add_argument("--speed", type=float, default=1.0, help="simulated seconds per wall second")
    p.add_argument("--no-gps-for", default="", metavar="IDS", help="instances (0-based) without GPS, e.g. 9-12 or 1,3")
    p.add_argument("--param", action="append", default=[], metavar="NAME=VALUE", help="PX4 parameter for every vehicle")
    p.add_argument("--signing-key", metavar="HEX", help="32-byte MAVLink 2 signing key (64 hex digits); GCS link requires it")
    p.add_argument("--fault", action="append", default=[], metavar="KIND:ID[:VALUE]@T", help="scheduled fault: kill, gps, battery, drop, delay, restore")
    p.add_argument("--pad-spacing-m", type=float, default=2.0, help="pads in a row along mission east, this far apart")
    p.add_argument("--stream-rates", choices=sorted(STREAM_PROFILES), default=DEFAULT_PROFILE, help="telemetry rate profile")
    p.add_argument("--px4-local-ports", action="store_true", help="bind links at PX4's 14580+i / 18570+i instead of ephemeral ports")
    p.add_argument("--home", default=None, metavar="LAT,LON,ALT", help="geodetic mission origin")
    p.add_argument("--duration", type=float, default=None, metavar="S", help="stop after S wall seconds (default: until Ctrl-C)")
    p.add_argument("-v", "--verbose", action="store_true")
    return p


def options_from_args(args: argparse.Namespace) -> FleetOptions:
    """Check every value; raise UsageError with a one-line message."""
    if args.vehicles < 1:
        raise UsageError("--vehicles must be >= 1")
    if not args.speed > 0:
        raise UsageError("--speed must be > 0")
    for name, port in (("--base-port", args.base_port), ("--gcs-port", args.gcs_port)):
        if not 1 <= port <= 65535:
            raise UsageError(f"{name} must be a UDP port (1-65535)")
    if onboard_port_range(args.base_port, args.vehicles, args.gcs_port)[1] > 65535:
        raise UsageError("--base-port + --vehicles exceeds 65535")
    params: dict[str, float] = {}
    for item in args.param:
        name, sep, value = item.partition("=")
        if not sep:
            raise UsageError(f"--param {item!r}: expected NAME=VALUE")
        try:
            params[name.strip()] = float(value)
        except ValueError as exc:
            raise UsageError(f"--param {item!r}: value is not a number") from exc
    try:
        ParamStore(params)
    except ParamError as exc:
        raise UsageError(f"--param {exc}") from exc
    no_gps = parse_id_list(args.no_gps_for)
    if any(i >= args.vehicles for i in no_gps):
        raise UsageError(f"--no-gps-for names an instance >= --vehicles ({args.vehicles})")
    key = None
    if args.signing_key is not None:
        try:
            key = parse_signing_key(args.signing_key)
        except ValueError as exc:
            raise UsageError(f"--signing-key: {exc}") from exc
    try:
        faults = tuple(parse_fault(f) for f in args.fault)
    except FaultSpecError as exc:
        raise UsageError(f"--{exc}") from exc
    if any(f.instance >= args.vehicles for f in faults):
        raise UsageError("--fault names an instance >= --vehicles")
    home = GeodeticHome()
    if args.home is not None:
        try:
            lat, lon, alt = (float(x) for x in args.home.split(","))
        except ValueError as exc:
            raise UsageError("--home must be LAT,LON,ALT") from exc
        if not (-90 <= lat <= 90 and -180 <= lon <= 180):
            raise UsageError("--home latitude/longitude out of range")
        home = GeodeticHome(lat, lon, alt)
    return FleetOptions(
        vehicles=args.vehicles, base_port=args.base_port, gcs_port=args.gcs_port, speed=args.speed, no_gps=no_gps,
        params=params, signing_key=key, faults=faults, pad_spacing_m=args.pad_spacing_m,
        stream_profile=args.stream_rates, px4_local_ports=args.px4_local_ports, home=home, duration_s=args.duration,
    )


def vehicle_configs(options: FleetOptions) -> list[VehicleConfig]:
    """One config per instance: pads in a row along mission east, GPS unless listed."""
    return [
        VehicleConfig(
            instance=i, has_gps=i not in options.no_gps, pad_enu_m=(i * options.pad_spacing_m, 0.0, 0.0),
            home=options.home, params=options.params, stream_profile=options.stream_profile,
        )
        for i in range(options.vehicles)
    ]


def main(options: FleetOptions) -> int:
    """Run the fleet until Ctrl-C / SIGTERM or the duration ends; returns the exit code."""
    stop = threading.Event()

    def on_signal(signum: int, frame: object) -> None:
        stop.set()

    previous = {s: signal.signal(s, on_signal) for s in (signal.SIGINT, signal.SIGTERM)}
    try:
        fleet = Fleet(
            vehicle_configs(options), base_port=options.base_port, gcs_port=options.gcs_port, speed=options.speed,
            px4_local_ports=options.px4_local_ports, signing_key=options.signing_key, faults=options.faults,
        )
        try:
            fleet.start()
        except OSError as exc:
            print(f"mock_autopilot: cannot bind a link socket: {exc}", file=sys.stderr)
            return 1
        try:
            first, last = onboard_port_range(options.base_port, options.vehicles, options.gcs_port)
            print(
                f"mock_autopilot: {options.vehicles} vehicle(s), onboard -> 127.0.0.1:{first}"
                f"{'' if last == first else f'-{last}'}, GCS -> 127.0.0.1:{options.gcs_port},"
                f" speed x{options.speed:g}, rates {options.stream_profile}",
                flush=True,
            )
            stop.wait(options.duration_s)
        finally:
            fleet.stop()
            for sysid, counters in fleet.drop_counters().items():
                print(f"mock_autopilot: system {sysid} drops {counters}", file=sys.stderr, flush=True)
    finally:
        for s, handler in previous.items():
            signal.signal(s, handler)
    return 0


def run(argv: Sequence[str] | None = None) -> int:
    """Entry point: parse, check, run; usage errors print one line and return 2."""
    parser = build_parser()
    try:
        args = parser.parse_args(argv)
    except SystemExit as exc:
        return int(exc.code or 0)
    logging.basicConfig(level=logging.INFO if args.verbose else logging.WARNING, format="%(name)s: %(message)s")
    try:
        options = options_from_args(args)
    except UsageError as exc:
        print(f"mock_autopilot: {exc}", file=sys.stderr)
        return 2
    return main(options)
