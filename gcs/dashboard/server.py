"""Runs one dashboard: the Zenoh feed, the frame pump and the ASGI app on uvicorn, in one asyncio loop.

The pump drains the feed at most every :data:`MIN_FRAME_GAP_S` and at least every :data:`FRAME_PERIOD_S`, so the
page redraws at 10-20 Hz: at once when the ground station publishes (status at 5 Hz, events, polygons), and in
between so that the ages of the values keep counting up when nothing arrives.
"""

from __future__ import annotations

import asyncio
import logging
import time
from dataclasses import dataclass
from pathlib import Path

import msgspec
import uvicorn

from comms.zenoh_session import ZenohConfig
from gcs.dashboard.app import AppSettings, create_app
from gcs.dashboard.broadcast import FrameBroadcast
from gcs.dashboard.feed import DashboardFeed
from gcs.dashboard.model import DashboardModel
from gcs.dashboard.tiles import TileArchive

FRAME_PERIOD_S = 0.1
MIN_FRAME_GAP_S = 0.05
FULL_FRAME_PERIOD_S = 2.0
"""Every so often a frame carries everything, so a page that skipped frames catches up (see ``model.RESEND_S``)."""


@dataclass(frozen=True)
class ServerOptions:
    mission: str
    zenoh: ZenohConfig
    host: str
    port: int
    token: str | None = None
    tiles: Path | None = None
    key_file: Path | None = None


async def _pump(feed: DashboardFeed, model: DashboardModel, broadcast: FrameBroadcast) -> None:
    loop = asyncio.get_running_loop()
    last_s = last_full_s = loop.time()
    while True:
        await feed.buffer.wait_async(max(0.0, last_s + FRAME_PERIOD_S - loop.time()))
        feed.apply(model)
        last_s = loop.time()
        full = last_s - last_full_s >= FULL_FRAME_PERIOD_S
        if full:
            last_full_s = last_s
        if broadcast.clients:
            await broadcast.publish(b"data: " + msgspec.json.encode(model.frame(time.time(), full)) + b"\n\n")
        await asyncio.sleep(MIN_FRAME_GAP_S)


async def serve(options: ServerOptions) -> None:
    """Serve until SIGINT/SIGTERM (uvicorn's handlers); the Zenoh session and the tile archive are closed on every
    exit path. Raises ``ZenohOpenError`` / ``TilesError`` before listening when either cannot be opened."""
    tiles = TileArchive(options.tiles) if options.tiles is not None else None
    feed: DashboardFeed | None = None
    try:
        feed = DashboardFeed(options.mission, options.zenoh, options.key_file)
        model = DashboardModel(options.mission)
        broadcast = FrameBroadcast()
        settings = AppSettings(mission=options.mission, host=options.host, token=options.token, tiles=tiles)
        app = create_app(settings, model, broadcast, feed, time.time)
        config = uvicorn.Config(app, host=options.host, port=options.port, log_level="warning", access_log=False,
                                lifespan="off", timeout_graceful_shutdown=1, timeout_keep_alive=5)
        server = uvicorn.Server(config)
        pump = asyncio.create_task(_pump(feed, model, broadcast))
        try:
            await server.serve()
        finally:
            pump.cancel()
    finally:
        if feed is not None:
            feed.close()
        if tiles is not None:
            tiles.close()

