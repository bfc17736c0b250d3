"""``mpa serve``'s page in a real browser: headless Chromium (Debian's) driven by playwright.

The server runs as ``mpa serve --port 0 --no-browser`` in a subprocess; the page is read through the state it
exposes as ``window.mpa`` and through what it shows. Skipped when playwright or Chromium is missing (``.ci/run``
installs Chromium: ``apt-get install chromium``).
"""

from __future__ import annotations

import contextlib
import io
import json
import os
import shutil
import signal
import statistics
import subprocess
import sys
import urllib.request
from collections.abc import Iterator
from pathlib import Path
from typing import Any

import numpy as np
import pytest

sync_api = pytest.importorskip("playwright.sync_api")
pytest.importorskip("starlette")
pytest.importorskip("uvicorn")

ROOT = Path(__file__).resolve().parents[2]
CHROMIUM = os.environ.get("MPA_CHROMIUM") or shutil.which("chromium") or shutil.which("chromium-browser")
if CHROMIUM is None:
    pytest.skip("no Chromium (apt-get install chromium)", allow_module_level=True)


@pytest.fixture(scope="module")
def server() -> Iterator[str]:
    env = {**os.environ, "PYTHONPATH": str(ROOT)}
    cmd = [sys.executable, "-m", "trajopt.cli", "serve", "--port", "0", "--no-browser"]
    with subprocess.Popen(cmd, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True, env=env, cwd=ROOT) as proc:
        try:
            assert proc.stdout is not None
            line = proc.stdout.readline()
            assert line.startswith("mpa serve: http://"), line
            yield line.split()[2]
        finally:
            proc.send_signal(signal.SIGINT)
            try:
                proc.wait(timeout=20)
            except subprocess.TimeoutExpired:
                proc.kill()


@pytest.fixture(scope="module")
def browser() -> Iterator[Any]:
    with sync_api.sync_playwright() as p:
        b = p.chromium.launch(executable_path=CHROMIUM, headless=True)
        try:
            yield b
        finally:
            b.close()


@pytest.fixture
def page(browser: Any, server: str) -> Iterator[Any]:
    pg = browser.new_page(viewport={"width": 1500, "height": 1100}, accept_downloads=True)
    errors: list[str] = []
    pg.on("console", lambda m: errors.append(m.text) if m.type == "error" else None)
    pg.on("pageerror", lambda e: errors.append(str(e)))
    pg.goto(server)
    pg.wait_for_function("window.mpa && window.mpa.ready && window.mpa.plan !== null")
    pg.errors = errors
    yield pg
    pg.close()
    # a query closer than the clearance or without a motion is answered 400/422 on purpose (the page shows the
    # reason); Chromium logs every such answer as a failed resource: not an error of the page
    answered = ("status of 400 (Bad Request)", "status of 422 (Unprocessable")
    assert [e for e in errors if not any(a in e for a in answered)] == [], errors


def _settle(pg: Any) -> None:
    """Wait until the page has no plan request in flight or pending."""
    pg.wait_for_function("!window.mpa.inflight && !window.mpa.pending")


def _post(server: str, path: str, body: dict[str, Any]) -> tuple[int, dict[str, Any]]:
    req = urllib.request.Request(server + path.lstrip("/"), data=json.dumps(body).encode(), method="POST")
    try:
        with urllib.request.urlopen(req, timeout=30) as r:
            return r.status, json.loads(r.read())
    except urllib.error.HTTPError as e:
        return e.code, json.loads(e.read())


def _drag(pg: Any, key: str, to: tuple[float, float], steps: int = 12) -> None:
    x0, y0 = pg.evaluate(f"window.mpa.markerScreen('{key}')")
    pg.mouse.move(x0, y0)
    pg.mouse.down()
    pg.mouse.move(to[0], to[1], steps=steps)
    pg.mouse.up()
    _settle(pg)


