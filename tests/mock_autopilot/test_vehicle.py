"""The sans-IO vehicle: PX4 behaviour through the wire format, with simulated time only (no sockets)."""

import math

import numpy as np
import pytest
from pymavlink.dialects.v20 import common as mavlink

from comms.frames import GeodeticHome, enu_to_geodetic
from comms.px4 import LandedState, Px4Mode, custom_mode
from mock_autopilot.harness import VehicleHarness
from mock_autopilot.px4_params import PARAM_TABLE, ParamType, encode_param_value
from mock_autopilot.setpoints import MASK_VELOCITY_AND_YAW
from mock_autopilot.vehicle import VehicleConfig

ACCEPTED, TEMP_REJECTED, DENIED, UNSUPPORTED = 0, 1, 2, 3
NAN = math.nan


def velocity(h: VehicleHarness, vn: float, ve: float, vd: float, yaw: float = 0.0, frame: int = 1, mask: int = MASK_VELOCITY_AND_YAW) -> None:
    h.send(mavlink.MAVLink_set_position_target_local_ned_message(
        0, h.vehicle.system_id, 1, frame, mask, NAN, NAN, NAN, vn, ve, vd, NAN, NAN, NAN, yaw, NAN))


def stream_velocity(h: VehicleHarness, seconds: float, vn: float, ve: float, vd: float, yaw: float = 0.0, frame: int = 1) -> None:
    for _ in range(int(round(seconds / 0.05))):
        velocity(h, vn, ve, vd, yaw, frame)
        h.run(0.05)


def set_mode(h: VehicleHarness, mode: Px4Mode) -> int:
    c = custom_mode(mode)
    return h.command(mavlink.MAV_CMD_DO_SET_MODE, 1, (c >> 16) & 0xFF, (c >> 24) & 0xFF)


def airborne(h: VehicleHarness, altitude_m: float = 5.0) -> None:
    set_param(h, "MIS_TAKEOFF_ALT", altitude_m)
    assert h.command(400, 1) == ACCEPTED
    assert h.command(22, NAN, NAN, NAN, NAN, NAN, NAN, NAN) == ACCEPTED
    h.run(altitude_m / 1.5 + 3.0)
    assert h.vehicle.mode is Px4Mode.AUTO_LOITER


def set_param(h: VehicleHarness, name: str, value: float) -> mavlink.MAVLink_message:
    spec = next(p for p in PARAM_TABLE if p.name == name)
    replies = h.send(mavlink.MAVLink_param_set_message(1, 1, name.encode(), encode_param_value(value, spec.type), int(spec.type)))
    values = [r for r in replies if r.get_type() == "PARAM_VALUE"]
    assert values
    return values[-1]


def test_heartbeat_identifies_px4_quadrotor() -> None:
    h = VehicleHarness()
    h.run(1.0)
    hb = h.last("HEARTBEAT")
    assert (hb.type, hb.autopilot, hb.system_status) == (2, 12, 3)
    assert hb.custom_mode == custom_mode(Px4Mode.AUTO_LOITER)
    assert hb.base_mode & 1 and not hb.base_mode & 128
    assert h.last("HEARTBEAT", "gcs") is not None


def test_sys_status_gives_mavsdk_health_for_gps_vehicle() -> None:
    h = VehicleHarness()
    h.run(1.1)
    s = h.last("SYS_STATUS")
    for bit in (mavlink.MAV_SYS_STATUS_SENSOR_GPS, mavlink.MAV_SYS_STATUS_PREARM_CHECK, mavlink.MAV_SYS_STATUS_SENSOR_3D_GYRO):
        assert s.onboard_control_sensors_present & bit and s.onboard_control_sensors_health & bit
    assert h.last("GPS_RAW_INT").fix_type == 3 and h.last("GPS_RAW_INT").satellites_visible >= 10
    assert h.last("HOME_POSITION") is not None


def test_global_position_is_home_plus_pad_plus_local() -> None:
    home = GeodeticHome(47.0, 8.0, 400.0)
    h = VehicleHarness(VehicleConfig(0, pad_enu_m=(14.0, 3.0, 0.0), home=home))
    airborne(h, 5.0)
    g = h.last("GLOBAL_POSITION_INT")
    p = h.vehicle.position_ned_m
    lat, lon, alt = enu_to_geodetic(np.array([14.0 + p[1], 3.0 + p[0], -p[2]]), home)
    assert g.lat == pytest.approx(lat * 1e7, abs=2) and g.lon == pytest.approx(lon * 1e7, abs=2)
    assert g.alt == pytest.approx(alt * 1000, abs=5)
    assert g.relative_alt == pytest.approx(5000, abs=250)


