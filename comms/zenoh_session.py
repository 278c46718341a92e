"""The one module that imports zenoh: open a session, publish, subscribe into latest-value buffers, liveliness.

Topologies (``ZenohConfig``):

* single machine, the default: every process is a Zenoh **peer** on loopback with explicit endpoints and multicast
  scouting off. The mission's hub peer listens on ``tcp/127.0.0.1:7447`` (Zenoh's conventional port) so any outside
  Zenoh client can join; member peers connect to it and listen on an ephemeral loopback port, and gossip lets them
  connect to each other directly (a full mesh: lowest latency, no single relay). Tests use their own ports.
* several machines: one Zenoh **router** per host (``python -m comms.router``, which is ``zenoh.open`` in router
  mode, not a home-made broker), routers connected to each other, and every process a **client** of its host's
  router. The same mode suits hundreds of processes on one host (a star instead of an N² mesh).

Callback discipline: our callbacks run directly on Zenoh's threads (no extra Python thread per subscriber). They
copy the payload into a ``LatestValueBuffer`` and return; they never block, never call Zenoh, and never raise
(errors are counted in ``callback_errors``). A consumer of thousands of samples a second that wants every one
(the radio emulator) subscribes with ``subscribe_queue`` instead: Zenoh keeps the samples in its own bounded ring
and the consumer's thread takes them, so no Python runs on Zenoh's threads at all.
Open sessions only after any ``fork``. ``close`` undeclares everything and closes the session; an ``atexit`` hook
closes sessions a caller forgot, so the interpreter never hangs at exit.

Threads and per-process cost: every mission process holds one session, and a host runs one agent process per drone,
so Zenoh's fixed cost per process is multiplied by the fleet. By default Zenoh 1.x starts five tokio runtimes (``rx``
with two workers, ``tx``, ``net``, ``acc``, ``app``) plus a shared-memory watchdog. Our processes each move a few
hundred small messages per second, which one worker carries easily, while every extra worker adds wake-ups and
cross-thread hand-offs (tokio wakes an idle worker to steal each newly ready task). Unless the environment already
sets it, ``ZENOH_RUNTIME`` (read by Zenoh once, when its first runtime starts) therefore hands the ``rx``, ``net``
and ``acc`` runtimes over to ``app``; shared memory is off by default (``ZenohConfig.shared_memory``) because we
publish plain bytes, never SHM buffers, so it only cost a watchdog thread and its negotiation on every link. Set
``ZENOH_RUNTIME='()'`` to get Zenoh's own defaults back. Numbers: docs/BENCHMARKS.md, "Agent cost per tick".
"""

from __future__ import annotations

import atexit
import json
import os
import re
import threading
import time
import weakref
from collections.abc import Callable, Iterable, Iterator
from dataclasses import dataclass, field
from typing import Any, Literal

LEAN_RUNTIME = "(rx: (handover: app), net: (handover: app), acc: (handover: app))"
"""The ``ZENOH_RUNTIME`` default: one tokio worker (``app``) for receiving, link management and accepting; ``tx``
keeps its own worker so sending never waits behind a slow receive callback."""
os.environ.setdefault("ZENOH_RUNTIME", LEAN_RUNTIME)

import zenoh  # noqa: E402 - after ZENOH_RUNTIME, which Zenoh reads once when its first runtime starts

from comms.latest_buffer import LatestValueBuffer

DEFAULT_ENDPOINT = "tcp/127.0.0.1:7447"
MAX_SAMPLE_BYTES = 32 * 1024 * 1024  # above every message kind's own limit; bounds what a buffer can hold
_ENDPOINT_RE = re.compile(r"^(tcp|udp|quic|tls|ws|unixsock-stream)/\S+$")

Unpack = Callable[[str, bytes], Iterable[tuple[str, bytes]]]


class ZenohOpenError(RuntimeError):
    """The session could not be opened (bad endpoint, port in use, no router reachable in client mode)."""


