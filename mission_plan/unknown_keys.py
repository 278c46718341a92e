"""Unknown keys are errors: the one-line message that names the key and the closest known one.

A typo such as ``radio.los`` must not run silently with the default; every table of a scenario (and every plan
file) rejects keys it does not know with this message.
"""

from __future__ import annotations

import difflib
from collections.abc import Collection, Iterable


def dotted(where: str, key: str) -> str:
    """``where.key``, or just ``key`` at the top level (``where`` empty)."""
    return f"{where}.{key}" if where else key


def unknown_key_message(where: str, key: str, known: Collection[str], what: str = "unknown key") -> str:
    """``radio.los: unknown key (did you mean radio.loss?)``; without a close match, the known keys are listed."""
    names = sorted(str(k) for k in known)
    close = difflib.get_close_matches(str(key), names, n=1)
    if close:
        hint = f"did you mean {dotted(where, close[0])}?"
    else:
        hint = f"known: {', '.join(names)}" if names else "this table takes no keys"
    return f"{dotted(where, str(key))}: {what} ({hint})"


def first_unknown(keys: Iterable[str], known: Collection[str]) -> str | None:
    """The first key (in sorted order, so the message is reproducible) not in ``known``, or None."""
    unknown = sorted(str(k) for k in keys if k not in known)
    return unknown[0] if unknown else None
