"""Fuzz: tens of thousands of malformed datagrams, then the vehicle still answers correctly and nothing changed.

The malformed set (seeded): random bytes; valid state-changing frames truncated, bit-flipped (CRC), given an
unknown message id, re-addressed to another system/component, sent as MAVLink 1, or carrying infinities;
well-formed frames with NaN, out-of-range enums and invalid type_masks; garbage glued before frames.
"""

import logging
import math
import os
import random
import socket
import time

os.environ["MAVLINK20"] = "1"

import pytest
from pymavlink.dialects.v20 import common as mavlink

from comms.px4 import Px4Mode
from mock_autopilot.fleet import Fleet
from mock_autopilot.harness import VehicleHarness

NAN, INF = math.nan, math.inf
ACCELERATION_WITH_FORCE = 0b1110_0011_1111
"""Accelerations used with FORCE_SET (bit 9): PX4 refuses it whatever the undefined bits above 11 say."""


def state_changing_messages(rng: random.Random, target: int = 1) -> list[mavlink.MAVLink_message]:
    """Messages that WOULD change state if accepted (arm, mode, takeoff, setpoint, parameter)."""
    return [
        mavlink.MAVLink_command_long_message(target, 1, 400, 0, 1, 0, 0, 0, 0, 0, 0),
        mavlink.MAVLink_command_long_message(target, 1, 176, 0, 1, 6, 0, 0, 0, 0, 0),
        mavlink.MAVLink_command_long_message(target, 1, 22, 0, NAN, NAN, NAN, NAN, NAN, NAN, NAN),
        mavlink.MAVLink_set_mode_message(target, 1, 6 << 16),
        mavlink.MAVLink_set_position_target_local_ned_message(0, target, 1, 1, 2503, NAN, NAN, NAN, rng.uniform(-5, 5), 0, 0, NAN, NAN, NAN, 0, NAN),
        mavlink.MAVLink_param_set_message(target, 1, b"MPC_XY_VEL_MAX", 3.0, 9),
    ]


def semantically_invalid(rng: random.Random) -> list[mavlink.MAVLink_message]:
    """Well-formed, correctly addressed, but meaningless: must be refused by the vehicle."""
    return [
        mavlink.MAVLink_command_long_message(1, 1, 400, 0, NAN, 0, 0, 0, 0, 0, 0),
        mavlink.MAVLink_command_long_message(1, 1, 400, 0, 2.0, 0, 0, 0, 0, 0, 0),
        mavlink.MAVLink_command_long_message(1, 1, 176, 0, 1, 99, 0, 0, 0, 0, 0),
        mavlink.MAVLink_command_long_message(1, 1, 176, 0, 1, 4, 77, 0, 0, 0, 0),
        mavlink.MAVLink_command_long_message(1, 1, 176, 0, NAN, NAN, 0, 0, 0, 0, 0),
        mavlink.MAVLink_command_long_message(1, 1, rng.randint(1000, 65535), 0, 1, 1, 1, 1, 1, 1, 1),
        mavlink.MAVLink_set_mode_message(1, 1, rng.randint(0, 2**32 - 1) | 0x1),
        mavlink.MAVLink_set_mode_message(1, 0, 6 << 16),
        mavlink.MAVLink_set_position_target_local_ned_message(0, 1, 1, 1, rng.randint(0, 15) << 12 | ACCELERATION_WITH_FORCE, 0, 0, 0, 1, 1, 1, 0, 0, 0, 0, 0),
        mavlink.MAVLink_set_position_target_local_ned_message(0, 1, 1, rng.choice([0, 2, 3, 6, 99, 255]), 2503, NAN, NAN, NAN, 1, 1, 1, NAN, NAN, NAN, 0, NAN),
        mavlink.MAVLink_set_position_target_local_ned_message(0, 1, 1, 1, 2503, NAN, NAN, NAN, NAN, 1, 1, NAN, NAN, NAN, 0, NAN),
        mavlink.MAVLink_set_position_target_local_ned_message(0, 1, 1, 1, 0b111111111111, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0),
        mavlink.MAVLink_param_set_message(1, 1, b"MPC_XY_VEL_MAX", NAN, 9),
        mavlink.MAVLink_param_set_message(1, 1, b"MPC_XY_VEL_MAX", 1e9, 9),
        mavlink.MAVLink_param_set_message(1, 1, b"COM_OBL_RC_ACT", rng.uniform(8, 1e6), 9),
        mavlink.MAVLink_param_set_message(1, 1, bytes(rng.getrandbits(8) | 1 for _ in range(16)), 1.0, 9),
        mavlink.MAVLink_param_request_read_message(1, 1, b"", rng.randint(200, 30000)),
        mavlink.MAVLink_command_int_message(1, 1, 6, 192, 0, 0, -1, 1, 0, 0, 2_000_000_000, 2_000_000_000, 10.0),
    ]


