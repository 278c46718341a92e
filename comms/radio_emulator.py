"""The central radio emulator: forwards each agent's state only to the agents within radio range.

Why central (like MOOS-IvP's ``uFldNodeComms`` and Gazebo's RF comms plugin): range must be
decided on the simulator's TRUE positions (SPEC §4), which no agent has and none may be trusted to report; one
process that owns the truth stream and every link also gives one place for seeded loss/latency/jitter and per-link
counters, and the agents stay unchanged for a real deployment (there the emulator is simply not started and
agents subscribe to each other's public state keys, see ``comms.swarm_link``).

Data path: agent -> ``floodwatch/<m>/uav/<id>/state`` (public) -> emulator -> ``RadioModel.send_many`` (one batch per tick) on the latest
``GroundTruth`` (``floodwatch/<m>/sim/truth``) -> held in flight (latency/jitter) -> one ``RadioBundle`` per
receiver per tick on ``floodwatch/<m>/radio/<rid>/inbox``.

``RadioRelay`` is the logic without Zenoh or clocks (time is passed in); ``RadioEmulator`` is the thin shell that
runs it on a thread against a ``ZenohSession``.

With a paced simulation clock (``paced``) the relay's clock is mission time itself: a message is received at the
time of the newest truth (the tick it was sent in), delays are mission seconds, and on each new truth the emulator
first takes the messages sent in the previous tick, decides them on the positions they were sent from, delivers
everything due by the new truth's time and then acknowledges that time on ``sim/pace/radio``
(:mod:`mock_autopilot.pacing`): the neighbours' inboxes for a tick are complete before any agent computes it.
"""

from __future__ import annotations

import threading
import time
from dataclasses import dataclass

import numpy as np

from comms.byte_budget import SenderBudgets
from comms.keys import MissionKeys
from comms.messages import (
    DecodeStats,
    GroundTruth,
    NeighbourState,
    PaceAck,
    RadioBundle,
    RadioLinkStats,
    decode,
    encode,
)
from comms.radio_model import GROUND_NODE_ID, RadioModel
from comms.signing import MissionKey, Verifier, unsigned_body
from comms.swarm_link import wall_clock_us
from comms.zenoh_session import ZenohConfig, ZenohSession


TRUTH_RESTART_S = 5.0
AGENT_RESTART_S = 1.0  # a lower seq with a source time this much newer is a restarted agent, not a stale message


@dataclass
class RelayCounters:
    """Totals since start: messages in, (message, receiver) pairs delivered / lost / out of range, and drops."""

    messages_in: int = 0
    delivered: int = 0
    lost: int = 0
    out_of_range: int = 0
    rejected: int = 0  # undecodable, or sender_id differing from the key's id (spoofing)
    ignored_old: int = 0  # seq not newer than the last one forwarded for that sender (unless the agent restarted)
    no_truth: int = 0  # no truth yet, or the sender is not in the truth (unknown or dead vehicle)
    queue_overflow: int = 0
    over_budget: int = 0  # dropped at the sender's radio: over its bytes per mission second


