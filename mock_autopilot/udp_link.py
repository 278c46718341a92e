"""The only module of the mock autopilot that touches sockets: one asyncio UDP endpoint per vehicle link.

A link starts by sending to its configured remote (PX4 SITL: 127.0.0.1:14540+i for the onboard/API link,
127.0.0.1:14550 for the GCS link) and afterwards replies to whatever address the peer used. Peer address rule
(stricter than PX4, which latches the source of the very first datagram, garbage included):

* only a datagram that *vouches* for its sender moves the peer (at least one frame passed every check of
  :mod:`mock_autopilot.mavlink_codec`: MAVLink 2, known id, CRC, target, signature where required); garbage, bad
  CRC, MAVLink 1, unknown ids or frames for another system never do;
* until the peer has been heard from, the first vouching datagram from any address latches it; afterwards only a
  vouching datagram that carries a HEARTBEAT moves it (a restarted MAVSDK or QGroundControl on a new port sends
  heartbeats at once; a stranger's stray commands do not steal the telemetry). A stranger who sends valid
  heartbeats can still take the link, exactly as with PX4; MAVLink 2 signing on the GCS link is the defence.

Fault injection (drop, delay) sits here because it is about the wire.

With ``skip_repeated_setpoints`` (the onboard link of a paced fleet) a datagram from the peer that only repeats the
setpoint the link handled last, at the same simulated time, is counted and not decoded
(:mod:`mock_autopilot.repeated_setpoint`): MAVSDK's 20 Hz re-sends while the clock waits for a slow agent.
"""

from __future__ import annotations

import asyncio
import logging
from collections import Counter
from typing import Callable

from mock_autopilot.clock import SimClock
from mock_autopilot.mavlink_codec import LinkCodec
from mock_autopilot.repeated_setpoint import RepeatedSetpoints, setpoint_content
from pymavlink.dialects.v20 import common as mavlink

log = logging.getLogger(__name__)

Address = tuple[str, int]
MAX_DATAGRAM_BYTES = 1400  # below the Ethernet MTU, as PX4's network buffer
MessageSink = Callable[[str, mavlink.MAVLink_message], None]


class UdpLink(asyncio.DatagramProtocol):
    """One vehicle's link: datagrams in -> codec -> ``on_message``; ``send`` -> codec -> datagrams out."""

    def __init__(self, name: str, codec: LinkCodec, remote: Address, clock: SimClock, on_message: MessageSink,
                 skip_repeated_setpoints: bool = False) -> None:
        self.name = name
        self.codec = codec
        self.peer: Address = remote
        self.peer_confirmed = False
        self.clock = clock
        self._on_message = on_message
        self._transport: asyncio.DatagramTransport | None = None
        self._loop: asyncio.AbstractEventLoop | None = None
        self.dropped_by_fault = False
        self.delay_s = 0.0
        self.fault_drops: Counter[str] = Counter()
        self.sent_datagrams = 0
        self.sent_messages = 0
        self._outbox = bytearray()
        self.received_datagrams = 0
        self.send_errors = 0
        self.peer_changes = 0
        self.repeated_setpoints = RepeatedSetpoints() if skip_repeated_setpoints else None

    @property
    def local_address(self) -> Address:
        """The (host, port) this link is bound to."""
        assert self._transport is not None
        host, port = self._transport.get_extra_info("sockname")[:2]
        return host, port

    async def open(self, local: Address) -> None:
        """Bind the socket (raises OSError when the port is taken)."""
        self._loop = asyncio.get_running_loop()
        await self._loop.create_datagram_endpoint(lambda: self, local_addr=local)

    def connection_made(self, transport: asyncio.BaseTransport) -> None:
        self._transport = transport  # type: ignore[assignment]

    def close(self) -> None:
        if self._transport is not None:
            self._transport.close()

    def error_received(self, exc: Exception) -> None:
        # ICMP port unreachable when nobody listens yet: normal for UDP telemetry, count it and carry on.
        self.send_errors += 1

    def datagram_received(self, data: bytes, addr: tuple) -> None:  # type: ignore[override]
        self.received_datagrams += 1
        if self.dropped_by_fault:
            self.fault_drops["inbound"] += 1
            return
        if self.delay_s > 0.0 and self._loop is not None:
            self._loop.call_later(self.clock.wall_delay_s(self.delay_s), self._process, data, addr)
            return
        self._process(data, addr)

    def _process(self, data: bytes, addr: tuple) -> None:
        source: Address = (addr[0], addr[1])
        repeated = self.repeated_setpoints
        if repeated is not None and self.peer_confirmed and source == self.peer:
            content, t_s = setpoint_content(data), self.clock.now_s()
            if repeated.repeats(content, t_s):
                return
            repeated.handled(content, t_s)
        parsed = self.codec.parse_datagram(data, self.clock.unix_time_s())
        if parsed.vouched:
            if source == self.peer:
                self.peer_confirmed = True
            elif not self.peer_confirmed or any(m.get_type() == "HEARTBEAT" for m in parsed.messages):
                log.info("link %s of system %d: peer %s:%d -> %s:%d", self.name, self.codec.system_id, *self.peer, *source)
                self.peer = source
                self.peer_confirmed = True
                self.peer_changes += 1
        for message in parsed.messages:
            self._on_message(self.name, message)

    def send(self, message: mavlink.MAVLink_message) -> None:
        """Encode one message into the outgoing datagram (subject to drop faults); :meth:`flush` sends it.

        Like PX4's UDP transport, the messages of one cycle share datagrams of up to ``MAX_DATAGRAM_BYTES``: a
        receiver parses them all, and the fleet saves one system call per message.
        """
        if self._transport is None or self._transport.is_closing():
            return
        if self.dropped_by_fault:
            self.fault_drops["outbound"] += 1
            return
        data = self.codec.encode(message, self.clock.unix_time_s())
        if len(self._outbox) + len(data) > MAX_DATAGRAM_BYTES:
            self.flush()
        self._outbox += data
        self.sent_messages += 1

    def flush(self) -> None:
        """Send the pending datagram to the current peer (after the link's delay fault, if any)."""
        if not self._outbox:
            return
        data, self._outbox = bytes(self._outbox), bytearray()
        if self.delay_s > 0.0 and self._loop is not None:
            self._loop.call_later(self.clock.wall_delay_s(self.delay_s), self._sendto, data, self.peer)
            return
        self._sendto(data, self.peer)

    def _sendto(self, data: bytes, peer: Address) -> None:
        if self._transport is None or self._transport.is_closing():
            return
        self._transport.sendto(data, peer)
        self.sent_datagrams += 1
