"""Benchmark of the live map during a real mission: page load, update latency (Zenoh sample -> browser), and the
dashboard server's CPU per connected event-stream client.

It starts ``python -m gcs.mission circle --dashboard-port 0`` (ports 27900-27970, never used by tests), waits for the
flight phase, then:

1. CPU: the dashboard process's CPU time (``/proc/<pid>/stat``) over a window with no client, then over one with
   ``--clients`` lightweight event-stream clients (raw asyncio sockets reading ``/api/stream`` in this process, whose
   CPU is not the server's); the ground station's own CPU in both windows shows whether mission control noticed;
2. page load in headless chromium: navigation to the load event, to the first frame drawn, and to 13 markers and a
   polygon on the map (``--loads`` times);
3. update latency: for every new vehicle-status report the page draws, browser clock at drawing minus the report's
   ``wall_s`` (the ground station's clock when it published it); one machine, one clock.

Usage::

    flock /tmp/fw-sockets.lock .venv/bin/python bench/dashboard_load.py --clients 20 --window-s 15
"""

from __future__ import annotations

import argparse
import asyncio
import json
import os
import re
import signal
import statistics
import subprocess
import sys
import threading
import time
import urllib.request
from pathlib import Path

REPO = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(REPO / "tests" / "gcs" / "dashboard"))
BASE_PORT = 27900
TICKS_PER_S = os.sysconf("SC_CLK_TCK")


def cpu_s(pid: int) -> float:
    fields = Path(f"/proc/{pid}/stat").read_text().rsplit(")", 1)[1].split()
    return (int(fields[11]) + int(fields[12])) / TICKS_PER_S


def state(url: str) -> dict:
    with urllib.request.urlopen(url + "api/state", timeout=5) as response:
        return json.loads(response.read())


async def stream_client(host: str, port: int, stop: asyncio.Event, counts: list[int], index: int) -> None:
    reader, writer = await asyncio.open_connection(host, port)
    writer.write(f"GET /api/stream HTTP/1.1\r\nHost: {host}\r\nAccept: text/event-stream\r\n\r\n".encode())
    await writer.drain()
    while not stop.is_set():
        try:
            chunk = await asyncio.wait_for(reader.read(65536), 0.5)
        except asyncio.TimeoutError:
            continue
        if not chunk:
            break
        counts[2 * index] += chunk.count(b"data: ")
        counts[2 * index + 1] += len(chunk)
    writer.close()


async def cpu_with_clients(url: str, pids: dict[str, int], clients: int, window_s: float) -> dict:
    host, port = re.match(r"http://([^:/]+):(\d+)/", url).groups()  # type: ignore[union-attr]
    stop = asyncio.Event()
    counts = [0] * (2 * clients)
    tasks = [asyncio.create_task(stream_client(host, int(port), stop, counts, i)) for i in range(clients)]
    await asyncio.sleep(2.0)  # connected and streaming
    frames0, bytes0 = sum(counts[0::2]), sum(counts[1::2])
    before = {name: cpu_s(pid) for name, pid in pids.items()}
    started = time.monotonic()
    await asyncio.sleep(window_s)
    elapsed = time.monotonic() - started
    after = {name: cpu_s(pid) for name, pid in pids.items()}
    frames, sent = sum(counts[0::2]) - frames0, sum(counts[1::2]) - bytes0
    stop.set()
    await asyncio.gather(*tasks, return_exceptions=True)
    result = {f"{name}_cpu_fraction": (after[name] - before[name]) / elapsed for name in pids}
    if clients:
        result["frames_per_client_per_s"] = frames / clients / elapsed
        result["kbytes_per_client_per_s"] = sent / clients / elapsed / 1024
    return result


