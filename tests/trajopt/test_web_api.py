"""``mpa serve``'s JSON API (Starlette's TestClient): answers equal the command line's, errors are JSON lines."""

from __future__ import annotations

import json
import os
import signal
import socket
import subprocess
import sys
import time
import urllib.request
from pathlib import Path
from typing import Any

import numpy as np
import pytest

pytest.importorskip("starlette")
pytest.importorskip("httpx2")

from starlette.testclient import TestClient

from tests.helpers.cli import run_redirected as _cli
from trajopt.web.api import MAX_BODY_BYTES
from trajopt.web.app import create_app

ROOT = Path(__file__).resolve().parents[2]
LAYOUT = ROOT / "examples" / "tracks" / "passing_loop.json"


def _timeless(summary: dict[str, Any]) -> dict[str, Any]:
    """A summary without its wall-clock times (the only fields two identical runs may differ in)."""
    s = json.loads(json.dumps(summary))
    s.pop("timings", None)
    s.get("solver", {}).pop("jerk_time", None)
    return s


def test_plan_equals_mpa_plan_json_on_seeded_lollipop_queries(client: TestClient) -> None:
    rng = np.random.default_rng(27)
    from mpa.tracks import Lollipop

    track = Lollipop(1.2, 0.9)
    done = 0
    while done < 6:
        s, g = rng.uniform(0, track.total_length, 2), rng.uniform(0, track.total_length, 2)
        if min(track.distance(*s), track.distance(*g)) < 0.1:
            continue
        body = {"track": "lollipop", "stick": 1.2, "loop": 0.9, "clearance": 0.1}
        body |= {"start": s.tolist(), "goal": g.tolist()}
        r = client.post("/api/plan", json=body)
        argv = ["plan", "--track", "lollipop", "--stick", "1.2", "--loop", "0.9", "--clearance", "0.1", "--json"]
        argv += ["--start", *map(repr, s.tolist()), "--goal", *map(repr, g.tolist())]
        rc, out, _ = _cli(argv)
        assert (r.status_code, rc) == (200, 0), (body, r.text)
        assert r.json() == json.loads(out), body
        done += 1


@pytest.mark.parametrize(
    ("extra", "flags"),
    [({}, []), ({"objective": "shortest"}, ["--objective", "shortest"]), ({"samples": 250}, ["--samples", "250"])],
)
def test_plan_on_a_layout_equals_mpa_plan_graph_json(client: TestClient, extra: dict, flags: list[str]) -> None:
    layout = json.loads(LAYOUT.read_text())
    from mpa.graph_track import GraphTrack

    names = GraphTrack.from_layout(layout).edge_names
    start, goal = [f"{names[0]}:0.2", f"{names[-1]}:0.3"], [f"{names[-1]}:0.3", f"{names[0]}:0.2"]
    r = client.post("/api/plan", json={"layout": layout, "start": start, "goal": goal, "clearance": 0.1, **extra})
    rc, out, err = _cli(
        ["plan", "--graph", str(LAYOUT), "--start", *start, "--goal", *goal, "--clearance", "0.1", "--json", *flags]
    )
    assert rc == 0, err
    assert r.status_code == 200, r.text
    assert r.json() == json.loads(out)


def test_plan_graph_planner_on_a_paper_track_equals_the_cli(client: TestClient) -> None:
    body = {"track": "lollipop", "start": [0.2, 0.5], "goal": [0.5, 0.2], "planner": "graph"}
    r = client.post("/api/plan", json=body)
    argv = ["plan", "--track", "lollipop", "--start", "0.2", "0.5", "--goal", "0.5", "0.2", "--json"]
    rc, out, _ = _cli([*argv, "--planner", "graph"])
    assert (r.status_code, rc) == (200, 0)
    assert r.json() == json.loads(out)
    assert r.json()["planner"] == "graph"