def test_page_loads_without_console_errors_and_shows_the_plan(page: Any, server: str) -> None:
    assert page.title().startswith("mpa explorer")
    _settle(page)
    body = page.evaluate("window.mpa.query()")
    assert body["track"] == "lollipop" and body["start"] == [0.2, 0.5] and body["goal"] == [0.5, 0.2]
    status, want = _post(server, "/api/plan", body)
    assert status == 200
    assert page.text_content("#domain") == str(want["domain"])
    assert page.text_content("#word") == " ".join(want["word"])
    page.wait_for_function("window.mpa.cspace !== null")
    # the makespan shown is the verified trajectory's (asked for once the answer settles)
    page.wait_for_function("document.getElementById('makespan').textContent.includes('verified')")
    status, traj = _post(server, "/api/trajectory", body)
    assert status == 200
    assert page.text_content("#makespan").startswith(f"{traj['summary']['makespan']:.3f} s")
    assert page.errors == []


def test_dragging_a_marker_changes_the_answer_and_matches_the_api(page: Any, server: str) -> None:
    _settle(page)
    before = page.text_content("#query")
    n0 = page.evaluate("window.mpa.latencies.length")
    _drag(page, "a_goal", page.evaluate("window.mpa.screenOf(1.3, 'a_goal')"))
    body = page.evaluate("window.mpa.query()")
    assert abs(body["goal"][0] - 1.3) < 0.02 and body["start"] == [0.2, 0.5], body
    _drag(page, "a_start", page.evaluate("window.mpa.screenOf(0.35)"))
    body = page.evaluate("window.mpa.query()")
    assert abs(body["start"][0] - 0.35) < 0.02 and abs(body["goal"][0] - 1.3) < 0.02, body
    assert page.text_content("#query") != before
    status, want = _post(server, "/api/plan", body)
    assert status == 200 and page.evaluate("window.mpa.plan") == want
    assert page.text_content("#domain") == str(want["domain"])
    assert page.text_content("#rule") == want["rule"]
    assert page.evaluate("window.mpa.latencies.length") > n0 + 1  # answered while dragging, not only at the end
    lat = page.evaluate("window.mpa.latencies")[1:]
    print(f"\nplan latency in the browser: median {statistics.median(lat):.1f} ms over {len(lat)} requests")


def _boundary_target() -> tuple[float, int]:
    """A position of B's start on the loop where the query from A = 0.2 to the goal (0.5, 0.2) leaves domain 1,
    with the same domain 0.03 m either side (so a pixel of rounding does not matter)."""
    from mpa import plan
    from mpa.tracks import Lollipop

    track = Lollipop(1.0, 1.0)

    def dom(b: float) -> int:
        return plan(track, (0.2, b), (0.5, 0.2), clearance=0.05).domain

    for b in np.arange(1.1, 1.95, 0.01):
        d = dom(b)
        if d != 1 and dom(b - 0.03) == d and dom(b + 0.03) == d:
            return float(b), d
    raise AssertionError("no domain boundary along B's start on the loop")


def test_crossing_a_domain_boundary_on_the_lollipop_changes_the_domain_shown(page: Any, server: str) -> None:
    _settle(page)
    assert page.text_content("#domain") == "1"
    b, d = _boundary_target()
    _drag(page, "b_start", page.evaluate(f"window.mpa.screenOf({b})"), steps=20)
    body = page.evaluate("window.mpa.query()")
    assert abs(body["start"][1] - b) < 0.02, body
    assert page.text_content("#domain") == str(d)
    status, want = _post(server, "/api/plan", body)
    assert status == 200 and want["domain"] == d


