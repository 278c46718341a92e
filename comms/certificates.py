"""``python -m comms.certificates --out DIR NAME...``: a mission CA and one TLS identity per host.

Zenoh's TLS transport with mutual authentication (``enable_mtls``) admits only peers whose certificate the mission
CA signed, and Zenoh's access control recognises each by its certificate's common name (``cert_common_names``).
This writes ``ca.pem`` (the CA certificate every host trusts), and for each NAME ``NAME.pem`` and ``NAME-key.pem``
(mode 0600). Names are the identities the access control knows, e.g. ``ground-station``, ``drone-host-1``,
``rescue-centre``. The CA's private key (``ca-key.pem``, 0600) stays with whoever issues identities; it is reused
when present, so new hosts can be added later. Every certificate names ``localhost`` and ``127.0.0.1`` plus any
``--san`` given, because a Zenoh client checks the router's name unless told not to. Needs the ``cryptography``
package (``pip install -e '.[tls]'``); the README shows the same with openssl.
"""

from __future__ import annotations

import argparse
import datetime as dt
import ipaddress
import os
import re
import sys
from collections.abc import Sequence
from pathlib import Path

from cryptography import x509
from cryptography.hazmat.primitives import hashes, serialization
from cryptography.hazmat.primitives.asymmetric import ec
from cryptography.x509.oid import ExtendedKeyUsageOID, NameOID

_NAME_RE = re.compile(r"^[A-Za-z0-9][A-Za-z0-9_.-]{0,63}$")
VALID_DAYS = 365


def _write_private(path: Path, data: bytes) -> None:
    fd = os.open(path, os.O_WRONLY | os.O_CREAT | os.O_TRUNC, 0o600)
    with os.fdopen(fd, "wb") as f:
        f.write(data)


def _key_pem(key: ec.EllipticCurvePrivateKey) -> bytes:
    return key.private_bytes(serialization.Encoding.PEM, serialization.PrivateFormat.PKCS8, serialization.NoEncryption())


def _load_or_create_ca(folder: Path) -> tuple[ec.EllipticCurvePrivateKey, x509.Certificate]:
    key_path, cert_path = folder / "ca-key.pem", folder / "ca.pem"
    if key_path.exists() and cert_path.exists():
        key = serialization.load_pem_private_key(key_path.read_bytes(), password=None)
        assert isinstance(key, ec.EllipticCurvePrivateKey)
        return key, x509.load_pem_x509_certificate(cert_path.read_bytes())
    key = ec.generate_private_key(ec.SECP256R1())
    name = x509.Name([x509.NameAttribute(NameOID.COMMON_NAME, "floodwatch-mission-ca")])
    now = dt.datetime.now(dt.timezone.utc)
    cert = (x509.CertificateBuilder().subject_name(name).issuer_name(name).public_key(key.public_key())
            .serial_number(x509.random_serial_number()).not_valid_before(now - dt.timedelta(minutes=5))
            .not_valid_after(now + dt.timedelta(days=VALID_DAYS))
            .add_extension(x509.BasicConstraints(ca=True, path_length=0), critical=True)
            .add_extension(x509.KeyUsage(digital_signature=True, key_cert_sign=True, crl_sign=True,
                                         content_commitment=False, key_encipherment=False, data_encipherment=False,
                                         key_agreement=False, encipher_only=False, decipher_only=False), critical=True)
            .sign(key, hashes.SHA256()))
    _write_private(key_path, _key_pem(key))
    cert_path.write_bytes(cert.public_bytes(serialization.Encoding.PEM))
    return key, cert


def issue_identity(folder: Path, name: str, sans: Sequence[str] = ()) -> tuple[Path, Path]:
    """Create (or reuse) the CA in ``folder`` and issue ``name``'s certificate and key; returns their paths."""
    if not _NAME_RE.match(name):
        raise ValueError(f"identity name {name!r}: use letters, digits, '_', '.', '-'")
    folder.mkdir(parents=True, exist_ok=True)
    ca_key, ca_cert = _load_or_create_ca(folder)
    key = ec.generate_private_key(ec.SECP256R1())
    alt: list[x509.GeneralName] = [x509.DNSName("localhost"), x509.IPAddress(ipaddress.ip_address("127.0.0.1"))]
    for san in sans:
        try:
            alt.append(x509.IPAddress(ipaddress.ip_address(san)))
        except ValueError:
            alt.append(x509.DNSName(san))
    now = dt.datetime.now(dt.timezone.utc)
    cert = (x509.CertificateBuilder()
            .subject_name(x509.Name([x509.NameAttribute(NameOID.COMMON_NAME, name)]))
            .issuer_name(ca_cert.subject).public_key(key.public_key()).serial_number(x509.random_serial_number())
            .not_valid_before(now - dt.timedelta(minutes=5)).not_valid_after(now + dt.timedelta(days=VALID_DAYS))
            .add_extension(x509.SubjectAlternativeName(alt), critical=False)
            .add_extension(x509.BasicConstraints(ca=False, path_length=None), critical=True)
            .add_extension(x509.ExtendedKeyUsage([ExtendedKeyUsageOID.SERVER_AUTH, ExtendedKeyUsageOID.CLIENT_AUTH]),
                           critical=False)
            .sign(ca_key, hashes.SHA256()))
    cert_path, key_path = folder / f"{name}.pem", folder / f"{name}-key.pem"
    cert_path.write_bytes(cert.public_bytes(serialization.Encoding.PEM))
    _write_private(key_path, _key_pem(key))
    return cert_path, key_path


def main(argv: Sequence[str] | None = None) -> int:
    parser = argparse.ArgumentParser(prog="python -m comms.certificates",
                                     description="Create the mission CA and TLS identities for Zenoh mutual TLS.")
    parser.add_argument("names", nargs="+", metavar="NAME", help="identities, e.g. ground-station drone-host-1")
    parser.add_argument("--out", type=Path, required=True, metavar="DIR")
    parser.add_argument("--san", action="append", default=[], metavar="HOST_OR_IP",
                        help="extra host name or address in every certificate issued now (the routers' addresses)")
    args = parser.parse_args(argv)
    try:
        for name in args.names:
            cert, key = issue_identity(args.out, name, args.san)
            print(f"{name}: {cert} {key}")
    except (ValueError, OSError) as exc:
        print(f"comms.certificates: {exc}", file=sys.stderr)
        return 2
    print(f"CA certificate: {args.out / 'ca.pem'} (give it to every host; keep ca-key.pem with the issuer)")
    return 0


if __name__ == "__main__":
    sys.exit(main())