def test_vehicle_without_gps_flies_on_local_position() -> None:
    h = VehicleHarness(VehicleConfig(0, has_gps=False))
    h.run(1.1)
    s = h.last("SYS_STATUS")
    assert not s.onboard_control_sensors_present & mavlink.MAV_SYS_STATUS_SENSOR_GPS
    assert s.onboard_control_sensors_health & mavlink.MAV_SYS_STATUS_SENSOR_VISION_POSITION
    assert s.onboard_control_sensors_health & mavlink.MAV_SYS_STATUS_PREARM_CHECK
    assert h.type_counts()["GLOBAL_POSITION_INT"] == 0 and h.type_counts()["HOME_POSITION"] == 0
    assert h.last("GPS_RAW_INT").fix_type == 0
    assert h.command(512, mavlink.MAVLINK_MSG_ID_HOME_POSITION) == DENIED
    assert h.command(mavlink.MAV_CMD_GET_HOME_POSITION) == DENIED
    velocity(h, 0, 0, 0)
    assert set_mode(h, Px4Mode.OFFBOARD) == ACCEPTED
    assert h.command(400, 1) == ACCEPTED
    stream_velocity(h, 3.0, 0.0, 0.0, -1.0)
    assert h.vehicle.position_ned_m[2] < -2.0
    assert set_mode(h, Px4Mode.AUTO_RTL) == TEMP_REJECTED
    assert any("not possible" in t for t in h.texts())


def test_arm_takeoff_loiter_land_auto_disarm() -> None:
    h = VehicleHarness()
    set_param(h, "MIS_TAKEOFF_ALT", 6.0)
    assert h.command(400, 1) == ACCEPTED
    assert h.command(400, 1) == ACCEPTED  # idempotent
    assert h.command(22, NAN, NAN, NAN, NAN, NAN, NAN, NAN) == ACCEPTED
    h.run(1.0)
    assert h.last("HEARTBEAT").custom_mode == custom_mode(Px4Mode.AUTO_TAKEOFF)
    assert h.last("HEARTBEAT").base_mode & 128 and h.last("HEARTBEAT").system_status == 4
    assert h.vehicle.mode is Px4Mode.AUTO_TAKEOFF and h.vehicle.landed_state is LandedState.TAKEOFF
    h.run(8.0)
    assert h.vehicle.mode is Px4Mode.AUTO_LOITER
    assert -h.vehicle.position_ned_m[2] == pytest.approx(6.0, abs=0.3)
    assert h.last("EXTENDED_SYS_STATE").landed_state == LandedState.IN_AIR
    assert h.command(21) == ACCEPTED
    h.run(1.0)
    assert h.last("EXTENDED_SYS_STATE").landed_state == LandedState.LANDING
    h.run(6.0 / 0.7 + 1.0)
    assert h.vehicle.armed, "must not disarm before COM_DISARM_LAND"
    h.run(2.5)
    assert not h.vehicle.armed
    assert any("Disarmed by landing" in t for t in h.texts())
    assert h.vehicle.mode is Px4Mode.AUTO_LOITER


def test_disarm_land_param_changes_the_timer() -> None:
    h = VehicleHarness()
    set_param(h, "COM_DISARM_LAND", 6.0)
    airborne(h, 2.0)
    h.command(21)
    h.run(2.0 / 0.7 + 1.0 + 4.0)
    assert h.vehicle.armed
    h.run(3.0)
    assert not h.vehicle.armed


def test_preflight_auto_disarm() -> None:
    h = VehicleHarness()
    set_param(h, "COM_DISARM_PRFLT", 4.0)
    assert h.command(400, 1) == ACCEPTED
    h.run(3.5)
    assert h.vehicle.armed
    h.run(1.0)
    assert not h.vehicle.armed
    assert any("preflight" in t for t in h.texts())


def test_disarm_in_air_refused_unless_forced() -> None:
    h = VehicleHarness()
    airborne(h)
    assert h.command(400, 0) == TEMP_REJECTED
    assert h.vehicle.armed
    assert h.command(400, 0, 21196) == ACCEPTED
    assert not h.vehicle.armed
    h.run(3.0)
    assert h.vehicle.position_ned_m[2] == 0.0  # fell