@dataclass(frozen=True)
class ZenohConfig:
    """How a process joins Zenoh. Endpoints are Zenoh locators such as ``tcp/127.0.0.1:7447``."""

    mode: Literal["peer", "client", "router"] = "peer"
    listen: tuple[str, ...] = ()
    connect: tuple[str, ...] = ()
    multicast_scouting: bool = False
    gossip_scouting: bool = True
    shared_memory: bool = False
    """Zenoh's shared-memory transport; our payloads are plain bytes, so it would only add a watchdog thread."""
    extra_json5: tuple[tuple[str, str], ...] = field(default=())

    def __post_init__(self) -> None:
        if self.mode not in ("peer", "client", "router"):
            raise ValueError(f"zenoh mode {self.mode!r}: use peer, client or router")
        for endpoint in (*self.listen, *self.connect):
            if not _ENDPOINT_RE.match(endpoint):
                raise ValueError(f"zenoh endpoint {endpoint!r}: expected e.g. tcp/127.0.0.1:7447")
        if self.mode == "client" and not self.connect:
            raise ValueError("zenoh client mode needs at least one --connect router endpoint")

    @staticmethod
    def hub(endpoint: str = DEFAULT_ENDPOINT) -> ZenohConfig:
        """The mission's own peer, listening where outside clients and member peers connect."""
        return ZenohConfig(mode="peer", listen=(endpoint,))

    @staticmethod
    def member(hub: str = DEFAULT_ENDPOINT, listen: str = "tcp/127.0.0.1:0") -> ZenohConfig:
        """A process of a running mission on this machine (agent, radio, simulator bridge): peer joining the hub."""
        return ZenohConfig(mode="peer", listen=(listen,), connect=(hub,))

    @staticmethod
    def client(*routers: str) -> ZenohConfig:
        """A process in a multi-machine deployment: client of its host's router(s)."""
        return ZenohConfig(mode="client", connect=tuple(routers) or (DEFAULT_ENDPOINT,))

    @staticmethod
    def router(listen: Iterable[str] = ("tcp/0.0.0.0:7447",), connect: Iterable[str] = ()) -> ZenohConfig:
        """A Zenoh router (one per host), optionally connected to the other hosts' routers."""
        return ZenohConfig(mode="router", listen=tuple(listen), connect=tuple(connect))

    def to_json5_items(self) -> list[tuple[str, str]]:
        """The (key, JSON5 value) pairs given to ``zenoh.Config.insert_json5``."""
        items = [
            ("mode", json.dumps(self.mode)),
            ("scouting/multicast/enabled", json.dumps(self.multicast_scouting)),
            ("connect/endpoints", json.dumps(list(self.connect))),
            ("transport/shared_memory/enabled", json.dumps(self.shared_memory)),
        ]
        if self.mode != "client":
            items.append(("listen/endpoints", json.dumps(list(self.listen))))
            items.append(("scouting/gossip/enabled", json.dumps(self.gossip_scouting)))
        items.extend(self.extra_json5)
        return items


def _direct(callback: Callable[[zenoh.Sample], None]) -> Any:
    """Run our (tiny, non-blocking) callback on Zenoh's own thread.

    zenoh-python's default wraps a Python callable in a dedicated non-daemon Python thread per subscriber; such a
    thread keeps the interpreter from exiting while the subscriber is declared (a process that forgets ``close``
    hangs at exit) and adds a thread hop of latency. Our callbacks only fill a buffer, so direct is safe.
    """
    return zenoh.handlers.Callback(callback, indirect=False)


def _source_zid(sample: zenoh.Sample) -> str:
    """The publishing session's Zenoh id if the sample carries its source, else ""."""
    info = sample.source_info
    return "" if info is None else str(info.source_id.zid)


_open_sessions: "weakref.WeakSet[ZenohSession]" = weakref.WeakSet()


@atexit.register
def _close_forgotten_sessions() -> None:
    for session in list(_open_sessions):
        session.close()


