"""The dashboard's HTTP side in-process (Starlette's test client): pages, downloads, refusals, tiles."""

from __future__ import annotations

import json
import sqlite3
from pathlib import Path

import pytest
from pmtiles.tile import Compression, TileType, zxy_to_tileid
from pmtiles.writer import Writer
from starlette.testclient import TestClient

from comms.frames import GeodeticHome
from comms.gcs_status import OperatorCommand
from comms.messages import flood_polygon_from_enu
from gcs.dashboard.app import AppSettings, create_app
from gcs.dashboard.broadcast import FrameBroadcast
from gcs.dashboard.model import DashboardModel
from gcs.dashboard.tiles import TileArchive, TilesError

HOME = GeodeticHome(lat_deg=47.0, lon_deg=8.0, alt_m=400.0)
PNG = b"\x89PNG\r\n\x1a\n" + b"tile"


class Commands:
    def __init__(self) -> None:
        self.sent: list[tuple[OperatorCommand, str]] = []

    def request(self, command: OperatorCommand, origin: str) -> None:
        self.sent.append((command, origin))


def _client(token: str | None = None, tiles: TileArchive | None = None, host: str = "127.0.0.1"):
    model = DashboardModel("circle")
    commands = Commands()
    app = create_app(AppSettings("circle", host=host, token=token, tiles=tiles), model, FrameBroadcast(), commands,
                     lambda: 1000.0)
    return TestClient(app, base_url="http://127.0.0.1:8080"), model, commands


def test_the_page_and_its_vendored_leaflet_are_served_with_a_self_only_policy() -> None:
    client, _, _ = _client()
    page = client.get("/")
    assert page.status_code == 200 and "leaflet.js" in page.text
    assert "default-src 'self'" in page.headers["content-security-policy"]
    for path in ("/static/vendor/leaflet/leaflet.js", "/static/vendor/leaflet/leaflet.css",
                 "/static/vendor/leaflet/LICENSE", "/static/app.js", "/static/grid.js"):
        assert client.get(path).status_code == 200, path
    html_and_js = page.text + client.get("/static/app.js").text + client.get("/static/grid.js").text
    assert "http://" not in html_and_js and "https://" not in html_and_js


def test_downloads_are_404_before_a_polygon_and_valid_after() -> None:
    client, model, _ = _client()
    assert client.get("/api/polygon.geojson").status_code == 404
    model.on_polygon(flood_polygon_from_enu([(0, 0), (20, 0), (20, 20), (0, 20)], HOME, mission="circle", t_s=4.0),
                     now_wall_s=999.0)
    feature = json.loads(client.get("/api/polygon.geojson").content)
    ring = feature["geometry"]["coordinates"][0]
    assert feature["type"] == "Feature" and feature["geometry"]["type"] == "Polygon"
    assert ring[0] == ring[-1] and len(ring) == 5 and feature["properties"]["area_m2"] == pytest.approx(400.0)
    kml = client.get("/api/polygon.kml")
    assert kml.status_code == 200 and "<Polygon>" in kml.text and "attachment" in kml.headers["content-disposition"]


def test_bad_requests_get_4xx() -> None:
    client, _, _ = _client()
    assert client.get("/api/history?start=-1").status_code == 400
    assert client.get("/api/history?start=abc").status_code == 400
    assert client.get("/api/history?start=0").json()["items"] == []
    assert client.get("/nothing/here").status_code == 404
    assert client.get("/api/command/hold").status_code == 405
    assert client.get("/tiles/1/2/3").status_code == 404
    assert client.get("/static/../../cli.py").status_code == 404
    rebound = client.get("/api/state", headers={"host": "attacker.example"})
    assert rebound.status_code == 400


def test_commands_are_refused_read_only_and_without_the_right_token() -> None:
    client, _, commands = _client()
    assert client.post("/api/command/hold").status_code == 403
    client, _, commands = _client(token="s3cret")
    assert client.post("/api/command/hold").status_code == 401
    assert client.post("/api/command/hold", headers={"authorization": "Bearer nope"}).status_code == 401
    assert client.post("/api/command/fly-away", headers={"authorization": "Bearer s3cret"}).status_code == 404
    assert commands.sent == []
    assert client.post("/api/command/land", headers={"authorization": "Bearer s3cret"}).status_code == 202
    assert [c for c, _ in commands.sent] == [OperatorCommand.LAND]


def _mbtiles(path: Path, fmt: str = "png") -> Path:
    db = sqlite3.connect(path)
    db.execute("CREATE TABLE metadata (name TEXT, value TEXT)")
    db.execute("CREATE TABLE tiles (zoom_level INTEGER, tile_column INTEGER, tile_row INTEGER, tile_data BLOB)")
    db.executemany("INSERT INTO metadata VALUES (?, ?)", [("format", fmt), ("minzoom", "0"), ("maxzoom", "2")])
    db.execute("INSERT INTO tiles VALUES (2, 1, 0, ?)", (PNG,))  # TMS row 0 at z2 = XYZ y 3
    db.commit()
    db.close()
    return path


def _pmtiles(path: Path) -> Path:
    with open(path, "wb") as f:
        writer = Writer(f)
        writer.write_tile(zxy_to_tileid(2, 1, 3), PNG)
        writer.finalize({"tile_type": TileType.PNG, "tile_compression": Compression.NONE, "min_zoom": 0,
                         "max_zoom": 2, "min_lon_e7": -1800000000, "min_lat_e7": -850000000,
                         "max_lon_e7": 1800000000, "max_lat_e7": 850000000, "center_zoom": 0,
                         "center_lon_e7": 0, "center_lat_e7": 0}, {})
    return path


@pytest.mark.parametrize("make", [_mbtiles, _pmtiles], ids=["mbtiles", "pmtiles"])
def test_local_tiles_are_served_in_the_xyz_scheme(tmp_path: Path, make) -> None:  # noqa: ANN001
    archive = TileArchive(make(tmp_path / ("t.mbtiles" if make is _mbtiles else "t.pmtiles")))
    client, _, _ = _client(tiles=archive)
    tile = client.get("/tiles/2/1/3")
    assert tile.status_code == 200 and tile.content == PNG and tile.headers["content-type"] == "image/png"
    assert client.get("/tiles/2/1/2").status_code == 204
    assert client.get("/tiles/2/9/9").status_code == 204
    assert client.get("/tiles/a/1/2").status_code == 400
    assert client.get("/api/config").json()["tiles"]["max_zoom"] == 2
    archive.close()


def test_vector_or_unreadable_archives_are_refused(tmp_path: Path) -> None:
    with pytest.raises(TilesError, match="only raster"):
        TileArchive(_mbtiles(tmp_path / "v.mbtiles", fmt="pbf"))
    (tmp_path / "bad.pmtiles").write_bytes(b"not a pmtiles archive at all" * 10)
    with pytest.raises(TilesError):
        TileArchive(tmp_path / "bad.pmtiles")
