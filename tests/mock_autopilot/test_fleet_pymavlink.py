"""Fleet over real loopback UDP with pymavlink as the client (ports from the ``udp_ports`` fixture)."""

import os
import socket
import time
from collections.abc import Callable

os.environ["MAVLINK20"] = "1"

import numpy as np
import pytest
from pymavlink import mavutil

mavutil.set_dialect("common")

from mock_autopilot.fleet import Fleet
from mock_autopilot.mavlink_codec import signing_timestamp
from mock_autopilot.vehicle import VehicleConfig

pytestmark = pytest.mark.integration
NAN = float("nan")
KEY = bytes(range(1, 33))


def connect(port: int, sysid: int = 255) -> mavutil.mavfile:
    m = mavutil.mavlink_connection(f"udpin:127.0.0.1:{port}", source_system=sysid, source_component=190)
    assert m.wait_heartbeat(timeout=5) is not None, f"no heartbeat on {port}"
    return m


def wait_msg(m: mavutil.mavfile, msg_type: str, cond=lambda msg: True, timeout_s: float = 5.0):  # type: ignore[no-untyped-def]
    deadline = time.monotonic() + timeout_s
    while time.monotonic() < deadline:
        msg = m.recv_match(type=msg_type, blocking=True, timeout=0.2)
        if msg is not None and cond(msg):
            return msg
    return None


def ack(m: mavutil.mavfile, command: int, *params: float, target: int = 1, timeout_s: float = 3.0):  # type: ignore[no-untyped-def]
    p = list(params) + [0.0] * (7 - len(params))
    m.mav.command_long_send(target, 1, command, 0, *p)
    return wait_msg(m, "COMMAND_ACK", lambda a: a.command == command, timeout_s)


def test_pymavlink_flight_on_onboard_and_gcs_links(udp_ports: Callable[[int], int]) -> None:
    base, gcs_port = udp_ports(1), udp_ports(1)
    with Fleet([VehicleConfig(0, pad_enu_m=(14.0, 0.0, 0.0))], base_port=base, gcs_port=gcs_port, speed=4.0) as fleet:
        onboard = connect(base)
        gcs = connect(gcs_port, sysid=254)
        assert onboard.target_system == 1 and gcs.target_system == 1
        gcs.mav.param_set_send(1, 1, b"MIS_TAKEOFF_ALT", 4.0, 9)
        value = wait_msg(gcs, "PARAM_VALUE", lambda v: v.param_id == "MIS_TAKEOFF_ALT")
        assert value is not None and value.param_value == 4.0
        assert ack(onboard, 400, 1).result == 0
        assert ack(onboard, 22, NAN, NAN, NAN, NAN, NAN, NAN, NAN).result == 0
        pos = wait_msg(onboard, "LOCAL_POSITION_NED", lambda p: p.z < -3.8, timeout_s=10)
        assert pos is not None
        truth = fleet.truth()
        assert truth.position_enu_m[0][0] == pytest.approx(14.0, abs=0.2)
        assert truth.position_enu_m[0][2] == pytest.approx(-pos.z, abs=0.5)
        # offboard east at 1 m/s for 4 simulated seconds, streamed at 20 Hz (5 Hz simulated)
        for _ in range(5):
            onboard.mav.set_position_target_local_ned_send(0, 1, 1, 1, 2503, NAN, NAN, NAN, 0, 0, 0, NAN, NAN, NAN, 0, NAN)
            time.sleep(0.02)
        assert ack(onboard, 176, 1, 6, 0).result == 0
        start = fleet.truth().position_enu_m[0].copy()
        t_end = fleet.clock.now_s() + 4.0
        while fleet.clock.now_s() < t_end:
            onboard.mav.set_position_target_local_ned_send(0, 1, 1, 1, 2503, NAN, NAN, NAN, 0, 1.0, 0, NAN, NAN, NAN, 0, NAN)
            time.sleep(0.02)
        moved = fleet.truth().position_enu_m[0] - start
        assert moved[0] == pytest.approx(4.0, abs=0.6) and abs(moved[1]) < 0.2
        assert ack(onboard, 21).result == 0
        assert wait_msg(onboard, "HEARTBEAT", lambda h: not h.base_mode & 128, timeout_s=15) is not None
        counters = fleet.drop_counters()[1]
        assert counters["onboard"] == {} and counters["gcs"] == {}
        onboard.close()
        gcs.close()