def test_takeoff_altitude_from_param7_amsl() -> None:
    home = GeodeticHome(47.0, 8.0, 400.0)
    h = VehicleHarness(VehicleConfig(0, home=home))
    h.command(400, 1)
    assert h.command(22, 0, 0, 0, NAN, NAN, NAN, 408.0) == ACCEPTED
    h.run(8.0)
    assert -h.vehicle.position_ned_m[2] == pytest.approx(8.0, abs=0.3)


def test_takeoff_when_disarmed_selects_the_mode_and_climbs_once_armed() -> None:
    # PX4 commander: NAV_TAKEOFF only switches to AUTO.TAKEOFF; arming then takes off.
    h = VehicleHarness()
    set_param(h, "MIS_TAKEOFF_ALT", 4.0)
    assert h.command(22, NAN, NAN, NAN, NAN, NAN, NAN, NAN) == ACCEPTED
    h.run(0.5)
    assert h.vehicle.mode is Px4Mode.AUTO_TAKEOFF and h.vehicle.position_ned_m[2] == 0.0
    assert h.command(400, 1) == ACCEPTED
    h.run(6.0)
    assert h.vehicle.mode is Px4Mode.AUTO_LOITER
    assert -h.vehicle.position_ned_m[2] == pytest.approx(4.0, abs=0.3)


def test_arm_param_is_rounded_and_anything_else_unsupported() -> None:
    h = VehicleHarness()
    assert h.command(400, 2.0) == UNSUPPORTED
    assert any(t.startswith("Unsupported ARM_DISARM param") for t in h.texts())
    assert h.command(400, 0.9) == ACCEPTED and h.vehicle.armed


def test_set_mode_follows_px4_commander() -> None:
    h = VehicleHarness()
    assert h.command(mavlink.MAV_CMD_DO_SET_MODE, 1, 4, 0) == TEMP_REJECTED  # AUTO alone is MISSION: no mission
    assert h.command(mavlink.MAV_CMD_DO_SET_MODE, 1, 4, 77) == TEMP_REJECTED
    assert any(t == "Unsupported auto mode" for t in h.texts())
    assert h.command(mavlink.MAV_CMD_DO_SET_MODE, 1, 99, 0) == ACCEPTED  # names no mode: nothing changes
    assert h.vehicle.mode is Px4Mode.AUTO_LOITER
    manual_guided = mavlink.MAV_MODE_FLAG_MANUAL_INPUT_ENABLED | mavlink.MAV_MODE_FLAG_GUIDED_ENABLED
    assert h.command(mavlink.MAV_CMD_DO_SET_MODE, manual_guided, 0, 0) == ACCEPTED  # base mode flags: POSCTL
    assert h.vehicle.mode is Px4Mode.POSCTL


def test_arming_refused_in_offboard_without_setpoints_and_in_manual_modes() -> None:
    h = VehicleHarness()
    assert set_mode(h, Px4Mode.OFFBOARD) == TEMP_REJECTED  # PX4: OFFBOARD needs the setpoint stream, armed or not
    velocity(h, 0, 0, 0)
    assert set_mode(h, Px4Mode.OFFBOARD) == ACCEPTED
    h.run(1.1)
    assert h.command(400, 1) == TEMP_REJECTED
    assert any(t.startswith("Arming denied") for t in h.texts())
    h.run(1.1)
    assert not h.last("SYS_STATUS").onboard_control_sensors_health & mavlink.MAV_SYS_STATUS_PREARM_CHECK
    assert set_mode(h, Px4Mode.POSCTL) == ACCEPTED
    assert h.command(400, 1) == TEMP_REJECTED


def test_offboard_needs_fresh_setpoints_when_armed() -> None:
    h = VehicleHarness()
    airborne(h)
    assert set_mode(h, Px4Mode.OFFBOARD) == TEMP_REJECTED
    velocity(h, 0, 0, 0)
    assert set_mode(h, Px4Mode.OFFBOARD) == ACCEPTED
    hb = h.run(0.02)
    assert h.vehicle.mode is Px4Mode.OFFBOARD


def test_heartbeat_reflects_mode_at_once_after_set_mode_message() -> None:
    h = VehicleHarness()
    h.send(mavlink.MAVLink_set_mode_message(1, 1, custom_mode(Px4Mode.POSCTL)))
    h.run(1.0)
    assert h.last("HEARTBEAT").custom_mode == custom_mode(Px4Mode.POSCTL)


