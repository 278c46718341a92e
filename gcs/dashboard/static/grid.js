// A base map without tiles: a metric grid around the mission's home and a latitude/longitude graticule, redrawn
// on every move so that about eight lines cross the view whatever the zoom. Drawn as vectors: nothing is fetched.
"use strict";
(function () {
  const M_PER_DEG_LAT = 111320;
  const NICE = [1, 2, 5];

  function niceStep(span, lines) {
    const raw = span / lines;
    const p = Math.pow(10, Math.floor(Math.log10(raw)));
    for (const n of NICE) { if (n * p >= raw) return n * p; }
    return 10 * p;
  }

  function fmtDeg(v, step) {
    const decimals = Math.max(0, Math.ceil(-Math.log10(step)));
    return v.toFixed(decimals) + "°";
  }

  window.FwGrid = L.LayerGroup.extend({
    initialize: function (origin) {
      L.LayerGroup.prototype.initialize.call(this);
      this.origin = origin;
    },
    onAdd: function (map) {
      L.LayerGroup.prototype.onAdd.call(this, map);
      map.on("moveend zoomend", this.redraw, this);
      this.redraw();
    },
    onRemove: function (map) {
      map.off("moveend zoomend", this.redraw, this);
      L.LayerGroup.prototype.onRemove.call(this, map);
    },
    setOrigin: function (origin) { this.origin = origin; this.redraw(); },
    redraw: function () {
      const map = this._map;
      if (!map) return;
      this.clearLayers();
      const b = map.getBounds();
      const s = b.getSouth(), n = b.getNorth(), w = b.getWest(), e = b.getEast();
      // metric grid around the origin (or the view's centre before the first report)
      const o = this.origin || map.getCenter();
      const mPerDegLon = M_PER_DEG_LAT * Math.cos(o.lat * Math.PI / 180);
      const widthM = (e - w) * mPerDegLon;
      const stepM = niceStep(widthM, 8);
      const dLat = stepM / M_PER_DEG_LAT, dLon = stepM / mPerDegLon;
      const metric = { color: "#9fb3c8", weight: 1, opacity: 0.6, interactive: false, className: "fw-grid" };
      for (let k = Math.ceil((w - o.lng) / dLon); o.lng + k * dLon <= e; k++) {
        const x = o.lng + k * dLon;
        this.addLayer(L.polyline([[s, x], [n, x]], metric));
      }
      for (let k = Math.ceil((s - o.lat) / dLat); o.lat + k * dLat <= n; k++) {
        const y = o.lat + k * dLat;
        this.addLayer(L.polyline([[y, w], [y, e]], metric));
      }
      // graticule in degrees
      const stepDeg = niceStep(Math.max(e - w, n - s), 4);
      const grat = { color: "#5b7088", weight: 1, opacity: 0.8, dashArray: "4 4", interactive: false,
                     className: "fw-graticule" };
      for (let x = Math.ceil(w / stepDeg) * stepDeg; x <= e; x += stepDeg) {
        this.addLayer(L.polyline([[s, x], [n, x]], grat));
        this.addLayer(L.marker([s, x], { interactive: false, icon: L.divIcon({
          className: "fw-grid-label", html: fmtDeg(x, stepDeg), iconAnchor: [-2, 14] }) }));
      }
      for (let y = Math.ceil(s / stepDeg) * stepDeg; y <= n; y += stepDeg) {
        this.addLayer(L.polyline([[y, w], [y, e]], grat));
        this.addLayer(L.marker([y, w], { interactive: false, icon: L.divIcon({
          className: "fw-grid-label", html: fmtDeg(y, stepDeg), iconAnchor: [-2, 12] }) }));
      }
      this.stepM = stepM;
    },
  });
})();