def test_trajectory_animation_plays_and_the_downloaded_csv_equals_mpa_trajectory(page: Any, tmp_path: Path) -> None:
    from trajopt.cli.main import main

    _settle(page)
    page.click("#trajectory-btn")
    page.wait_for_function("window.mpa.traj !== null && window.mpa.playing")
    t0 = page.evaluate("window.mpa.animT")
    page.wait_for_timeout(600)
    t1 = page.evaluate("window.mpa.animT")
    assert t1 > t0, (t0, t1)
    assert float(page.eval_on_selector("#time", "e => e.value")) > 0
    assert page.locator("#robot-a").count() == 1 and page.locator("#robot-b").count() == 1
    body = page.evaluate("window.mpa.query()")
    with page.expect_download() as dl:
        page.click("#dl-csv")
    got = Path(dl.value.path()).read_text()
    with page.expect_download() as dl:
        page.click("#dl-yaml")
    yaml_got = Path(dl.value.path()).read_text()
    lim = {k: page.eval_on_selector(f"#{k}", "e => e.value") for k in ("vmax", "amax", "jmax", "rate")}
    argv = ["trajectory", "--track", "lollipop", "--stick", str(body["stick"]), "--loop", str(body["loop"])]
    argv += ["--start", *map(str, body["start"]), "--goal", *map(str, body["goal"])]
    argv += ["--clearance", str(body["clearance"]), "--format", "csv,ros2-yaml", "--out", str(tmp_path)]
    argv += [x for k, v in lim.items() for x in (f"--{k}", v)]
    with contextlib.redirect_stdout(io.StringIO()):
        assert main(argv) == 0
    assert got == (tmp_path / "setpoints.csv").read_text()
    assert yaml_got == (tmp_path / "trajectory.yaml").read_text()


def test_an_example_layout_shows_routes(page: Any, server: str) -> None:
    page.select_option("#track-select", "example:passing_loop")
    page.wait_for_function("window.mpa.geometry && window.mpa.geometry.kind === 'graph'")
    _settle(page)
    page.wait_for_function("window.mpa.planBody && window.mpa.planBody.layout !== undefined")
    body = page.evaluate("window.mpa.query()")
    status, want = _post(server, "/api/plan", body)
    if status == 200:
        assert page.text_content("#routes").startswith("A: ")
        assert page.evaluate("window.mpa.plan") == want
    else:
        assert page.text_content("#reason") != ""
    assert page.is_hidden("#cspace-panel")


def test_an_uploaded_layout_is_drawn_and_planned_and_a_bad_file_is_reported(page: Any, tmp_path: Path) -> None:
    layout = {
        "vertices": {"W": [0, 0], "X": [2, 0], "E": [4, 0]},
        "edges": [
            {"name": "west", "from": "W", "to": "X", "length": 2.0},
            {"name": "east", "from": "X", "to": "E", "length": 2.0},
        ],
    }
    path = tmp_path / "line.json"
    path.write_text(json.dumps(layout))
    page.set_input_files("#upload", str(path))
    page.wait_for_function("window.mpa.geometry && window.mpa.geometry.kind === 'graph'")
    page.wait_for_function("window.mpa.planBody && window.mpa.planBody.layout !== undefined")
    _settle(page)
    assert [e["name"] for e in page.evaluate("window.mpa.geometry.edges")] == ["west", "east"]
    body = page.evaluate("window.mpa.query()")
    assert body["start"] == ["west:0.4000", "east:1.2000"], body
    # on a path graph the robots cannot swap: the page shows the reason
    assert page.text_content("#reason").startswith("no motion: ")
    bad = tmp_path / "bad.json"
    bad.write_text('{"edges": [["A", "B", -1]]}')
    page.set_input_files("#upload", str(bad))
    page.wait_for_function("document.getElementById('reason').textContent.includes('length')")
    assert page.text_content("#reason").startswith("error: ")


def test_clicking_the_configuration_space_sets_the_start(page: Any, server: str) -> None:
    _settle(page)
    page.wait_for_function("window.mpa.cspace !== null")
    box = page.locator("#cspace").bounding_box()
    a, b = 0.3, 1.6  # the paper's lollipop: both axes over [0, 2)
    page.mouse.click(box["x"] + box["width"] * a / 2.0, box["y"] + box["height"] * (1 - b / 2.0))
    _settle(page)
    body = page.evaluate("window.mpa.query()")
    assert abs(body["start"][0] - a) < 0.01 and abs(body["start"][1] - b) < 0.01, body
    status, want = _post(server, "/api/plan", body)
    assert status == 200 and page.text_content("#domain") == str(want["domain"])


