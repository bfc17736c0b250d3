"""The seeded large layouts of the scaling benchmark: edge counts, connectivity, planarity, determinism."""

from __future__ import annotations

import itertools
import sys
from pathlib import Path

import numpy as np
import pytest

ROOT = Path(__file__).resolve().parents[2]
sys.path.insert(0, str(ROOT / "experiments"))

from bench.graph_scale import KINDS, road_map_layout, run_scale, scale_markdown, warehouse_layout  # noqa: E402


def _segments_cross(p: np.ndarray, q: np.ndarray, r: np.ndarray, s: np.ndarray) -> bool:
    """Whether segments pq and rs cross at a point interior to both."""

    def orient(a: np.ndarray, b: np.ndarray, c: np.ndarray) -> float:
        return float((b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0]))

    d1, d2, d3, d4 = orient(p, q, r), orient(p, q, s), orient(r, s, p), orient(r, s, q)
    return d1 * d2 < -1e-9 and d3 * d4 < -1e-9


@pytest.mark.parametrize("kind", list(KINDS))
@pytest.mark.parametrize("n", [10, 30, 100, 300, 1000, 3000])
def test_layouts_have_the_asked_edges_and_are_connected(kind: str, n: int) -> None:
    t = KINDS[kind](n, 7)
    assert t.n_edges == n, (kind, n, t.n_edges)
    assert t.graph.betti()[0] == 1, (kind, n)
    assert t.has_coordinates and float(np.min(t.lengths)) > 0.5
    again = KINDS[kind](n, 7)
    assert again.to_dict() == t.to_dict()  # seeded: the same layout every time
    assert KINDS[kind](n, 8).to_dict() != t.to_dict()


@pytest.mark.parametrize("make", [warehouse_layout, road_map_layout])
def test_layouts_are_planar(make) -> None:  # type: ignore[no-untyped-def]
    t = make(100, 3)
    d = t.to_dict()
    xy = {k: np.array(v, dtype=float) for k, v in d["vertices"].items()}
    segs = [(xy[e["from"]], xy[e["to"]]) for e in d["edges"]]
    crossings = [(i, j) for i, j in itertools.combinations(range(len(segs)), 2) if _segments_cross(*segs[i], *segs[j])]
    assert crossings == []


def test_scale_run_and_table() -> None:
    recs = run_scale(sizes=(10, 30), kinds=("warehouse",), queries=4, trajectories=1, clearance=1.0)
    assert [r["edges"] for r in recs] == [10, 30]
    for r in recs:
        assert r["build"] > 0 and r["memory"] > 0 and r["polygons"] > 0
        assert r["plan_median"] <= r["plan_p95"] <= r["plan_max"]
        assert r["queries"] == 4 and r["over_budget"] == 0 and r["build_cpu"] > 0
        assert r["plan_cpu_median"] <= r["plan_cpu_p95"] <= r["plan_cpu_max"]
    md = scale_markdown(recs)
    assert "| warehouse | 10 |" in md and "exponent" in md