@pytest.mark.parametrize("north,east,down,frame,yaw0", [
    (2.0, 0.0, 0.0, 1, 0.0), (0.0, -1.5, 0.0, 1, 0.0), (1.0, 1.0, -0.5, 1, 0.0), (2.0, 0.0, 0.0, 8, math.pi / 2),
])
def test_offboard_velocity_moves_right_distance_and_direction(north: float, east: float, down: float, frame: int, yaw0: float) -> None:
    h = VehicleHarness(VehicleConfig(0, initial_yaw_rad=yaw0))
    airborne(h, 10.0)
    velocity(h, 0, 0, 0, yaw0)
    assert set_mode(h, Px4Mode.OFFBOARD) == ACCEPTED
    start = h.vehicle.position_ned_m.copy()
    stream_velocity(h, 10.0, north, east, down, yaw0, frame)
    moved = h.vehicle.position_ned_m - start
    if frame == 8:  # body: forward at yaw 90 deg is east
        expected = np.array([-east, north, down]) * 10.0
    else:
        expected = np.array([north, east, down]) * 10.0
    # first-order response (0.3 s) and acceleration limit lag a little behind the ideal distance
    assert np.allclose(moved, expected, atol=0.1 * np.linalg.norm(expected) + 0.3)
    assert np.linalg.norm(moved) < np.linalg.norm(expected) + 0.05
    pt = h.last("POSITION_TARGET_LOCAL_NED")
    assert pt.type_mask == MASK_VELOCITY_AND_YAW


def test_velocity_clamped_by_mpc_xy_vel_max() -> None:
    h = VehicleHarness()
    set_param(h, "MPC_XY_VEL_MAX", 3.0)
    airborne(h)
    velocity(h, 0, 0, 0)
    set_mode(h, Px4Mode.OFFBOARD)
    stream_velocity(h, 5.0, 10.0, 0.0, 0.0)
    assert np.hypot(*h.vehicle.velocity_ned_mps[:2]) == pytest.approx(3.0, abs=0.05)


FALLBACKS = {0: Px4Mode.POSCTL, 1: Px4Mode.ALTCTL, 2: Px4Mode.STABILIZED, 3: Px4Mode.AUTO_RTL, 4: Px4Mode.AUTO_LAND, 5: Px4Mode.AUTO_LOITER}


@pytest.mark.parametrize("action", range(8))
def test_offboard_loss_fallback_after_com_of_loss_t(action: int) -> None:
    h = VehicleHarness()
    set_param(h, "COM_OBL_RC_ACT", action)
    set_param(h, "COM_OF_LOSS_T", 2.0)
    airborne(h)
    velocity(h, 0, 0, 0)
    set_mode(h, Px4Mode.OFFBOARD)
    stream_velocity(h, 1.0, 1.0, 0.0, 0.0)
    h.run(1.9)
    assert h.vehicle.mode is Px4Mode.OFFBOARD
    h.run(0.2)
    assert h.vehicle.failsafe or action == 7
    assert any("offboard lost" in t for t in h.texts())
    if action in FALLBACKS:
        assert h.vehicle.mode is FALLBACKS[action]
        h.run(1.1)
        assert h.last("HEARTBEAT").system_status == 5
        assert h.last("HEARTBEAT").custom_mode == custom_mode(FALLBACKS[action])
    else:
        assert not h.vehicle.armed


def test_parameter_protocol() -> None:
    h = VehicleHarness()
    replies = h.send(mavlink.MAVLink_param_request_list_message(1, 1))
    values = [r for r in replies if r.get_type() == "PARAM_VALUE"]
    assert len(values) == len(PARAM_TABLE)
    assert [v.param_index for v in values] == list(range(len(PARAM_TABLE)))
    assert all(v.param_count == len(PARAM_TABLE) for v in values)
    by_name = {v.param_id: v for v in values}
    assert by_name["MAV_SYS_ID"].param_type == ParamType.INT32
    assert by_name["MAV_SYS_ID"].param_value == encode_param_value(1, ParamType.INT32)
    read = h.send(mavlink.MAVLink_param_request_read_message(1, 1, b"COM_OF_LOSS_T", -1))
    assert read[0].param_value == 1.0 and read[0].param_type == ParamType.REAL32
    by_index = h.send(mavlink.MAVLink_param_request_read_message(1, 1, b"", 0))
    assert by_index[0].param_id == PARAM_TABLE[0].name
    echo = set_param(h, "COM_OBL_RC_ACT", 4)
    assert echo.param_value == encode_param_value(4, ParamType.INT32)
    assert h.vehicle.params["COM_OBL_RC_ACT"] == 4


