"""Latest-value buffer: newest wins per key, bounded, wakes thread and asyncio consumers."""

from __future__ import annotations

import asyncio
import threading
import time

from comms.latest_buffer import LatestValueBuffer


def test_newest_wins_and_is_counted() -> None:
    buf = LatestValueBuffer()
    buf.put("a", b"1")
    buf.put("b", b"x")
    buf.put("a", b"2")
    items = {r.key: r.payload for r in buf.drain()}
    assert items == {"a": b"2", "b": b"x"}
    assert buf.received == 3 and buf.superseded == 1
    assert buf.drain() == []


def test_bounded_number_of_keys() -> None:
    buf = LatestValueBuffer(max_keys=2)
    for k in "abc":
        buf.put(k, b"")
    buf.put("a", b"new")
    assert sorted(r.key for r in buf.drain()) == ["a", "b"]
    assert buf.rejected == 1


def test_put_many_and_kinds() -> None:
    buf = LatestValueBuffer()
    buf.put_many([("x", b"1"), ("y", b"2"), ("x", b"3")], kind="delete")
    got = {r.key: (r.payload, r.kind) for r in buf.drain()}
    assert got == {"x": (b"3", "delete"), "y": (b"2", "delete")}


def test_thread_wait_wakes_on_put() -> None:
    buf = LatestValueBuffer()
    threading.Timer(0.05, lambda: buf.put("k", b"v")).start()
    t0 = time.monotonic()
    assert buf.wait(5.0)
    assert time.monotonic() - t0 < 4.0
    assert not LatestValueBuffer().wait(0.01)


def test_asyncio_wait_wakes_on_put_from_another_thread() -> None:
    async def scenario() -> tuple[bool, bool, list[bytes]]:
        buf = LatestValueBuffer()
        timeout_result = await buf.wait_async(0.01)
        threading.Timer(0.05, lambda: buf.put("k", b"v")).start()
        woke = await buf.wait_async(5.0)
        return timeout_result, woke, [r.payload for r in buf.drain()]

    assert asyncio.run(scenario()) == (False, True, [b"v"])


def test_put_after_event_loop_closed_does_not_raise() -> None:
    buf = LatestValueBuffer()

    async def wait_briefly() -> None:
        task = asyncio.ensure_future(buf.wait_async(10.0))
        await asyncio.sleep(0.01)
        task.cancel()

    asyncio.run(wait_briefly())
    buf.put("k", b"v")  # the registered waiter's loop is gone
    assert len(buf) == 1
