"""Run the onboard perception on an image file: ``python -m vehicle_agents.perception frame.png --alt 10 --fov 60``.

Prints the ``PerceptionResult`` as JSON; offsets are metres on the ground, east and north (at ``--yaw 0`` image up
is north). Exit code 2 for an unreadable image or bad arguments; an image that yields no measurement is still
printed (``has_edge`` false, ``water_fraction`` null).
"""

from __future__ import annotations

import argparse
import json
import math
import sys
from collections.abc import Sequence
from pathlib import Path
from typing import Any

import cv2
import numpy as np

from vehicle_agents.perception.result import PerceptionResult
from vehicle_agents.perception.segmentation import perceive


def result_to_json(result: PerceptionResult) -> dict[str, Any]:
    """A JSON-ready dict of a result (arrays as lists, NaN as null)."""

    def plain(value: Any) -> Any:
        if isinstance(value, np.ndarray):
            return plain(value.tolist())
        if isinstance(value, (list, tuple)):
            return [plain(v) for v in value]
        if isinstance(value, float) and not math.isfinite(value):
            return None
        return value

    return {name: plain(getattr(result, name)) for name in result.__dataclass_fields__}


def main(image_path: Path, altitude_m: float, fov_deg: float, yaw_deg: float) -> int:
    image = cv2.imread(str(image_path), cv2.IMREAD_COLOR) if image_path.is_file() else None
    if image is None:
        print(f"error: {image_path}: cannot read as an image", file=sys.stderr)
        return 2
    if not (math.isfinite(altitude_m) and altitude_m > 0.0):
        print("error: --alt: must be a finite height > 0 m", file=sys.stderr)
        return 2
    if not (math.isfinite(fov_deg) and 0.0 < fov_deg < 180.0):
        print("error: --fov: must be in (0, 180) degrees", file=sys.stderr)
        return 2
    result = perceive(image, altitude_m, fov_deg, math.radians(yaw_deg))
    print(json.dumps(result_to_json(result), indent=2))
    return 0


def parse_args(argv: Sequence[str] | None) -> argparse.Namespace:
    parser = argparse.ArgumentParser(prog="python -m vehicle_agents.perception", description=__doc__.split("\n\n")[0])
    parser.add_argument("image", type=Path, help="camera frame (PNG/JPEG, BGR colour)")
    parser.add_argument("--alt", type=float, required=True, help="height above ground [m]")
    parser.add_argument("--fov", type=float, default=60.0, help="horizontal field of view [deg]")
    parser.add_argument("--yaw", type=float, default=0.0, help="PX4 yaw [deg, clockwise from north]")
    return parser.parse_args(argv)


if __name__ == "__main__":
    args = parse_args(None)
    sys.exit(main(args.image, args.alt, args.fov, args.yaw))