class ZenohSession:
    """An open Zenoh session with our conventions; use as a context manager (``with ZenohSession(cfg) as z:``)."""

    def __init__(self, config: ZenohConfig = ZenohConfig()) -> None:
        self.config = config
        zconf = zenoh.Config()
        try:
            for key, value in config.to_json5_items():
                zconf.insert_json5(key, value)
            self._session = zenoh.open(zconf)
        except Exception as error:  # zenoh.ZError and friends: one clear line for the CLI
            raise ZenohOpenError(f"cannot open zenoh {config.mode} session ({', '.join(config.listen + config.connect) or 'no endpoints'}): {error}") from error
        self._lock = threading.Lock()
        self._entities: list[Any] = []
        self._publishers: dict[str, Any] = {}
        self._key_exprs: list[Any] = []
        self._closed = False
        self.callback_errors = 0
        self.oversized_samples = 0
        self.dropped_after_close = 0
        _open_sessions.add(self)

    def __enter__(self) -> ZenohSession:
        return self

    def __exit__(self, *exc: object) -> None:
        self.close()

    @property
    def closed(self) -> bool:
        return self._closed

    @property
    def zid(self) -> str:
        return str(self._session.zid())

    # ---- publishing (call from our own threads, never from a Zenoh callback)
    def put(self, key: str, payload: bytes) -> None:
        """Publish one payload on a key, through a publisher declared on first use (cheaper on hot keys).

        After ``close`` (e.g. a worker thread still finishing during shutdown) the payload is dropped and counted
        in ``dropped_after_close`` instead of raising.
        """
        if self._closed:
            self.dropped_after_close += 1
            return
        publisher = self._publishers.get(key)
        if publisher is None:
            with self._lock:
                publisher = self._publishers.get(key)
                if publisher is None:
                    publisher = self._session.declare_publisher(key)
                    self._publishers[key] = publisher
        publisher.put(payload)

    def publisher_of(self, key: str, block: bool = False) -> Callable[[bytes], None]:
        """``put`` on a hot key without ``put``'s lookups; dropped and counted after ``close``. ``block`` (the key's
        first call sets it): a full link makes the put wait, where by default Zenoh drops it unseen after 1 ms."""
        with self._lock:
            if self._closed:
                raise RuntimeError("zenoh session is closed")
            if key not in self._publishers:
                congestion = zenoh.CongestionControl.BLOCK if block else zenoh.CongestionControl.DROP
                self._publishers[key] = self._session.declare_publisher(key, congestion_control=congestion)
            publisher = self._publishers[key]
        put = publisher.put

        def put_unless_closed(payload: bytes) -> None:
            if self._closed:
                self.dropped_after_close += 1
                return
            put(payload)

        return put_unless_closed

    def declare_key(self, key: str) -> None:
        """Declare a key this session receives thousands of samples a second on (the radio emulator's state keys):
        Zenoh then keeps its route, where an undeclared key's subscriber matches are searched again for every
        sample (``Resource::get_matches``: ~10 % of the receiving thread's CPU at 6000 states a second)."""
        with self._lock:
            if not self._closed:
                self._key_exprs.append(self._session.declare_keyexpr(key))

    def put_once(self, key: str, payload: bytes) -> None:
        """Publish on a key without keeping a publisher (rare messages on many keys); dropped after ``close``."""
        if self._closed:
            self.dropped_after_close += 1
            return
        self._session.put(key, payload)

    # ---- subscribing
    def subscribe(
        self,
        key_expr: str,
        buffer: LatestValueBuffer | None = None,
        unpack: Unpack | None = None,
        max_payload_bytes: int = MAX_SAMPLE_BYTES,
        with_source: bool = False,
    ) -> LatestValueBuffer:
        """One (wildcard) subscriber whose samples land in ``buffer`` (newest per key); returns the buffer.

        ``unpack(key, payload) -> [(subkey, payload), ...]`` splits a bundle into several entries inside the
        callback (it must be cheap and pure); if it raises, the sample is dropped and counted. Samples above
        ``max_payload_bytes`` are dropped before being copied (counted in ``oversized_samples``). ``with_source``
        keeps the publishing session's Zenoh id in ``Received.source`` when the sample carries one (a publisher
        that sets ``source_info``; a plain ``put`` carries none).
        """
        buf = LatestValueBuffer() if buffer is None else buffer

        def on_sample(sample: zenoh.Sample) -> None:
            try:
                if len(sample.payload) > max_payload_bytes:
                    self.oversized_samples += 1
                    return
                key = str(sample.key_expr)
                payload = sample.payload.to_bytes()
                kind = "delete" if sample.kind == zenoh.SampleKind.DELETE else "put"
                source = _source_zid(sample) if with_source else ""
                if unpack is None:
                    buf.put(key, payload, kind, source=source)
                else:
                    buf.put_many(unpack(key, payload), kind, source=source)
            except Exception:
                self.callback_errors += 1

        self._declare(lambda: self._session.declare_subscriber(key_expr, _direct(on_sample)))
        return buf

    def address_of(self, zid: str) -> str:
        """The remote address of this session's link to the session ``zid`` ("" when not directly linked); a Zenoh
        call: never from a callback."""
        try:
            for link in self._session.info.links():
                if str(link.zid) == zid:
                    return str(link.dst)
        except Exception:
            return ""
        return ""

    # ---- liveliness
    def declare_alive(self, key: str) -> None:
        """Hold a liveliness token on ``key`` until this session closes (or the process dies)."""
        self._declare(lambda: self._session.liveliness().declare_token(key))

    def subscribe_queue(self, key_expr: str, capacity: int = 65536) -> SampleQueue:
        """A (wildcard) subscriber whose samples wait in Zenoh's own bounded ring, drained by the consumer's thread.

        For a consumer that takes thousands of samples per second and wants every one of them (the radio
        emulator): no Python runs on Zenoh's threads, so there is no interpreter-lock hand-over per sample, only a
        ``try_recv`` per sample in the consumer's loop (about a fifth of the callback path's CPU, see
        docs/BENCHMARKS.md). When the ring is full the oldest sample is dropped; the consumer polls."""
        return SampleQueue(self._declare(
            lambda: self._session.declare_subscriber(key_expr, zenoh.handlers.RingChannel(capacity))))

    def subscribe_alive(self, key_expr: str, buffer: LatestValueBuffer | None = None, history: bool = True) -> LatestValueBuffer:
        """Liveliness changes under ``key_expr`` into ``buffer``: kind "put" = token appeared, "delete" = gone.

        With ``history`` the tokens alive at declaration time are reported too.
        """
        buf = LatestValueBuffer() if buffer is None else buffer

        def on_change(sample: zenoh.Sample) -> None:
            try:
                kind = "delete" if sample.kind == zenoh.SampleKind.DELETE else "put"
                buf.put(str(sample.key_expr), b"", kind)
            except Exception:
                self.callback_errors += 1

        self._declare(lambda: self._session.liveliness().declare_subscriber(key_expr, _direct(on_change), history=history))
        return buf

    def alive_now(self, key_expr: str, timeout_s: float = 1.0) -> list[str]:
        """The keys of the liveliness tokens currently alive under ``key_expr`` (a blocking query: not in callbacks)."""
        keys: list[str] = []
        for reply in self._session.liveliness().get(key_expr, timeout=timeout_s):
            try:
                keys.append(str(reply.ok.key_expr))
            except Exception:
                continue
        return sorted(keys)

    # ---- lifecycle
    def _declare(self, make: Callable[[], Any]) -> Any:
        with self._lock:
            if self._closed:
                raise RuntimeError("zenoh session is closed")
            entity = make()
            self._entities.append(entity)
            return entity

    def close(self) -> None:
        """Undeclare tokens, subscribers and publishers, then close the session; idempotent, never raises."""
        with self._lock:
            if self._closed:
                return
            self._closed = True
            entities, self._entities = self._entities, []
            publishers, self._publishers = list(self._publishers.values()), {}
        for entity in reversed(entities + publishers):
            try:
                entity.undeclare()
            except Exception:
                pass
        try:
            self._session.close()
        except Exception:
            pass
        _open_sessions.discard(self)


