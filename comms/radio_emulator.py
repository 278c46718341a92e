"""The central radio emulator: forwards each agent's state only to the agents within radio range.

Why central (like MOOS-IvP's ``uFldNodeComms`` and Gazebo's RF comms plugin): range must be
decided on the simulator's TRUE positions (SPEC §4), which no agent has and none may be trusted to report; one
process that owns the truth stream and every link also gives one place for seeded loss/latency/jitter and per-link
counters, and the agents stay unchanged for a real deployment (there the emulator is simply not started and
agents subscribe to each other's public state keys, see ``comms.swarm_link``).

Data path: agent -> ``floodwatch/<m>/uav/<id>/state`` (public) -> emulator -> ``RadioRelay.flush`` (one batch per
tick, ``RadioModel.send_many``'s gate and draws) on the latest ``GroundTruth`` (``floodwatch/<m>/sim/truth``) -> held in flight (latency/jitter) -> one
``RadioGroupBundle`` per group of receivers per tick on ``floodwatch/<m>/radio/group/<g>``, each receiver's
selection inside it (:mod:`comms.radio_groups`), framed from entries encoded once per message.

``comms.radio_relay.RadioRelay`` is the logic without Zenoh or clocks (time is passed in); ``RadioEmulator`` is the
thin shell that runs it on a thread against a ``ZenohSession``. The states wait in Zenoh's own ring
(``ZenohSession.subscribe_queue``) until the emulator's thread takes them, every one of them, once per delivery
cycle: thousands of states per second never run Python on Zenoh's threads. The truth (20 Hz) comes through a
latest-value buffer, whose arrival wakes the thread.

With a paced simulation clock (``paced``) the relay's clock is mission time itself: a message is received at the
time of the newest truth (the tick it was sent in), delays are mission seconds, and on each new truth the emulator
first takes the messages sent in the previous tick, decides them on the positions they were sent from, delivers
everything due by the new truth's time and then acknowledges that time on ``sim/pace/radio``
(:mod:`mock_autopilot.pacing`): the neighbours' inboxes for a tick are complete before any agent computes it.
"""

from __future__ import annotations

import threading
import time
from collections.abc import Callable
from dataclasses import dataclass, replace

from comms.keys import MissionKeys
from comms.messages import GroundTruth, PaceAck, decode, encode
from comms.radio_model import RadioModel
from comms.radio_relay import RadioRelay
from comms.signing import MissionKey, Verifier
from comms.swarm_link import wall_clock_us
from comms.zenoh_session import ZenohConfig, ZenohSession

MIN_POLL_S = 0.001
"""The free clock's shortest delivery cycle: states cannot wake the emulator (they wait in a ring), so it polls."""
RADIO_BATCH_BYTES = 16384
"""The emulator's Zenoh batch size (``transport/link/tx/batch_size``; each link uses the smaller of its two ends'):
its receiving thread takes a fresh zeroed buffer of a batch's size for nearly every state that arrives (the states
wait in the ring, holding their buffers), so Zenoh's 64 KiB default made ``memset`` and page faults a tenth of that
thread's work at 6000 states a second. States are 0.2–1 KiB; a larger message (the truth at 300 vehicles, a full
group bundle) is sent in fragments."""
_STOP_CHECK_S = 0.05  # the free clock's longest sleep: how soon it sees ``stop`` with a long tick
_MAX_KNOWN_KEYS = 4096  # state keys whose vehicle id is remembered (a flood of made-up keys is parsed, not stored)


@dataclass(frozen=True)
class RadioEmulatorConfig:
    """Everything ``python -m comms.radio`` sets: which mission, how to join Zenoh, and the radio parameters."""

    mission: str
    zenoh: ZenohConfig
    radio: RadioModel
    speed: float = 1.0
    stats_period_s: float = 1.0
    max_wait_s: float = 0.05
    tick_s: float = 0.005  # at most one delivery cycle per tick: batches messages, bounds puts per second
    paced: bool = False
    """Mission time from the truth stream, and each truth acknowledged (a paced simulation clock)."""
    ground_node_enu_m: tuple[float, float, float] | None = None
    """The ground station's antenna [m; mission ENU] when it is a radio node (its inbox is ``radio/0/inbox``)."""
    key: MissionKey | None = None
    """The mission key: states without a valid tag are not relayed (None: relayed unchecked)."""


