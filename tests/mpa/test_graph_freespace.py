"""The exact free space: polygons against dense sampling, components against topology, swap oracles."""

from __future__ import annotations

import numpy as np
import pytest

from mpa import configuration_space_topology
from mpa.freespace import FreeSpace, free_space
from mpa.graph_track import GraphTrack
from tests.helpers.graph_helpers import random_layout


def _inside(poly: np.ndarray, pts: np.ndarray, tol: float) -> np.ndarray:
    """Points inside a counter-clockwise convex polygon (with tolerance); degenerate polygons never contain."""
    if len(poly) < 3:
        return np.zeros(len(pts), dtype=bool)
    ok = np.ones(len(pts), dtype=bool)
    for i in range(len(poly)):
        a, b = poly[i], poly[(i + 1) % len(poly)]
        cross = (b[0] - a[0]) * (pts[:, 1] - a[1]) - (b[1] - a[1]) * (pts[:, 0] - a[0])
        ok &= cross >= -tol * max(1.0, float(np.hypot(*(b - a))))
    return ok


@pytest.mark.parametrize("seed", range(25))
def test_polygons_equal_the_sampled_free_set(seed: int) -> None:
    rng = np.random.default_rng(seed)
    track = random_layout(rng)
    D = float(rng.uniform(0.05, 1.2))
    fs = FreeSpace(track, D)
    g = track.geometry
    tol = 1e-9
    for e in range(track.n_edges):
        for f in range(track.n_edges):
            s, t = np.meshgrid(np.linspace(0, track.lengths[e], 41), np.linspace(0, track.lengths[f], 41))
            pts = np.stack([s.ravel(), t.ravel()], axis=1)
            d = g.distance(e, pts[:, 0], f, pts[:, 1])
            inside = np.zeros(len(pts), dtype=bool)
            for k in (0, 1):
                if (e, f, k) in fs._index:
                    poly = fs.vertices((e, f, k))
                    area = 0.5 * np.sum(poly[:, 0] * np.roll(poly[:, 1], -1) - np.roll(poly[:, 0], -1) * poly[:, 1])
                    assert area >= -1e-12, (seed, e, f, k, "clockwise")
                    inside |= _inside(poly, pts, tol)
            bad_in = inside & (d < D - 1e-9)
            bad_out = ~inside & (d > D + 1e-7)
            assert not bad_in.any(), (seed, D, e, f, pts[bad_in][:3], d[bad_in][:3])
            assert not bad_out.any(), (seed, D, e, f, pts[bad_out][:3], d[bad_out][:3])


@pytest.mark.parametrize("seed", range(40))
def test_component_count_at_tiny_clearance_equals_b0_of_configuration_space(seed: int) -> None:
    rng = np.random.default_rng(1000 + seed)
    track = random_layout(rng, loops=bool(seed % 2))
    b0 = configuration_space_topology(track.graph).betti[0]
    assert FreeSpace(track, 0.0).components() == b0, (seed, track.to_dict())


@pytest.mark.parametrize(("b1", "b2", "b3"), [(1.0, 2.0, 3.0), (0.7, 0.7, 1.5), (0.3, 2.0, 2.0)])
def test_y_junction_swaps_iff_clearance_fits_the_shortest_branch(b1: float, b2: float, b3: float) -> None:
    y = GraphTrack.from_layout({"edges": [["J", "x1", b1], ["J", "x2", b2], ["J", "x3", b3]]})
    for D in (0.5 * b1, b1, b1 * (1 + 1e-9), 1.2 * b1):
        fs = FreeSpace(y, D)
        assert fs.can_swap("x2", "x3") == (D <= b1), (b1, b2, b3, D)
        assert fs.can_swap() == (D <= b1), (b1, b2, b3, D)


def test_path_graph_never_swaps() -> None:
    path = GraphTrack.from_layout({"edges": [["a", "b", 1.0], ["b", "c", 2.0], ["c", "d", 0.5]]})
    for D in (0.0, 0.1, 1.0):
        fs = FreeSpace(path, D)
        assert not fs.can_swap()
        assert fs.components() == 2


@pytest.mark.parametrize("c", [1.0, 2.5])
def test_cycle_circulates_iff_clearance_at_most_half(c: float) -> None:
    # two edges forming a cycle, and a single loop edge
    for layout in ({"edges": [["P", "P", c]]}, {"edges": [["u", "v", 0.4 * c], ["v", "u", 0.6 * c]]}):
        track = GraphTrack.from_layout(layout)
        for D in (0.25 * c, 0.5 * c):
            fs = FreeSpace(track, D)
            assert fs.components() == 1 and fs.can_swap()
        fs = FreeSpace(track, 0.5 * c * (1 + 1e-6))
        assert fs.components() == 0 and not fs.can_swap()


def test_passing_loop_on_a_line() -> None:
    # line W - A ... B - E with a passing loop of two parallel edges between A and B (cycle length 2 + 3 = 5)
    track = GraphTrack.from_layout({"edges": [["W", "A", 4.0], ["A", "B", 2.0], ["A", "B", 3.0], ["B", "E", 4.0]]})
    assert FreeSpace(track, 2.5).can_swap("W", "E")
    assert not FreeSpace(track, 2.5001).can_swap("W", "E")


def test_entirely_free_and_blocked_cells_are_cheap_and_cached() -> None:
    track = GraphTrack.from_layout({"edges": [["a", "b", 10.0], ["c", "d", 10.0], ["b", "c", 100.0]]})
    fs = free_space(track, 1.0)
    assert fs.status[0, 1] == 1  # far apart: the whole box
    assert free_space(track, 1.0) is fs
    assert fs.vertices((0, 1, 0)).shape == (4, 2)


def test_paper_lollipop_components() -> None:
    from mpa import Lollipop

    t = Lollipop(1.0, 1.0).as_graph_track()
    assert FreeSpace(t, 0.5).can_swap() and FreeSpace(t, 0.5).components() == 1
    assert not FreeSpace(t, 0.6).can_swap()
