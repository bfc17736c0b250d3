"""Shared helpers of the graph-track tests: random small layouts and queries, a brute-force distance."""

from __future__ import annotations

import heapq
import math
from typing import Any

import numpy as np

from mpa.graph_track import GraphTrack

EXACT = 1e-9  # metres


def random_layout(rng: np.random.Generator, n_edges: int | None = None, loops: bool = True) -> GraphTrack:
    """A random connected layout of 3-6 edges (loops and parallel edges included), lengths 0.3-2 m."""
    n_e = int(rng.integers(3, 7)) if n_edges is None else n_edges
    n_v = int(rng.integers(2, n_e + 1))
    edges = []
    for v in range(1, n_v):  # a random spanning tree keeps it connected
        u = int(rng.integers(0, v))
        edges.append([f"v{u}", f"v{v}", round(float(rng.uniform(0.3, 2.0)), 3)])
    while len(edges) < n_e:
        u = int(rng.integers(0, n_v))
        w = u if (loops and rng.random() < 0.3) else int(rng.integers(0, n_v))
        length = round(float(rng.uniform(0.3, 2.0)), 3)
        if u == w and length < 0.6:
            length += 0.6
        edges.append([f"v{u}", f"v{w}", length])
    return GraphTrack.from_layout({"edges": edges})


def random_position(track: GraphTrack, rng: np.random.Generator, vertex_p: float = 0.15) -> tuple[int, float]:
    """A random position; with probability ``vertex_p`` exactly at an end of its edge."""
    e = int(rng.integers(0, track.n_edges))
    length = float(track.lengths[e])
    if rng.random() < vertex_p:
        return e, float(rng.choice([0.0, length]))
    return e, float(rng.uniform(0.0, length))


Query = tuple[tuple[int, float], tuple[int, float]]


def random_free_query(
    track: GraphTrack, fs: Any, rng: np.random.Generator, vertex_p: float = 0.0, tries: int = 20
) -> tuple[Query, Query] | None:
    """A random query both of whose states are free in ``fs`` (a :class:`mpa.freespace.FreeSpace` of ``track``):
    up to ``tries`` draws of four positions ``(edge, offset)`` (A's and B's start, then goal), each with
    probability ``vertex_p`` moved to the tail of its edge; None when no draw is free."""
    for _ in range(tries):
        e = rng.integers(track.n_edges, size=4)
        o = rng.uniform(0, 1, 4) * track.lengths[e]
        if vertex_p:
            o[rng.random(4) < vertex_p] = 0.0
        s = ((int(e[0]), float(o[0])), (int(e[1]), float(o[1])))
        t = ((int(e[2]), float(o[2])), (int(e[3]), float(o[3])))
        if fs.is_free(*s) and fs.is_free(*t):
            return s, t
    return None


def brute_distance(track: GraphTrack, a: tuple[int, float], b: tuple[int, float]) -> float:
    """Graph distance by Dijkstra on the graph subdivided at both positions (independent of mpa.geometry)."""
    nodes: dict[object, list[tuple[object, float]]] = {}

    def link(x: object, y: object, w: float) -> None:
        nodes.setdefault(x, []).append((y, w))
        nodes.setdefault(y, []).append((x, w))

    for i, e in enumerate(track.graph.edges):
        offs = sorted({0.0, e.length} | {p[1] for p in (a, b) if p[0] == i})
        keys = [("v", e.tail) if o == 0.0 else ("v", e.head) if o == e.length else ("p", i, o) for o in offs]
        for k in range(len(offs) - 1):
            link(keys[k], keys[k + 1], offs[k + 1] - offs[k])

    def key(p: tuple[int, float]) -> object:
        e = track.graph.edges[p[0]]
        return ("v", e.tail) if p[1] == 0.0 else ("v", e.head) if p[1] == e.length else ("p", p[0], p[1])

    src, dst = key(a), key(b)
    best = {src: 0.0}
    heap = [(0.0, 0, src)]
    n = 1
    while heap:
        d, _, x = heapq.heappop(heap)
        if x == dst:
            return d
        if d > best.get(x, np.inf):
            continue
        for y, w in nodes.get(x, []):
            if d + w < best.get(y, np.inf):
                best[y] = d + w
                heapq.heappush(heap, (d + w, n, y))
                n += 1
    return float("inf")


