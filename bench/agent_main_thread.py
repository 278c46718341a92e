"""An agent's main-thread work per control tick, stage by stage, without sockets: replayed from a lockstep run.

The lockstep engine flies ``circle`` (improved, seed 1) and records, for one boundary drone, what reached it each
tick: its telemetry, the neighbour states the radio delivered (as the bytes on the wire) and its camera frames. The
replay then does what the agent's loop does with them, on this thread, in the agent's own code: the radio bundle
split as on Zenoh's thread (``zenoh_rx``), command and frame read (``inputs``), perception of each new frame
(``frame``), the inbox decoded (``inbox``), the onboard core with N = 1 (``core``), the state message encoded and the
acknowledgement put (``publish``, to an in-memory stand-in). CPU time of this thread (``time.thread_time``), best of
``--repeat`` replays, so the neighbours' load inflates it less than wall time. What it leaves out: asyncio, MAVSDK,
Zenoh itself. It also prints a digest of every output (actions, setpoints, yaw, encoded state message), so two
checkouts can be shown to compute the same thing.

Usage::

    python bench/agent_main_thread.py                     # this checkout
    python bench/agent_main_thread.py --tree /tmp/before  # another checkout (e.g. ``git archive REV | tar -x``)
    python bench/agent_main_thread.py --without-relay     # the same bytes, relaying and not, alternated
    python bench/agent_main_thread.py --evict-mib 64      # every tick with cold data caches
"""

from __future__ import annotations

import argparse
import dataclasses
import hashlib
import pickle
import sys
import time
from pathlib import Path

STAGES = ("zenoh_rx", "inputs", "frame", "inbox", "core", "publish")


def capture(vehicle_id: int, duration_s: float) -> dict[str, object]:
    """Fly lockstep and keep what reached ``vehicle_id`` each tick (imports from the checkout on sys.path)."""
    import gcs.lockstep.engine as engine  # noqa: PLC0415 - after sys.path is set
    from comms.messages import encode  # noqa: PLC0415
    from gcs.scenario import load_scenario  # noqa: PLC0415
    from mock_autopilot.camera.render import render_frame  # noqa: PLC0415
    from vehicle_agents.perception.segmentation import perceive  # noqa: PLC0415

    scenario = load_scenario("circle", ())
    index = [v.vehicle_id for v in scenario.vehicles].index(vehicle_id)
    frames: dict[int, tuple[bytes, tuple[int, int], float, float, float]] = {}
    ticks: list[dict[str, object]] = []
    onboard_step, last_perception = engine.onboard_step, [None]

    def perception_for(flood, t_s, position_enu_m, camera, seed, *_pose_and_attitude):  # noqa: ANN001, ANN002, ANN202 - the engine's signature, level camera
        frame = render_frame(flood, t_s, position_enu_m, 0.0, camera, seed)
        result = perceive(frame.image_bgr, float(position_enu_m[2]), camera.fov_deg, 0.0)
        frames[id(result)] = (frame.image_bgr.tobytes(), frame.image_bgr.shape[:2], float(position_enu_m[2]),
                              camera.fov_deg, t_s)
        return result

    def step(plan, state, inputs):  # noqa: ANN001, ANN202
        perception = inputs.perception[index]
        new = perception is not None and perception is not last_perception[0]
        last_perception[0] = perception
        ticks.append({"t_s": inputs.t_s, "telemetry": inputs.telemetry.vehicle(index),
                      "frame": frames.get(id(perception)) if new else None, "order": inputs.orders[index],
                      "states": [(m.sender_id, encode(m)) for m in inputs.inbox[index].states]})
        return onboard_step(plan, state, inputs)

    engine.onboard_step, engine._perception_for = step, perception_for
    engine.run_lockstep(scenario, "improved", 1, duration_s, cameras="boundary")
    vehicle = scenario.vehicles[index]
    return {"vehicle": vehicle, "params": scenario.control_params("improved"), "altitude_m": scenario.altitude_m,
            "ticks": ticks}


