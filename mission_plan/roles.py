"""The three roles of the paper's swarm: boundary drones cage the flood, the leader and followers cover it."""

from __future__ import annotations

ROLE_BOUNDARY = "boundary"
ROLE_LEADER = "leader"
ROLE_FOLLOWER = "follower"
ROLES = (ROLE_BOUNDARY, ROLE_LEADER, ROLE_FOLLOWER)
