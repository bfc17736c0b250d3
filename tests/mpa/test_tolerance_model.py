"""One tolerance model (mpa.tolerance) for the planner and the gate, scaled with the layout; answers at thresholds."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest

from mpa import GraphTrack, tolerance
from mpa.freespace import FreeSpace
from tests.reliability.test_reliability_cli import _one_error_line as one_line
from tests.reliability.test_reliability_cli import run
from trajopt import generate_trajectory
from trajopt.generator import _decimal_at_most

ROOT = Path(__file__).resolve().parents[2]
Y = str(ROOT / "examples" / "tracks" / "y_junction.json")
Y_QUERY = ["--graph", Y, "--start", "left", "right", "--goal", "right", "left", "--amax", "2", "--jmax", "10"]
BIG_Y = {"edges": [["J", "a", 1000000], ["J", "b", 2], ["J", "c", 2]]}


@pytest.mark.parametrize("scale", [0.0, 1e-3, 1.0, 124.0, 125.0, 126.0, 1e3, 1e6, 1e9])
def test_gate_tolerance_is_at_least_eight_times_the_planners(scale: float) -> None:
    plan, gate = tolerance.membership_tol(scale), tolerance.separation_tol(scale)
    assert gate >= 8.0 * plan and gate >= 1e-9, (scale, plan, gate)
    assert plan == 1e-12 * max(1.0, scale)
    if scale <= 125.0:
        assert gate == 1e-9


def test_free_space_and_gate_use_the_layouts_scale() -> None:
    track = GraphTrack.from_layout(BIG_Y)
    fs = FreeSpace(track, 1.0)
    scale = tolerance.layout_scale(track.lengths)
    assert scale == 1000004.0 and fs.tol == tolerance.membership_tol(scale)
    tr = generate_trajectory(track, ("b", "c"), ("c", "b"), clearance=1.0)
    assert tr.verification["ok"] and tr.min_separation >= 1.0 - tolerance.separation_tol(scale)


def _names_a_clearance_that_works(q: list[str], clearance: str, rate: str, tmp_path: Path) -> None:
    """A verified motion, or one error line naming a lower clearance or a higher rate, which then works."""
    for _ in range(3):
        argv = ["trajectory", *q, "--clearance", clearance, "--rate", rate, "--out", str(tmp_path / "o")]
        code, _, err = run(argv)
        print(argv, code, err.strip())
        if code == 0:
            return
        line = one_line(err)
        assert code == 2, line
        if "works at" in line:
            lower = line.split("expected a clearance below it: ")[1].split(" m works")[0]
            assert float(lower) < float(clearance), line
            clearance = lower
        else:
            assert "lowest usable rate is" in line, line
            higher = line.split("lowest usable rate is ")[1].split(" Hz")[0]
            assert float(higher) > float(rate), line
            rate = higher
    raise AssertionError(f"no motion after following the errors: {q}")


def test_an_edge_of_1e6_m_at_the_threshold_and_below(tmp_path: Path) -> None:
    layout = tmp_path / "big.json"
    layout.write_text(json.dumps(BIG_Y))
    q = ["--graph", str(layout), "--start", "b", "c", "--goal", "c", "b"]
    for clearance in ("2.0", "1.999999", "1.0"):
        _names_a_clearance_that_works(q, clearance, "100", tmp_path)


@pytest.mark.slow
def test_issue_threshold_on_the_y_at_20_khz(tmp_path: Path) -> None:
    _names_a_clearance_that_works(Y_QUERY, "1.0", "20000", tmp_path)


@pytest.mark.slow
def test_three_arms_of_1e6_m_at_the_threshold(tmp_path: Path) -> None:
    layout = tmp_path / "big3.json"
    layout.write_text(json.dumps({"edges": [["J", "a", 1e6], ["J", "b", 1e6], ["J", "c", 1e6]]}))
    q = ["--graph", str(layout), "--start", "b", "c", "--goal", "c", "b", "--vmax", "5000", "--amax", "10000"]
    _names_a_clearance_that_works([*q, "--jmax", "50000"], "1000000", "100", tmp_path)


@pytest.mark.parametrize("x", [1.0 - 1e-9, 0.99999998, 0.9998, 1999999.9999, 0.1 + 0.2, 1e-300, 123.456])
def test_named_clearance_is_at_most_the_value_tried(x: float) -> None:
    text = _decimal_at_most(x)
    assert float(text) <= x and len(text.replace("-", "").replace(".", "").lstrip("0")) <= 17, text
    assert float(text) < 1.0 or x >= 1.0


def test_decimal_at_most_on_seeded_values() -> None:
    rng = np.random.default_rng(6)
    for x in (1.0 - 10.0 ** rng.uniform(-16, -1, 500)).tolist() + (10.0 ** rng.uniform(-5, 7, 500)).tolist():
        text = _decimal_at_most(x)
        assert float(text) <= x, (x, text)
