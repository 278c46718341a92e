"""A local base map: raster tiles from an MBTiles (SQLite) or PMTiles (v3, single file) archive on disk.

The page asks ``/tiles/{z}/{x}/{y}`` in the XYZ scheme Leaflet uses; MBTiles rows are TMS (y counted from the
south), PMTiles addresses by Hilbert tile id (read through the ``pmtiles`` package's reader). Vector tiles would
need a renderer in the page, so only PNG, JPEG and WebP archives are accepted.
"""

from __future__ import annotations

import sqlite3
import threading
from dataclasses import dataclass
from pathlib import Path

from pmtiles.reader import MmapSource, Reader
from pmtiles.tile import Compression, MagicNumberNotFound, SpecVersionUnsupported, TileType

_MEDIA_TYPES = {"png": "image/png", "jpg": "image/jpeg", "jpeg": "image/jpeg", "webp": "image/webp"}
_PMTILES_TYPES = {TileType.PNG: "png", TileType.JPEG: "jpg", TileType.WEBP: "webp"}


class TilesError(ValueError):
    """The archive cannot be served (unreadable, vector tiles, compressed raster tiles)."""


@dataclass(frozen=True)
class TilesInfo:
    media_type: str
    min_zoom: int
    max_zoom: int


class TileArchive:
    """Read-only access to one archive; :meth:`tile` is safe from several threads."""

    def __init__(self, path: Path) -> None:
        self.path = path
        self._lock = threading.Lock()
        suffix = path.suffix.lower()
        try:
            if suffix == ".mbtiles":
                self._db = sqlite3.connect(f"file:{path}?mode=ro", uri=True, check_same_thread=False)
                self.info = self._mbtiles_info()
                self._pm = None
            elif suffix == ".pmtiles":
                self._file = open(path, "rb")  # noqa: SIM115 - kept open for the server's life, closed in close()
                self._pm = Reader(MmapSource(self._file))
                self.info = self._pmtiles_info()
            else:
                raise TilesError(f"{path}: neither .mbtiles nor .pmtiles")
        except (sqlite3.Error, OSError, ValueError, KeyError, MagicNumberNotFound, SpecVersionUnsupported) as exc:
            if isinstance(exc, TilesError):
                raise
            raise TilesError(f"{path}: cannot read the tile archive ({exc})") from exc

    def _mbtiles_info(self) -> TilesInfo:
        meta = dict(self._db.execute("SELECT name, value FROM metadata").fetchall())
        fmt = str(meta.get("format", "png")).lower()
        if fmt not in _MEDIA_TYPES:
            raise TilesError(f"{self.path}: tiles of format {fmt!r}; only raster png, jpg or webp can be shown")
        zooms = self._db.execute("SELECT MIN(zoom_level), MAX(zoom_level) FROM tiles").fetchone()
        return TilesInfo(_MEDIA_TYPES[fmt], int(meta.get("minzoom", zooms[0] or 0)),
                         int(meta.get("maxzoom", zooms[1] or 0)))

    def _pmtiles_info(self) -> TilesInfo:
        assert self._pm is not None
        header = self._pm.header()
        kind = _PMTILES_TYPES.get(header["tile_type"])
        if kind is None:
            raise TilesError(f"{self.path}: {header['tile_type'].name} tiles; "
                             "only raster png, jpg or webp can be shown")
        if header["tile_compression"] not in (Compression.NONE, Compression.UNKNOWN):
            raise TilesError(f"{self.path}: raster tiles stored with {header['tile_compression'].name} compression")
        return TilesInfo(_MEDIA_TYPES[kind], int(header["min_zoom"]), int(header["max_zoom"]))

    def tile(self, z: int, x: int, y: int) -> bytes | None:
        """The tile at XYZ address (z, x, y), or None when the archive has none there (or the address is invalid)."""
        if not (0 <= z <= 30 and 0 <= x < (1 << z) and 0 <= y < (1 << z)):
            return None
        with self._lock:
            if self._pm is not None:
                data = self._pm.get(z, x, y)
                return bytes(data) if data else None
            row = self._db.execute(
                "SELECT tile_data FROM tiles WHERE zoom_level=? AND tile_column=? AND tile_row=?",
                (z, x, (1 << z) - 1 - y)).fetchone()
        return bytes(row[0]) if row else None

    def close(self) -> None:
        if self._pm is not None:
            self._file.close()
        else:
            self._db.close()
