"""Authenticated links between hosts: two ``python -m comms.router`` processes over TLS with mutual authentication
on loopback, each applying the mission's access control, and clients holding (or lacking) certificates."""

from __future__ import annotations

import time
from collections.abc import Callable
from pathlib import Path

import pytest

from comms.certificates import issue_identity
from comms.keys import MissionKeys
from comms.latest_buffer import LatestValueBuffer
from comms.link_security import AccessPolicy, TlsIdentity, parse_drone_host
from comms.zenoh_session import ZenohConfig, ZenohOpenError, ZenohSession

MISSION = "tls1"
KEYS = MissionKeys(MISSION)


def _identity(folder: Path, name: str) -> TlsIdentity:
    return TlsIdentity(folder / "ca.pem", folder / f"{name}.pem", folder / f"{name}-key.pem")


def _client(endpoint: str, identity: TlsIdentity | None = None, extra: tuple[tuple[str, str], ...] = ()) -> ZenohSession:
    items = extra if identity is None else identity.json5_items()
    return ZenohSession(ZenohConfig(mode="client", connect=(endpoint,), extra_json5=items))


def _payloads(buf: LatestValueBuffer) -> list[bytes]:
    return [item.payload for item in buf.drain()]


def test_policy_gives_each_identity_only_its_keys() -> None:
    acl = AccessPolicy(MISSION, drone_hosts={"drone-host-1": (1, 2)}).access_control()
    assert acl["default_permission"] == "deny"
    rules = {r["id"]: r for r in acl["rules"]}  # type: ignore[index, union-attr]
    assert rules["host-0-publish"]["key_exprs"] == [KEYS.state(1), KEYS.edge(1), KEYS.pace(1), KEYS.state(2),
                                                    KEYS.edge(2), KEYS.pace(2)]
    assert KEYS.command not in str(rules["readers-subscribe"]) and KEYS.polygon in rules["readers-subscribe"]["key_exprs"]
    assert parse_drone_host("h=1-3,7") == ("h", (1, 2, 3, 7))
    with pytest.raises(ValueError, match="--drone-host"):
        parse_drone_host("h=a")


@pytest.mark.integration
def test_two_tls_routers_admit_only_mission_identities_and_enforce_who_publishes(
        tmp_path: Path, free_endpoint: Callable[[], str], spawn: Callable) -> None:
    certs, rogue = tmp_path / "certs", tmp_path / "rogue"
    for name in ("ground-station", "drone-host-1", "rescue-centre"):
        issue_identity(certs, name)
    issue_identity(rogue, "rescue-centre")  # right name, another CA
    ep_a, ep_b = (free_endpoint().replace("tcp/", "tls/") for _ in range(2))
    acl = ["--mission", MISSION, "--drone-host", "drone-host-1=1-2"]
    gcs_id, drone_id, rescue_id = (_identity(certs, n) for n in ("ground-station", "drone-host-1", "rescue-centre"))
    routers = [
        spawn("-m", "comms.router", "--listen", ep_a, "--tls-ca", str(gcs_id.ca_pem), "--tls-cert", str(gcs_id.cert_pem),
              "--tls-key", str(gcs_id.key_pem), *acl),
        spawn("-m", "comms.router", "--listen", ep_b, "--connect", ep_a, "--tls-ca", str(drone_id.ca_pem),
              "--tls-cert", str(drone_id.cert_pem), "--tls-key", str(drone_id.key_pem), *acl),
    ]
    for router in routers:
        assert "listening on" in router.stderr.readline()

    ca_only = (("transport/link/tls/root_ca_certificate", f'"{gcs_id.ca_pem}"'),)
    for name, attempt in [("no client certificate", lambda: _client(ep_a, extra=ca_only)),
                          ("a certificate from another CA", lambda: _client(ep_a, _identity(rogue, "rescue-centre"))),
                          ("plain TCP", lambda: _client(ep_a.replace("tls/", "tcp/")))]:
        with pytest.raises(ZenohOpenError):
            attempt().close()
            pytest.fail(f"{name}: connected")

    with _client(ep_a, gcs_id) as gcs, _client(ep_b, drone_id) as drone, _client(ep_b, drone_id) as other_drone, \
            _client(ep_a, rescue_id) as rescue, _client(ep_b, rescue_id) as rescue_at_drone_host:
        drone_commands = other_drone.subscribe(KEYS.command)  # a session hears its own puts without any router
        gcs_commands = gcs.subscribe(KEYS.command)
        gcs_states = gcs.subscribe(KEYS.all_states)
        polygons = rescue.subscribe(KEYS.polygon)
        deadline = time.monotonic() + 15.0
        while time.monotonic() < deadline and not (len(drone_commands) and len(polygons)):
            gcs.put(KEYS.command, b"genuine")
            gcs.put(KEYS.polygon, b"polygon")
            time.sleep(0.2)
        assert _payloads(drone_commands)[-1] == b"genuine", "the routers' TLS link carries commands"
        assert _payloads(polygons)[-1] == b"polygon", "the rescue centre reads the polygon"
        gcs_commands.drain()

        rescue.put(KEYS.command, b"rescue land")
        rescue_at_drone_host.put(KEYS.command, b"rescue land via the drone host")
        drone.put(KEYS.command, b"drone land")
        drone.put(KEYS.state(9), b"state for another host's drone")
        drone.put(KEYS.state(2), b"own state")
        assert _wait(lambda: gcs_states.drain(), 5.0) == [KEYS.state(2)], "a drone host publishes its own drones"
        time.sleep(1.0)
        assert _payloads(drone_commands) == [] and _payloads(gcs_commands) == [], "access control refused commands"
        assert _payloads(gcs_states) == []


def _wait(take: Callable[[], list], timeout_s: float) -> list[str]:
    keys: list[str] = []
    deadline = time.monotonic() + timeout_s
    while time.monotonic() < deadline and not keys:
        keys = [item.key for item in take()]
        time.sleep(0.05)
    return keys