def malformed_datagrams(count: int, seed: int) -> list[bytes]:
    """``count`` datagrams none of which may change the vehicle's state."""
    rng = random.Random(seed)
    mav = mavlink.MAVLink(None, 255, 190)
    out: list[bytes] = []
    while len(out) < count:
        kind = rng.randrange(10)
        if kind == 0:
            out.append(bytes(rng.getrandbits(8) for _ in range(rng.randint(0, 280))))
            continue
        if kind == 8:
            out.append(rng.choice(semantically_invalid(rng)).pack(mav))
            continue
        msg = rng.choice(state_changing_messages(rng))
        frame = bytearray(msg.pack(mav))
        if kind == 1:
            out.append(bytes(frame[: rng.randint(0, len(frame) - 1)]))
        elif kind == 2:
            bit = rng.randrange(len(frame) * 8 - 8) + 8  # any bit but the magic byte
            frame[bit // 8] ^= 1 << (bit % 8)
            out.append(bytes(frame))
        elif kind == 3:
            frame[7:10] = rng.choice([12345, 0xFFFFFF, 60000, 500]).to_bytes(3, "little")
            out.append(bytes(frame))
        elif kind == 4:
            wrong = rng.choice(state_changing_messages(rng, target=rng.choice([0, 2, 7, 255])))
            out.append(wrong.pack(mav))
        elif kind == 5:
            out.append(msg.pack(mav, force_mavlink1=True))
        elif kind == 6:
            inf_msg = mavlink.MAVLink_set_position_target_local_ned_message(0, 1, 1, 1, 2503, NAN, NAN, NAN, rng.choice([INF, -INF]), 0, 0, NAN, NAN, NAN, 0, NAN)
            out.append(inf_msg.pack(mav))
        elif kind == 7:
            junk = bytes(rng.getrandbits(8) for _ in range(rng.randint(1, 40)))
            out.append(junk + bytes(frame[: rng.randint(1, len(frame) - 1)]))
        else:
            incompat = bytearray(frame)
            incompat[2] = rng.choice([0x02, 0x80, 0xFE])
            out.append(bytes(incompat))
    return out


def assert_untouched(h: VehicleHarness) -> None:
    v = h.vehicle
    assert not v.armed
    assert v.mode is Px4Mode.AUTO_LOITER
    assert v.offboard_setpoint is None or not v.offboard_setpoint.flyable  # PX4 takes some as proof of life only
    assert v.params["MPC_XY_VEL_MAX"] == 12.0 and v.params["COM_OBL_RC_ACT"] == 0


def test_sans_io_fuzz_fifty_thousand_datagrams_then_answers() -> None:
    h = VehicleHarness()
    datagrams = malformed_datagrams(50_000, seed=1)
    pings_answered = 0
    for i, data in enumerate(datagrams):
        h.send_bytes(data)
        if i % 500 == 0:
            replies = h.send(mavlink.MAVLink_ping_message(i, i % 256, 0, 0))
            pings_answered += sum(1 for r in replies if r.get_type() == "PING" and r.time_usec == i)
            h.run(0.02)
    assert pings_answered == 100
    assert_untouched(h)
    drops = sum(h.codecs["onboard"].drops.values())
    refusals = sum(h.vehicle.rejections.values())
    assert drops > 35_000 and refusals > 3_000
    assert h.command(400, 1) == 0 and h.vehicle.armed


def test_garbage_datagram_never_swallows_next_datagrams_frame() -> None:
    h = VehicleHarness()
    rng = random.Random(3)
    for i in range(2000):
        prefix = bytes([0xFD]) + bytes(rng.getrandbits(8) for _ in range(rng.randint(0, 60)))
        h.send_bytes(prefix)
        replies = h.send(mavlink.MAVLink_ping_message(i, i % 256, 0, 0))
        assert [r.time_usec for r in replies if r.get_type() == "PING"] == [i]


def wait_for(m, msg_type: str, ok, timeout_s: float = 3.0):  # type: ignore[no-untyped-def]
    deadline = time.monotonic() + timeout_s
    while time.monotonic() < deadline:
        msg = m.recv_match(type=msg_type, blocking=True, timeout=0.1)
        if msg is not None and ok(msg):
            return msg
    return None


@pytest.mark.integration
def test_udp_fuzz_then_vehicle_answers_and_telemetry_stays_with_owner(udp_ports, caplog) -> None:  # noqa: ANN001
    os.environ["MAVLINK20"] = "1"
    from pymavlink import mavutil

    mavutil.set_dialect("common")
    datagrams = malformed_datagrams(20_000, seed=2)
    base, gcs = udp_ports(1), udp_ports(1)
    caplog.set_level(logging.ERROR)
    with Fleet(1, base_port=base, gcs_port=gcs, speed=1.0) as fleet:
        owner = mavutil.mavlink_connection(f"udpin:127.0.0.1:{base}", source_system=255, source_component=190)
        assert owner.wait_heartbeat(timeout=5) is not None
        target = fleet.ports(0).onboard_local
        owner.mav.heartbeat_send(6, 8, 0, 0, 4, 3)  # every real client (MAVSDK, QGC) starts with heartbeats
        stranger = socket.socket(socket.AF_INET, socket.SOCK_DGRAM)
        stranger.bind(("127.0.0.1", 0))
        link = fleet.links[0]["onboard"]
        before = link.received_datagrams
        for i, data in enumerate(datagrams):
            (stranger if i % 2 else owner.port).sendto(data, target)
            if i % 100 == 99:  # let the fleet drain its socket: this tests parsing, not kernel buffer sizes
                seen, idle_since = -1, time.monotonic()
                while link.received_datagrams - before < i + 1 and time.monotonic() - idle_since < 0.05:
                    if link.received_datagrams != seen:
                        seen, idle_since = link.received_datagrams, time.monotonic()
                    time.sleep(0.001)
        time.sleep(0.3)
        # asyncio logs an exception raised in datagram_received and carries on: any such log is a parser crash
        crashes = [r for r in caplog.records if r.levelno >= logging.ERROR]
        assert not crashes, f"{len(crashes)} errors logged in the fleet's loop, first: {crashes[0].getMessage()}"
        assert link.received_datagrams - before >= 0.99 * len(datagrams)
        drops = fleet.drop_counters()[1]
        assert sum(drops["onboard"].values()) > 0.6 * len(datagrams)
        assert sum(drops["vehicle"].values()) > 0.05 * len(datagrams)
        truth = fleet.truth()
        assert not truth.armed[0] and truth.modes[0] == "AUTO.LOITER"
        assert fleet.vehicles[0].params["MPC_XY_VEL_MAX"] == 12.0
        assert fleet.links[0]["onboard"].peer_changes == 0
        stranger.setblocking(False)
        with pytest.raises(BlockingIOError):
            stranger.recv(4096)
        deadline = time.monotonic() + 0.5
        while time.monotonic() < deadline:
            owner.recv_match(blocking=True, timeout=0.05)  # replies to the fuzz's well-formed-but-invalid requests
        owner.mav.param_request_read_send(1, 1, b"COM_OF_LOSS_T", -1)
        value = wait_for(owner, "PARAM_VALUE", lambda v: v.param_id == "COM_OF_LOSS_T")
        assert value is not None and value.param_value == 1.0
        owner.mav.command_long_send(1, 1, 400, 0, 1, 0, 0, 0, 0, 0, 0)
        ack = wait_for(owner, "COMMAND_ACK", lambda a: a.command == 400)
        assert ack is not None and ack.result == 0
        stranger.close()
        owner.close()
