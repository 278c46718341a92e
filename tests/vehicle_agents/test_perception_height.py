"""Perception's scale on a drone: the rangefinder's height above ground, the frame's altitude only without one."""

from __future__ import annotations

import math

from comms.messages import CameraFrame
from vehicle_agents.agent import perception_height_m
from vehicle_agents.autopilot_link import AutopilotTelemetry


def _frame(altitude_m: float) -> CameraFrame:
    return CameraFrame(vehicle_id=1, seq=0, t_s=1.0, altitude_m=altitude_m, yaw_ned_rad=0.0, fov_deg=90.0,
                       width_px=1, height_px=1, encoding="raw_bgr", image=b"\0\0\0")


def test_the_rangefinder_reading_scales_perception_over_relief() -> None:
    telemetry = AutopilotTelemetry(position_ned_m=(0.0, 0.0, -10.0), height_above_ground_m=11.37)
    assert perception_height_m(telemetry, _frame(10.0)) == 11.37


def test_without_a_reading_the_frame_altitude_is_used() -> None:
    assert perception_height_m(AutopilotTelemetry(), _frame(9.5)) == 9.5
    assert math.isnan(AutopilotTelemetry().height_above_ground_m)
    assert perception_height_m(AutopilotTelemetry(height_above_ground_m=0.0), _frame(9.5)) == 9.5
