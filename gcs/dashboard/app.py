"""The dashboard's HTTP side, a Starlette app: the page and its vendored Leaflet, a Server-Sent-Events stream of
frames, the polygon history and downloads, local tiles, and the token-guarded operator commands.

Every response forbids loading anything from another origin (Content-Security-Policy ``default-src 'self'``), so
the page is offline by construction: a slip that adds a CDN link fails in the browser, not at the rescue centre.
Bad requests get a 4xx with a one-line JSON reason; nothing a client sends can stop the server.
"""

from __future__ import annotations

import hmac
import logging
from dataclasses import dataclass
from pathlib import Path
from typing import Any, Protocol

import msgspec
from starlette.applications import Starlette
from starlette.exceptions import HTTPException
from starlette.middleware import Middleware
from starlette.middleware.trustedhost import TrustedHostMiddleware
from starlette.requests import Request
from starlette.responses import FileResponse, JSONResponse, Response, StreamingResponse
from starlette.routing import Mount, Route
from starlette.staticfiles import StaticFiles
from starlette.types import ASGIApp, Receive, Scope, Send

from comms.gcs_status import OperatorCommand
from gcs.dashboard.broadcast import FrameBroadcast
from gcs.dashboard.downloads import polygon_geojson, polygon_kml
from gcs.dashboard.feed import OperatorKeyMissing
from gcs.dashboard.model import DashboardModel
from gcs.dashboard.ports import is_loopback
from gcs.dashboard.tiles import TileArchive

STATIC_DIR = Path(__file__).resolve().parent / "static"
KEEPALIVE_S = 10.0
CSP = ("default-src 'self'; img-src 'self' data: blob:; style-src 'self' 'unsafe-inline'; script-src 'self'; "
       "connect-src 'self'; font-src 'self'; frame-ancestors 'none'; base-uri 'none'; form-action 'none'")
log = logging.getLogger("gcs.dashboard")


class CommandSink(Protocol):
    def request(self, command: OperatorCommand, origin: str) -> None: ...


@dataclass(frozen=True)
class AppSettings:
    mission: str
    host: str = "127.0.0.1"
    token: str | None = None
    tiles: TileArchive | None = None


class _SecurityHeaders:
    """Adds the CSP and friends to every response."""

    def __init__(self, app: ASGIApp) -> None:
        self.app = app

    async def __call__(self, scope: Scope, receive: Receive, send: Send) -> None:
        if scope["type"] != "http":
            await self.app(scope, receive, send)
            return

        async def with_headers(message: dict[str, Any]) -> None:
            if message["type"] == "http.response.start":
                headers = list(message.get("headers", []))
                headers += [(b"content-security-policy", CSP.encode()), (b"x-content-type-options", b"nosniff"),
                            (b"referrer-policy", b"no-referrer"), (b"cache-control", b"no-store")]
                message = {**message, "headers": headers}
            await send(message)

        await self.app(scope, receive, with_headers)


def _error(status: int, reason: str) -> JSONResponse:
    return JSONResponse({"error": reason}, status_code=status)


