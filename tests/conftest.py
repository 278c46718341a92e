"""Fixtures every test package may use: blocks of free loopback UDP ports.

A test asks for ports here instead of writing numbers down, so two test runs (or two tests) never pick the same
port on purpose. Vehicles of a fleet use consecutive ports (PX4 SITL's 14540+i), so ports come in blocks: a
random block in 20000-32699, drawn per process, kept only if every port of it binds now (UDP and TCP: a mission's
block also holds its Zenoh hub). The range stays below Linux's ephemeral ports (32768-60999 by default), so a socket
the kernel numbers itself (a Zenoh client's connection, a MAVSDK or pymavlink socket bound to port 0) can never take a
port of a block between the check and the mission's own bind.
"""

from __future__ import annotations

import os
import random
import socket
from collections.abc import Callable

import pytest

PORT_RANGE = (20000, 32699)
_rng = random.Random(os.getpid())
_handed_out: set[int] = set()


def udp_port_is_free(port: int, host: str = "127.0.0.1") -> bool:
    """Whether a UDP socket can bind ``host:port`` right now."""
    with socket.socket(socket.AF_INET, socket.SOCK_DGRAM) as s:
        try:
            s.bind((host, port))
        except OSError:
            return False
    return True


def free_udp_block(count: int) -> int:
    """First port of ``count`` consecutive loopback UDP ports that bind now and were not handed out before."""
    low, high = PORT_RANGE
    for _ in range(500):
        first = _rng.randint(low, high - count)
        block = range(first, first + count)
        if not _handed_out.intersection(block) and all(udp_port_is_free(p) and tcp_port_is_free(p) for p in block):
            _handed_out.update(block)
            return first
    raise RuntimeError(f"no {count} consecutive free UDP ports in {low}-{high}")


@pytest.fixture
def udp_ports() -> Callable[[int], int]:
    """``udp_ports(n)`` -> the first of n consecutive free loopback UDP ports."""
    return free_udp_block


def tcp_port_is_free(port: int, host: str = "127.0.0.1") -> bool:
    """Whether a TCP socket can bind ``host:port`` right now."""
    with socket.socket(socket.AF_INET, socket.SOCK_STREAM) as s:
        s.setsockopt(socket.SOL_SOCKET, socket.SO_REUSEADDR, 1)
        try:
            s.bind((host, port))
        except OSError:
            return False
    return True


@pytest.fixture
def zenoh_endpoint() -> Callable[[], str]:
    """``zenoh_endpoint()`` -> ``tcp/127.0.0.1:<port>`` with a port free now and not handed out before."""

    def pick() -> str:
        for _ in range(500):
            port = free_udp_block(1)
            if tcp_port_is_free(port):
                return f"tcp/127.0.0.1:{port}"
        raise RuntimeError("no free TCP port")

    return pick
