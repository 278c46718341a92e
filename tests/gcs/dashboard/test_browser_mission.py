"""The live map in a real headless browser during a real mission (``python -m gcs.mission circle``: the mock PX4
fleet over UDP MAVLink, 13 agent processes, Zenoh, the ground station and its dashboard process).

One mission serves every test of this module, in order: the page shows the fleet and the polygon, makes no request
beyond 127.0.0.1, offers a valid GeoJSON download, refuses commands without the token, and shows an agent killed
with SIGKILL as an alert within 3 s. Ports 27800-27870 (no other test uses them)."""

from __future__ import annotations

import json
import math
import os
import re
import shutil
import signal
import subprocess
import sys
import threading
import time
import urllib.error
import urllib.parse
import urllib.request
from collections.abc import Iterator
from dataclasses import dataclass
from pathlib import Path

import pytest

CHROMIUM = shutil.which("chromium") or shutil.which("chromium-browser")
CHROMEDRIVER = shutil.which("chromedriver")
SKIP_REASON = ("needs Debian's chromium and chromium-driver (apt-get install -y chromium chromium-driver; .ci/run "
               "installs them): a browser build downloaded at run time cannot work offline")
needs_chromium = pytest.mark.skipif(CHROMIUM is None or CHROMEDRIVER is None, reason=SKIP_REASON)


def start_chromium(download_dir: Path):  # noqa: ANN201 - selenium's WebDriver, imported lazily
    """Headless chromium with the network log on (every request the page makes) and downloads into a folder."""
    from selenium import webdriver
    from selenium.webdriver.chrome.service import Service

    options = webdriver.ChromeOptions()
    options.binary_location = CHROMIUM or ""
    for arg in ("--headless=new", "--no-sandbox", "--disable-dev-shm-usage", "--disable-gpu",
                "--window-size=1400,900", "--no-first-run", "--disable-background-networking",
                "--disable-component-update", "--disable-default-apps", "--disable-sync"):
        options.add_argument(arg)
    options.set_capability("goog:loggingPrefs", {"performance": "ALL"})
    options.add_experimental_option("prefs", {"download.default_directory": str(download_dir),
                                              "download.prompt_for_download": False})
    driver = webdriver.Chrome(options=options, service=Service(executable_path=CHROMEDRIVER))
    driver.execute_cdp_cmd("Browser.setDownloadBehavior", {"behavior": "allow", "downloadPath": str(download_dir)})
    return driver


def requested_urls(driver) -> list[str]:  # noqa: ANN001
    """Every URL the page asked for since the last call (chromium's performance log, Network.requestWillBeSent)."""
    urls = []
    for entry in driver.get_log("performance"):
        message = json.loads(entry["message"])["message"]
        if message.get("method") == "Network.requestWillBeSent":
            urls.append(message["params"]["request"]["url"])
    return urls


pytestmark = [pytest.mark.integration, pytest.mark.e2e, needs_chromium]

REPO = Path(__file__).resolve().parents[3]
BASE_PORT = 27800
TOKEN = "rescue-centre-token"
FLYING_TIMEOUT_S = 300.0
SCREENSHOT_ENV = "FLOODWATCH_SCREENSHOT"
"""Set to a path to keep the screenshot there as well (docs/dashboard.png is made this way)."""


@dataclass
class Mission:
    process: subprocess.Popen[str]
    url: str
    out_dir: Path
    lines: list[str]


def _state(url: str) -> dict:
    with urllib.request.urlopen(url + "api/state", timeout=5) as response:
        return json.loads(response.read())


def _post(url: str, token: str | None) -> int:
    request = urllib.request.Request(url, method="POST", headers={"Authorization": f"Bearer {token}"} if token else {})
    try:
        with urllib.request.urlopen(request, timeout=5) as response:
            return response.status
    except urllib.error.HTTPError as error:
        return error.code


@pytest.fixture(scope="module")
def mission(tmp_path_factory: pytest.TempPathFactory) -> Iterator[Mission]:
    out_dir = tmp_path_factory.mktemp("browser_mission")
    env = dict(os.environ, FLOODWATCH_ZENOH_ENDPOINT=f"tcp/127.0.0.1:{BASE_PORT + 60}", PYTHONUNBUFFERED="1")
    process = subprocess.Popen(
        [sys.executable, "-m", "gcs.mission", "circle", "--duration", "400", "--no-live", "--out", str(out_dir),
         "--base-port", str(BASE_PORT), "--gcs-port", str(BASE_PORT + 50), "--dashboard-port", "0",
         "--dashboard-token", TOKEN],
        cwd=REPO, env=env, text=True, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, start_new_session=True)
    lines: list[str] = []
    threading.Thread(target=lambda: lines.extend(iter(process.stdout.readline, "")), daemon=True).start()  # type: ignore[union-attr]
    try:
        deadline = time.monotonic() + FLYING_TIMEOUT_S
        url = None
        while url is None and time.monotonic() < deadline and process.poll() is None:
            url = next((m.group(1) for m in map(re.compile(r"live map: (http://\S+)").search, lines) if m), None)
            time.sleep(0.2)
        assert url is not None, f"the mission printed no live map URL: {lines[-5:]}"
        phase = None
        while phase != "mission" and time.monotonic() < deadline and process.poll() is None:
            try:
                phase = _state(url)["phase"]
            except OSError:
                pass
            time.sleep(0.5)
        assert phase == "mission", f"the mission did not reach its flight phase: {lines[-5:]}"
        yield Mission(process, url, out_dir, lines)
    finally:
        if process.poll() is None:
            process.send_signal(signal.SIGINT)
            try:
                process.wait(timeout=30)
            except subprocess.TimeoutExpired:
                os.killpg(process.pid, signal.SIGKILL)
                process.wait(timeout=10)


