"""Where the dashboard listens: the port it asks for or any free one, its URL, and whether the address is local."""

from __future__ import annotations

import ipaddress
import socket

TOKEN_ENV = "FLOODWATCH_DASHBOARD_TOKEN"
"""The operator token reaches a dashboard process through the environment (a command line is visible to every user
of the machine in ``ps``)."""
DEFAULT_HOST = "127.0.0.1"
DEFAULT_PORT = 8080


def choose_port(host: str, preferred: int) -> int:
    """``preferred`` if it can be bound on ``host`` now, else a free port the kernel picks (``preferred`` 0: any)."""
    for port in (preferred, 0) if preferred else (0,):
        with socket.socket(_family(host), socket.SOCK_STREAM) as sock:
            sock.setsockopt(socket.SOL_SOCKET, socket.SO_REUSEADDR, 1)
            try:
                sock.bind((host, port))
            except OSError:
                continue
            return int(sock.getsockname()[1])
    raise OSError(f"no free TCP port on {host}")


def _family(host: str) -> socket.AddressFamily:
    try:
        return socket.AF_INET6 if ipaddress.ip_address(host).version == 6 else socket.AF_INET
    except ValueError:
        return socket.AF_INET


def is_loopback(host: str) -> bool:
    """True for 127.0.0.0/8, ::1 and ``localhost``; every other address is reachable from other machines."""
    if host == "localhost":
        return True
    try:
        return ipaddress.ip_address(host).is_loopback
    except ValueError:
        return False


def dashboard_url(host: str, port: int) -> str:
    """The URL to open; an unspecified bind address (0.0.0.0, ::) is shown as this machine's loopback."""
    shown = {"0.0.0.0": "127.0.0.1", "::": "[::1]"}.get(host, f"[{host}]" if ":" in host else host)
    return f"http://{shown}:{port}/"
