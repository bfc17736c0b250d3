"""PVT with its default interval on every example layout and the paper's tracks, default limits.

The motions there ride their acceleration limit, where cubics through exact samples overshoot ``amax`` at any
interval; the written rows (fitted velocities, exact positions) must keep every limit, checked here from the file
alone (per-piece Hermite peaks, independent of :mod:`trajopt.io.pvt`).
"""

from __future__ import annotations

import csv
import json
from pathlib import Path

import numpy as np
import pytest

from mpa import defaults
from trajopt.cli import main

RTOL = 1e-6
FORMATS = "csv,ros2-yaml,mcap,pvt"
ROOT = Path(__file__).resolve().parents[2]
LAYOUTS = ROOT / "examples" / "tracks"

#: One query per example layout (swaps where the layout has room) and per paper track.
QUERIES = {
    "circle": ["--graph", "circle.json", "--start", "loop:0.1", "loop:0.5", "--goal", "loop:0.6", "loop:0.9"],
    "figure_eight": ["--graph", "figure_eight.json", "--start", "left:1", "right:1", "--goal", "right:3", "left:3"],
    "interval": ["--graph", "interval.json", "--start", "F", "stick:0.5", "--goal", "stick:0.4", "E"],
    "lollipop": ["--graph", "lollipop.json", "--start", "stick:0.35", "loop:0.75", "--goal", "loop:0.75", "stick:0.35"],
    "passing_loop": ["--graph", "passing_loop.json", "--start", "W", "E", "--goal", "E", "W"],
    "rail_yard": ["--graph", "rail_yard.json", "--start", "W", "E", "--goal", "E", "W"],
    "theta": ["--graph", "theta.json", "--start", "upper:1", "lower:1", "--goal", "lower:1", "upper:1"],
    "two_sidings": [
        "--graph",
        "two_sidings.json",
        *("--start", "north_end", "south_end", "--goal", "south_end", "north_end"),
    ],
    "warehouse": ["--graph", "warehouse.json", "--start", "A1_X1", "A3_X4", "--goal", "A3_X4", "A1_X1"],
    "y_junction": ["--graph", "y_junction.json", "--start", "left", "right", "--goal", "right", "left"],
    "paper_interval": ["--track", "interval", "--start", "0.2", "0.8", "--goal", "0.5", "0.9"],
    "paper_circle": ["--track", "circle", "--start", "0.1", "0.5", "--goal", "0.6", "0.9"],
    "paper_lollipop": ["--track", "lollipop", "--start", "0.35", "1.75", "--goal", "1.75", "0.35"],
}


def _argv(name: str, out: Path) -> list[str]:
    q = list(QUERIES[name])
    if q[0] == "--graph":
        q[1] = str(LAYOUTS / q[1])
    return ["trajectory", *q, "--format", FORMATS, "--out", str(out)]


def _piece_peaks(t: np.ndarray, s: np.ndarray, v: np.ndarray) -> tuple[float, float, float]:
    """Largest |v|, |a|, |j| of the Hermite cubics through rows (t, s, v) of one robot, by dense sampling."""
    h = np.diff(t)
    ds = np.diff(s)
    c2 = (3 * ds / h - 2 * v[:-1] - v[1:]) / h
    c3 = (v[:-1] + v[1:] - 2 * ds / h) / h**2
    u = np.linspace(0.0, 1.0, 201)[:, None] * h
    vel = v[:-1] + 2 * c2 * u + 3 * c3 * u**2
    acc = 2 * c2 + 6 * c3 * u
    return float(np.abs(vel).max()), float(np.abs(acc).max()), float(np.abs(6 * c3).max())


def _check_run(out: Path) -> None:
    summary = json.loads((out / "summary.json").read_text())
    assert summary["verification"]["ok"]
    assert summary["pvt"]["auto"] is True and summary["pvt"]["stretch"] == 1.0
    assert 0.001 <= summary["pvt"]["interval"] <= 0.1
    for name in ("setpoints.csv", "trajectory.yaml", "trajectory.mcap", "pvt.csv"):
        assert (out / name).stat().st_size > 0, name
    with open(out / "pvt.csv", newline="") as fh:
        rows = np.array(list(csv.reader(fh))[1:], dtype=float)
    t = rows[:, 0]
    assert t[0] == 0.0 and np.all(np.diff(t) > 0)
    assert rows[-1, 2] == 0.0 and rows[-1, 4] == 0.0
    lim = (defaults.VMAX, defaults.AMAX, defaults.JMAX)
    for cols in ((1, 2), (3, 4)):
        peaks = _piece_peaks(t, rows[:, cols[0]], rows[:, cols[1]])
        for name, val, limit in zip("vaj", peaks, lim):
            # the file's 12 significant digits perturb a piece's jerk by ~1e-12 m / h^3
            slack = 1e-9 / summary["pvt"]["interval"] ** 3 if name == "j" else 0.0
            assert val <= limit * (1 + RTOL) + slack, (out.name, cols, name, val, limit)


def test_y_swap_writes_every_format_with_defaults(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    """The issue's case: the Y-junction swap at the acceleration limit, every format, default options."""
    out = tmp_path / "y"
    assert main(_argv("y_junction", out)) == 0, capsys.readouterr().err
    _check_run(out)
    assert json.loads((out / "summary.json").read_text())["pvt"]["velocity_change"] > 0.0


@pytest.mark.slow
@pytest.mark.parametrize("name", sorted(QUERIES))
def test_default_pvt_works_on_every_example(name: str, tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    out = tmp_path / name
    assert main(_argv(name, out)) == 0, capsys.readouterr().err
    _check_run(out)