def test_trajectory_equals_mpa_trajectory_files(client: TestClient, tmp_path: Path) -> None:
    body = {"track": "lollipop", "start": [0.2, 0.5], "goal": [0.5, 0.2], "clearance": 0.1}
    body |= {"vmax": 0.8, "amax": 1.5, "jmax": 9.0, "rate": 50.0}
    r = client.post("/api/trajectory", json=body)
    assert r.status_code == 200, r.text
    got = r.json()
    assert set(got) == {"summary", "csv"}
    argv = ["trajectory", "--track", "lollipop", "--start", "0.2", "0.5", "--goal", "0.5", "0.2", "--clearance", "0.1"]
    argv += ["--vmax", "0.8", "--amax", "1.5", "--jmax", "9", "--rate", "50", "--out", str(tmp_path)]
    rc, _, err = _cli(argv)
    assert rc == 0, err
    assert got["csv"] == (tmp_path / "setpoints.csv").read_text()
    assert _timeless(got["summary"]) == _timeless(json.loads((tmp_path / "summary.json").read_text()))
    assert got["summary"]["rate"] == 50.0 and got["summary"]["limits"]["vmax"] == [0.8, 0.8]


def test_trajectory_on_a_layout_with_ros2_yaml_equals_the_cli(client: TestClient, tmp_path: Path) -> None:
    layout = json.loads(LAYOUT.read_text())
    from mpa.graph_track import GraphTrack

    names = GraphTrack.from_layout(layout).edge_names
    start, goal = [f"{names[0]}:0.2", f"{names[-1]}:0.3"], [f"{names[-1]}:0.3", f"{names[0]}:0.2"]
    body = {"layout": layout, "start": start, "goal": goal, "formats": ["csv", "ros2-yaml"]}
    r = client.post("/api/trajectory", json=body)
    assert r.status_code == 200, r.text
    argv = ["trajectory", "--graph", str(LAYOUT), "--start", *start, "--goal", *goal, "--format", "csv,ros2-yaml"]
    rc, _, err = _cli([*argv, "--out", str(tmp_path)])
    assert rc == 0, err
    got = r.json()
    assert got["csv"] == (tmp_path / "setpoints.csv").read_text()
    assert got["ros2_yaml"] == (tmp_path / "trajectory.yaml").read_text()
    assert _timeless(got["summary"]) == _timeless(json.loads((tmp_path / "summary.json").read_text()))


@pytest.mark.parametrize(
    ("body", "cli"),
    [
        (
            {"track": "lollipop", "start": [0.2, 0.25], "goal": [0.5, 0.2], "clearance": 0.1},
            ["--track", "lollipop", "--start", "0.2", "0.25", "--goal", "0.5", "0.2", "--clearance", "0.1"],
        ),
        (
            {"track": "circle", "loop": -1, "start": [0.2, 0.5], "goal": [0.5, 0.2]},
            ["--track", "circle", "--loop", "-1", "--start", "0.2", "0.5", "--goal", "0.5", "0.2"],
        ),
        (
            {"track": "lollipop", "start": [0.2, 0.5], "goal": [0.5, 7.0]},
            ["--track", "lollipop", "--start", "0.2", "0.5", "--goal", "0.5", "7"],
        ),
    ],
)
def test_bad_input_is_400_with_the_cli_message(client: TestClient, body: dict, cli: list[str]) -> None:
    r = client.post("/api/plan", json=body)
    rc, _, err = _cli(["plan", *cli])
    assert (r.status_code, rc) == (400, 2), r.text
    assert set(r.json()) == {"error"}
    assert err == f"error: {r.json()['error']}\n"


def test_no_motion_is_422_with_the_cli_reason(client: TestClient) -> None:
    body = {"track": "interval", "start": [0.2, 0.5], "goal": [0.5, 0.2]}
    r = client.post("/api/plan", json=body)
    rc, _, err = _cli(["plan", "--track", "interval", "--start", "0.2", "0.5", "--goal", "0.5", "0.2"])
    assert (r.status_code, rc) == (422, 3)
    assert err == f"no motion: {r.json()['no_motion']}\n"
    t = client.post("/api/trajectory", json=body)
    assert t.status_code == 422 and set(t.json()) == {"no_motion"}


