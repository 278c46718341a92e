"""Bundles framed from pre-encoded entries are byte for byte what the codec encodes, at every array-header size."""

import pytest

from comms.bundle_wire import bundle_bytes, bundle_head, encode_entry
from comms.messages import RadioBundle, decode, encode


@pytest.mark.parametrize("count", [0, 1, 15, 16, 300, 65535, 65536])
def test_framed_bundle_equals_the_codecs_encoding(count: int) -> None:
    entries = [(i % 7 + 1, bytes([i % 251]) * (i % 5)) for i in range(count)]
    t_s = 12.345678
    framed = bundle_bytes(bundle_head(t_s), [encode_entry(s, p) for s, p in entries])
    assert framed == encode(RadioBundle(t_s=t_s, entries=entries))
    assert decode(RadioBundle, framed) == RadioBundle(t_s=t_s, entries=entries)

