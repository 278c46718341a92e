"""The three roles of the paper's swarm: boundary drones cage the flood, the leader and followers cover it."""

from __future__ import annotations

import enum


class Role(enum.StrEnum):
    """A drone's role. A ``StrEnum``: it compares equal to its name on the wire ("boundary", ...), so plans and
    messages carry plain strings, and :meth:`parse` turns a string into a role or fails with the accepted ones."""

    BOUNDARY = "boundary"
    LEADER = "leader"
    FOLLOWER = "follower"

    @classmethod
    def parse(cls, text: str) -> Role:
        """The role named ``text``; ValueError naming the accepted roles otherwise."""
        try:
            return cls(text)
        except ValueError:
            raise ValueError(f"unknown role {text!r}: must be one of {', '.join(ROLES)}") from None


ROLE_BOUNDARY = Role.BOUNDARY
ROLE_LEADER = Role.LEADER
ROLE_FOLLOWER = Role.FOLLOWER
ROLES: tuple[Role, ...] = tuple(Role)
