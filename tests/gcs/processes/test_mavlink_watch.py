"""The GCS link: framing, PX4 mode names, and .tlog files that pymavlink reads back (real loopback UDP)."""

from __future__ import annotations

import asyncio
import os
import socket
from pathlib import Path

os.environ["MAVLINK20"] = "1"
from pymavlink import mavutil  # noqa: E402
from pymavlink.dialects.v20 import common as mavlink2  # noqa: E402

from comms.px4 import mode_name as px4_mode_name, split_frames  # noqa: E402
from gcs.processes.mavlink_watch import MavlinkWatcher  # noqa: E402


def _frame(system_id: int, msg: mavlink2.MAVLink_message) -> bytes:
    mav = mavlink2.MAVLink(None, srcSystem=system_id, srcComponent=1)
    return bytes(msg.pack(mav))


def _heartbeat(custom_mode: int, armed: bool) -> mavlink2.MAVLink_heartbeat_message:
    return mavlink2.MAVLink_heartbeat_message(2, 12, 1 | (128 if armed else 0), custom_mode, 4, 3)


def test_px4_mode_names() -> None:
    assert px4_mode_name(6 << 16) == "OFFBOARD"
    assert px4_mode_name((3 << 24) | (4 << 16)) == "AUTO.LOITER"
    assert px4_mode_name((2 << 24) | (4 << 16)) == "AUTO.TAKEOFF"
    assert px4_mode_name(3 << 16) == "POSCTL"


def test_split_frames_skips_garbage_and_truncation() -> None:
    a = _frame(3, _heartbeat(6 << 16, True))
    b = _frame(4, mavlink2.MAVLink_local_position_ned_message(1, 1.0, 2.0, -10.0, 0, 0, 0))
    frames, skipped = split_frames(b"\x00\x01" + a + b + a[:5])
    assert [(f.system_id, f.message_id) for f in frames] == [(3, 0), (4, 32)]
    assert frames[0].frame == a
    assert skipped == 2 + 5


def test_watcher_logs_tlogs_that_pymavlink_reads(tmp_path: Path) -> None:
    events: list[str] = []

    async def run() -> MavlinkWatcher:
        watcher = MavlinkWatcher(tmp_path, events.append)
        await watcher.open("127.0.0.1", 0)
        port = watcher._transport.get_extra_info("sockname")[1]  # type: ignore[union-attr]
        sender = socket.socket(socket.AF_INET, socket.SOCK_DGRAM)
        try:
            sender.sendto(_frame(1, _heartbeat(6 << 16, True)), ("127.0.0.1", port))
            sender.sendto(_frame(2, _heartbeat((3 << 24) | (4 << 16), False)), ("127.0.0.1", port))
            sender.sendto(b"garbage that is not mavlink", ("127.0.0.1", port))
            sender.sendto(_frame(1, mavlink2.MAVLink_local_position_ned_message(1, 1.0, 2.0, -9.5, 0, 0, 0)), ("127.0.0.1", port))
            sender.sendto(_frame(1, mavlink2.MAVLink_statustext_message(4, b"Failsafe: offboard lost")), ("127.0.0.1", port))
            for _ in range(50):
                await asyncio.sleep(0.02)
                if 1 in watcher.vehicles and watcher.vehicles[1].frames >= 3:
                    break
        finally:
            sender.close()
            watcher.close()
        return watcher

    watcher = asyncio.run(run())
    assert watcher.vehicles[1].mode == "OFFBOARD" and watcher.vehicles[1].armed
    assert watcher.vehicles[1].altitude_m == 9.5
    assert watcher.vehicles[2].mode == "AUTO.LOITER" and not watcher.vehicles[2].armed
    assert watcher.garbage_bytes > 0
    assert any("offboard lost" in e for e in events)
    log = mavutil.mavlink_connection(str(tmp_path / "vehicle_1.tlog"))
    types = []
    while (msg := log.recv_match()) is not None:
        types.append(msg.get_type())
    assert types == ["HEARTBEAT", "LOCAL_POSITION_NED", "STATUSTEXT"]