def replay(recorded: dict[str, object], repeat: int, evict_mib: int = 0) -> tuple[dict[str, float], str]:
    """Best CPU time per tick of each stage [ms] over ``repeat`` replays, and a digest of the outputs.

    ``evict_mib``: before each tick (outside the timed stages) stream through that many MiB, so every tick starts
    with the data caches holding something else, as an agent's tick does after ~40 other processes ran on its core.
    """
    import numpy as np  # noqa: PLC0415

    from comms.keys import MissionKeys  # noqa: PLC0415
    from comms.messages import CameraFrame, MissionCommand, RadioBundle, encode  # noqa: PLC0415
    from comms.swarm_link import bundle_unpacker  # noqa: PLC0415
    from vehicle_agents.agent import decode_image  # noqa: PLC0415
    from vehicle_agents.core.onboard import OnboardInputs, OnboardPlan, initial_state, onboard_step  # noqa: PLC0415
    from vehicle_agents.core.telemetry import telemetry_batch  # noqa: PLC0415
    from vehicle_agents.flight_phase import Phase, PhaseLimits  # noqa: PLC0415
    from vehicle_agents.perception.segmentation import perceive  # noqa: PLC0415

    evicting = np.zeros(evict_mib * (1 << 20) // 8)
    vehicle = recorded["vehicle"]
    vid = vehicle.vehicle_id  # type: ignore[attr-defined]
    keys = MissionKeys("bench")
    key = _mission_key()
    signed_from_us = time.time_ns() // 1000
    tagger = _tagger(key)
    replay_now_us = _replay_clock(signed_from_us)
    wire: list[tuple[bytes | None, bytes | None]] = []
    for seq, tick in enumerate(recorded["ticks"]):  # type: ignore[attr-defined]
        entries = [(sender, _signed(tagger, state, sender, signed_from_us + seq)) for sender, state in tick["states"]]
        bundle = encode(RadioBundle(t_s=tick["t_s"], entries=entries)) if entries else None
        frame = None
        if tick["frame"] is not None:
            image, (height, width), altitude_m, fov_deg, t_s = tick["frame"]
            frame = encode(CameraFrame(vehicle_id=vid, seq=seq, t_s=t_s, altitude_m=altitude_m, yaw_ned_rad=0.0,
                                       fov_deg=fov_deg, width_px=width, height_px=height, encoding="raw_bgr",
                                       image=image))
        wire.append((bundle, frame))
    command = _signed(tagger, encode(MissionCommand(seq=1, t_s=0.0, command="start", flood_clock_start_t_s=0.0)), 0,
                      signed_from_us)
    best = {stage: float("inf") for stage in STAGES}
    digest = hashlib.sha256()
    for run in range(repeat):
        session = _MemorySession()
        swarm = _agent_swarm_link(session, keys.mission, vid, key, recorded["params"].relay_max_hops > 0)
        inbox_buffer = swarm.link.buffer
        unpack = bundle_unpacker(keys)
        session.feed(keys.command, command)
        plan = OnboardPlan(vehicle_ids=(vid,), roles=(vehicle.role,), pads_en_m=(tuple(vehicle.pad_enu_m[:2]),),
                           has_gps=(vehicle.has_gps,), params=recorded["params"],
                           limits=PhaseLimits(takeoff_altitude_m=recorded["altitude_m"]))
        state = initial_state(plan, Phase.MISSION)
        spent = dict.fromkeys(STAGES, 0.0)
        perception, frame_seq = None, -1
        clock = time.thread_time
        for seq, (tick, (bundle, frame)) in enumerate(zip(recorded["ticks"], wire)):  # type: ignore[arg-type]
            replay_now_us[0] = signed_from_us + seq
            if evicting.size:
                evicting += 1.0
            t0 = clock()
            if bundle is not None:
                inbox_buffer.put_many(unpack(keys.inbox(vid), bundle))
            if frame is not None:
                session.feed(keys.camera(vid), frame)
            t1 = clock()
            swarm.latest_command()
            camera_frame = swarm.latest_frame()
            t2 = clock()
            if camera_frame is not None and camera_frame.seq != frame_seq:
                frame_seq = camera_frame.seq
                perception = perceive(decode_image(camera_frame), camera_frame.altitude_m, camera_frame.fov_deg,
                                      camera_frame.yaw_ned_rad)
            t3 = clock()
            inbox = swarm.take_inbox()
            t4 = clock()
            telemetry = dataclasses.replace(tick["telemetry"], last_message_monotonic_s=1.0)
            inputs = OnboardInputs(t_s=tick["t_s"], telemetry=telemetry_batch([telemetry], 1.0),
                                   perception=(perception,), inbox=(inbox,), orders=(tick["order"],), stop=(False,))
            outputs, state = onboard_step(plan, state, inputs)
            t5 = clock()
            _publish(swarm, session, keys, vid, outputs.state_messages[0])
            t6 = clock()
            for stage, start, end in zip(STAGES, (t0, t1, t2, t3, t4, t5), (t1, t2, t3, t4, t5, t6)):
                spent[stage] += end - start
            if run == 0:
                digest.update(repr((outputs.actions, outputs.velocity_setpoint_ned_mps.tolist(),
                                    outputs.yaw_ned_rad.tolist())).encode())
                digest.update(encode(outputs.state_messages[0]))
        for stage in STAGES:
            best[stage] = min(best[stage], 1000.0 * spent[stage] / len(wire))
    return best, digest.hexdigest()[:16]


class _MemorySession:
    """The few ZenohSession calls the agent's swarm link makes, in memory: subscriptions are buffers fed by hand."""

    def __init__(self) -> None:
        from comms.latest_buffer import LatestValueBuffer  # noqa: PLC0415

        self._buffer_type = LatestValueBuffer
        self.buffers: dict[str, object] = {}
        self.sent: list[bytes] = []

    def feed(self, key: str, payload: bytes) -> None:
        self.buffers[key].put(key, payload)  # type: ignore[attr-defined]

    def subscribe(self, key: str, buffer: object = None, unpack: object = None, **_: object) -> object:
        self.buffers[key] = self._buffer_type() if buffer is None else buffer
        return self.buffers[key]

    def subscribe_alive(self, key: str, buffer: object = None, history: bool = True) -> object:
        return self.subscribe(key, buffer)

    def declare_alive(self, key: str) -> None:
        pass

    def put(self, key: str, payload: bytes) -> None:
        self.sent.append(payload)


def _mission_key() -> object | None:
    """A fixed mission key when the checkout signs its messages (None for a checkout from before signing)."""
    try:
        from comms.signing import MissionKey  # noqa: PLC0415
    except ImportError:
        return None
    return MissionKey(bytes(range(32)))


def _tagger(key: object | None) -> object | None:
    """The key's tagger, set up once (None for a checkout from before signing)."""
    if key is None:
        return None
    from comms.signing import Tagger  # noqa: PLC0415

    return Tagger(key)  # type: ignore[arg-type]


def _signed(tagger: object | None, body: bytes, sender: int, timestamp_us: int) -> bytes:
    """``body`` as the sender puts it on the wire: signed when the checkout signs."""
    if tagger is None:
        return body
    from comms.signing import sign  # noqa: PLC0415

    return sign(tagger, body, sender, timestamp_us)  # type: ignore[arg-type]


def _replay_clock(start_us: int) -> list[int]:
    """The receivers' wall clock during a replay: the signing time of the tick being replayed (set per tick in the
    returned cell), so that however slowly the host replays, the tag checks pass as they did in flight."""
    import comms.swarm_link as link_module  # noqa: PLC0415
    import vehicle_agents.swarm_link_zenoh as agent_module  # noqa: PLC0415

    now_us = [start_us]
    for module in (link_module, agent_module):
        if hasattr(module, "wall_clock_us"):
            module.wall_clock_us = lambda: now_us[0]  # type: ignore[attr-defined]
    return now_us


def _agent_swarm_link(session: _MemorySession, mission: str, vid: int, key: object | None, relays: bool) -> object:
    """The checkout's own agent swarm link (its subscriptions, its decoding, its tag checks) on the in-memory
    session."""
    import vehicle_agents.swarm_link_zenoh as module  # noqa: PLC0415

    original = module.ZenohSession
    module.ZenohSession = lambda _config: session  # type: ignore[assignment,misc]
    try:
        if key is None:
            return module.ZenohSwarmLink(vid, mission, None, via_radio=True)  # type: ignore[arg-type]
        return module.ZenohSwarmLink(vid, mission, None, via_radio=True, key=key,  # type: ignore[arg-type]
                                     relays=relays)
    finally:
        module.ZenohSession = original  # type: ignore[misc]


def _publish(swarm: object, session: _MemorySession, keys: object, vid: int, message: object) -> None:
    """What the agent sends after its step: the state message and, in a checkout whose state message does not
    carry the pace acknowledgement, a separate acknowledgement."""
    swarm.publish_state(message)  # type: ignore[attr-defined]
    if not hasattr(message, "pace_t_s"):
        session.put(keys.pace(vid), b"ack")  # type: ignore[attr-defined]


def main() -> int:
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--tree", type=Path, default=Path(__file__).resolve().parents[1], help="checkout to measure")
    p.add_argument("--vehicle", type=int, default=3, help="the boundary drone replayed")
    p.add_argument("--duration", type=float, default=40.0, help="mission seconds of the lockstep capture")
    p.add_argument("--repeat", type=int, default=3)
    p.add_argument("--capture", type=Path, default=None, help="pickle of a capture to reuse (written if missing)")
    p.add_argument("--without-relay", action="store_true",
                   help="also replay the same bytes as a drone that does not relay (relay_max_hops = 0: states "
                        "decoded for control only, no copies filed), alternating with the relaying one: the relay's "
                        "share of the main thread")
    p.add_argument("--evict-mib", type=int, default=0, metavar="MIB",
                   help="stream through MIB MiB before each tick (untimed): the replay with cold data caches")
    args = p.parse_args()
    sys.path.insert(0, str(args.tree.resolve()))
    if args.capture is not None and args.capture.exists():
        recorded = pickle.loads(args.capture.read_bytes())
    else:
        recorded = capture(args.vehicle, args.duration)
        if args.capture is not None:
            args.capture.write_bytes(pickle.dumps(recorded))
    states = sum(len(t["states"]) for t in recorded["ticks"]) / len(recorded["ticks"])  # type: ignore[attr-defined]
    cases = [("relaying", recorded)]
    if args.without_relay:
        cases.append(("not relaying", {**recorded, "params": dataclasses.replace(recorded["params"], relay_max_hops=0)}))
    for _ in range(args.repeat if args.without_relay else 1):
        for name, case in cases:
            best, digest = replay(case, 1 if args.without_relay else args.repeat, args.evict_mib)
            print(f"{args.tree}: {name}, {len(recorded['ticks'])} ticks, {states:.1f} neighbour states per tick, "  # type: ignore[arg-type]
                  f"outputs digest {digest}")
            print(" | ".join(f"{stage} {best[stage]:.3f}" for stage in STAGES)
                  + f" | main thread total {sum(best.values()):.3f} ms per tick", flush=True)
    return 0


if __name__ == "__main__":
    sys.exit(main())