class SampleQueue:
    """The consumer's side of :meth:`ZenohSession.subscribe_queue` (undeclared with the session)."""

    def __init__(self, subscriber: Any) -> None:
        self.subscriber = subscriber
        self.received = 0

    def drain(self, max_samples: int = 1 << 20) -> list[tuple[str, bytes]]:
        """Everything waiting (at most ``max_samples``), oldest first, as (key, payload) of the PUT samples."""
        out = list(self._puts(max_samples))
        self.received += len(out)
        return out

    def drain_newest(self, max_samples: int = 1 << 20) -> dict[str, bytes]:
        """Like ``drain``, but only the newest payload per key (keys in the order first seen)."""
        out: dict[str, bytes] = {}
        taken = 0
        for key, payload in self._puts(max_samples):
            out[key] = payload
            taken += 1
        self.received += taken
        return out

    def _puts(self, max_samples: int) -> Iterator[tuple[str, bytes]]:
        try_recv, put = self.subscriber.try_recv, zenoh.SampleKind.PUT
        for _ in range(max_samples):
            try:
                sample = try_recv()
            except Exception:  # the subscriber was undeclared (session closing)
                return
            if sample is None:
                return
            if sample.kind == put:
                yield str(sample.key_expr), sample.payload.to_bytes()


def wait_for_peers(session: ZenohSession, key_expr: str, count: int, timeout_s: float = 10.0) -> bool:
    """Block until at least ``count`` liveliness tokens are visible under ``key_expr`` (start-up barrier)."""
    deadline = time.monotonic() + timeout_s
    while time.monotonic() < deadline:
        if len(session.alive_now(key_expr, timeout_s=0.5)) >= count:
            return True
        time.sleep(0.05)
    return False