def test_bad_param_sets_are_refused_and_answered_with_current_value() -> None:
    h = VehicleHarness()
    before = h.vehicle.params["MPC_XY_VEL_MAX"]
    replies = h.send(mavlink.MAVLink_param_set_message(1, 1, b"MPC_XY_VEL_MAX", NAN, 9))
    assert [r.param_value for r in replies if r.get_type() == "PARAM_VALUE"] == [before]
    replies = h.send(mavlink.MAVLink_param_set_message(1, 1, b"COM_OBL_RC_ACT", encode_param_value(99, ParamType.INT32), 6))
    assert h.vehicle.params["COM_OBL_RC_ACT"] == 0
    assert any(r.get_type() == "STATUSTEXT" for r in replies)
    assert h.send(mavlink.MAVLink_param_set_message(1, 1, b"NOPE", 1.0, 9))[0].get_type() == "STATUSTEXT"


def test_message_interval_and_request_message() -> None:
    h = VehicleHarness()
    assert h.command(511, mavlink.MAVLINK_MSG_ID_LOCAL_POSITION_NED, 200_000) == ACCEPTED
    h.run(0.1)
    h.received.clear()
    h.run(2.0)
    assert h.type_counts()["LOCAL_POSITION_NED"] == pytest.approx(10, abs=1)
    assert h.command(511, mavlink.MAVLINK_MSG_ID_LOCAL_POSITION_NED, -1) == ACCEPTED
    h.received.clear()
    h.run(1.0)
    assert h.type_counts()["LOCAL_POSITION_NED"] == 0
    assert h.command(511, 99999, 1000) == DENIED
    replies = h.send(mavlink.MAVLink_command_long_message(1, 1, 512, 0, mavlink.MAVLINK_MSG_ID_AUTOPILOT_VERSION, 0, 0, 0, 0, 0, 0))
    assert [r.get_type() for r in replies] == ["COMMAND_ACK", "AUTOPILOT_VERSION"]
    caps = replies[1].capabilities
    for cap in (mavlink.MAV_PROTOCOL_CAPABILITY_MAVLINK2, mavlink.MAV_PROTOCOL_CAPABILITY_PARAM_ENCODE_BYTEWISE,
                mavlink.MAV_PROTOCOL_CAPABILITY_SET_POSITION_TARGET_LOCAL_NED, mavlink.MAV_PROTOCOL_CAPABILITY_COMMAND_INT):
        assert caps & cap
    replies = h.send(mavlink.MAVLink_command_long_message(1, 1, 520, 0, 1, 0, 0, 0, 0, 0, 0))
    assert [r.get_type() for r in replies] == ["COMMAND_ACK", "AUTOPILOT_VERSION"]
    assert h.command(512, mavlink.MAVLINK_MSG_ID_HOME_POSITION) == ACCEPTED


def test_unsupported_command_ping_timesync_mission() -> None:
    h = VehicleHarness()
    assert h.command(mavlink.MAV_CMD_DO_SET_SERVO, 1, 1500) == UNSUPPORTED
    pong = h.send(mavlink.MAVLink_ping_message(42, 9, 0, 0))
    assert pong[0].time_usec == 42 and pong[0].seq == 9 and pong[0].target_system == 255
    ts = h.send(mavlink.MAVLink_timesync_message(0, 777))
    assert ts[0].ts1 == 777 and ts[0].tc1 >= 0
    count = h.send(mavlink.MAVLink_mission_request_list_message(1, 1, 0))
    assert count[0].get_type() == "MISSION_COUNT" and count[0].count == 0


def test_rtl_returns_home_and_lands() -> None:
    h = VehicleHarness()
    set_param(h, "RTL_RETURN_ALT", 8.0)
    airborne(h, 5.0)
    velocity(h, 0, 0, 0)
    set_mode(h, Px4Mode.OFFBOARD)
    stream_velocity(h, 5.0, 3.0, 0.0, 0.0)
    assert h.command(20) == ACCEPTED
    h.run(4.0)
    assert -h.vehicle.position_ned_m[2] > 7.0
    h.run(40.0)
    assert np.hypot(*h.vehicle.position_ned_m[:2]) < 0.6
    assert not h.vehicle.armed