class _Endpoints:
    """The app's request handlers over one dashboard's settings, model, broadcast and command sink;
    ``now_wall_s()`` is the clock used for the ages in a frame (the server passes ``time.time``)."""

    def __init__(self, settings: AppSettings, model: DashboardModel, broadcast: FrameBroadcast, commands: CommandSink,
                 now_wall_s: Any) -> None:
        self.settings, self.model, self.broadcast, self.commands = settings, model, broadcast, commands
        self.now_wall_s = now_wall_s

    async def index(self, _: Request) -> Response:
        return FileResponse(STATIC_DIR / "index.html", media_type="text/html")

    async def config(self, _: Request) -> Response:
        tiles = self.settings.tiles.info if self.settings.tiles else None
        return JSONResponse({
            "mission": self.settings.mission, "commands": self.settings.token is not None,
            "tiles": None if tiles is None else {"min_zoom": tiles.min_zoom, "max_zoom": tiles.max_zoom},
        })

    async def state(self, _: Request) -> Response:
        return Response(msgspec.json.encode(self.model.frame(self.now_wall_s())), media_type="application/json")

    async def stream(self, _: Request) -> Response:
        broadcast, model = self.broadcast, self.model

        async def events() -> Any:
            broadcast.clients += 1
            try:
                yield b"retry: 1000\n\n"
                yield b"data: " + msgspec.json.encode(model.frame(self.now_wall_s())) + b"\n\n"
                version = broadcast.version
                while True:
                    version, frame = await broadcast.next_frame(version, KEEPALIVE_S)
                    yield b": keep-alive\n\n" if frame is None else frame
            finally:
                broadcast.clients -= 1

        return StreamingResponse(events(), media_type="text/event-stream",
                                 headers={"X-Accel-Buffering": "no", "Cache-Control": "no-store"})

    async def history(self, request: Request) -> Response:
        raw = request.query_params.get("start", "0")
        if not raw.isdigit() or len(raw) > 9:
            return _error(400, "start: expected a polygon index, a non-negative integer")
        return Response(msgspec.json.encode(self.model.history(int(raw))), media_type="application/json")

    def download(self, suffix: str, media_type: str, render: Any) -> Any:
        async def handler(_: Request) -> Response:
            feature = self.model.current_polygon
            if feature is None:
                return _error(404, "no caged polygon yet")
            name = f"floodwatch-{self.settings.mission}-polygon.{suffix}"
            return Response(render(feature), media_type=media_type,
                            headers={"Content-Disposition": f'attachment; filename="{name}"'})

        return handler

    async def tile(self, request: Request) -> Response:
        tiles = self.settings.tiles
        if tiles is None:
            return _error(404, "no --tiles archive")
        parts = [request.path_params[k] for k in ("z", "x", "y")]
        if not all(p.isdigit() and len(p) < 9 for p in parts):
            return _error(400, "tile address: expected /tiles/<z>/<x>/<y> with integers")
        data = tiles.tile(*(int(p) for p in parts))
        if data is None:
            return Response(status_code=204)
        return Response(data, media_type=tiles.info.media_type)

    async def command(self, request: Request) -> Response:
        name = request.path_params["name"]
        try:
            order = OperatorCommand(name)
        except ValueError:
            return _error(404, f"unknown command {name!r}: hold, resume or land")
        token = self.settings.token
        if token is None:
            return _error(403, "read-only: this dashboard was started without --dashboard-token")
        header = request.headers.get("authorization", "")
        given = header[7:] if header.lower().startswith("bearer ") else ""
        if not given or not hmac.compare_digest(given.encode(), token.encode()):
            log.warning("operator %s from %s refused: %s token", name, _origin(request),
                        "no" if not given else "wrong")
            return _error(401, "operator commands need the dashboard token (Authorization: Bearer <token>)")
        try:
            self.commands.request(order, _origin(request))
        except OperatorKeyMissing as exc:
            log.warning("operator %s from %s not sent: %s", name, _origin(request), exc)
            return _error(503, f"cannot sign the request: {exc}")
        log.warning("operator %s from %s: sent to the ground station", name, _origin(request))
        return JSONResponse({"accepted": name}, status_code=202)


async def _http_error(_: Request, exc: Exception) -> Response:
    assert isinstance(exc, HTTPException)
    return _error(exc.status_code, str(exc.detail))


def create_app(settings: AppSettings, model: DashboardModel, broadcast: FrameBroadcast, commands: CommandSink,
               now_wall_s: Any) -> Starlette:
    """The app; ``now_wall_s()`` is the clock used for the ages in a frame (the server passes ``time.time``)."""
    e = _Endpoints(settings, model, broadcast, commands, now_wall_s)
    routes = [
        Route("/", e.index),
        Route("/api/config", e.config),
        Route("/api/state", e.state),
        Route("/api/stream", e.stream),
        Route("/api/history", e.history),
        Route("/api/polygon.geojson", e.download("geojson", "application/geo+json", polygon_geojson)),
        Route("/api/polygon.kml", e.download("kml", "application/vnd.google-earth.kml+xml", polygon_kml)),
        Route("/api/command/{name}", e.command, methods=["POST"]),
        Route("/tiles/{z}/{x}/{y}", e.tile),
        Mount("/static", StaticFiles(directory=STATIC_DIR), name="static"),
    ]
    middleware = [Middleware(_SecurityHeaders)]
    if is_loopback(settings.host):
        # a page on another site cannot reach a loopback-only server through a DNS name that rebinds to 127.0.0.1
        middleware.append(Middleware(TrustedHostMiddleware, allowed_hosts=["127.0.0.1", "localhost", "[::1]", "::1"]))
    return Starlette(routes=routes, middleware=middleware, exception_handlers={HTTPException: _http_error})


def _origin(request: Request) -> str:
    client = request.client
    return f"{client.host}:{client.port}" if client else "unknown"