@pytest.mark.parametrize(("track", "domain"), [("circle", "2"), ("interval", "1")])
def test_the_other_paper_tracks(page: Any, server: str, track: str, domain: str) -> None:
    page.select_option("#track-select", f"paper:{track}")
    page.wait_for_function(f"window.mpa.geometry && window.mpa.geometry.kind === '{track}'")
    page.wait_for_function(f"window.mpa.planBody && window.mpa.planBody.track === '{track}'")
    _settle(page)
    page.wait_for_function("window.mpa.cspace !== null")
    body = page.evaluate("window.mpa.query()")
    status, want = _post(server, "/api/plan", body)
    assert status == 200 and str(want["domain"]) == domain
    assert page.text_content("#domain") == domain
    assert page.is_visible("#cspace-panel")


def _polygon_sides(points: str) -> list[float]:
    """Side lengths (pixels) of an SVG polygon's ``points`` attribute."""
    xy = np.array([[float(v) for v in p.split(",")] for p in points.split()])
    return np.hypot(*np.diff(np.vstack([xy, xy[:1]]), axis=0).T).tolist()


def test_footprints_are_an_input_and_the_bodies_are_drawn_to_scale(page: Any, server: str) -> None:
    page.select_option("#track-select", "example:rail_yard")
    page.wait_for_function("window.mpa.geometry && window.mpa.geometry.kind === 'graph'")
    _settle(page)
    assert page.query_selector("#body-a_start") is None  # no footprint: no bodies
    page.fill("#footprint", "2.0x0.8,0.5")
    page.dispatch_event("#footprint", "change")
    page.wait_for_function("window.mpa.planBody && window.mpa.planBody.footprint === '2.0x0.8,0.5'")
    _settle(page)
    body = page.evaluate("window.mpa.query()")
    assert body["footprint"] == "2.0x0.8,0.5"
    status, want = _post(server, "/api/plan", body)
    assert status == 200, want
    assert page.evaluate("window.mpa.plan") == want
    scale = page.evaluate("window.mpa.viewScale()")  # pixels per metre
    for key in ("a_start", "a_goal"):
        sides = _polygon_sides(page.get_attribute(f"#body-{key}", "points"))
        assert np.allclose(sorted(sides), sorted([2.0 * scale, 0.8 * scale] * 2), rtol=1e-3), (key, sides, scale)
    for key in ("b_start", "b_goal"):
        r = float(page.get_attribute(f"#body-{key}", "r"))
        assert abs(r - 0.5 * scale) < 1e-3 * scale, (key, r, scale)
    # a malformed spec: the page shows the command line's message and draws no bodies
    page.fill("#footprint", "2x")
    page.dispatch_event("#footprint", "change")
    page.wait_for_function("document.getElementById('reason').textContent.startsWith('error: footprint')")
    assert page.query_selector("#body-a_start") is None
    # the trajectory's bodies move with the carts
    page.fill("#footprint", "2.0x0.8,0.5")
    page.dispatch_event("#footprint", "change")
    page.wait_for_function("window.mpa.planBody && window.mpa.planBody.footprint === '2.0x0.8,0.5'")
    _settle(page)
    page.fill("#rate", "20")
    page.click("#trajectory-btn")
    page.wait_for_function("window.mpa.traj !== null", timeout=120_000)
    page.wait_for_selector("#body-a", timeout=10_000)
    assert page.evaluate("window.mpa.traj.footprint") == "2x0.8,0.5"
    sides = _polygon_sides(page.get_attribute("#body-a", "points"))
    assert np.allclose(sorted(sides), sorted([2.0 * scale, 0.8 * scale] * 2), rtol=1e-3), sides
    assert abs(float(page.get_attribute("#body-b", "r")) - 0.5 * scale) < 1e-3 * scale
