"""The agent's (and ground station's) side of the swarm radio: publish my state, hear my neighbours.

The same calls work in both worlds, so the agent code does not change between simulation and a real deployment:

* ``via_radio=True`` (simulation): the agent hears only what the radio emulator delivers to its inbox
  (``floodwatch/<m>/radio/<id>/inbox``): neighbours within range of its TRUE position, after loss and delay;
* ``via_radio=False`` (real deployment, or the ground station): it subscribes to everyone's public state keys
  ``floodwatch/<m>/uav/*/state`` directly; the real radio does the range limiting.

Either way the agent always publishes its own state on its public key, declares its liveliness token
``floodwatch/<m>/alive/<id>``, and watches everyone's tokens. ``poll()`` returns decoded states (bad payloads are
dropped and counted) and liveliness changes; feed them into a ``NeighbourTable``.

With the mission key (:mod:`comms.signing`) every state published is signed and every state heard must carry a
valid tag from the vehicle whose key it came on, newer than the last one accepted from it; anything else is dropped
and listed in ``FeedUpdate.rejected`` (counted in ``verifier.counts``). ``audit=True`` (the ground station) keeps
every sample instead of only the newest per key, so that a forged state followed at once by a genuine one is still
seen and counted.
"""

from __future__ import annotations

import itertools
import time
from collections.abc import Iterable
from dataclasses import dataclass, field
from typing import Protocol

import msgspec

from comms.keys import MissionKeys
from comms.latest_buffer import LatestValueBuffer
from comms.messages import (
    DecodeStats,
    HeardState,
    NeighbourState,
    NeighbourStateForControl,
    PeerEvent,
    RadioBundle,
    RadioGroupBundle,
    decode,
    decode_stats,
    encode,
)
from comms.neighbour_table import NeighbourEvent, NeighbourTable
from comms.radio_groups import group_inbox_key, selected_entries
from comms.signing import MissionKey, Rejection, Signer, Verifier
from comms.zenoh_session import ZenohSession

_bundle_decoder = msgspec.msgpack.Decoder(RadioBundle | RadioGroupBundle)
_PEER_EVENT = {"joined": "alive", "alive": "alive", "rejoined": "rejoined", "stale": "stale", "dead": "dead", "left": "dead"}


def bundle_unpacker(keys: MissionKeys, receiver_id: int | None = None, max_bytes: int = 16 * 1024 * 1024):
    """The inbox callback's splitter: a ``RadioBundle``, or ``receiver_id``'s selection of a ``RadioGroupBundle``
    (:mod:`comms.radio_groups`) -> [(public state key of sender, state payload), ...].

    Runs on a Zenoh thread: only msgpack framing is parsed here; the states are decoded later by the consumer.
    Raises on a bad bundle (the session counts it in ``callback_errors`` and drops it).
    """

    def unpack(_key: str, payload: bytes) -> Iterable[tuple[str, bytes]]:
        if len(payload) > max_bytes:
            raise ValueError("oversized radio bundle")
        bundle = _bundle_decoder.decode(payload)
        if isinstance(bundle, RadioGroupBundle):
            if receiver_id is None:
                raise ValueError("a radio group bundle needs the receiver's id")
            return [(keys.state(sender_id), state) for sender_id, state in selected_entries(bundle, receiver_id)]
        return [(keys.state(sender_id), state) for sender_id, state in bundle.entries]

    return unpack


AUDIT_MAX_PENDING = 65536
"""Samples an audit-mode link holds between polls: several seconds of 200 drones at 20 Hz, so a stalled consumer
loses none."""


def every_sample_unpacker():
    """A callback splitter that files each sample under its own key (``<key>#<n>``), so none is coalesced."""
    counter = itertools.count()

    def unpack(key: str, payload: bytes) -> Iterable[tuple[str, bytes]]:
        return ((f"{key}#{next(counter)}", payload),)

    return unpack


def wall_clock_us() -> int:
    """This host's wall clock in microseconds since the Unix epoch (the signature timestamps' clock)."""
    return time.time_ns() // 1000


class StateDecoder(Protocol):
    """Decodes the state payloads of one poll (e.g. sharing what several messages carry alike); ``next_poll`` is
    called before each poll's first payload."""

    def next_poll(self) -> None: ...

    def decode(self, payload: bytes | memoryview, stats: DecodeStats) -> HeardState | None: ...


@dataclass(frozen=True)
class RejectedMessage:
    """A payload dropped by the tag check: the key it came on, why, and the sender it claimed (None if unsigned)."""

    key: str
    reason: Rejection
    claimed_sender: int | None
    source: str = ""
    """The publisher's Zenoh id when the sample carried one."""


@dataclass(frozen=True)
class FeedUpdate:
    """What arrived since the last poll: decoded neighbour states (newest per sender) and liveliness changes
    (vehicle ids whose token appeared / vanished; services such as ``gcs`` are in ``services_*``)."""

    states: list[HeardState] = field(default_factory=list)
    alive: list[int] = field(default_factory=list)
    dead: list[int] = field(default_factory=list)
    services_alive: list[str] = field(default_factory=list)
    services_dead: list[str] = field(default_factory=list)
    rejected: list[RejectedMessage] = field(default_factory=list)


