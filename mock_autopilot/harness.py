"""Drive one vehicle bytes-in/bytes-out without sockets or wall time (httpx's MockTransport idea).

A client-side pymavlink encoder builds frames, the vehicle's own :class:`LinkCodec` parses them exactly as the
UDP link would, the vehicle answers, and the answers are encoded and decoded again; simulated time advances only
when :meth:`VehicleHarness.run` says so. Tests of the protocol and the PX4 logic use this; benchmarks too.
"""

from __future__ import annotations

from collections import Counter

from pymavlink.dialects.v20 import common as mavlink

from mock_autopilot.mavlink_codec import LinkCodec, SigningState
from mock_autopilot.px4_streams import GCS, LINKS, ONBOARD
from mock_autopilot.vehicle import Outgoing, Vehicle, VehicleConfig

UNIX_TIME_S = 1_750_000_000.0


class VehicleHarness:
    """One vehicle, its two link codecs and a client; every message crosses the wire format both ways."""

    def __init__(
        self,
        config: VehicleConfig | None = None,
        client_system_id: int = 255,
        client_component_id: int = 190,
        gcs_signing: SigningState | None = None,
    ) -> None:
        self.vehicle = Vehicle(config or VehicleConfig(0), 0.0)
        self.now_s = 0.0
        self.codecs = {
            ONBOARD: LinkCodec(self.vehicle.system_id, 1),
            GCS: LinkCodec(self.vehicle.system_id, 1, gcs_signing),
        }
        self.client = mavlink.MAVLink(None, client_system_id, client_component_id)
        self._client_decoder = mavlink.MAVLink(None, 0, 0)
        self.received: list[tuple[float, str, mavlink.MAVLink_message]] = []
        self.vouched: list[bool] = []

    def frame(self, msg: mavlink.MAVLink_message) -> bytes:
        """The client's frame for ``msg`` (advances the client's sequence number)."""
        data = msg.pack(self.client)
        self.client.seq = (self.client.seq + 1) % 256
        return data

    def send_bytes(self, data: bytes, link: str = ONBOARD) -> list[mavlink.MAVLink_message]:
        """Deliver one datagram to the vehicle; returns the replies (also kept in :attr:`received`)."""
        parsed = self.codecs[link].parse_datagram(data, UNIX_TIME_S + self.now_s)
        self.vouched.append(parsed.vouched)
        replies: list[Outgoing] = []
        for msg in parsed.messages:
            replies.extend(self.vehicle.handle(link, msg, self.now_s))
        return self._deliver(replies)

    def send(self, msg: mavlink.MAVLink_message, link: str = ONBOARD) -> list[mavlink.MAVLink_message]:
        """Encode ``msg`` as the client and deliver it."""
        return self.send_bytes(self.frame(msg), link)

    def command(self, command: int, *params: float, link: str = ONBOARD) -> int:
        """Send COMMAND_LONG (params padded with 0) and return the COMMAND_ACK result."""
        p = list(params) + [0.0] * (7 - len(params))
        msg = mavlink.MAVLink_command_long_message(self.vehicle.system_id, 1, command, 0, *p)
        acks = [r for r in self.send(msg, link) if r.get_type() == "COMMAND_ACK" and r.command == command]
        assert len(acks) == 1, f"expected one COMMAND_ACK for {command}, got {acks}"
        return int(acks[0].result)

    def run(self, duration_s: float, step_s: float = 0.02) -> list[mavlink.MAVLink_message]:
        """Advance simulated time by ``duration_s`` in ticks of ``step_s``; returns what the vehicle sent."""
        out: list[mavlink.MAVLink_message] = []
        end = self.now_s + duration_s
        while self.now_s < end - 1e-9:
            self.now_s = min(end, self.now_s + step_s)
            out.extend(self._deliver(self.vehicle.tick(self.now_s)))
        return out

    def _deliver(self, outgoing: list[Outgoing]) -> list[mavlink.MAVLink_message]:
        result = []
        for item in outgoing:
            links = LINKS if item.link is None else (item.link,)
            for link in links:
                data = self.codecs[link].encode(item.message, UNIX_TIME_S + self.now_s)
                msg = self._client_decoder.decode(bytearray(data))
                self.received.append((self.now_s, link, msg))
                if link == (item.link or ONBOARD):
                    result.append(msg)
        return result

    def last(self, msg_type: str, link: str = ONBOARD) -> mavlink.MAVLink_message | None:
        """The newest received message of a type on a link."""
        for _, lk, msg in reversed(self.received):
            if lk == link and msg.get_type() == msg_type:
                return msg
        return None

    def texts(self) -> list[str]:
        """Every STATUSTEXT received so far (onboard link)."""
        return [m.text for _, lk, m in self.received if lk == ONBOARD and m.get_type() == "STATUSTEXT"]

    def type_counts(self, link: str = ONBOARD) -> Counter[str]:
        """How many messages of each type arrived on ``link``."""
        return Counter(m.get_type() for _, lk, m in self.received if lk == link)
