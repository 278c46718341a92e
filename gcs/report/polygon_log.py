"""Incremental GeoJSON + KML polygon files, valid after every append, so a crash keeps what was recorded.

The ground station appends a polygon while the mission runs. Each append rewrites only the file's tail: it seeks
back over the closing text (``]}`` for GeoJSON, ``</Document></kml>`` for KML), writes the new feature and the
closing text again, and flushes. Between appends both files are complete, parseable documents; only a crash in the
middle of one write can leave that one sample torn. Cost per append is independent of the file length.
"""

from __future__ import annotations

import json
import os
from datetime import datetime, timezone
from pathlib import Path
from types import TracebackType
from typing import IO, Any

from numpy.typing import ArrayLike

from comms.frames import GeodeticHome
from gcs.report.geojson import polygon_feature
from gcs.report.kml import KML_FOOTER, kml_header, kml_placemark

GEOJSON_NAME = "polygons.geojson"
KML_NAME = "polygons.kml"
_GEOJSON_TAIL = "\n]}\n"


class _TailFile:
    """A text file made of head + items + tail, where items are appended by rewriting the tail."""

    def __init__(self, path: Path, head: str, tail: str, separator: str, fsync: bool) -> None:
        self.path = path
        self._tail = tail.encode()
        self._separator = separator.encode()
        self._fsync = fsync
        self._count = 0
        self._file: IO[bytes] = open(path, "wb+")
        self._file.write(head.encode() + self._tail)
        self._flush()

    def append(self, item: str) -> None:
        data = (self._separator if self._count else b"") + item.encode() + self._tail
        self._file.seek(-len(self._tail), os.SEEK_END)
        self._file.write(data)
        self._file.truncate()
        self._flush()
        self._count += 1

    def close(self) -> None:
        if not self._file.closed:
            self._file.close()

    def _flush(self) -> None:
        self._file.flush()
        if self._fsync:
            os.fsync(self._file.fileno())


class PolygonLog:
    """``polygons.geojson`` (RFC 7946 FeatureCollection) and ``polygons.kml`` in ``out_dir``, appended live.

    ``start_utc`` is the wall-clock instant of flood time 0 (timestamps of the features); ``fsync=True`` makes each
    append durable against power loss at the cost of a disk sync.
    """

    def __init__(
        self,
        out_dir: str | os.PathLike[str],
        home: GeodeticHome,
        *,
        name: str = "FloodWatch caged flood polygon",
        start_utc: datetime | None = None,
        fsync: bool = False,
    ) -> None:
        self.out_dir = Path(out_dir)
        self.out_dir.mkdir(parents=True, exist_ok=True)
        self.home = home
        self.start_utc = start_utc or datetime.now(timezone.utc)
        self.count = 0
        collection_props = json.dumps({"name": name, "home": {"lat_deg": home.lat_deg, "lon_deg": home.lon_deg, "alt_m": home.alt_m}})
        self._geojson = _TailFile(
            self.out_dir / GEOJSON_NAME,
            '{"type": "FeatureCollection", "properties": ' + collection_props + ', "features": [\n',
            _GEOJSON_TAIL,
            ",\n",
            fsync,
        )
        self._kml = _TailFile(self.out_dir / KML_NAME, kml_header(name), KML_FOOTER, "", fsync)

    @property
    def geojson_path(self) -> Path:
        return self._geojson.path

    @property
    def kml_path(self) -> Path:
        return self._kml.path

    def append(self, t_s: float, ring_en_m: ArrayLike, properties: dict[str, Any] | None = None) -> bool:
        """Record one polygon sample; False (nothing written) when the ring has fewer than 3 vertices."""
        feature = polygon_feature(ring_en_m, t_s, self.home, self.start_utc, properties)
        if feature is None:
            return False
        self._geojson.append(json.dumps(feature, separators=(",", ":"), allow_nan=False))
        self._kml.append(kml_placemark(ring_en_m, t_s, self.home, self.start_utc))
        self.count += 1
        return True

    def close(self) -> None:
        self._geojson.close()
        self._kml.close()

    def __enter__(self) -> "PolygonLog":
        return self

    def __exit__(self, exc_type: type[BaseException] | None, exc: BaseException | None, tb: TracebackType | None) -> None:
        self.close()
