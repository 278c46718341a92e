"""The mission key on disk: created by the ground station for each mission (mode 0600), read by every process.

The file holds the 32 key bytes as 64 hexadecimal characters and a newline, so it can be copied with the plan files
to a drone's companion computer (``scp -p``) and checked by eye. A key is the one thing in a mission not drawn from
the mission seed: a key that a seed reproduces is no secret. Reading refuses a file that others can read, as ssh
does for private keys, because anyone holding the key can command the fleet.
"""

from __future__ import annotations

import os
import stat
from pathlib import Path

from comms.signing import KEY_BYTES, MissionKey

KEY_FILE_NAME = "mission.key"
"""The key's file name in a plan folder (beside ``agent_<id>.json``)."""


class KeyFileError(ValueError):
    """A key file that is missing, unreadable, readable by others or not 64 hex digits; the message is one line."""


def create_key_file(path: Path) -> MissionKey:
    """Write a new random key to ``path`` (mode 0600); returns it."""
    key = MissionKey(os.urandom(KEY_BYTES))
    write_key_file(path, key)
    return key


def write_key_file(path: Path, key: MissionKey) -> None:
    """Write ``key`` to ``path``, created with mode 0600 (never readable by others, not even briefly)."""
    path.parent.mkdir(parents=True, exist_ok=True)
    try:
        fd = os.open(path, os.O_WRONLY | os.O_CREAT | os.O_TRUNC, 0o600)
    except OSError as exc:
        raise KeyFileError(f"key file {path}: cannot create it ({exc.strerror})") from None
    with os.fdopen(fd, "w", encoding="ascii") as f:
        os.fchmod(fd, 0o600)
        f.write(key.secret.hex() + "\n")


def read_key_file(path: Path) -> MissionKey:
    """The key in ``path``; raises :class:`KeyFileError` with the reason."""
    try:
        mode = path.stat().st_mode
        text = path.read_text(encoding="ascii").strip()
    except (OSError, UnicodeDecodeError) as exc:
        reason = exc.strerror if isinstance(exc, OSError) else "not text"
        raise KeyFileError(f"key file {path}: cannot read it ({reason})") from None
    if mode & (stat.S_IRWXG | stat.S_IRWXO):
        raise KeyFileError(f"key file {path}: readable by others (mode {stat.S_IMODE(mode):o}); chmod 600 it")
    try:
        secret = bytes.fromhex(text)
    except ValueError:
        secret = b""
    if len(secret) != KEY_BYTES:
        raise KeyFileError(f"key file {path}: expected {2 * KEY_BYTES} hexadecimal digits")
    return MissionKey(secret)