@pytest.mark.parametrize(
    "raw",
    [
        b"",
        b"{",
        b"[1, 2]",
        b'"lollipop"',
        b"\xff\xfe",
        b'{"track": "lollipop"}',
        b'{"track": "lollipop", "start": [0.2], "goal": [0.5, 0.2]}',
        b'{"track": "lollipop", "start": [0.2, "x"], "goal": [0.5, 0.2]}',
        b'{"track": "lollipop", "start": [0.2, 0.5], "goal": [0.5, 0.2], "clearance": "big"}',
        b'{"track": "lollipop", "start": [0.2, 0.5], "goal": [0.5, 0.2], "clearance": NaN}',
        b'{"track": "square", "start": [0.2, 0.5], "goal": [0.5, 0.2]}',
        b'{"track": "lollipop", "layout": {"edges": [["A", "B", 1]]}, "start": [0.2, 0.5], "goal": [0.5, 0.2]}',
        b'{"layout": "examples/tracks/theta.json", "start": ["a:0", "b:0"], "goal": ["a:0", "b:0"]}',
        b'{"layout": {"edges": [["A", "B", -1]]}, "start": ["e0:0", "e0:1"], "goal": ["e0:0", "e0:1"]}',
        b'{"layout": {"edges": [["A", "B", 1]]}, "start": ["e0:0", "nowhere"], "goal": ["e0:0", "e0:1"]}',
        b'{"track": "lollipop", "start": [0.2, 0.5], "goal": [0.5, 0.2], "planner": "magic"}',
        b'{"track": "lollipop", "start": [0.2, 0.5], "goal": [0.5, 0.2], "objective": "cheapest"}',
        b'{"track": "lollipop", "start": [0.2, 0.5], "goal": [0.5, 0.2], "samples": 1}',
        b'{"track": "lollipop", "start": [0.2, 0.5], "goal": [0.5, 0.2], "surprise": 1}',
    ],
)
def test_malformed_requests_are_400_json_lines(client: TestClient, raw: bytes) -> None:
    for route in ("/api/plan", "/api/trajectory", "/api/track"):
        r = client.post(route, content=raw)
        if route == "/api/track" and r.status_code == 200:
            continue  # the track alone may be fine
        assert r.status_code == 400, (route, raw, r.text)
        body = r.json()
        assert set(body) == {"error"} and "\n" not in body["error"] and "Traceback" not in body["error"]


@pytest.mark.parametrize(
    "body",
    [
        {"track": "lollipop", "start": [0.2, 0.5], "goal": [0.5, 0.2], "vmax": -1},
        {"track": "lollipop", "start": [0.2, 0.5], "goal": [0.5, 0.2], "rate": 0},
        {"track": "lollipop", "start": [0.2, 0.5], "goal": [0.5, 0.2], "jmax": True},
        {"track": "lollipop", "start": [0.2, 0.5], "goal": [0.5, 0.2], "formats": ["mcap"]},
        {"track": "lollipop", "start": [0.2, 0.5], "goal": [0.5, 0.2], "formats": "xml"},
    ],
)
def test_bad_trajectory_options_are_400(client: TestClient, body: dict) -> None:
    r = client.post("/api/trajectory", json=body)
    assert r.status_code == 400, r.text
    assert set(r.json()) == {"error"}


def test_body_limit_is_413(client: TestClient) -> None:
    small = TestClient(create_app(max_body_bytes=1000))
    body = {"track": "lollipop", "start": [0.2, 0.5], "goal": [0.5, 0.2], "samples": 400}
    assert small.post("/api/plan", json=body).status_code == 200
    big = json.dumps({**body, "layout_note": "x" * 2000}).encode()
    r = small.post("/api/plan", content=big)
    assert r.status_code == 413 and "1000 bytes" in r.json()["error"]
    r = client.post("/api/plan", content=b" " * (MAX_BODY_BYTES + 1))
    assert r.status_code == 413


