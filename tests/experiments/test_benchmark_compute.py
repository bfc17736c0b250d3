"""The lean OMPL pipeline of the compute comparison (issue 12, point 1) and a smoke run of ``--compute``."""

from __future__ import annotations

import sys
from pathlib import Path

import numpy as np
import pytest

from mpa import Circle, Lollipop, Track

ROOT = Path(__file__).resolve().parents[2]
sys.path.insert(0, str(ROOT / "experiments"))

from bench.compute import compare_compute  # noqa: E402  (at import: a Dask test re-imports `bench` from a zip)
from bench.geometry import leg_moves_geodesic  # noqa: E402
from bench.lean import LeanOmpl, _positions  # noqa: E402
from bench.runner import BenchConfig  # noqa: E402

from trajopt import Limits  # noqa: E402

pytest.importorskip("ompl")
pytest.importorskip("ruckig")


@pytest.mark.parametrize("track", [Lollipop(1.0, 1.0), Circle(1.0), Lollipop(0.3, 1.2)], ids=repr)
def test_lean_pipeline_setpoints_are_checked_and_reach_the_goal(track: Track) -> None:
    lim, D = Limits(0.5, 1.0, 5.0), 0.05
    lean = LeanOmpl(track, D, D + 1e-4, lim, 100.0)
    rng = np.random.default_rng(1)
    done = 0
    try:
        while done < 6:
            s, g = rng.uniform(0, track.total_length, 2), rng.uniform(0, track.total_length, 2)
            if track.distance(*s) < D + 0.01 or track.distance(*g) < D + 0.01:
                continue
            r = lean.solve(s, g)
            assert r.success and r.verified, r.error
            assert np.max(track.distance(r.q[0], s)) < 1e-9 and np.max(track.distance(r.q[-1], g)) < 1e-9
            assert np.all(track.distance(r.q[:, 0], r.q[:, 1]) >= D)
            step = track.distance(r.q[1:], r.q[:-1])
            assert np.all(step <= 0.5 / 100.0 * (1 + 1e-6))  # vmax respected between rows
            assert np.all(np.diff(r.t) > 0) and r.t[-1] == pytest.approx(r.makespan)
            done += 1
    finally:
        lean.close()


def test_positions_follow_the_geodesic_through_p_and_the_seam() -> None:
    tr = Lollipop(1.0, 1.0)
    moves = leg_moves_geodesic(tr, 0.8, 1.9)  # up the stick to P, then clockwise through the seam
    x = np.linspace(0.0, 0.3, 31)
    p = _positions(tr, moves, x)
    assert p[0] == pytest.approx(0.8) and p[-1] == pytest.approx(1.9)
    np.testing.assert_allclose(tr.distance(p, 0.8), x, atol=1e-12)  # arc length from the start, monotone
    assert np.all(p[x < 0.2] <= 1.0 + 1e-12) and np.all(p[x > 0.2] > 1.5)


def test_compute_mode_smoke(tmp_path: Path) -> None:
    res = compare_compute(BenchConfig(track="lollipop"), 4, warmup=1)
    s = res["summary"]
    assert s["n"] == 4 and s["ours_verified"] == 1.0 and s["lean_verified"] == 1.0
    assert s["all"]["ours_median_ms"] > 0 and s["all"]["lean_median_ms"] > 0
    assert s["ours_discontinuity_rate"] == 0.0
