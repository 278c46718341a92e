"""Authenticated links between hosts: Zenoh TLS with mutual authentication, and who may publish what (pure).

In a multi-host deployment every host runs one router (``python -m comms.router``) and its processes join it as
clients; all of them speak TLS and present a certificate signed by the mission CA (``comms.certificates``). A peer
without such a certificate cannot open a link. On each link Zenoh's access control knows the peer by its
certificate's common name and applies the same policy on every router, default deny:

* the ground-station identity may do everything under ``floodwatch/<mission>/**`` (it also hosts the simulation
  when one runs across hosts);
* a drone host may publish only its own drones' keys (``uav/<id>/state``, ``uav/<id>/edge``, ``sim/pace/<id>``)
  and hold their liveliness tokens, and may subscribe to (and receive) the whole mission;
* a reader (the rescue centre) may subscribe to the public keys only (polygon, states, liveliness) and publish
  nothing.

Zenoh refuses what a rule does not allow where it enters a router (``ingress``) and where it would leave one
towards a peer (``egress``); refused messages are dropped (Zenoh logs them at debug level). A drone host also
receives the subscriptions of others (``declare_subscriber`` egress): a Zenoh client publishes only towards
subscribers it knows of, so without them its states would never leave it. These are Zenoh's 1.x
configuration keys (``transport/link/tls/*``, ``access_control``).
"""

from __future__ import annotations

import json
from collections.abc import Mapping
from dataclasses import dataclass, field
from pathlib import Path

from comms.keys import MissionKeys

_TLS = "transport/link/tls"
_PUBLISH = ["put", "delete"]
_TOKENS = ["liveliness_token"]
_SUBSCRIBE = ["declare_subscriber", "declare_liveliness_subscriber", "liveliness_query"]
_ALL = [*_PUBLISH, *_TOKENS, *_SUBSCRIBE, "query", "declare_queryable", "reply"]


@dataclass(frozen=True)
class TlsIdentity:
    """One host's TLS files: the mission CA certificate, this host's certificate and its private key (PEM)."""

    ca_pem: Path
    cert_pem: Path
    key_pem: Path

    def __post_init__(self) -> None:
        for name in ("ca_pem", "cert_pem", "key_pem"):
            path = getattr(self, name)
            if not Path(path).is_file():
                raise ValueError(f"--tls-{name.split('_')[0]}: {path}: no such file")

    def json5_items(self) -> tuple[tuple[str, str], ...]:
        """Zenoh configuration for TLS with mutual authentication, as (key, JSON5 value) pairs."""
        files = {"root_ca_certificate": self.ca_pem, "listen_certificate": self.cert_pem,
                 "listen_private_key": self.key_pem, "connect_certificate": self.cert_pem,
                 "connect_private_key": self.key_pem}
        items = [(f"{_TLS}/{name}", json.dumps(str(Path(path).resolve()))) for name, path in files.items()]
        items.append((f"{_TLS}/enable_mtls", "true"))
        return tuple(items)


@dataclass(frozen=True)
class AccessPolicy:
    """Who may publish what in one mission, by certificate common name (see the module docstring)."""

    mission: str
    ground_station: tuple[str, ...] = ("ground-station",)
    drone_hosts: Mapping[str, tuple[int, ...]] = field(default_factory=dict)
    readers: tuple[str, ...] = ("rescue-centre",)
    trust_loopback: bool = False
    """Give plain-TCP links over the loopback interface the ground station's rights: the ground-station host's
    router joins the mission's own hub peer that way (the hub stays on 127.0.0.1). Never on a drone host."""

    def access_control(self) -> dict[str, object]:
        """The ``access_control`` section of a Zenoh configuration."""
        keys = MissionKeys(self.mission)
        rules: list[dict[str, object]] = [
            _rule("ground-station-all", _ALL, [keys.everything]),
            _rule("hosts-subscribe", _SUBSCRIBE, [keys.everything]),
            _rule("hosts-receive", [*_PUBLISH, *_TOKENS, "reply"], [keys.everything], flows=["egress"]),
            _rule("readers-subscribe", _SUBSCRIBE, _public(keys), flows=["ingress"]),
            _rule("readers-receive", [*_PUBLISH, *_TOKENS], _public(keys), flows=["egress"]),
        ]
        subjects: list[dict[str, object]] = [{"id": "ground-station", "cert_common_names": list(self.ground_station)}]
        policies: list[dict[str, object]] = [{"rules": ["ground-station-all"], "subjects": ["ground-station"]}]
        if self.trust_loopback:
            subjects.append({"id": "loopback", "interfaces": ["lo"], "link_protocols": ["tcp"]})
            policies.append({"rules": ["ground-station-all"], "subjects": ["loopback"]})
        for n, (name, ids) in enumerate(sorted(self.drone_hosts.items())):
            own = [k for vid in ids for k in (keys.state(vid), keys.edge(vid), keys.pace(vid))]
            rules.append(_rule(f"host-{n}-publish", _PUBLISH, own or [f"{keys.prefix}/uav/none"], flows=["ingress"]))
            rules.append(_rule(f"host-{n}-tokens", _TOKENS, [keys.alive(vid) for vid in ids] or [keys.alive("none")],
                               flows=["ingress"]))
            subjects.append({"id": f"host-{n}", "cert_common_names": [name]})
            policies.append({"rules": [f"host-{n}-publish", f"host-{n}-tokens", "hosts-subscribe", "hosts-receive"],
                             "subjects": [f"host-{n}"]})
        if self.readers:
            subjects.append({"id": "readers", "cert_common_names": list(self.readers)})
            policies.append({"rules": ["readers-subscribe", "readers-receive"], "subjects": ["readers"]})
        return {"enabled": True, "default_permission": "deny", "rules": rules, "subjects": subjects,
                "policies": policies}

    def json5_items(self) -> tuple[tuple[str, str], ...]:
        return (("access_control", json.dumps(self.access_control())),)


def _rule(rule_id: str, messages: list[str], key_exprs: list[str], flows: list[str] | None = None) -> dict[str, object]:
    return {"id": rule_id, "messages": messages, "flows": flows or ["ingress", "egress"], "permission": "allow",
            "key_exprs": key_exprs}


def _public(keys: MissionKeys) -> list[str]:
    return [keys.polygon, keys.all_states, keys.all_alive]


def parse_drone_host(text: str) -> tuple[str, tuple[int, ...]]:
    """``NAME=1,2,5`` or ``NAME=1-13`` -> (common name, vehicle ids); raises ValueError naming the flag."""
    name, sep, spec = text.partition("=")
    if not sep or not name:
        raise ValueError(f"--drone-host {text!r}: expected NAME=IDS, e.g. drone-host-1=1-7")
    ids: list[int] = []
    try:
        for part in spec.split(","):
            lo, dash, hi = part.partition("-")
            ids.extend(range(int(lo), int(hi) + 1) if dash else [int(lo)])
    except ValueError:
        raise ValueError(f"--drone-host {text!r}: ids are numbers or ranges like 1-7,9") from None
    return name, tuple(ids)