def test_page_and_static_files_are_served(client: TestClient) -> None:
    r = client.get("/")
    assert r.status_code == 200 and "text/html" in r.headers["content-type"]
    for src in ("/static/app.js", "/static/style.css"):
        assert src in r.text
        assert client.get(src).status_code == 200
    assert "http://" not in r.text and "https://" not in r.text  # no CDN: works offline
    cfg = client.get("/api/config").json()
    assert cfg["initial"]["track"] == "lollipop" and "passing_loop" in cfg["examples"]
    assert client.get("/api/examples/passing_loop").json() == json.loads(LAYOUT.read_text())
    assert client.get("/api/examples/..%2Fpyproject").status_code == 404


def test_track_drawing_is_to_scale(client: TestClient) -> None:
    t = client.post("/api/track", json={"track": "lollipop", "stick": 1.5, "loop": 2.0}).json()
    for e in t["edges"]:
        pts = np.asarray(e["points"])
        drawn = np.sum(np.hypot(*np.diff(pts[:, 1:], axis=0).T))
        assert drawn == pytest.approx(e["length"], rel=1e-3), e["name"]
        assert pts[-1, 0] == pytest.approx(e["length"])
    assert {e["name"]: e["p0"] for e in t["edges"]} == {"stick": 0.0, "loop": 1.5}


def test_cspace_domains_equal_the_planner_on_seeded_cells(client: TestClient) -> None:
    from mpa import plan
    from mpa.tracks import Lollipop

    body = {"track": "lollipop", "start": [0.2, 0.5], "goal": [1.25, 1.75], "clearance": 0.1, "cells": 60}
    r = client.post("/api/cspace", json=body)
    assert r.status_code == 200, r.text
    c = r.json()
    dom = np.asarray(c["domain"])
    assert dom.shape == (60, 60) and c["no_motion"] is None
    track = Lollipop(1.0, 1.0)
    centres = (np.arange(60) + 0.5) * 2.0 / 60
    rng = np.random.default_rng(7)
    free = np.argwhere(dom > 0)
    assert len(free) > 0 and (dom[np.argwhere(dom == 0)[:, 0], np.argwhere(dom == 0)[:, 1]] == 0).all()
    for i, j in free[rng.choice(len(free), 25, replace=False)]:
        want = plan(track, (centres[j], centres[i]), (1.25, 1.75), clearance=0.1).domain
        assert dom[i, j] == want, (centres[j], centres[i])
    for i, j in np.argwhere(dom == 0)[:10]:
        assert track.distance(centres[j], centres[i]) < 0.1
    assert {s["edge"] for s in c["skeleton"]} >= {"I1", "S2a", "I2"}
    assert client.post("/api/cspace", json={**body, "cells": 5000}).status_code == 400
    lay = {"layout": {"edges": [["A", "B", 1]]}, "start": ["e0:0", "e0:1"], "goal": ["e0:0", "e0:1"]}
    assert client.post("/api/cspace", json=lay).status_code == 400


def test_serve_without_the_extra_names_it(monkeypatch: pytest.MonkeyPatch) -> None:
    import importlib.util

    import trajopt.cli.serve as serve

    real = importlib.util.find_spec
    monkeypatch.setattr(serve.importlib.util, "find_spec", lambda n, *a: None if n == "uvicorn" else real(n, *a))
    rc, out, err = _cli(["serve", "--no-browser", "--port", "0"])
    assert rc == 2 and out == ""
    assert err.count("\n") == 1 and err.startswith("error: ") and "pip install 'lollipop-mpa[serve]'" in err


def test_serve_bad_graph_and_busy_port_are_exit_2(tmp_path: Path) -> None:
    rc, _, err = _cli(["serve", "--no-browser", "--graph", str(tmp_path / "missing.json")])
    assert rc == 2 and err.startswith("error: ") and err.count("\n") == 1
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        s.listen(1)
        port = s.getsockname()[1]
        rc, _, err = _cli(["serve", "--no-browser", "--port", str(port)])
    assert rc == 2 and err.startswith(f"error: --port {port}: cannot listen") and err.count("\n") == 1


