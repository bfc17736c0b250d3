"""The web API with footprints: ``"footprint"`` on /api/plan and /api/trajectory answers as ``--footprint`` does."""

from __future__ import annotations

import json
from pathlib import Path
from typing import Any

import pytest

pytest.importorskip("starlette")
pytest.importorskip("httpx")

from starlette.testclient import TestClient

from tests.trajopt.test_web_api import _cli, _timeless

ROOT = Path(__file__).resolve().parents[2]
YARD = ROOT / "examples" / "tracks" / "rail_yard.json"
LOOP = ROOT / "examples" / "tracks" / "passing_loop.json"


@pytest.mark.parametrize("spec", ["0.3", "2.0x0.8", "0.3,2x0.8"])
def test_plan_with_a_footprint_equals_mpa_plan_json(client: TestClient, spec: str) -> None:
    layout = json.loads(YARD.read_text())
    start, goal = ["W", "E"], ["E", "W"]
    body = {"layout": layout, "start": start, "goal": goal, "clearance": 2.5, "footprint": spec}
    r = client.post("/api/plan", json=body)
    argv = ["plan", "--graph", str(YARD), "--start", *start, "--goal", *goal, "--clearance", "2.5", "--json"]
    rc, out, err = _cli([*argv, "--footprint", spec])
    assert (r.status_code, rc) == (200, 0), (r.text, err)
    assert r.json() == json.loads(out)


def test_plan_with_a_footprint_on_a_paper_track_equals_the_cli(client: TestClient) -> None:
    body = {"track": "lollipop", "start": [0.1, 0.6], "goal": [0.6, 0.1], "clearance": 0.1, "footprint": "0.04"}
    r = client.post("/api/plan", json=body)
    argv = ["plan", "--track", "lollipop", "--start", "0.1", "0.6", "--goal", "0.6", "0.1", "--clearance", "0.1"]
    rc, out, err = _cli([*argv, "--json", "--footprint", "0.04"])
    assert (r.status_code, rc) == (200, 0), (r.text, err)
    assert r.json() == json.loads(out)
    assert r.json()["planner"] == "graph"


def test_wide_bodies_cannot_pass_is_422_with_the_cli_reason(client: TestClient) -> None:
    layout = json.loads(LOOP.read_text())
    body = {"layout": layout, "start": ["W", "E"], "goal": ["E", "W"], "clearance": 1.5, "footprint": "0.65"}
    r = client.post("/api/plan", json=body)
    rc, _, err = _cli(["plan", "--graph", str(LOOP), "--start", "W", "E", "--goal", "E", "W", "--clearance", "1.5",
                       "--footprint", "0.65"])  # fmt: skip
    assert (r.status_code, rc) == (422, 3), r.text
    assert err == f"no motion: {r.json()['no_motion']}\n"
    ok = client.post("/api/plan", json=body | {"footprint": "0.55"})
    assert ok.status_code == 200, ok.text


@pytest.mark.parametrize("spec", ["2x", "-0.3", "nan", "0", "1x2x3", "a,b,c", "0.3,"])
def test_bad_footprint_specs_are_400_with_the_cli_message(client: TestClient, spec: str) -> None:
    layout = json.loads(YARD.read_text())
    body = {"layout": layout, "start": ["W", "E"], "goal": ["E", "W"], "clearance": 2.5, "footprint": spec}
    for route in ("/api/plan", "/api/trajectory"):
        r = client.post(route, json=body)
        assert r.status_code == 400 and set(r.json()) == {"error"}, (route, r.text)
    rc, _, err = _cli(["plan", "--graph", str(YARD), "--start", "W", "E", "--goal", "E", "W", "--clearance", "2.5",
                       f"--footprint={spec}"])  # fmt: skip
    assert rc == 2
    assert err == f"error: {r.json()['error']}\n"
    assert "footprint" in r.json()["error"] and repr(spec) in r.json()["error"]


@pytest.mark.parametrize("value", [0.3, ["0.3"], {"r": 0.3}, True])
def test_a_footprint_that_is_not_a_string_is_400(client: TestClient, value: Any) -> None:
    body = {"track": "lollipop", "start": [0.1, 0.6], "goal": [0.6, 0.1], "footprint": value}
    r = client.post("/api/plan", json=body)
    assert r.status_code == 400, r.text
    assert r.json()["error"].startswith(f"footprint is {value!r}, expected a spec string")


def test_a_footprint_on_a_layout_without_coordinates_is_400(client: TestClient) -> None:
    layout = {"vertices": {"A": None, "B": None}, "edges": [{"name": "e", "from": "A", "to": "B", "length": 10.0}]}
    body = {"layout": layout, "start": ["e:1", "e:5"], "goal": ["e:2", "e:8"], "footprint": "0.3"}
    r = client.post("/api/plan", json=body)
    assert r.status_code == 400, r.text
    assert "coordinates" in r.json()["error"]


def test_bodies_overlapping_at_the_start_are_400(client: TestClient) -> None:
    layout = json.loads(YARD.read_text())
    body = {"layout": layout, "start": ["main:5", "siding:5"], "goal": ["W", "E"], "clearance": 0.1}
    r = client.post("/api/plan", json=body | {"footprint": "2.0x3.0"})
    assert r.status_code == 400, r.text
    assert "overlapping" in r.json()["error"]


def test_trajectory_with_a_footprint_equals_mpa_trajectory_files(client: TestClient, tmp_path: Path) -> None:
    layout = json.loads(YARD.read_text())
    start, goal = ["west:1", "east:5"], ["west:4", "spur:3"]
    body = {"layout": layout, "start": start, "goal": goal, "clearance": 1.0, "footprint": "2.0x0.8,0.5"}
    body |= {"vmax": 1.0, "amax": 1.0, "jmax": 5.0, "rate": 20.0}
    r = client.post("/api/trajectory", json=body)
    assert r.status_code == 200, r.text
    argv = ["trajectory", "--graph", str(YARD), "--start", *start, "--goal", *goal, "--clearance", "1"]
    argv += ["--vmax", "1", "--amax", "1", "--jmax", "5", "--rate", "20", "--footprint", "2.0x0.8,0.5"]
    rc, _, err = _cli([*argv, "--out", str(tmp_path)])
    assert rc == 0, err
    got = r.json()
    assert got["csv"] == (tmp_path / "setpoints.csv").read_text()
    assert got["csv"].splitlines()[0].endswith(",a_heading,b_heading")
    summary = _timeless(got["summary"])
    assert summary == _timeless(json.loads((tmp_path / "summary.json").read_text()))
    assert summary["footprint"]["spec"] == "2x0.8,0.5"
    assert summary["min_gap_plane"] > 0.0