@pytest.fixture(scope="module")
def browser(mission: Mission, tmp_path_factory: pytest.TempPathFactory) -> Iterator[tuple[object, Path]]:
    downloads = tmp_path_factory.mktemp("downloads")
    driver = start_chromium(downloads)
    try:
        yield driver, downloads
    finally:
        driver.quit()


def _wait(condition, timeout_s: float, period_s: float = 0.05):  # noqa: ANN001, ANN202
    deadline = time.monotonic() + timeout_s
    while True:
        value = condition()
        if value or time.monotonic() > deadline:
            return value
        time.sleep(period_s)


def test_the_page_shows_13_vehicles_and_the_polygon_within_15_s_and_updates_at_5_hz(
        mission: Mission, browser: tuple, tmp_path: Path) -> None:
    driver, _ = browser
    opened_s = time.monotonic()
    driver.get(mission.url)
    shown = _wait(lambda: driver.execute_script(
        "return document.querySelectorAll('path.fw-vehicle').length === 13 && window.fwDebug.polygonVertices >= 3"),
        timeout_s=15.0)
    took_s = time.monotonic() - opened_s
    debug = driver.execute_script("return {v: document.querySelectorAll('path.fw-vehicle').length, "
                                  "p: window.fwDebug.polygonVertices}")
    assert shown, f"after 15 s the page shows {debug['v']} vehicle markers and {debug['p']} polygon vertices"
    assert took_s <= 15.0
    frames_before = driver.execute_script("return window.fwDebug.frames")
    time.sleep(2.0)
    rate_hz = (driver.execute_script("return window.fwDebug.frames") - frames_before) / 2.0
    assert rate_hz >= 5.0, f"the page redrew at {rate_hz:.1f} Hz"
    shot = tmp_path / "dashboard.png"
    assert driver.save_screenshot(str(shot)) and shot.stat().st_size > 10_000
    if os.environ.get(SCREENSHOT_ENV):
        driver.save_screenshot(os.environ[SCREENSHOT_ENV])


def test_no_request_leaves_127_0_0_1(mission: Mission, browser: tuple) -> None:
    driver, _ = browser
    time.sleep(1.5)  # a history poll and the stream are in the log by now
    urls = requested_urls(driver)
    assert any(u.endswith("/static/vendor/leaflet/leaflet.js") for u in urls)
    outside = [u for u in urls if urllib.parse.urlsplit(u).scheme not in ("data", "blob")
               and urllib.parse.urlsplit(u).hostname != "127.0.0.1"]
    assert outside == []


def test_the_geojson_download_is_a_valid_rfc7946_polygon(mission: Mission, browser: tuple) -> None:
    from selenium.webdriver.common.by import By

    driver, downloads = browser
    driver.find_element(By.ID, "dl-geojson").click()
    files = _wait(lambda: [p for p in downloads.glob("*.geojson")], timeout_s=10.0, period_s=0.1)
    assert files, "no GeoJSON file was downloaded"
    feature = json.loads(files[0].read_text())
    ring = feature["geometry"]["coordinates"][0]
    assert feature["type"] == "Feature" and feature["geometry"]["type"] == "Polygon"
    assert len(ring) >= 4 and ring[0] == ring[-1]
    assert all(-180 <= lon <= 180 and -90 <= lat <= 90 and math.isfinite(lon + lat) for lon, lat in ring)
    twice_area = sum(x0 * y1 - x1 * y0 for (x0, y0), (x1, y1) in zip(ring, ring[1:]))
    assert twice_area > 0, "RFC 7946: the outer ring runs counter-clockwise"
    assert feature["properties"]["schema"] == "fw/polygon/1" and feature["properties"]["area_m2"] > 0


def test_a_command_without_the_token_is_refused_and_with_it_is_logged(mission: Mission, browser: tuple) -> None:
    from selenium.webdriver.common.by import By

    driver, _ = browser
    driver.find_element(By.CSS_SELECTOR, "#commands button[data-command='hold']").click()
    refused = _wait(lambda: "token" in driver.find_element(By.ID, "command-result").text, timeout_s=5.0)
    assert refused, driver.find_element(By.ID, "command-result").text
    endpoint = mission.url + "api/command/hold"
    assert _post(endpoint, None) == 401 and _post(endpoint, "guess") == 401
    events_log = mission.out_dir / "events.log"
    time.sleep(1.0)
    assert "operator hold" not in events_log.read_text()
    assert _post(endpoint, TOKEN) == 202
    assert _wait(lambda: "operator hold requested" in events_log.read_text(), timeout_s=5.0)
    assert _wait(lambda: _state(mission.url)["operator_order"] == "hold", timeout_s=5.0)
    assert _post(mission.url + "api/command/resume", TOKEN) == 202
    assert _wait(lambda: "operator resume requested" in events_log.read_text(), timeout_s=5.0)


def test_killing_an_agent_raises_its_alert_on_the_page_within_3_s(mission: Mission, browser: tuple) -> None:
    driver, _ = browser
    pid = json.loads((mission.out_dir / "processes.json").read_text())["agent_5"]
    os.kill(pid, signal.SIGKILL)
    killed_s = time.monotonic()
    shown = _wait(lambda: driver.execute_script(
        "return document.querySelector('li.fw-alert[data-kind=\"agent_lost\"][data-vehicle=\"5\"]') !== null"),
        timeout_s=3.0)
    took_s = time.monotonic() - killed_s
    assert shown and took_s <= 3.0, f"no agent-lost alert for vehicle 5 on the page {took_s:.1f} s after the kill"
