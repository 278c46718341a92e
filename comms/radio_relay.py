"""The radio emulator's logic without Zenoh or clocks: range gate, loss and delay for a stream of agent states.

Each agent's state is validated on arrival (``on_state``), the fates of everything received in a tick are decided
at once on the simulator's TRUE positions (``flush``: ``RadioModel.send_many``'s range gate and draws), the survivors
are held in flight, and ``pop_due`` hands out what is due, grouped by receiver. Without jitter a tick's batch is due
at one time and is held as one (receiver id × message) matrix (:mod:`comms.radio_matrix`); otherwise as one row per
delivery. Both hand out the same deliveries in the same order (tested).

Cost per message is what limits a large fleet: at 300 drones × 20 Hz the emulator takes 6000 states and hands out
about 100 000 copies per second. So a state is read only as far as the radio needs it (:class:`StateHeader`: sender,
seq and time stamp; msgspec skips the rest without building it) and forwarded as the sender's own bytes; every
receiver decodes and checks the whole message again, so nothing the radio skips reaches a control law unchecked.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import msgspec
import numpy as np

from comms.bundle_wire import encode_entries
from comms.byte_budget import SenderBudgets
from comms.messages import MAX_PAYLOAD_BYTES, DecodeStats, GroundTruth, NeighbourState, RadioLinkStats
from comms.radio_groups import framed_group_bundles
from comms.link_counters import LinkCounters
from comms.radio_matrix import MAX_MATRIX_ID, MatrixBatch, framed_matrix_bundles, matrix_deliveries, padded_rows
from comms.radio_model import GROUND_NODE_ID, RadioModel, Transmission
from comms.signing import Verifier, unsigned_body

TRUTH_RESTART_S = 5.0
AGENT_RESTART_S = 1.0  # a lower seq with a source time this much newer is a restarted agent, not a stale message
_MAX_STATE_BYTES = MAX_PAYLOAD_BYTES[NeighbourState]
_STATE_KIND = NeighbourState.__name__
_DUE, _RECEIVER, _SENDER, _PAYLOAD, _ENTRY, _MESSAGE = range(6)  # the in-flight columns


class StateHeader(msgspec.Struct, frozen=True, tag_field="schema", tag="fw/state/1"):
    """The part of a ``NeighbourState`` the radio reads: who sent it, its sequence number and its source time [s]."""

    sender_id: int
    seq: int
    t_s: float


_header_decoder = msgspec.msgpack.Decoder(StateHeader)


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
    input_gaps: int = 0  # seq numbers a sender skipped: states that never reached the radio (transport or input queue)


class RadioRelay:
    """Range gate + loss + delay for a stream of agent messages, against the latest truth. No I/O, no clock.

    Times (``now_s``) are the relay's own clock; delays from the model are in simulation seconds and are divided by
    ``speed`` (simulation seconds per relay second).
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
        self._budget_limited = self.budgets.limited
        self.ground_node_enu_m = ground_node_enu_m  # the ground station's antenna: one more receiver, id 0
        self.verifier = verifier
        self._in_flight: list[tuple[np.ndarray, ...]] = []  # due, receiver id, sender id, payload, bundle entry, message
        self._matrix_flight: list[MatrixBatch] = []  # batches due at one time each, in due order (no jitter)
        self._matrix_rows = 0  # rows of a delivery matrix under the current truth (0: decide in rows)
        self._positions_by_id = np.zeros((0, 3))  # the truth's positions by vehicle id (NaN: none), for matrices
        self.links = LinkCounters()
        self._messages_decided = 0  # numbers the messages, so a group's bundle carries each one once
        self._in_flight_count = 0
        self._positions: np.ndarray | None = None
        self._alive_count = 0
        self._ids = np.zeros(0, dtype=np.int64)
        self._slot_of: dict[int, int] = {}  # vehicle id -> truth row, for vehicles alive in the newest truth
        self._last_seq: dict[int, tuple[int, float]] = {}  # sender -> (seq, t_s) of the last one accepted
        self.truth_t_s: float | None = None
        self._link_slot_of_truth = np.zeros(0, dtype=np.int64)
        self._truth_layout: tuple[tuple[int, ...], bytes] | None = None  # vehicle ids and alive flags of the truth

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
        alive = np.isfinite(self._positions).all(axis=1)
        layout = (tuple(vehicle_ids), alive.tobytes())
        if layout != self._truth_layout:  # other vehicles alive than in the last truth: new lookups
            self._truth_layout = layout
            self._alive_count = int(np.count_nonzero(alive))
            self._ids = np.asarray(vehicle_ids, dtype=np.int64)
            self._slot_of = {int(v): i for i, v in enumerate(truth.vehicle_ids) if alive[i]}
            self._link_slot_of_truth = self.links.slots_of(vehicle_ids)
            fits = len(set(vehicle_ids)) == len(vehicle_ids) and 0 <= min(vehicle_ids, default=-1)
            fits = fits and max(vehicle_ids) <= MAX_MATRIX_ID
            self._matrix_rows = padded_rows(max(vehicle_ids)) if fits else 0
        if self._matrix_rows:
            self._positions_by_id = np.full((self._matrix_rows, self._positions.shape[1]), np.nan)
            self._positions_by_id[self._ids] = self._positions

    def on_state(self, key_vehicle_id: int | None, payload: bytes, now_s: float, now_us: int = 0) -> StateHeader | None:
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
        header = self._read_header(body)
        ground_id_taken = self.ground_node_enu_m is not None and header is not None and header.sender_id == GROUND_NODE_ID
        if header is None or header.sender_id != key_vehicle_id or ground_id_taken:
            self.counters.rejected += 1
            return None
        sid = header.sender_id
        last = self._last_seq.get(sid)
        if last is not None:
            if header.seq <= last[0] and header.t_s <= last[1] + AGENT_RESTART_S:
                self.counters.ignored_old += 1
                return None
            if header.seq > last[0] + 1:
                self.counters.input_gaps += header.seq - last[0] - 1
        self._last_seq[sid] = (header.seq, header.t_s)
        slot = self._slot_of.get(sid)
        if slot is None:
            self.counters.no_truth += 1
            return None
        if self._budget_limited and not self.budgets.admit(sid, len(payload), header.t_s):
            self.counters.over_budget += 1
            return None
        self._batch.append((slot, header.seq, payload, now_s, header.t_s))
        return header

    def _read_header(self, body: bytes) -> StateHeader | None:
        """The header of a state message, or None (counted in ``stats``) when it is not a well-formed one."""
        if len(body) > _MAX_STATE_BYTES:
            self.stats.count_drop(_STATE_KIND, "oversized")
            return None
        try:
            header = _header_decoder.decode(body)
        except msgspec.DecodeError:
            self.stats.count_drop(_STATE_KIND, "malformed")
            return None
        if header.sender_id < 0 or header.seq < 0 or not math.isfinite(header.t_s):
            self.stats.count_drop(_STATE_KIND, "invalid")
            return None
        return header

    def flush(self) -> None:
        """Decide the fate of every queued message at once and put the survivors in flight."""
        if not self._batch:
            return
        batch, self._batch = self._batch, []
        assert self._positions is not None
        slots, seqs, payload_list, rx_list, source_list = zip(*batch)
        slots_a = np.array(slots, dtype=np.int64)
        if self._one_due_time(rx_list):
            self._flush_matrix(slots_a, seqs, payload_list, rx_list[0], source_list)
            return
        self._rows_from_matrices()
        rx_s = np.array(rx_list, dtype=float)
        payloads = np.empty(len(batch), dtype=object)
        payloads[:] = payload_list
        tx = self.radio.send_many(slots_a, self._positions, 0.0, np.array(seqs, dtype=np.int64), vehicle_ids=self._ids,
                                  clock_t_s=np.array(source_list, dtype=float))
        assert tx.message_index is not None
        c = self.counters
        c.out_of_range += len(batch) * (self._alive_count - 1) - tx.receiver_index.size
        ok = tx.delivered
        self.links.add_rows(self._link_slot_of_truth[tx.sender_index], self._link_slot_of_truth[tx.receiver_index], ok)
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
        if n_ok < ok.size:
            tx = Transmission(tx.sender_index[ok], tx.receiver_index[ok], ok[ok], tx.delivery_t_s[ok], tx.message_index[ok])
        m = tx.message_index
        due = rx_s[m] + tx.delivery_t_s / self.speed
        entries = np.empty(len(batch), dtype=object)
        entries[:] = encode_entries(self._ids[slots_a].tolist(), payload_list)
        self._in_flight.append((due, self._ids[tx.receiver_index], self._ids[tx.sender_index], payloads[m],
                                entries[m], self._messages_decided + m))
        self._messages_decided += len(batch)
        self._in_flight_count += n_ok

    def _one_due_time(self, rx_list: tuple[float, ...]) -> bool:
        """Whether a batch can be held as one ``MatrixBatch``: one delay for every link (no jitter), one arrival
        time, due no earlier than the batches before it, nothing held in rows, ids that fit a matrix."""
        if self.radio.jitter_s > 0.0 or self._matrix_rows == 0 or self._in_flight:
            return False
        rx = rx_list[0]
        if rx_list.count(rx) != len(rx_list):
            return False
        return not self._matrix_flight or rx + self.radio.latency_s / self.speed >= self._matrix_flight[-1].due_s

    def _flush_matrix(self, slots: np.ndarray, seqs: tuple[int, ...], payload_list: tuple[bytes, ...], rx_s: float,
                      source_list: tuple[float, ...]) -> None:
        """``flush`` of a batch due at one time: the same gate, draws and counters as the row form (``send_many``),
        held as a (receiver id × message) matrix (:mod:`comms.radio_matrix`)."""
        k = slots.size
        radio, positions, sender_ids = self.radio, self._positions_by_id, self._ids[slots]
        delivered = radio.heard_by(positions, sender_ids)
        in_range = int(np.count_nonzero(delivered))
        c = self.counters
        c.out_of_range += k * (self._alive_count - 1) - in_range
        n_ok = in_range
        lost_senders = lost_receivers = None
        if radio.loses_packets and in_range:
            receivers, messages = np.nonzero(delivered)
            senders = sender_ids[messages]
            ok, _ = radio.link_fate(senders, receivers, np.array(seqs, dtype=np.int64)[messages], 0.0,
                                    radio.link_distances(positions, senders, receivers),
                                    np.array(source_list, dtype=float)[messages])
            lost = ~ok
            delivered[receivers[lost], messages[lost]] = False
            lost_senders, lost_receivers = senders[lost], receivers[lost]
            n_ok = in_range - lost_senders.size
        self.links.note_matrix(sender_ids, delivered, lost_senders, lost_receivers)
        c.delivered += n_ok
        c.lost += in_range - n_ok
        room = self.max_in_flight - self._in_flight_count
        if n_ok > room:
            c.queue_overflow += n_ok - max(room, 0)
            delivered = self._first_deliveries(delivered, max(room, 0))
            n_ok = max(room, 0)
        if n_ok == 0:
            return
        payloads = np.empty(k, dtype=object)
        payloads[:] = payload_list
        entries = np.empty(k, dtype=object)
        entries[:] = encode_entries(sender_ids.tolist(), payload_list)
        self._matrix_flight.append(MatrixBatch(rx_s + radio.latency_s / self.speed, delivered, sender_ids, payloads,
                                               entries, self._messages_decided, n_ok))
        self._messages_decided += k
        self._in_flight_count += n_ok

    def _first_deliveries(self, delivered: np.ndarray, keep: int) -> np.ndarray:
        """Only the first ``keep`` deliveries in the row form's order (message, then truth row)."""
        receivers, messages = np.nonzero(delivered)
        row_of_id = np.zeros(delivered.shape[0], dtype=np.int64)
        row_of_id[self._ids] = np.arange(self._ids.size)
        order = np.lexsort((row_of_id[receivers], messages))[:keep]
        kept = np.zeros_like(delivered)
        kept[receivers[order], messages[order]] = True
        return kept

    def _rows_from_matrices(self) -> None:
        """Hand the matrix batches in flight to the row form (before a batch that must be held in rows)."""
        self._in_flight[:0] = [batch.as_rows() for batch in self._matrix_flight]
        self._matrix_flight = []

    # ---- outputs
    def pop_due(self, now_s: float) -> dict[int, list[tuple[int, bytes]]]:
        """Flush, then the messages to hand over now, by receiver id: {receiver: [(sender_id, payload), ...]}
        in delivery-time order."""
        self.flush()
        if not self._in_flight:
            batches = self._take_matrices(now_s)
            return matrix_deliveries(batches) if batches else {}
        ready = self._take_ready(now_s, (_SENDER, _PAYLOAD))
        if ready is None:
            return {}
        receivers, columns = ready
        bounds = (np.flatnonzero(np.diff(receivers)) + 1).tolist()
        starts, ends = [0, *bounds], [*bounds, receivers.size]
        senders, payloads = columns[_SENDER].tolist(), columns[_PAYLOAD].tolist()
        return {r: list(zip(senders[a:b], payloads[a:b])) for r, a, b in zip(receivers[starts].tolist(), starts, ends)}

    def pop_due_group_bundles(self, now_s: float, t_s: float) -> list[tuple[int, bytes]]:
        """What ``pop_due`` hands over, as one encoded ``RadioGroupBundle`` stamped ``t_s`` per group of receivers
        (:mod:`comms.radio_groups`): [(group, bytes), ...]. The entries were encoded once per message in ``flush``
        and are only framed here."""
        self.flush()
        if not self._in_flight:
            batches = self._take_matrices(now_s)
            return framed_matrix_bundles(t_s, batches) if batches else []
        ready = self._take_ready(now_s, (_ENTRY, _MESSAGE))
        if ready is None:
            return []
        receivers, columns = ready
        return framed_group_bundles(t_s, receivers, columns[_MESSAGE], columns[_ENTRY])

    def _take_matrices(self, now_s: float) -> list[MatrixBatch]:
        """The matrix batches due by ``now_s``, out of flight (a prefix: they are in due order)."""
        flight = self._matrix_flight
        ready = 0
        while ready < len(flight) and flight[ready].due_s <= now_s:
            ready += 1
        taken, self._matrix_flight = flight[:ready], flight[ready:]
        self._in_flight_count -= sum(batch.count for batch in taken)
        return taken

    def _take_ready(self, now_s: float, wanted: tuple[int, ...]) -> tuple[np.ndarray, dict[int, np.ndarray]] | None:
        """Flush, then take the in-flight messages due by ``now_s`` out of flight, sorted by receiver then due
        time: (the receiver id of each, the ``wanted`` in-flight columns in that order by column index)."""
        self.flush()
        if not self._in_flight:
            return None
        parts: list[tuple[np.ndarray, ...]] = []
        remaining: list[tuple[np.ndarray, ...]] = []
        for chunk in self._in_flight:
            ready = chunk[0] <= now_s
            if ready.all():
                parts.append(chunk)
            elif ready.any():
                parts.append(tuple(a[ready] for a in chunk))
                remaining.append(tuple(a[~ready] for a in chunk))
            else:
                remaining.append(chunk)
        self._in_flight = remaining
        if not parts:
            return None
        def column(i: int) -> np.ndarray:
            return parts[0][i] if len(parts) == 1 else np.concatenate([part[i] for part in parts])

        due, receivers = column(_DUE), column(_RECEIVER)
        self._in_flight_count -= due.size
        order = np.lexsort((due, receivers))
        return receivers[order], {i: column(i)[order] for i in wanted}

    def next_due_s(self) -> float | None:
        """When the earliest message in flight is due (None when nothing is in flight or queued)."""
        if self._batch:
            return float("-inf")
        if not self._in_flight:
            return self._matrix_flight[0].due_s if self._matrix_flight else None
        return float(min(chunk[0].min() for chunk in self._in_flight))

    def link_stats(self, t_s: float) -> RadioLinkStats:
        """Counters as a message (after deciding queued messages); ``links``: every (sender, receiver) pair with traffic."""
        self.flush()
        links = self.links.links()
        c = self.counters
        return RadioLinkStats(
            t_s=t_s, messages_in=c.messages_in, delivered=c.delivered, lost=c.lost,
            out_of_range=c.out_of_range, rejected=c.rejected, links=links,
        )
