"""The planar search's regions and landmarks (:func:`mpa.planar.search._dijkstra`) find paths of the least cost over
the whole graph of moves: the same cost as scipy's Dijkstra over every node, on seeded queries over the example
layouts, for both objectives."""

from __future__ import annotations

from pathlib import Path
from typing import Any

import numpy as np
import pytest
from scipy.sparse import csr_matrix
from scipy.sparse.csgraph import dijkstra

import mpa
from mpa.graph_track import GraphTrack
from mpa.planar import plan_planar, planar_free_space
from mpa.planar import search as planar_search
from mpa.planar.search import _cell_speeds, _region_search

ROOT = Path(__file__).resolve().parents[2]
EXAMPLES = ROOT / "examples" / "tracks"
CASES = [
    (EXAMPLES / "circle.json", "0.05", 0.2),
    (EXAMPLES / "figure_eight.json", "0.5", 1.0),
    (EXAMPLES / "two_sidings.json", "1.5x0.8", 1.0),
    (EXAMPLES / "rail_yard.json", "2x0.8", 2.5),
]


def _queries(tr: GraphTrack, seed: int, n: int) -> list[list[tuple[int, float]]]:
    rng = np.random.default_rng(seed)
    out = []
    for _ in range(n):
        out.append([(int(e), float(rng.uniform(0.0, tr.lengths[e]))) for e in rng.integers(tr.n_edges, size=4)])
    return out


def _whole_graph(monkeypatch: pytest.MonkeyPatch) -> None:
    """The reference search: no A*, no region (every region reaches nothing), the whole graph at once."""

    def nothing(G: Any, region: Any, fk: Any, fw: Any) -> tuple[np.ndarray, np.ndarray]:
        return np.full(G.n, np.inf), np.full(G.n, -9999, dtype=np.int64)

    monkeypatch.setattr(planar_search, "_region_search", nothing)
    monkeypatch.setattr(planar_search, "_astar", lambda *a, **k: None)


@pytest.mark.parametrize(("path", "spec", "clearance"), CASES, ids=lambda x: getattr(x, "stem", None))
@pytest.mark.parametrize("objective", ["fastest", "shortest"])
def test_regions_find_the_least_cost_of_the_whole_graph(
    path: Path, spec: str, clearance: float, objective: str, monkeypatch: pytest.MonkeyPatch
) -> None:
    tr = GraphTrack.from_file(path)
    fps = mpa.footprint.footprints(spec)
    assert fps is not None
    speeds = (1.0, 0.7)
    planned = []
    for q in _queries(tr, 23, 12):
        try:
            plan = plan_planar(tr, (q[0], q[1]), (q[2], q[3]), clearance, objective, speeds, fps)
        except (mpa.InvalidInputError, mpa.NoMotionError):
            continue
        planned.append((q, plan))
    assert len(planned) >= 4
    with monkeypatch.context() as m:
        _whole_graph(m)
        for q, plan in planned:
            ref = plan_planar(tr, (q[0], q[1]), (q[2], q[3]), clearance, objective, speeds, fps)
            got = plan.makespan if objective == "fastest" else plan.length
            want = ref.makespan if objective == "fastest" else ref.length
            assert abs(got - want) <= 1e-9 * max(1.0, want), f"{path.name} {objective} {q}: {got!r} vs whole {want!r}"


def test_region_search_is_dijkstra_restricted_to_the_region() -> None:
    """Over every node it is scipy's Dijkstra; over a region its costs are never below the whole graph's and equal
    them where a cheapest path stays inside."""
    tr = GraphTrack.from_file(EXAMPLES / "two_sidings.json")
    space = planar_free_space(tr, 1.0, "1.5x0.8")
    G = space.search_graph("fastest", *_cell_speeds(tr, 1.0, 1.0))
    rng = np.random.default_rng(5)
    fk = np.sort(rng.choice(G.n, size=5, replace=False)).astype(np.int64)
    fw = rng.uniform(0.1, 1.0, size=5)
    indptr = np.concatenate([G.indptr, [G.indptr[-1] + 5]])
    data, cols = np.concatenate([G.weights, fw]), np.concatenate([G.indices, fk])
    whole = csr_matrix((data, cols, indptr), shape=(G.n + 1, G.n + 1))
    ref = dijkstra(whole, directed=True, indices=G.n)[: G.n]
    dist, pred = _region_search(G, np.ones(G.n, dtype=bool), fk, fw)
    np.testing.assert_array_equal(dist, ref)
    assert np.all((pred[np.isfinite(dist)] >= 0) & (pred[np.isfinite(dist)] <= G.n))
    cut = np.isfinite(ref) & (ref <= np.median(ref[np.isfinite(ref)]))
    part, _ = _region_search(G, cut, fk, fw)
    assert np.all(part[cut] >= ref[cut] - 1e-12) and np.all(np.isinf(part[~cut]))
    # the nodes whose cheapest path stays in the region (all of them here: the region is a Dijkstra ball)
    np.testing.assert_allclose(part[cut], ref[cut], rtol=0, atol=1e-12)


def test_landmark_bounds_never_exceed_the_costs() -> None:
    """The landmarks' triangle bounds: out[l, v] - out[l, u] <= cost(u -> v) on seeded node pairs."""
    tr = GraphTrack.from_file(EXAMPLES / "circle.json")
    space = planar_free_space(tr, 0.2, "0.05")
    G = space.search_graph("fastest", *_cell_speeds(tr, 1.0, 1.0))
    out, back = G.landmarks()
    assert out.shape == back.shape == (G.LANDMARKS, G.n)
    g = csr_matrix((G.weights, G.indices, G.indptr), shape=(G.n, G.n))
    rng = np.random.default_rng(7)
    us = rng.choice(G.n, size=6, replace=False)
    d = dijkstra(g, directed=True, indices=us)
    with np.errstate(invalid="ignore"):
        for row, u in zip(d, us, strict=True):
            ok = np.isfinite(row)
            lb_out = np.nanmax(out[:, ok] - out[:, [u]], axis=0)
            lb_back = np.nanmax(back[:, [u]] - back[:, ok], axis=0)
            assert np.all(lb_out <= row[ok] + 1e-9), u
            assert np.all(lb_back <= row[ok] + 1e-9), u