def test_gps_loss_in_rtl_lands_and_drain_battery_triggers_failsafe() -> None:
    h = VehicleHarness()
    airborne(h)
    h.command(20)
    h.vehicle.set_gps_available(False, h.now_s)
    h.run(0.1)
    assert h.vehicle.mode is Px4Mode.AUTO_LAND
    h.run(1.1)
    assert h.last("GPS_RAW_INT").fix_type == 1
    h2 = VehicleHarness()
    set_param(h2, "COM_LOW_BAT_ACT", 2)
    airborne(h2)
    h2.vehicle.set_battery_remaining(0.06)
    h2.run(0.1)
    assert h2.vehicle.mode is Px4Mode.AUTO_LAND and h2.vehicle.failsafe
    assert h2.command(400, 1) == ACCEPTED  # already armed: idempotent


def test_datalink_loss_action() -> None:
    h = VehicleHarness()
    set_param(h, "NAV_DLL_ACT", 3)
    h.send(mavlink.MAVLink_heartbeat_message(6, 8, 0, 0, 4, 3), "gcs")
    airborne(h)
    h.run(10.0)
    assert h.vehicle.mode is Px4Mode.AUTO_LAND
    assert any("GCS connection lost" in t for t in h.texts())


def test_setpoint_px4_cannot_fly_is_proof_of_life_and_the_vehicle_hovers() -> None:
    # PX4: NaN in a used field means "not set"; north then has no setpoint, which the position controller's input
    # check rejects: offboard stays alive (offboard_control_mode is published) and the vehicle flies its failsafe.
    h = VehicleHarness()
    airborne(h, 5.0)
    velocity(h, 0.0, 0.0, 0.0)
    assert set_mode(h, Px4Mode.OFFBOARD) == ACCEPTED
    start = h.vehicle.position_ned_m.copy()
    for _ in range(40):
        velocity(h, NAN, 2.0, 0.0)
        h.run(0.05)
    assert h.vehicle.mode is Px4Mode.OFFBOARD and not h.vehicle.offboard_setpoint.flyable
    assert h.vehicle.rejections["setpoint_not_flyable"] == 40
    assert h.vehicle.position_ned_m == pytest.approx(start, abs=0.1)


def test_setpoint_setting_nothing_is_refused_with_px4_text() -> None:
    h = VehicleHarness()
    velocity(h, NAN, NAN, NAN)
    assert h.vehicle.offboard_setpoint is None and h.vehicle.rejections["setpoint_no_setpoint"] == 1
    assert "SET_POSITION_TARGET_LOCAL_NED invalid" in h.texts()


def test_killed_vehicle_is_silent_and_falls() -> None:
    h = VehicleHarness()
    airborne(h)
    h.vehicle.kill()
    h.received.clear()
    h.run(3.0)
    assert h.received == []
    assert h.vehicle.position_ned_m[2] == 0.0


def test_reposition_by_command_int_and_change_speed() -> None:
    home = GeodeticHome(47.0, 8.0, 400.0)
    h = VehicleHarness(VehicleConfig(0, home=home, pad_enu_m=(10.0, 0.0, 0.0)))
    airborne(h, 5.0)
    assert h.command(178, 1, 2.0, -1) == ACCEPTED
    lat, lon, _ = enu_to_geodetic(np.array([10.0, 20.0, 0.0]), home)  # 20 m north of the pad
    replies = h.send(mavlink.MAVLink_command_int_message(
        1, 1, mavlink.MAV_FRAME_GLOBAL_RELATIVE_ALT_INT, 192, 0, 0, -1, 1, 0, NAN, int(round(lat * 1e7)), int(round(lon * 1e7)), 8.0))
    assert [r.result for r in replies if r.get_type() == "COMMAND_ACK"] == [ACCEPTED]
    h.run(3.0)
    assert np.hypot(*h.vehicle.velocity_ned_mps[:2]) == pytest.approx(2.0, abs=0.1)  # DO_CHANGE_SPEED cruise
    h.run(20.0)
    assert h.vehicle.position_ned_m == pytest.approx([20.0, 0.0, -8.0], abs=0.3)
    assert h.vehicle.mode is Px4Mode.AUTO_LOITER
    assert h.command(178, 1, NAN) == DENIED
    assert h.command(192, -1, 0, 0, NAN, 47.0, 8.0, 500.0) == UNSUPPORTED  # PX4 needs the change-mode flag


def test_reposition_refused_without_gps() -> None:
    h = VehicleHarness(VehicleConfig(0, has_gps=False))
    assert h.command(192, -1, 1, 0, NAN, 47.0, 8.0, 500.0) == TEMP_REJECTED
