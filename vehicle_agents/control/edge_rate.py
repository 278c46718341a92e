"""The feed-forward ṗ of eq 5: a filtered finite difference of the tracked edge point p.

``p`` is measured inside the drone's own footprint, so when the drone slides along the edge p slides with it:
the tangential part of ṗ is the drone's own motion, and feeding it forward is positive feedback (the drone would
accelerate along the edge to its speed limit). Only the part along the edge normal is the flood's own motion.
SPEC §2 asks for both readings; :func:`feedforward` takes ``reading`` = "normal" (both modes' default),
"full" (eq 5 literally) or "none".
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray


@dataclass(frozen=True)
class EdgeRateState:
    """Last edge point [m; E, N] and its time [s], and the filtered rate ṗ [m/s; E, N]."""

    p_en_m: NDArray[np.float64] | None = None
    t_s: float = 0.0
    rate_en_mps: NDArray[np.float64] | None = None


def update_edge_rate(state: EdgeRateState, p_en_m: NDArray[np.float64] | None, t_s: float, filter_time_s: float) -> EdgeRateState:
    """Fold one new measurement of p in; ``None`` (no edge in view) resets the estimate."""
    if p_en_m is None:
        return EdgeRateState()
    p = np.asarray(p_en_m, dtype=float)
    if state.p_en_m is None or t_s <= state.t_s:
        return EdgeRateState(p_en_m=p, t_s=t_s, rate_en_mps=state.rate_en_mps if state.p_en_m is not None else np.zeros(2))
    dt = t_s - state.t_s
    raw = (p - state.p_en_m) / dt
    alpha = 1.0 - math.exp(-dt / filter_time_s)
    previous = state.rate_en_mps if state.rate_en_mps is not None else np.zeros(2)
    return EdgeRateState(p_en_m=p, t_s=t_s, rate_en_mps=previous + alpha * (raw - previous))


def feedforward(rate_en_mps: NDArray[np.float64] | None, normal_en: NDArray[np.float64] | None, reading: str) -> NDArray[np.float64]:
    """ṗ as fed forward in eq 5 under one reading: "full", "normal" (projection on the edge normal) or "none"."""
    if rate_en_mps is None or reading == "none":
        return np.zeros(2)
    if reading == "full":
        return np.asarray(rate_en_mps, dtype=float)
    if normal_en is None:
        return np.zeros(2)
    n = np.asarray(normal_en, dtype=float)
    return float(np.dot(rate_en_mps, n)) * n
