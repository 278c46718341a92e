"""Counter-based random draws: the same inputs always give the same number, in any order (pure).

The radio's fates (loss, jitter, burst states) are hashes of ``(seed, sender, receiver, counter, stream)`` rather
than draws from a stateful generator, so that two engines processing different subsets of messages, in different
orders, still give the same fate to the same message, and a test can recompute any fate independently.
"""

from __future__ import annotations

import numpy as np
from numpy.typing import ArrayLike, NDArray

_GOLDEN = np.uint64(0x9E3779B97F4A7C15)
_MIX1 = np.uint64(0xBF58476D1CE4E5B9)
_MIX2 = np.uint64(0x94D049BB133111EB)
_TWO_POW_53 = float(2**53)


def _mix(x: NDArray[np.uint64]) -> NDArray[np.uint64]:
    """splitmix64 finaliser on an array (uint64 arithmetic wraps, which is what the hash wants)."""
    x = x + _GOLDEN
    x = (x ^ (x >> np.uint64(30))) * _MIX1
    x = (x ^ (x >> np.uint64(27))) * _MIX2
    return x ^ (x >> np.uint64(31))


def _as_u64(values: ArrayLike) -> NDArray[np.uint64]:
    return np.asarray(values, dtype=np.int64).astype(np.uint64)


def uniform_draw(seed: int, sender_ids: ArrayLike, receiver_ids: ArrayLike, seq: ArrayLike, stream: int) -> NDArray[np.float64]:
    """Deterministic U[0, 1) draws, one per broadcast element of the inputs (a counter-based RNG).

    The same ``(seed, sender, receiver, seq, stream)`` always gives the same number; neighbouring tuples give
    independent-looking numbers (splitmix64 chained over the fields).
    """
    s, r, q = np.broadcast_arrays(_as_u64(sender_ids), _as_u64(receiver_ids), _as_u64(seq))
    with np.errstate(over="ignore"):
        h = _mix(np.full(s.shape, np.uint64(seed & 0xFFFFFFFFFFFFFFFF), dtype=np.uint64))
        h = _mix(h ^ s)
        h = _mix(h ^ r)
        h = _mix(h ^ q)
        h = _mix(h ^ np.uint64(stream))
    return (h >> np.uint64(11)).astype(np.float64) / _TWO_POW_53