def test_several_vehicles_on_distinct_ports(udp_ports: Callable[[int], int]) -> None:
    base, gcs = udp_ports(3), udp_ports(1)
    configs = [VehicleConfig(i, pad_enu_m=(1.5 * i, 0.0, 0.0), has_gps=i != 2) for i in range(3)]
    with Fleet(configs, base_port=base, gcs_port=gcs, speed=2.0) as fleet:
        clients = [connect(base + i) for i in range(3)]
        for i, c in enumerate(clients):
            assert c.target_system == i + 1
            assert ack(c, 400, 1, target=i + 1).result == 0
        truth = fleet.truth()
        assert list(truth.system_ids) == [1, 2, 3]
        assert truth.armed.all()
        assert np.allclose(truth.position_enu_m[:, 0], [0.0, 1.5, 3.0])
        assert list(truth.has_gps) == [True, True, False]
        gpos = wait_msg(clients[2], "GLOBAL_POSITION_INT", timeout_s=1.0)
        assert gpos is None
        # a command addressed to system 2 on vehicle 1's port is ignored and counted
        clients[0].mav.command_long_send(2, 1, 400, 0, 0, 0, 0, 0, 0, 0, 0)
        time.sleep(0.3)
        assert fleet.drop_counters()[1]["onboard"].get("wrong_target_system") == 1
        for c in clients:
            c.close()


def test_garbage_from_a_stranger_does_not_redirect_telemetry(udp_ports: Callable[[int], int]) -> None:
    base, gcs = udp_ports(1), udp_ports(1)
    with Fleet(1, base_port=base, gcs_port=gcs, speed=2.0) as fleet:
        owner = connect(base)
        stranger = socket.socket(socket.AF_INET, socket.SOCK_DGRAM)
        stranger.bind(("127.0.0.1", 0))
        stranger.settimeout(0.2)
        target = fleet.ports(0).onboard_local
        frame = owner.mav.command_long_encode(1, 1, 400, 0, 1, 0, 0, 0, 0, 0, 0).pack(owner.mav)
        bad_crc = bytearray(frame)
        bad_crc[-1] ^= 0x55
        wrong_target = owner.mav.command_long_encode(9, 1, 400, 0, 1, 0, 0, 0, 0, 0, 0).pack(owner.mav)
        for payload in (b"\x00garbage", bytes(bad_crc), wrong_target, frame[:-3], b"\xfe\x09" + bytes(15)):
            stranger.sendto(payload, target)
        time.sleep(0.3)
        with pytest.raises(socket.timeout):
            stranger.recv(2048)
        assert wait_msg(owner, "HEARTBEAT", timeout_s=2.0) is not None
        assert fleet.links[0]["onboard"].peer_changes == 0
        assert not fleet.truth().armed[0]
        # once the owner has been heard, a stranger's valid non-heartbeat frames do not move the peer either
        owner.mav.heartbeat_send(6, 8, 0, 0, 4, 3)
        time.sleep(0.1)
        stranger.sendto(owner.mav.ping_encode(1, 1, 0, 0).pack(owner.mav), target)
        assert wait_msg(owner, "PING", lambda p: p.target_system == 255, timeout_s=2.0) is not None
        with pytest.raises(socket.timeout):
            stranger.recv(2048)
        assert fleet.links[0]["onboard"].peer_changes == 0
        # a valid MAVLink 2 heartbeat from a new address is a new peer (PX4 follows the sender too)
        hb = owner.mav.heartbeat_encode(6, 8, 0, 0, 4, 3).pack(owner.mav)
        stranger.sendto(hb, target)
        stranger.settimeout(2.0)
        assert stranger.recv(2048)[0] == 0xFD
        stranger.close()
        owner.close()