def makespans_with(
    monkeypatch: Any,
    module: Any,
    name: str,
    values: Any,
    track: GraphTrack,
    start: Any,
    goal: Any,
    clearance: float,
    speeds: tuple[float, float] = (1.0, 1.0),
    after_each: Any = None,
) -> list[float | None]:
    """``plan_graph``'s makespan with ``module.name`` set to each of ``values`` in turn (None: no motion); every plan
    keeps the clearance. ``after_each(value)`` runs after each plan (to read what a patched search recorded)."""
    from mpa.errors import NoMotionError
    from mpa.planners.graph.query import plan_graph

    out: list[float | None] = []
    for value in values:
        monkeypatch.setattr(module, name, value)
        try:
            p = plan_graph(track, start, goal, clearance, speeds=speeds)
        except NoMotionError:
            out.append(None)
            continue
        finally:
            if after_each is not None:
                after_each(value)
        assert p.min_distance() >= p.clearance_used - 1e-9, (name, value, start, goal, clearance)
        out.append(p.makespan)
    return out


def same_makespans(spans: list[float | None], context: tuple[Any, ...]) -> bool:
    """Whether both of two plans exist (then their makespans agree to 1e-9); when one is missing, so is the other."""
    import pytest

    if spans[0] is None or spans[1] is None:
        assert spans[0] is None and spans[1] is None, (*context, spans)
        return False
    assert spans[1] == pytest.approx(spans[0], rel=1e-9, abs=1e-12), (*context, spans)
    return True


def random_face_case(rng: np.random.Generator) -> tuple[Any, ...]:
    """Arguments of :func:`mpa.planners.search_common.least_through_face` drawn as a search meets them: an edge of
    length ``L``, the part ``[y0, y1]`` of it, the edge robot's root coordinate ``r`` (unfolded, possibly outside the
    edge), its goal distance's terms ``cp``, ``cm`` consistent with a graph (the goal on the edge one time in three),
    the vertex robot's travels, both objectives and unequal speeds; one in four with the vertex robot's way the longer
    (the cost's ``max`` then flat along the part, the ``hypot`` terms deciding); one in twenty with a corridor class's
    unreachable ends (``inf``)."""
    length = float(rng.uniform(0.5, 30.0))
    y0, y1 = sorted(rng.uniform(0.0, length, size=2).tolist())
    if rng.random() < 0.1:
        y1 = y0
    r = float(rng.uniform(-length, 2.0 * length))
    on_edge = bool(rng.random() < 1 / 3)
    off = float(rng.uniform(0.0, length))
    if on_edge:
        d_th = float(rng.uniform(0.0, 3.0 * length))
        cp = min(off, d_th + length - off)
        cm = length + min(d_th + off, length - off)
    else:
        cp = float(rng.uniform(0.0, 100.0))
        cm = length + max(0.0, cp + float(rng.uniform(-length, length)))
        if rng.random() < 0.05:
            cp, cm = (math.inf, cm) if rng.random() < 0.5 else (cp, math.inf)
    scale = 20.0 * (length + cp) if rng.random() < 0.25 else float(rng.uniform(0.0, 60.0))
    x_seg = float(rng.uniform(0.0, 1.0) * scale)
    x_rest = float(rng.uniform(0.0, 3.0) * scale)
    if rng.random() < 0.05:
        x_seg = 0.0
    va, vb = (1.0, 1.0) if rng.random() < 0.5 else (float(rng.uniform(0.2, 3.0)), float(rng.uniform(0.2, 3.0)))
    ax = int(rng.integers(0, 2))
    fastest = bool(rng.random() < 0.8)
    return ax, x_seg, x_rest, r, y0, y1, cp, cm, on_edge, off, fastest, va, vb
