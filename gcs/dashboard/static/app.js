// The live page: one EventSource frame at 10-20 Hz redraws vehicles, the caged polygon, the true edge, alerts and
// events; the polygon history (slider and chart) is fetched by index once a second. Nothing leaves this server.
"use strict";
(function () {
  const STALE_S = 2.0;
  const ROLE_COLOURS = { boundary: "#1565c0", leader: "#c62828", follower: "#2e7d32" };
  const debug = window.fwDebug = { frames: 0, vehicles: 0, polygonVertices: 0, latencies: [], alerts: [],
                                   frameTimes: [], firstFrameMs: null };

  const map = L.map("map", { attributionControl: false, zoomControl: true, maxZoom: 22, zoomSnap: 0.25 })
    .setView([0, 0], 2);
  L.control.scale({ metric: true, imperial: false }).addTo(map);
  const grid = new window.FwGrid(null).addTo(map);
  const layers = {
    truth: L.polyline([], { color: "#d32f2f", weight: 2, dashArray: "6 4", interactive: false, className: "fw-truth" }),
    history: L.polygon([], { color: "#6a1b9a", weight: 2, fillOpacity: 0.15, className: "fw-polygon-history" }),
    polygon: L.polygon([], { color: "#0d47a1", weight: 2, fillColor: "#42a5f5", fillOpacity: 0.25,
                             className: "fw-polygon" }),
    footprints: L.layerGroup(), velocities: L.layerGroup(), vehicles: L.layerGroup(),
  };
  layers.footprints.addTo(map); layers.truth.addTo(map); layers.polygon.addTo(map);
  layers.history.addTo(map); layers.velocities.addTo(map); layers.vehicles.addTo(map);
  const markers = new Map();
  let centred = false, lastReportWall = null, config = { commands: false, tiles: null };
  let history = [], sliderLive = true;
  // a frame may leave out the polygon, the true edge and the events when they did not change: keep the last ones
  const kept = { polygon: null, flood_edge: null, events: [], alerts: [] };

  const $ = (id) => document.getElementById(id);
  const lonlatToLatLng = (ring) => ring.map((p) => [p[1], p[0]]);
  const fmt = (v, d) => (v === null || v === undefined || !isFinite(v)) ? "–" : Number(v).toFixed(d);

  fetch("/api/config").then((r) => r.json()).then((c) => {
    config = c;
    $("mission").textContent = c.mission;
    if (c.tiles) {
      L.tileLayer("/tiles/{z}/{x}/{y}", { minZoom: 0, maxNativeZoom: c.tiles.max_zoom, maxZoom: 22 }).addTo(map)
        .bringToBack();
    }
    $("commands").hidden = !c.commands;
    $("readonly").hidden = c.commands;
  });

  function vehicleLayers(v) {
    let m = markers.get(v.vehicle_id);
    if (!m) {
      const colour = ROLE_COLOURS[v.role] || "#555";
      m = {
        dot: L.circleMarker([0, 0], { radius: 6, color: "#fff", weight: 1.5, fillColor: colour, fillOpacity: 1,
                                      className: "fw-vehicle" }),
        foot: L.polygon([], { color: colour, weight: 1, fillOpacity: 0.06, interactive: false,
                              className: "fw-footprint" }),
        vel: L.polyline([], { color: colour, weight: 2, interactive: false, className: "fw-velocity" }),
      };
      m.dot.bindTooltip("", { direction: "top", offset: [0, -6] });
      markers.set(v.vehicle_id, m);
    }
    return m;
  }

  function drawVehicles(frame) {
    const seen = new Set();
    const rows = [];
    for (const v of frame.vehicles) {
      const age = v.state_age_s, hb = v.heartbeat_age_s;
      const stale = age === null || age > STALE_S;
      const lost = v.link === "lost" || !v.agent_alive;
      const speed = Math.hypot(v.velocity_en_mps[0], v.velocity_en_mps[1]);
      const cls = lost ? "lost" : (stale ? "stale" : "");
      rows.push(`<tr class="${cls}" data-vehicle="${v.vehicle_id}"><td>${v.vehicle_id}</td><td>${v.role}${v.group ? " " + v.group : ""}</td>` +
        `<td>${v.flight_mode || "–"}${v.armed ? "" : " (disarmed)"}${v.failsafe ? " FAILSAFE" : ""}</td>` +
        `<td class="num">${v.battery_fraction === null || v.battery_fraction === undefined ? "–" : Math.round(100 * v.battery_fraction) + "%"}</td>` +
        `<td>${v.link}${hb === null ? "" : " " + fmt(hb, 1)}</td><td>${v.agent_alive ? "up" : "GONE"}</td>` +
        `<td class="num">${fmt(speed, 1)}</td><td class="num">${fmt(age, 1)}</td></tr>`);
      if (v.lat_deg === null || v.lat_deg === undefined) continue;
      seen.add(v.vehicle_id);
      const m = vehicleLayers(v);
      const ll = [v.lat_deg, v.lon_deg];
      m.dot.setLatLng(ll);
      m.dot.setStyle({ fillOpacity: stale || lost ? 0.35 : 1, dashArray: stale ? "2 2" : null,
                       color: lost ? "#b00" : "#fff" });
      m.dot.setTooltipContent(`#${v.vehicle_id} ${v.role} · ${v.flight_mode || "?"} · batt ` +
        `${v.battery_fraction === null || v.battery_fraction === undefined ? "–" : Math.round(100 * v.battery_fraction) + "%"} · link ${v.link} · ` +
        `${fmt(speed, 1)} m/s · position ${fmt(age, 1)} s old`);
      m.foot.setLatLngs(lonlatToLatLng(v.footprint_lonlat || []));
      const k = 2.0 / 111320;  // the velocity drawn as the way covered in 2 s
      m.vel.setLatLngs([ll, [v.lat_deg + v.velocity_en_mps[1] * k,
        v.lon_deg + v.velocity_en_mps[0] * k / Math.cos(v.lat_deg * Math.PI / 180)]]);
      if (!layers.vehicles.hasLayer(m.dot)) {
        layers.vehicles.addLayer(m.dot); layers.footprints.addLayer(m.foot); layers.velocities.addLayer(m.vel);
      }
    }
    for (const [id, m] of markers) {
      if (!seen.has(id) && layers.vehicles.hasLayer(m.dot)) {
        layers.vehicles.removeLayer(m.dot); layers.footprints.removeLayer(m.foot); layers.velocities.removeLayer(m.vel);
      }
    }
    $("vehicles").tBodies[0].innerHTML = rows.join("");
    debug.vehicles = seen.size;
  }

  function drawPolygon(frame) {
    const p = kept.polygon;
    const ring = p ? p.geometry.coordinates[0] : [];
    layers.polygon.setLatLngs(lonlatToLatLng(ring.slice(0, -1)));
    layers.polygon.setStyle({ opacity: sliderLive ? 1 : 0.3, fillOpacity: sliderLive ? 0.25 : 0.05 });
    debug.polygonVertices = Math.max(0, ring.length - 1);
    if (p) {
      const pr = p.properties;
      const cls = frame.polygon_age_s > 3 ? "stale" : "";
      $("polygon-info").innerHTML = `<span class="${cls}">flood t ${fmt(pr.t_s, 1)} s · area ${fmt(pr.area_m2, 0)} m² · ` +
        `growth ${fmt(pr.growth_rate_m2_per_s, 1)} m²/s · ${debug.polygonVertices} vertices · ` +
        `${fmt(frame.polygon_age_s, 1)} s old</span>`;
    }
    const edge = kept.flood_edge;
    layers.truth.setLatLngs(edge && $("show-truth").checked ? lonlatToLatLng(edge.ring_lonlat) : []);
  }

  function drawAlerts() {
    const list = $("alerts");
    debug.alerts = kept.alerts;
    if (!kept.alerts.length) { list.innerHTML = '<li class="none">none</li>'; return; }
    list.innerHTML = kept.alerts.map((a) => `<li class="fw-alert" data-kind="${a.kind}" data-vehicle="${a.vehicle_id ?? ""}">` +
      `t=${fmt(a.t_s, 1)} s · ${escapeHtml(a.text)}</li>`).join("");
  }

  function drawEvents() {
    $("events").innerHTML = kept.events.slice().reverse().map((e) => {
      const cls = e.kind === "info" ? "" : (e.active === false ? "cleared" : "alert");
      return `<li class="${cls}" data-kind="${e.kind}">t=${fmt(e.t_s, 1)} s ${escapeHtml(e.text)}</li>`;
    }).join("");
  }

  function escapeHtml(s) {
    return String(s).replace(/[&<>"']/g, (c) => ({ "&": "&amp;", "<": "&lt;", ">": "&gt;", '"': "&quot;", "'": "&#39;" }[c]));
  }

  function drawStatus(frame) {
    const now = Date.now();
    debug.frameTimes.push(now);
    while (debug.frameTimes.length && now - debug.frameTimes[0] > 5000) debug.frameTimes.shift();
    const rate = debug.frameTimes.length > 1 ? 1000 * (debug.frameTimes.length - 1) / (now - debug.frameTimes[0]) : 0;
    const age = frame.report_age_s;
    $("status").innerHTML = `${frame.phase}${frame.operator_order ? " · OPERATOR " + frame.operator_order.toUpperCase() : ""}` +
      ` · mission ${fmt(frame.t_s, 1)} s · flood ${fmt(frame.flood_t_s, 1)} s<br>` +
      `<span class="${age === null || age > STALE_S ? "stale" : ""}">status ${fmt(age, 1)} s old</span> · ${fmt(rate, 1)} updates/s`;
  }

  function render(frame) {
    debug.frames += 1;
    if (debug.firstFrameMs === null) debug.firstFrameMs = performance.now();
    if (frame.report_wall_s !== null && frame.report_wall_s !== lastReportWall) {
      lastReportWall = frame.report_wall_s;
      debug.latencies.push(Date.now() / 1000 - frame.report_wall_s);
      if (debug.latencies.length > 2000) debug.latencies.shift();
    }
    if (frame.home) grid.origin = L.latLng(frame.home[0], frame.home[1]);
    for (const part of Object.keys(kept)) { if (part in frame) kept[part] = frame[part]; }
    drawVehicles(frame); drawPolygon(frame); drawStatus(frame);
    if ("events" in frame) { drawAlerts(); drawEvents(); }
    if (!centred && (frame.home || frame.vehicles.some((v) => v.lat_deg !== null && v.lat_deg !== undefined))) {
      const pts = frame.vehicles.filter((v) => v.lat_deg !== null && v.lat_deg !== undefined).map((v) => [v.lat_deg, v.lon_deg]);
      if (kept.flood_edge) pts.push(...lonlatToLatLng(kept.flood_edge.ring_lonlat));
      if (pts.length > 1) { map.fitBounds(L.latLngBounds(pts).pad(0.6)); centred = true; }
      else if (frame.home) map.setView(frame.home, 18);
      grid.redraw();
    }
    if (frame.polygon_count < history.length) history = [];  // a new run: start the history again
    updateSlider(frame.polygon_count);
  }

  // ---- history: slider over the polygons, area and growth rate chart
  function updateSlider(count) {
    const slider = $("slider");
    slider.max = Math.max(0, count - 1);
    if (sliderLive) { slider.value = slider.max; $("slider-label").textContent = "live"; }
  }
  $("slider").addEventListener("input", () => {
    const slider = $("slider");
    sliderLive = Number(slider.value) >= Number(slider.max);
    showHistoric();
  });
  $("live").addEventListener("click", () => { sliderLive = true; showHistoric(); });
  function showHistoric() {
    const item = sliderLive ? null : history[Number($("slider").value)];
    layers.history.setLatLngs(item ? lonlatToLatLng(item.ring.slice(0, -1)) : []);
    $("slider-label").textContent = item ? `flood t ${fmt(item.t_s, 1)} s · ${fmt(item.area_m2, 0)} m²` : "live";
    drawChart();
  }
  function pollHistory() {
    fetch(`/api/history?start=${history.length}`).then((r) => r.json()).then((h) => {
      if (h.start === history.length) history.push(...h.items);
      drawChart();
    }).catch(() => {}).finally(() => setTimeout(pollHistory, 1000));
  }
  function drawChart() {
    const c = $("chart"), ctx = c.getContext("2d");
    c.width = c.clientWidth || 800;
    ctx.clearRect(0, 0, c.width, c.height);
    if (history.length < 2) { ctx.fillStyle = "#678"; ctx.fillText("area and growth rate appear with the polygon", 8, 20); return; }
    const t0 = history[0].t_s, t1 = history[history.length - 1].t_s || 1;
    const areaMax = Math.max(...history.map((h) => h.area_m2)) || 1;
    const rates = history.map((h) => h.growth_rate_m2_per_s).filter((r) => r !== null);
    const rateMax = Math.max(1e-9, ...rates.map(Math.abs));
    const x = (t) => 40 + (c.width - 90) * (t - t0) / Math.max(1e-9, t1 - t0);
    const line = (values, scale, colour) => {
      ctx.strokeStyle = colour; ctx.beginPath(); let started = false;
      history.forEach((h, i) => { const v = values(h); if (v === null) return;
        const y = c.height - 14 - (c.height - 24) * v / scale;
        if (started) ctx.lineTo(x(h.t_s), y); else { ctx.moveTo(x(h.t_s), y); started = true; } });
      ctx.stroke();
    };
    line((h) => h.area_m2, areaMax, "#0d47a1");
    line((h) => h.growth_rate_m2_per_s === null ? null : Math.max(0, h.growth_rate_m2_per_s), rateMax, "#ef6c00");
    ctx.fillStyle = "#0d47a1"; ctx.fillText(`area ≤ ${fmt(areaMax, 0)} m²`, 4, 10);
    ctx.fillStyle = "#ef6c00"; ctx.fillText(`growth ≤ ${fmt(rateMax, 1)} m²/s`, c.width - 130, 10);
    ctx.fillStyle = "#456"; ctx.fillText(`flood t ${fmt(t0, 0)}–${fmt(t1, 0)} s`, 40, c.height - 2);
    if (!sliderLive && history[Number($("slider").value)]) {
      const xs = x(history[Number($("slider").value)].t_s);
      ctx.strokeStyle = "#6a1b9a"; ctx.beginPath(); ctx.moveTo(xs, 12); ctx.lineTo(xs, c.height - 12); ctx.stroke();
    }
  }

  // ---- operator commands (the server refuses them without the token)
  document.querySelectorAll("#commands button").forEach((b) => b.addEventListener("click", () => {
    const command = b.dataset.command;
    if (command === "land" && !window.confirm("Land every vehicle?")) return;
    fetch(`/api/command/${command}`, { method: "POST", headers: { Authorization: `Bearer ${$("token").value}` } })
      .then((r) => r.json().then((body) => { $("command-result").textContent = r.ok ? `${command}: sent` : `${command}: ${body.error}`; }))
      .catch((e) => { $("command-result").textContent = `${command}: ${e}`; });
  }));

  $("show-truth").addEventListener("change", () => { if (!$("show-truth").checked) layers.truth.setLatLngs([]); });

  const source = new EventSource("/api/stream");
  source.onmessage = (msg) => render(JSON.parse(msg.data));
  source.onerror = () => { $("status").innerHTML = '<span class="lost">connection to the server lost: retrying</span>'; };
  pollHistory();
})();