def test_serve_prints_the_address_answers_and_stops_on_ctrl_c() -> None:
    env = {**os.environ, "PYTHONPATH": str(ROOT)}
    cmd = [sys.executable, "-m", "trajopt.cli", "serve", "--port", "0", "--no-browser", "--track", "circle"]
    with subprocess.Popen(cmd, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True, env=env, cwd=ROOT) as proc:
        rc, err = _serve_session(proc)
    assert rc == 130 and err == "interrupted\n"


def _serve_session(proc: subprocess.Popen) -> tuple[int, str]:
    """Ask the server started by ``proc`` for its config and a plan, then press Ctrl-C; its exit status and stderr."""
    try:
        assert proc.stdout is not None
        line = proc.stdout.readline()
        assert line.startswith("mpa serve: http://127.0.0.1:"), line
        url = line.split()[2]
        cfg: dict[str, Any] = {}
        for _ in range(100):
            try:
                with urllib.request.urlopen(url + "api/config", timeout=2) as resp:
                    cfg = json.loads(resp.read())
                break
            except OSError:
                time.sleep(0.1)
        assert cfg["initial"] == {"track": "circle", "loop": 1.0}
        data = json.dumps({"track": "circle", "start": [0.1, 0.6], "goal": [0.3, 0.8]}).encode()
        req = urllib.request.Request(url + "api/plan", data=data, method="POST")
        with urllib.request.urlopen(req, timeout=10) as resp:
            assert resp.status == 200 and json.loads(resp.read())["domain"] == 2
        proc.send_signal(signal.SIGINT)
        rc = proc.wait(timeout=20)
        err = proc.stderr.read() if proc.stderr else ""
    finally:
        if proc.poll() is None:
            proc.kill()
    return rc, err


def test_serve_with_a_layout_opens_on_it(tmp_path: Path) -> None:
    import argparse

    from trajopt.cli.serve import _initial

    args = argparse.Namespace(graph=str(LAYOUT), track=None, stick=None, loop=None)
    initial = _initial(args)
    assert initial["name"] == "passing_loop"
    cfg = TestClient(create_app(initial)).get("/api/config").json()
    assert cfg["initial"]["layout"] == initial["layout"]
    t = TestClient(create_app(initial)).post("/api/track", json={"layout": initial["layout"]}).json()
    assert t["kind"] == "graph" and {e["name"] for e in t["edges"]} == {"west", "main", "siding", "east"}
    rc, _, err = _cli(["serve", "--no-browser", "--graph", str(LAYOUT), "--track", "lollipop"])
    assert rc == 2 and err.startswith("error: both --track lollipop and --graph")


def test_unknown_routes_and_methods_are_json_errors(client: TestClient) -> None:
    r = client.get("/api/plan")
    assert r.status_code == 405 and set(r.json()) == {"error"}
    r = client.post("/api/nothing", json={})
    assert r.status_code == 404 and "/api/nothing" in r.json()["error"]


def test_no_browser_is_one_line_on_stdout(monkeypatch: pytest.MonkeyPatch, capsys: pytest.CaptureFixture) -> None:
    import webbrowser

    import trajopt.cli.serve as serve

    def fail(url: str) -> bool:
        raise webbrowser.Error("could not locate runnable browser")

    monkeypatch.setattr(serve.webbrowser, "open", fail)
    serve._open_browser("http://127.0.0.1:1/")
    out, err = capsys.readouterr()
    assert out == "mpa serve: no browser to open here, open http://127.0.0.1:1/ yourself\n" and err == ""
    monkeypatch.setattr(serve.webbrowser, "open", lambda url: True)
    serve._open_browser("http://127.0.0.1:1/")
    assert capsys.readouterr() == ("", "")