class RadioEmulator:
    """Runs a ``RadioRelay`` on its own thread against Zenoh; ``start()``/``stop()`` or a ``with`` block.

    Only the emulator thread calls Zenoh (put, and taking the queued states); the truth's callback only fills the
    latest-value buffer.
    """

    def __init__(self, config: RadioEmulatorConfig, session: ZenohSession | None = None) -> None:
        self.config = config
        self.keys = MissionKeys(config.mission)
        self._own_session = session is None
        batch = (("transport/link/tx/batch_size", str(RADIO_BATCH_BYTES)),)
        own_config = replace(config.zenoh, extra_json5=config.zenoh.extra_json5 + batch)
        self.session = ZenohSession(own_config) if session is None else session
        self.relay = RadioRelay(config.radio, speed=1.0 if config.paced else config.speed,
                                ground_node_enu_m=config.ground_node_enu_m,
                                verifier=None if config.key is None else Verifier(config.key))
        self.bundles_out = 0
        self._stop = threading.Event()
        self._thread: threading.Thread | None = None
        self._states = self.session.subscribe_queue(self.keys.all_states)
        self._truth = self.session.subscribe(self.keys.truth)
        self._truth_key = self.keys.truth
        self._vehicle_of_key: dict[str, int | None] = {}
        self._inboxes: dict[int, Callable[[bytes], None]] = {}  # receiver group -> put on its key
        self.session.declare_alive(self.keys.alive("radio"))
        self.error: BaseException | None = None

    @property
    def input_gaps(self) -> int:
        """States the senders' sequence numbers say were sent but never reached the relay (lost in transport, a
        full input ring, or superseded by a newer one from the same sender within a cycle): non-zero only when
        Zenoh or the emulator falls behind."""
        return self.relay.counters.input_gaps

    def __enter__(self) -> RadioEmulator:
        self.start()
        return self

    def __exit__(self, *exc: object) -> None:
        self.stop()

    def start(self) -> None:
        self._thread = threading.Thread(target=self._run, name="radio-emulator", daemon=True)
        self._thread.start()

    def stop(self) -> None:
        """Stop the thread, then close the session if this emulator opened it."""
        self._stop.set()
        self._truth.wake()
        if self._thread is not None:
            self._thread.join(timeout=5.0)
            self._thread = None
        if self._own_session:
            self.session.close()

    def run_until(self, stop: threading.Event) -> None:
        """Run on the calling thread until ``stop`` is set (the CLI's main loop)."""
        self._stop = stop
        self._run()

    def _take_states(self, rx_s: float) -> None:
        """Hand the queued states to the relay as received at ``rx_s`` (relay clock), the newest per sender's key:
        a state superseded within one delivery cycle happens only when the emulator falls behind, and then the
        newest is what the radio should carry (the skipped ones count as ``input_gaps``)."""
        relay, known = self.relay, self._vehicle_of_key
        now_us = wall_clock_us()
        for key, payload in self._states.drain_newest().items():
            vehicle_id = known.get(key, -1)
            if vehicle_id == -1:
                vehicle_id = self.keys.vehicle_id_of(key)
                if len(known) < _MAX_KNOWN_KEYS:
                    known[key] = vehicle_id
                    if vehicle_id is not None:
                        self.session.declare_key(key)
            relay.on_state(vehicle_id, payload, rx_s, now_us)

    def _newest_truth(self) -> GroundTruth | None:
        truth = None
        for item in self._truth.drain():
            if item.key == self._truth_key:
                decoded = decode(GroundTruth, item.payload, self.relay.stats)
                if decoded is not None:
                    truth = decoded
        return truth

    def _deliver(self, now_s: float, t_s: float) -> None:
        inboxes = self._inboxes
        bundles = self.relay.pop_due_group_bundles(now_s, t_s)
        for group, bundle in bundles:
            put = inboxes.get(group)
            if put is None:
                put = inboxes[group] = self.session.publisher_of(self.keys.radio_group(group), block=True)
            put(bundle)
        self.bundles_out += len(bundles)

    def _run(self) -> None:
        if self.config.paced:
            self._run_paced()
            return
        relay, cfg = self.relay, self.config
        poll_s = max(cfg.tick_s, MIN_POLL_S)
        next_stats = time.monotonic() + cfg.stats_period_s
        last_cycle = 0.0
        try:
            while not self._stop.is_set():
                wait_s = poll_s - (time.monotonic() - last_cycle)
                if wait_s > 0.0:  # a plain sleep: an event's timed wait costs the thread about twice the CPU
                    time.sleep(min(wait_s, _STOP_CHECK_S))
                    continue
                last_cycle = time.monotonic()
                truth = self._newest_truth()
                if truth is not None:
                    relay.on_truth(truth)
                self._take_states(last_cycle)
                self._deliver(time.monotonic(), relay.truth_t_s or 0.0)
                if last_cycle >= next_stats:
                    self.session.put(self.keys.radio_stats, encode(relay.link_stats(relay.truth_t_s or 0.0)))
                    next_stats = last_cycle + cfg.stats_period_s
        except BaseException as error:  # surfaced to the owner; the CLI exits non-zero
            self.error = error
            raise

    def _run_paced(self) -> None:
        """One delivery cycle per truth, on mission time: states of the last tick, then the truth, then deliveries."""
        relay, cfg = self.relay, self.config
        next_stats = time.monotonic() + cfg.stats_period_s
        try:
            while not self._stop.is_set():
                self._truth.wait(cfg.max_wait_s)
                self._take_states(relay.truth_t_s or 0.0)
                truth = self._newest_truth()
                if truth is None or (relay.truth_t_s is not None and truth.t_s <= relay.truth_t_s):
                    continue
                relay.on_truth(truth)
                self._deliver(truth.t_s, truth.t_s)
                self.session.put(self.keys.pace("radio"), encode(PaceAck(participant="radio", t_s=truth.t_s)))
                if time.monotonic() >= next_stats:
                    self.session.put(self.keys.radio_stats, encode(relay.link_stats(truth.t_s)))
                    next_stats = time.monotonic() + cfg.stats_period_s
        except BaseException as error:  # surfaced to the owner; the CLI exits non-zero
            self.error = error
            raise