def browser_figures(url: str, loads: int, latency_window_s: float, screenshot: Path | None) -> dict:
    import tempfile

    from test_browser_mission import start_chromium  # the tests' chromium set-up (headless, offline)

    driver = start_chromium(Path(tempfile.mkdtemp(prefix="fw-bench-")))
    try:
        load_ms, first_frame_ms, full_map_ms = [], [], []
        for _ in range(loads):
            driver.get("about:blank")
            driver.get(url)
            t0 = time.monotonic()
            while not driver.execute_script("return document.querySelectorAll('path.fw-vehicle').length === 13 "
                                            "&& window.fwDebug.polygonVertices >= 3") and time.monotonic() - t0 < 30:
                time.sleep(0.02)
            timing = driver.execute_script(
                "const n = performance.getEntriesByType('navigation')[0];"
                "return {load: n.loadEventEnd - n.startTime, first: window.fwDebug.firstFrameMs, now: performance.now()}")
            load_ms.append(timing["load"])
            first_frame_ms.append(timing["first"])
            full_map_ms.append(timing["now"])
        driver.execute_script("window.fwDebug.latencies = []")
        time.sleep(latency_window_s)
        latencies = sorted(1000 * x for x in driver.execute_script("return window.fwDebug.latencies"))
        if screenshot is not None:
            driver.save_screenshot(str(screenshot))
    finally:
        driver.quit()
    return {
        "page_load_ms_median": statistics.median(load_ms), "first_frame_ms_median": statistics.median(first_frame_ms),
        "map_complete_ms_median": statistics.median(full_map_ms), "loads": loads,
        "latency_ms_p50": latencies[len(latencies) // 2], "latency_ms_p95": latencies[int(0.95 * len(latencies))],
        "latency_ms_max": latencies[-1], "latency_samples": len(latencies),
    }


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--clients", type=int, default=20)
    parser.add_argument("--window-s", type=float, default=15.0)
    parser.add_argument("--loads", type=int, default=3)
    parser.add_argument("--out", type=Path, default=Path("/tmp/fw-bench-dashboard"))
    parser.add_argument("--screenshot", type=Path, default=None, help="save the page as PNG after the latency window")
    args = parser.parse_args()
    args.out.mkdir(parents=True, exist_ok=True)
    env = dict(os.environ, FLOODWATCH_ZENOH_ENDPOINT=f"tcp/127.0.0.1:{BASE_PORT + 60}", PYTHONUNBUFFERED="1")
    mission = subprocess.Popen(
        [sys.executable, "-m", "gcs.mission", "circle", "--duration", "400", "--no-live", "--out", str(args.out / "run"),
         "--base-port", str(BASE_PORT), "--gcs-port", str(BASE_PORT + 50), "--dashboard-port", "0"],
        cwd=REPO, env=env, text=True, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, start_new_session=True)
    lines: list[str] = []
    threading.Thread(target=lambda: lines.extend(iter(mission.stdout.readline, "")), daemon=True).start()  # type: ignore[union-attr]
    try:
        deadline = time.monotonic() + 300
        url = None
        while url is None and time.monotonic() < deadline:
            url = next((m.group(1) for m in map(re.compile(r"live map: (http://\S+)").search, lines) if m), None)
            time.sleep(0.2)
        while time.monotonic() < deadline:
            try:
                if state(url)["phase"] == "mission":
                    break
            except OSError:
                pass
            time.sleep(0.5)
        pids = json.loads((args.out / "run" / "processes.json").read_text())
        watched = {"dashboard": pids["dashboard"], "ground_station": mission.pid}
        load_before = os.getloadavg()
        idle = asyncio.run(cpu_with_clients(url, watched, 0, args.window_s))
        loaded = asyncio.run(cpu_with_clients(url, watched, args.clients, args.window_s))
        browser = browser_figures(url, args.loads, latency_window_s=10.0, screenshot=args.screenshot)
        result = {
            "clients": args.clients, "window_s": args.window_s, "idle": idle, "with_clients": loaded,
            "dashboard_cpu_fraction_per_client": (loaded["dashboard_cpu_fraction"] - idle["dashboard_cpu_fraction"])
            / max(1, args.clients),
            **browser, "loadavg_before": load_before, "loadavg_after": os.getloadavg(), "cores": os.cpu_count(),
        }
    finally:
        mission.send_signal(signal.SIGINT)
        try:
            mission.wait(timeout=60)
        except subprocess.TimeoutExpired:
            os.killpg(mission.pid, signal.SIGKILL)
    print(json.dumps(result, indent=1))
    (args.out / "result.json").write_text(json.dumps(result, indent=1))
    return 0


if __name__ == "__main__":
    sys.exit(main())
