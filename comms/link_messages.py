"""What the links themselves report over Zenoh: the radio emulator's bundles and per-link statistics, peers joining
and leaving, and the messages the ground station dropped for their authentication tag. Named in
:mod:`comms.messages` with every other schema, and encoded by its codec."""

from __future__ import annotations

from typing import Literal

import msgspec


class RadioLinkStats(msgspec.Struct, frozen=True, omit_defaults=True, tag_field="schema", tag="fw/radiostats/1"):
    """Per-link counters of the radio emulator, published periodically for the ground station and tests.

    ``links`` rows: (sender_id, receiver_id, delivered, lost). ``out_of_range`` counts (message, vehicle) pairs
    that did not hear a message only because of range; ``rejected`` counts malformed/spoofed agent messages.
    """

    t_s: float
    messages_in: int
    delivered: int
    lost: int
    out_of_range: int
    rejected: int
    links: list[tuple[int, int, int, int]] = []


class RadioBundle(msgspec.Struct, frozen=True, omit_defaults=True, tag_field="schema", tag="fw/radio/1"):
    """What the radio emulator hands one receiver in one delivery tick: (sender_id, NeighbourState payload) pairs.

    Bundling keeps the emulator at one Zenoh put per receiver per tick instead of one per (sender, receiver)
    link; the payloads are the senders' own bytes, forwarded untouched.
    """

    t_s: float
    entries: list[tuple[int, bytes]]


class RadioGroupBundle(msgspec.Struct, frozen=True, tag_field="schema", tag="fw/radiogroup/1"):
    """What the radio emulator hands a group of receivers in one delivery tick (:mod:`comms.radio_groups`).

    ``entries``: (sender_id, NeighbourState payload) pairs, each message once, the senders' own bytes. Receiver
    ``receivers[k]`` gets ``counts[k]`` of them: its run of ``indices`` (into ``entries``, in its delivery order),
    the runs one after another in the order of ``receivers``. A receiver keeps only its own run.
    """

    t_s: float
    receivers: list[int]
    counts: list[int]
    indices: list[int]
    entries: list[tuple[int, bytes]]


class PeerEvent(msgspec.Struct, frozen=True, omit_defaults=True, tag_field="schema", tag="fw/peer/1"):
    """A vehicle or agent joining or leaving, as the observer saw it (liveliness token or staleness)."""

    t_s: float
    vehicle_id: int
    event: Literal["alive", "dead", "stale", "rejoined"]
    observer: str = ""


class SecurityEvent(msgspec.Struct, frozen=True, omit_defaults=True, tag_field="schema", tag="fw/security/1"):
    """Messages the ground station dropped for their authentication tag (:mod:`comms.signing`), one per kind of
    attempt per second at most: ``reason`` (``unsigned``, ``bad_tag``, ``wrong_sender``, ``replayed``,
    ``out_of_window``), the ``key`` they came on, the sender they claimed (``unknown`` when unsigned), how many
    since the previous report (``count``) and in all (``total``), and the sender's address when Zenoh gives one."""

    t_s: float
    reason: str
    key: str
    claimed_sender: str
    count: int
    total: int
    source: str = ""
