"""Tracks: exact graph distance (against an independent Dijkstra on the generic graph), validation, embedding."""

from __future__ import annotations

import heapq

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from mpa import Circle, Interval, InvalidInputError, Lollipop, MetricGraph, make_track
from tests.helpers.common import ALL_TRACKS, EXACT, random_states


def _edge_point(track, p: float) -> tuple[str, float]:  # type: ignore[no-untyped-def]
    """(edge name, offset from the edge's tail) of a track coordinate, written independently of mpa."""
    if isinstance(track, Interval):
        return "stick", p
    if isinstance(track, Circle):
        return "loop", p
    return ("stick", p) if p <= track.stick else ("loop", p - track.stick)


def _dijkstra_distance(graph: MetricGraph, a: tuple[str, float], b: tuple[str, float]) -> float:
    """Graph metric between two points on edges by Dijkstra over the vertices plus the two points."""
    lengths = {e.name: e.length for e in graph.edges}
    ends = {e.name: (e.tail, e.head) for e in graph.edges}
    adj: dict[object, list[tuple[object, float]]] = {v: [] for v in graph.vertices}
    for e in graph.edges:
        adj[e.tail].append((e.head, e.length))
        adj[e.head].append((e.tail, e.length))
    for name, (edge, off) in (("#a", a), ("#b", b)):
        t, h = ends[edge]
        adj[name] = [(t, off), (h, lengths[edge] - off)]
        adj[t].append((name, off))
        adj[h].append((name, lengths[edge] - off))
    best = {"#a": 0.0}
    heap = [(0.0, "#a")]
    while heap:
        d, v = heapq.heappop(heap)
        if v == "#b":
            break
        if d > best.get(v, np.inf):
            continue
        for w, length in adj[v]:
            if d + length < best.get(w, np.inf):
                best[w] = d + length
                heapq.heappush(heap, (d + length, w))
    direct = abs(a[1] - b[1]) if a[0] == b[0] else np.inf  # both on the same edge: the segment between them
    if a[0] == b[0] and ends[a[0]][0] == ends[a[0]][1]:  # a loop edge: also the way round
        direct = min(direct, lengths[a[0]] - direct)
    return float(min(best["#b"], direct))


@pytest.mark.parametrize("track", ALL_TRACKS, ids=repr)
def test_distance_matches_dijkstra_on_the_generic_graph(track) -> None:  # type: ignore[no-untyped-def]
    rng = np.random.default_rng(7)
    pts = random_states(track, 400, rng, min_gap=0.0)
    graph = track.as_graph()
    got = track.distance(pts[:, 0], pts[:, 1])
    for i, (p, q) in enumerate(pts):
        want = _dijkstra_distance(graph, _edge_point(track, p), _edge_point(track, q))
        assert abs(got[i] - want) < EXACT, f"case {i}: d({p}, {q}) = {got[i]}, Dijkstra {want}"


@settings(max_examples=2000, deadline=None)
@given(st.sampled_from(ALL_TRACKS), st.floats(0, 1), st.floats(0, 1), st.floats(0, 1))
def test_distance_is_a_metric(track, u, v, w) -> None:  # type: ignore[no-untyped-def]
    L = np.nextafter(track.total_length, 0)
    p, q, r = u * L, v * L, w * L
    d = track.distance
    assert d(p, p) == 0.0
    assert abs(d(p, q) - d(q, p)) < EXACT
    assert d(p, r) <= d(p, q) + d(q, r) + EXACT
    assert d(p, q) <= track.total_length


def test_lollipop_distance_cases_from_the_spec() -> None:
    L = Lollipop(1.0, 1.0)
    assert L.distance(0.1, 0.6) == pytest.approx(0.5)  # both on the stick
    assert L.distance(1.25, 1.75) == pytest.approx(0.5)  # antipodal on the loop
    assert L.distance(0.8, 1.3) == pytest.approx(0.5)  # stick to loop through P
    assert L.distance(0.8, 1.9) == pytest.approx(0.3)  # the short way round
    assert L.distance(0.0, 1.5) == pytest.approx(1.5)  # farthest pair


@pytest.mark.parametrize(
    ("make", "match"),
    [
        (lambda: Lollipop(0.0, 1.0), "stick length is 0.0, expected a positive"),
        (lambda: Lollipop(1.0, -2.0), "loop length is -2.0"),
        (lambda: Circle(float("nan")), "loop length is nan"),
        (lambda: Interval(float("inf")), "stick length is inf"),
        (lambda: make_track("figure8"), "track is 'figure8', expected one of"),
        (lambda: make_track("circle", stick=1.0), "circle track has no stick"),
        (lambda: make_track("interval", loop=1.0), "interval track has no loop"),
    ],
)
def test_bad_track_parameters(make, match) -> None:  # type: ignore[no-untyped-def]
    with pytest.raises(InvalidInputError, match=match):
        make()


@pytest.mark.parametrize(
    ("track", "value", "match"),
    [
        (Lollipop(1.0, 1.0), float("nan"), "is nan, expected a finite number"),
        (Lollipop(1.0, 1.0), float("inf"), "is inf, expected a finite number"),
        (Lollipop(1.0, 1.0), 2.0, r"is 2.0, expected a track coordinate in \[0, 2\)"),
        (Lollipop(1.0, 1.0), -0.1, "is -0.1"),
        (Circle(1.0), 1.5, r"expected a track coordinate in \[0, 1\)"),
        (Interval(1.0), 1.01, r"\[0, 1\]"),
    ],
)
def test_position_validation(track, value, match) -> None:  # type: ignore[no-untyped-def]
    with pytest.raises(InvalidInputError, match=match):
        track.validate(value, "start of robot A")


def test_end_of_loop_wraps_to_the_pole() -> None:
    assert Lollipop(1.0, 1.0).validate(2.0 - 1e-14) == pytest.approx(1.0)
    assert Circle(1.0).validate(1.0 - 1e-14) == 0.0


@pytest.mark.parametrize("track", ALL_TRACKS, ids=repr)
def test_embedding_is_continuous_and_shaped(track) -> None:  # type: ignore[no-untyped-def]
    p = np.linspace(0, np.nextafter(track.total_length, 0), 20001)
    xy = track.embed(p)
    assert xy.shape == (len(p), 2)
    step = np.linalg.norm(np.diff(xy, axis=0), axis=1)
    if isinstance(track, Lollipop):  # the only jump: from P (end of the stick) to the first loop point is small too
        assert step.max() < 1e-3 * max(1.0, track.total_length)
    else:
        assert step.max() < 1e-3 * max(1.0, track.total_length)
    if isinstance(track, Lollipop):
        assert np.allclose(track.embed(track.stick), [0.0, 0.0])


@pytest.mark.parametrize("track", ALL_TRACKS, ids=repr)
def test_generic_graph_of_each_track(track) -> None:  # type: ignore[no-untyped-def]
    g = track.as_graph()
    assert g.total_length() == pytest.approx(track.total_length)
    b0, b1 = g.betti()
    assert b0 == 1
    assert b1 == (0 if isinstance(track, Interval) else 1)