class SwarmLink:
    """One process's membership of the swarm over Zenoh (an agent with ``vehicle_id``, or the GCS with None)."""

    def __init__(
        self,
        session: ZenohSession,
        keys: MissionKeys,
        vehicle_id: int | None,
        *,
        via_radio: bool,
        participant: str | None = None,
        stats: DecodeStats | None = None,
        key: MissionKey | None = None,
        audit: bool = False,
        state_type: type[NeighbourState] | type[NeighbourStateForControl] = NeighbourState,
        state_decoder: StateDecoder | None = None,
    ) -> None:
        """Subscribe (inbox or public states, plus liveliness) and declare this participant's token.

        ``participant`` names the liveliness token (default: the vehicle id; e.g. ``"gcs"`` for the ground station;
        no token when both are None). ``via_radio`` needs a ``vehicle_id``. Without ``key`` states travel unsigned
        (read-only tools and tests of the transport); every mission process passes one. ``state_type``: what neighbour
        states are decoded into (an agent's control laws need only :class:`NeighbourStateForControl`).
        """
        if via_radio and vehicle_id is None:
            raise ValueError("via_radio needs the receiving vehicle's id")
        self.session = session
        self.keys = keys
        self.vehicle_id = vehicle_id
        self.via_radio = via_radio
        self.stats = decode_stats if stats is None else stats
        self.state_type = state_type
        self.state_decoder = state_decoder
        self._sender_of_key: dict[str, int | None] = {}
        self.buffer = LatestValueBuffer(max_keys=AUDIT_MAX_PENDING if audit else 4096)
        self.rejected_spoofed = 0
        self.signer = None if key is None or vehicle_id is None else Signer(key, vehicle_id)
        self.verifier = None if key is None else Verifier(key)
        if via_radio:
            assert vehicle_id is not None
            session.subscribe(group_inbox_key(keys, vehicle_id), self.buffer, unpack=bundle_unpacker(keys, vehicle_id))
        else:
            session.subscribe(keys.all_states, self.buffer, unpack=every_sample_unpacker() if audit else None,
                              with_source=audit)
        session.subscribe_alive(keys.all_alive, self.buffer, history=True)
        name = participant if participant is not None else (None if vehicle_id is None else str(vehicle_id))
        if name is not None:
            session.declare_alive(keys.alive(name))

    def publish(self, state: NeighbourState) -> None:
        """Broadcast my state on my public key (the radio emulator, neighbours and the GCS pick it up there)."""
        if self.vehicle_id is not None and state.sender_id != self.vehicle_id:
            raise ValueError(f"state.sender_id {state.sender_id} is not this link's vehicle {self.vehicle_id}")
        body = encode(state)
        self.session.put(self.keys.state(state.sender_id), body if self.signer is None else self.signer.sign(body, wall_clock_us()))

    def poll(self) -> FeedUpdate:
        """Everything pending, decoded; never blocks. States whose key id differs from sender_id are dropped."""
        update = FeedUpdate()
        alive_prefix = self.keys.prefix + "/alive/"
        verifier = self.verifier
        decoder = self.state_decoder
        if decoder is not None:
            decoder.next_poll()
        now_us = wall_clock_us()
        for item in self.buffer.drain():
            if item.key.startswith(alive_prefix):
                name = self.keys.participant_of(item.key)
                if name is None:
                    continue
                if name.isdigit():
                    (update.alive if item.kind == "put" else update.dead).append(int(name))
                else:
                    (update.services_alive if item.kind == "put" else update.services_dead).append(name)
                continue
            if item.kind != "put":
                continue
            key_id = self._sender_of(item.key.partition("#")[0])
            payload = item.payload
            if verifier is not None:
                verdict = verifier.check(payload, -1 if key_id is None else key_id, now_us)
                if verdict.body is None:
                    assert verdict.reason is not None
                    update.rejected.append(RejectedMessage(item.key.partition("#")[0], verdict.reason, verdict.sender,
                                                           item.source))
                    continue
                payload = verdict.body
            state = (decode(self.state_type, payload, self.stats) if decoder is None
                     else decoder.decode(payload, self.stats))
            if state is None:
                continue
            if key_id != state.sender_id:
                self.rejected_spoofed += 1
                continue
            if state.sender_id == self.vehicle_id:
                continue
            update.states.append(state)
        return update

    def _sender_of(self, key: str) -> int | None:
        """The vehicle id in a state key, parsed once per key (the same few keys arrive every tick)."""
        if key not in self._sender_of_key:
            if len(self._sender_of_key) >= 4096:
                self._sender_of_key.clear()
            self._sender_of_key[key] = self.keys.vehicle_id_of(key)
        return self._sender_of_key[key]

    def wait(self, timeout_s: float | None = None) -> bool:
        """Block (a non-Zenoh thread) until something arrives; True if there is something to poll."""
        return self.buffer.wait(timeout_s)

    async def wait_async(self, timeout_s: float | None = None) -> bool:
        """Await (asyncio) until something arrives; True if there is something to poll."""
        return await self.buffer.wait_async(timeout_s)

    def report_events(self, events: Iterable[NeighbourEvent], observer: str) -> int:
        """Publish table events (dead, stale, left, rejoined, ...) as ``PeerEvent`` on ``floodwatch/<m>/gcs/events``
        so the ground station's log and any outside client see who dropped out and why; returns how many."""
        n = 0
        for e in events:
            self.session.put(self.keys.events, encode(PeerEvent(t_s=e.t_s, vehicle_id=e.vehicle_id, event=_PEER_EVENT[e.event], observer=observer)))
            n += 1
        return n

    def update_table(self, table: NeighbourTable, now_s: float) -> FeedUpdate:
        """Poll and apply to ``table`` (liveliness first, then states), then expire stale entries."""
        update = self.poll()
        for vid in update.dead:
            table.liveliness(vid, False, now_s)
        for vid in update.alive:
            table.liveliness(vid, True, now_s)
        for state in update.states:
            table.heard(state, now_s)
        table.expire(now_s)
        return update
