"""When each telemetry stream of each link is due: the periods (PX4's or the reduced profile, then
SET_MESSAGE_INTERVAL) and the next due time of every stream, as PX4's mavlink loop keeps them per instance.
"""

from __future__ import annotations

import math

from mock_autopilot.px4_streams import LINKS, stream_periods_s


class StreamSchedule:
    """Periods [s] and next due times [s, simulated] of every stream on every link."""

    def __init__(self, profile: str, now_s: float) -> None:
        self.profile = profile
        self.periods: dict[str, dict[str, float]] = {link: stream_periods_s(profile, link) for link in LINKS}
        self._next_due: dict[str, dict[str, float]] = {
            link: {name: now_s for name in periods} for link, periods in self.periods.items()
        }
        self._epoch_s = now_s  # every stream is due on multiples of its period from here
        self._earliest_due: dict[str, float] = {link: now_s for link in LINKS}

    def rates_hz(self, link: str) -> dict[str, float]:
        """Message name -> rate [Hz, simulated] on ``link`` now."""
        return {name: 1.0 / period for name, period in self.periods[link].items()}

    def anything_due(self, horizon_s: float) -> bool:
        """Whether any stream of any link falls due by ``horizon_s``."""
        return any(horizon_s >= t for t in self._earliest_due.values())

    def take_due(self, now_s: float, horizon_s: float) -> list[tuple[str, str]]:
        """(link, message name) of every stream due by ``horizon_s``, in table order, and book each one's next time.

        A stream that fell behind (its next time still not after ``now_s``) restarts one period from now rather
        than bursting to catch up.
        """
        due_now: list[tuple[str, str]] = []
        for link, periods in self.periods.items():
            if horizon_s < self._earliest_due[link]:
                continue
            due = self._next_due[link]
            for name, period in periods.items():
                next_t = due.get(name, now_s)
                if horizon_s < next_t:
                    continue
                due_now.append((link, name))
                next_t += period
                if next_t <= now_s:
                    next_t = now_s + period
                due[name] = next_t
            self._earliest_due[link] = min((due.get(n, now_s) for n in periods), default=math.inf)
        return due_now

    def set_interval(self, link: str, name: str, interval_us: float, now_s: float) -> bool:
        """MAV_CMD_SET_MESSAGE_INTERVAL: -1 stops the stream, 0 restores its default, > 0 sets the period [µs].
        Returns False for an interval MAVLink does not define."""
        periods = self.periods[link]
        if interval_us == -1:
            periods.pop(name, None)
        elif interval_us == 0:
            default = stream_periods_s(self.profile, link).get(name)
            if default is None:
                periods.pop(name, None)
            else:
                periods[name] = default
        elif interval_us > 0:
            periods[name] = max(interval_us * 1e-6, 0.001)
        else:
            return False
        if name in periods:
            # Keep the stream on its grid from boot rather than starting it now: streams whose rates divide each
            # other then fall due in the same tick and leave together, as in PX4's mavlink loop, which sends what
            # is due in one pass; a stream restarted at the command's time would wake the receiver separately.
            period = periods[name]
            due_s = self._epoch_s + math.ceil((now_s - self._epoch_s) / period - 1e-9) * period
            self._next_due[link][name] = due_s
            self._earliest_due[link] = min(self._earliest_due[link], due_s)
        return True
