"""Group bundles: framed bytes equal the codec's, each receiver reads back exactly its own deliveries."""

from __future__ import annotations

import numpy as np
import pytest

from comms.bundle_wire import encode_entry
from comms.keys import MissionKeys
from comms import radio_groups
from comms.messages import RadioGroupBundle, decode, encode
from comms.radio_groups import (
    RADIO_GROUP_SIZE,
    framed_group_bundles,
    group_bundle_bytes,
    group_head,
    group_inbox_key,
    group_of,
    selected_entries,
)
from comms.swarm_link import bundle_unpacker


@pytest.mark.parametrize("count", [0, 1, 15, 16, 300, 65536])
def test_group_bundle_bytes_equal_the_codecs_encoding(count: int) -> None:
    entries = [(i % 7 + 1, bytes([i % 251]) * (i % 5)) for i in range(count)]
    receivers, indices = [3, 5], [*range(0, count, 2), *range(count - 1, -1, -3)]
    counts = [len(range(0, count, 2)), len(range(count - 1, -1, -3))]
    framed = group_bundle_bytes(group_head(12.345678), receivers, counts, indices, [encode_entry(s, p) for s, p in entries])
    expected = RadioGroupBundle(t_s=12.345678, receivers=receivers, counts=counts, indices=indices, entries=entries)
    assert framed == encode(expected)
    assert decode(RadioGroupBundle, framed) == expected


def _deliveries(seed: int) -> dict[int, list[int]]:
    """Random receivers (ids 0-60, several groups) and, per receiver, the message numbers due to it in delivery order."""
    rng = np.random.default_rng(seed)
    receivers = sorted(rng.choice(61, size=25, replace=False).tolist())
    return {r: rng.permutation(40)[: rng.integers(1, 20)].tolist() for r in receivers}


@pytest.mark.parametrize("seed", range(5))
@pytest.mark.parametrize("dense_cells", [1 << 20, 0])  # a mark per (group, message) cell, or a sort
def test_every_receiver_reads_back_exactly_its_deliveries(seed: int, dense_cells: int,
                                                          monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setattr(radio_groups, "_DENSE_CELLS", dense_cells)
    due = _deliveries(seed)
    messages = {m: (100 + m, bytes([m]) * (m % 9 + 1)) for m in range(40)}
    receivers = list(due)
    rows = np.array([r for r, v in due.items() for _ in v], dtype=np.int64)
    message_ids = np.array([m for v in due.values() for m in v], dtype=np.int64) + 1000
    entries = np.empty(message_ids.size, dtype=object)
    entries[:] = [encode_entry(*messages[m - 1000]) for m in message_ids.tolist()]
    bundles = framed_group_bundles(4.5, rows, message_ids, entries)
    assert [g for g, _ in bundles] == sorted({group_of(r) for r in receivers})
    got = {}
    for group, payload in bundles:
        bundle = decode(RadioGroupBundle, payload)
        assert bundle is not None
        members = bundle.receivers
        assert members == [r for r in receivers if group_of(r) == group]
        wanted = sorted({m for r in members for m in due[r]})
        assert bundle.entries == [messages[m] for m in wanted]  # each message once, in message order
        got.update({r: selected_entries(bundle, r) for r in members})
    assert got == {r: [messages[m] for m in ms] for r, ms in due.items()}


def _bundle(receivers: list[int], counts: list[int], indices: list[int]) -> bytes:
    return encode(RadioGroupBundle(t_s=1.0, receivers=receivers, counts=counts, indices=indices,
                                   entries=[(1, b"a"), (2, b"b"), (3, b"c")]))


def test_a_receiver_takes_only_its_run_through_the_inbox_unpacker() -> None:
    keys = MissionKeys("m")
    payload = _bundle([9, 10], [2, 1], [2, 0, 1])
    assert bundle_unpacker(keys, 9)("k", payload) == [(keys.state(3), b"c"), (keys.state(1), b"a")]
    assert bundle_unpacker(keys, 10)("k", payload) == [(keys.state(2), b"b")]
    assert bundle_unpacker(keys, 11)("k", payload) == []
    with pytest.raises(ValueError):
        bundle_unpacker(keys)("k", payload)


@pytest.mark.parametrize("receivers, counts, indices, error", [
    ([9], [1], [3], IndexError),  # past the entries
    ([9], [1], [-1], IndexError),
    ([9, 10], [1], [0], ValueError),  # a count missing
    ([9], [2], [0], ValueError),  # counts add up to more indices than there are
    ([9, 10], [-1, 2], [0], ValueError),
])
def test_a_bundle_whose_lists_do_not_fit_is_refused(receivers: list[int], counts: list[int], indices: list[int],
                                                    error: type[Exception]) -> None:
    with pytest.raises(error):
        bundle_unpacker(MissionKeys("m"), 9)("k", _bundle(receivers, counts, indices))


def test_group_keys() -> None:
    keys = MissionKeys("m")
    assert group_inbox_key(keys, 0) == group_inbox_key(keys, RADIO_GROUP_SIZE - 1) == "floodwatch/m/radio/group/0"
    assert group_inbox_key(keys, RADIO_GROUP_SIZE) == "floodwatch/m/radio/group/1"
    assert keys.vehicle_id_of(keys.radio_group(3)) is None