class RadioRelay:
    """Range gate + loss + delay for a stream of agent messages, against the latest truth. No I/O, no clock.

    Messages are validated one by one (``on_state``) and then processed in batches (``flush``): one vectorised
    ``RadioModel.send_many`` for everything received in a tick, so the cost per message is a few microseconds
    even with hundreds of drones. Times (``now_s``) are the relay's own clock; delays from the model are in
    simulation seconds and are divided by ``speed`` (simulation seconds per relay second).
    """

    def __init__(self, radio: RadioModel, speed: float = 1.0, stats: DecodeStats | None = None, max_in_flight: int = 1_000_000,
                 ground_node_enu_m: tuple[float, float, float] | None = None, verifier: Verifier | None = None) -> None:
        if speed <= 0:
            raise ValueError("speed must be > 0")
        self.radio = radio
        self.speed = speed
        self.stats = DecodeStats() if stats is None else stats
        self.counters = RelayCounters()
        self.max_in_flight = max_in_flight
        self._batch: list[tuple[int, int, bytes, float, float]] = []  # (truth slot, seq, payload, rx time, source t)
        self.budgets = SenderBudgets(radio.bandwidth_bytes_per_s)
        self.ground_node_enu_m = ground_node_enu_m  # the ground station's antenna: one more receiver, id 0
        self.verifier = verifier
        self._batch_ids: list[int] = []
        self._in_flight: list[tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]] = []  # due, receiver id, sender id, payload
        self._in_flight_count = 0
        self._positions: np.ndarray | None = None
        self._alive_count = 0
        self._ids = np.zeros(0, dtype=np.int64)
        self._slot_of: dict[int, int] = {}
        self._last_seq: dict[int, tuple[int, float]] = {}  # sender -> (seq, t_s) of the last one accepted
        self.truth_t_s: float | None = None
        self._link_delivered = np.zeros((0, 0), dtype=np.int64)
        self._link_lost = np.zeros((0, 0), dtype=np.int64)
        self._link_ids: list[int] = []
        self._link_slot: dict[int, int] = {}
        self._link_slot_of_truth = np.zeros(0, dtype=np.int64)

    # ---- inputs
    def on_truth(self, truth: GroundTruth) -> None:
        """Adopt the newest truth: an older one (by ``t_s``, reordered in transit) is ignored, unless it is older by
        more than ``TRUTH_RESTART_S`` (the simulator restarted its clock). Queued messages are decided first, on
        the truth they arrived under."""
        if self.truth_t_s is not None and self.truth_t_s - TRUTH_RESTART_S <= truth.t_s < self.truth_t_s:
            return
        self.flush()
        self.truth_t_s = truth.t_s
        self._positions = truth.positions_array()
        vehicle_ids = list(truth.vehicle_ids)
        if self.ground_node_enu_m is not None:
            self._positions = np.vstack([self._positions, np.asarray(self.ground_node_enu_m, dtype=float)[None, :]])
            vehicle_ids.append(GROUND_NODE_ID)
        self._alive_count = int(np.count_nonzero(np.isfinite(self._positions).all(axis=1)))
        self._ids = np.asarray(vehicle_ids, dtype=np.int64)
        self._slot_of = {int(v): i for i, v in enumerate(truth.vehicle_ids)}
        self._link_slot_of_truth = np.array([self._link_index(int(v)) for v in vehicle_ids], dtype=np.int64)

    def on_state(self, key_vehicle_id: int | None, payload: bytes, now_s: float, now_us: int = 0) -> NeighbourState | None:
        """Validate one agent message that arrived on ``key_vehicle_id``'s state key and queue it for ``flush``.

        With a ``verifier`` a state must carry the tag of the vehicle whose key it came on, checked against the wall
        clock ``now_us`` [µs since the epoch] (a forged state with a huge ``seq`` cannot silence a genuine sender);
        the signed payload is forwarded whole, so every receiver checks it again."""
        self.counters.messages_in += 1
        if self.verifier is None:
            body = unsigned_body(payload)
        else:
            body = self.verifier.check(payload, -1 if key_vehicle_id is None else key_vehicle_id, now_us).body
            if body is None:
                self.counters.rejected += 1
                return None
        state = decode(NeighbourState, body, self.stats)
        ground_id_taken = self.ground_node_enu_m is not None and state is not None and state.sender_id == GROUND_NODE_ID
        if state is None or state.sender_id != key_vehicle_id or ground_id_taken:
            self.counters.rejected += 1
            return None
        sid = state.sender_id
        last = self._last_seq.get(sid)
        if last is not None and state.seq <= last[0] and state.t_s <= last[1] + AGENT_RESTART_S:
            self.counters.ignored_old += 1
            return None
        self._last_seq[sid] = (state.seq, state.t_s)
        slot = self._slot_of.get(sid)
        if self._positions is None or slot is None or not np.isfinite(self._positions[slot]).all():
            self.counters.no_truth += 1
            return None
        if not self.budgets.admit(sid, len(payload), state.t_s):
            self.counters.over_budget += 1
            return None
        self._batch.append((slot, state.seq, payload, now_s, state.t_s))
        return state

    def flush(self) -> None:
        """Decide the fate of every queued message at once and put the survivors in flight."""
        if not self._batch:
            return
        batch, self._batch = self._batch, []
        assert self._positions is not None
        slots = np.fromiter((b[0] for b in batch), dtype=np.int64, count=len(batch))
        seqs = np.fromiter((b[1] for b in batch), dtype=np.int64, count=len(batch))
        rx_s = np.fromiter((b[3] for b in batch), dtype=float, count=len(batch))
        source_t_s = np.fromiter((b[4] for b in batch), dtype=float, count=len(batch))
        payloads = np.empty(len(batch), dtype=object)
        payloads[:] = [b[2] for b in batch]
        tx = self.radio.send_many(slots, self._positions, 0.0, seqs, vehicle_ids=self._ids, clock_t_s=source_t_s)
        assert tx.message_index is not None
        c = self.counters
        c.out_of_range += len(batch) * (self._alive_count - 1) - tx.receiver_index.size
        link_s = self._link_slot_of_truth[tx.sender_index]
        link_r = self._link_slot_of_truth[tx.receiver_index]
        ok = tx.delivered
        np.add.at(self._link_delivered, (link_s[ok], link_r[ok]), 1)
        np.add.at(self._link_lost, (link_s[~ok], link_r[~ok]), 1)
        n_ok = int(np.count_nonzero(ok))
        c.delivered += n_ok
        c.lost += ok.size - n_ok
        if n_ok == 0:
            return
        room = self.max_in_flight - self._in_flight_count
        if n_ok > room:
            c.queue_overflow += n_ok - max(room, 0)
            keep = np.flatnonzero(ok)[: max(room, 0)]
            ok = np.zeros_like(ok)
            ok[keep] = True
            n_ok = keep.size
            if n_ok == 0:
                return
        m = tx.message_index[ok]
        due = rx_s[m] + tx.delivery_t_s[ok] / self.speed
        self._in_flight.append((due, self._ids[tx.receiver_index[ok]], self._ids[tx.sender_index[ok]], payloads[m]))
        self._in_flight_count += n_ok

    # ---- outputs
    def pop_due(self, now_s: float) -> dict[int, list[tuple[int, bytes]]]:
        """Flush, then the messages to hand over now, by receiver id: {receiver: [(sender_id, payload), ...]}
        in delivery-time order."""
        self.flush()
        if not self._in_flight:
            return {}
        parts: list[tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]] = []
        remaining = []
        for chunk in self._in_flight:
            due = chunk[0]
            ready = due <= now_s
            if ready.all():
                parts.append(chunk)
            elif ready.any():
                parts.append(tuple(a[ready] for a in chunk))  # type: ignore[arg-type]
                remaining.append(tuple(a[~ready] for a in chunk))
            else:
                remaining.append(chunk)
        self._in_flight = remaining  # type: ignore[assignment]
        if not parts:
            return {}
        due = np.concatenate([p[0] for p in parts])
        receivers = np.concatenate([p[1] for p in parts])
        senders = np.concatenate([p[2] for p in parts])
        payloads = np.concatenate([p[3] for p in parts])
        self._in_flight_count -= due.size
        order = np.lexsort((due, receivers))
        receivers, senders, payloads = receivers[order], senders[order].tolist(), payloads[order].tolist()
        bounds = np.flatnonzero(np.diff(receivers)) + 1
        starts = [0, *bounds.tolist()]
        ends = [*bounds.tolist(), receivers.size]
        return {int(receivers[a]): list(zip(senders[a:b], payloads[a:b])) for a, b in zip(starts, ends)}

    def next_due_s(self) -> float | None:
        """When the earliest message in flight is due (None when nothing is in flight or queued)."""
        if self._batch:
            return float("-inf")
        if not self._in_flight:
            return None
        return float(min(chunk[0].min() for chunk in self._in_flight))

    def link_stats(self, t_s: float) -> RadioLinkStats:
        """Counters as a message (after deciding queued messages); ``links``: every (sender, receiver) pair with traffic."""
        self.flush()
        s_idx, r_idx = np.nonzero((self._link_delivered + self._link_lost) > 0)
        ids = self._link_ids
        links = [
            (ids[s], ids[r], int(self._link_delivered[s, r]), int(self._link_lost[s, r]))
            for s, r in zip(s_idx.tolist(), r_idx.tolist())
        ]
        c = self.counters
        return RadioLinkStats(
            t_s=t_s, messages_in=c.messages_in, delivered=c.delivered, lost=c.lost,
            out_of_range=c.out_of_range, rejected=c.rejected, links=links,
        )

    def _link_index(self, vehicle_id: int) -> int:
        slot = self._link_slot.get(vehicle_id)
        if slot is None:
            slot = len(self._link_ids)
            self._link_slot[vehicle_id] = slot
            self._link_ids.append(vehicle_id)
            if slot >= self._link_delivered.shape[0]:
                size = max(16, 2 * slot)
                for name in ("_link_delivered", "_link_lost"):
                    old = getattr(self, name)
                    grown = np.zeros((size, size), dtype=np.int64)
                    grown[: old.shape[0], : old.shape[1]] = old
                    setattr(self, name, grown)
        return slot


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

    Only the emulator thread calls Zenoh (put); the Zenoh callbacks only fill the latest-value buffer.
    """

    def __init__(self, config: RadioEmulatorConfig, session: ZenohSession | None = None) -> None:
        self.config = config
        self.keys = MissionKeys(config.mission)
        self._own_session = session is None
        self.session = ZenohSession(config.zenoh) if session is None else session
        self.relay = RadioRelay(config.radio, speed=1.0 if config.paced else config.speed,
                                ground_node_enu_m=config.ground_node_enu_m,
                                verifier=None if config.key is None else Verifier(config.key))
        self.bundles_out = 0
        self._stop = threading.Event()
        self._thread: threading.Thread | None = None
        self._buffer = self.session.subscribe(self.keys.all_states)
        self.session.subscribe(self.keys.truth, self._buffer)
        self.session.declare_alive(self.keys.alive("radio"))
        self.error: BaseException | None = None

    @property
    def input_superseded(self) -> int:
        """Agent messages overwritten by a newer one from the same sender before the emulator got to them
        (newest wins: non-zero only when the emulator falls behind)."""
        return self._buffer.superseded

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
        self._buffer.wake()
        if self._thread is not None:
            self._thread.join(timeout=5.0)
            self._thread = None
        if self._own_session:
            self.session.close()

    def run_until(self, stop: threading.Event) -> None:
        """Run on the calling thread until ``stop`` is set (the CLI's main loop)."""
        self._stop = stop
        self._run()

    def _run(self) -> None:
        if self.config.paced:
            self._run_paced()
            return
        relay, keys, session, cfg = self.relay, self.keys, self.session, self.config
        next_stats = time.monotonic() + cfg.stats_period_s
        last_cycle = 0.0
        try:
            while not self._stop.is_set():
                now = time.monotonic()
                if now - last_cycle < cfg.tick_s:
                    time.sleep(cfg.tick_s - (now - last_cycle))
                    now = time.monotonic()
                due = relay.next_due_s()
                wait_s = cfg.max_wait_s if due is None else min(cfg.max_wait_s, max(0.0, due - now))
                if wait_s > 0:
                    self._buffer.wait(wait_s)
                last_cycle = time.monotonic()
                items = self._buffer.drain()
                for item in items:
                    if item.key == keys.truth:
                        truth = decode(GroundTruth, item.payload, relay.stats)
                        if truth is not None:
                            relay.on_truth(truth)
                for item in items:
                    if item.key != keys.truth and item.kind == "put":
                        relay.on_state(keys.vehicle_id_of(item.key), item.payload, item.rx_monotonic_s, wall_clock_us())
                t_s = relay.truth_t_s or 0.0
                for receiver, entries in relay.pop_due(time.monotonic()).items():
                    session.put(keys.inbox(receiver), encode(RadioBundle(t_s=t_s, entries=entries)))
                    self.bundles_out += 1
                if last_cycle >= next_stats:
                    session.put(keys.radio_stats, encode(relay.link_stats(t_s)))
                    next_stats = last_cycle + cfg.stats_period_s
        except BaseException as error:  # surfaced to the owner; the CLI exits non-zero
            self.error = error
            raise

    def _run_paced(self) -> None:
        """One delivery cycle per truth, on mission time: states of the last tick, then the truth, then deliveries."""
        relay, keys, session, cfg = self.relay, self.keys, self.session, self.config
        next_stats = time.monotonic() + cfg.stats_period_s
        try:
            while not self._stop.is_set():
                self._buffer.wait(cfg.max_wait_s)
                items = self._buffer.drain()
                sent_at_s = relay.truth_t_s or 0.0
                for item in items:
                    if item.key != keys.truth and item.kind == "put":
                        relay.on_state(keys.vehicle_id_of(item.key), item.payload, sent_at_s, wall_clock_us())
                truth = None
                for item in items:
                    if item.key == keys.truth:
                        truth = decode(GroundTruth, item.payload, relay.stats)
                if truth is None or (relay.truth_t_s is not None and truth.t_s <= relay.truth_t_s):
                    continue
                relay.on_truth(truth)
                for receiver, entries in relay.pop_due(truth.t_s).items():
                    session.put(keys.inbox(receiver), encode(RadioBundle(t_s=truth.t_s, entries=entries)))
                    self.bundles_out += 1
                session.put(keys.pace("radio"), encode(PaceAck(participant="radio", t_s=truth.t_s)))
                if time.monotonic() >= next_stats:
                    session.put(keys.radio_stats, encode(relay.link_stats(truth.t_s)))
                    next_stats = time.monotonic() + cfg.stats_period_s
        except BaseException as error:  # surfaced to the owner; the CLI exits non-zero
            self.error = error
            raise