def test_gcs_link_requires_signing_onboard_link_does_not(udp_ports: Callable[[int], int]) -> None:
    base, gcs_port = udp_ports(1), udp_ports(1)
    with Fleet(1, base_port=base, gcs_port=gcs_port, speed=2.0, signing_key=KEY) as fleet:
        gcs = mavutil.mavlink_connection(f"udpin:127.0.0.1:{gcs_port}", source_system=254, source_component=190)
        hb = gcs.wait_heartbeat(timeout=5)
        assert hb is not None
        assert ack(gcs, 400, 1, timeout_s=1.0) is None
        assert fleet.drop_counters()[1]["gcs"].get("unsigned", 0) >= 1
        assert not fleet.truth().armed[0]
        gcs.setup_signing(bytes(32), sign_outgoing=True, initial_timestamp=signing_timestamp(time.time()))
        assert ack(gcs, 400, 1, timeout_s=1.0) is None
        assert fleet.drop_counters()[1]["gcs"].get("bad_signature", 0) >= 1
        gcs.setup_signing(KEY, sign_outgoing=True, initial_timestamp=signing_timestamp(time.time()))
        reply = ack(gcs, 400, 1)
        assert reply is not None and reply.result == 0
        onboard = connect(base)
        assert ack(onboard, 400, 0).result == 0
        gcs.close()
        onboard.close()


def test_fault_api_drop_delay_kill_gps_battery(udp_ports: Callable[[int], int]) -> None:
    base, gcs = udp_ports(2), udp_ports(1)
    with Fleet(2, base_port=base, gcs_port=gcs, speed=2.0) as fleet:
        c0 = connect(base)
        fleet.drop_links(0)
        c0.recv_match(blocking=True, timeout=0.3)
        while c0.recv_match(blocking=False) is not None:
            pass
        assert wait_msg(c0, "HEARTBEAT", timeout_s=1.5) is None
        fleet.restore_links(0)
        assert wait_msg(c0, "HEARTBEAT", timeout_s=2.0) is not None
        fleet.delay_links(0, 1.0)
        sent = time.monotonic()
        c0.mav.ping_send(int(time.time() * 1e6), 5, 0, 0)
        pong = wait_msg(c0, "PING", lambda p: p.seq == 5, timeout_s=3.0)
        assert pong is not None and time.monotonic() - sent >= 0.9  # 2 x 1 s simulated at speed 2
        fleet.restore_links(0)
        fleet.lose_gps(0)
        assert wait_msg(c0, "GPS_RAW_INT", lambda g: g.fix_type < 3, timeout_s=3.0) is not None
        fleet.drain_battery(0, 0.1)
        assert wait_msg(c0, "BATTERY_STATUS", lambda b: b.battery_remaining == 10, timeout_s=5.0) is not None
        fleet.kill(1)
        c1 = mavutil.mavlink_connection(f"udpin:127.0.0.1:{base + 1}", source_system=255)
        assert c1.wait_heartbeat(timeout=1.5) is None
        assert not fleet.truth().alive[1]
        c0.close()
        c1.close()


def test_start_failure_raises_and_leaves_nothing_running() -> None:
    fleet = Fleet(1, base_port=30000, gcs_port=30001, host="203.0.113.1")  # TEST-NET: nothing binds there at all
    with pytest.raises(OSError):
        fleet.start()
    assert fleet._thread is None
    with pytest.raises(ValueError):
        Fleet([])
    with pytest.raises(ValueError):
        Fleet([VehicleConfig(0), VehicleConfig(1, system_id=1)])
