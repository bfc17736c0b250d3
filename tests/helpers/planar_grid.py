"""A grid search in the plane model, the reference of the completeness tests with footprints.

Both robots' positions are sampled along every edge (vertices shared); a configuration of the grid is kept when the
bodies stay at least ``step + 0.02`` m apart in the plane (a step moves a body at most ``step``, so every grid move
is a motion of the model). A rectangle on a corner where the drawing turns counts as the disc of its half-diagonal
(it may turn there). The poses come from :class:`tests.helpers.planar_checker.Drawn` (no code of ``mpa.planar``).
"""

from __future__ import annotations

import itertools
import math
from collections.abc import Iterator
from typing import Any

import numpy as np

from mpa import Disc, GraphTrack, Rectangle
from tests.helpers.planar_checker import Drawn

Position = tuple[int, float]


def drawn_of(track: GraphTrack) -> Drawn:
    """The layout's drawing (polylines per edge) read from ``track.to_dict()``."""
    d = track.to_dict()
    names = [str(v) for v in track.graph.vertices]
    if isinstance(d.get("vertices"), list):
        d["vertices"] = dict(zip(names, d["vertices"]))
    return Drawn(d, [float(x) for x in track.lengths])


def grid_nodes(tr: GraphTrack, step: float, *, oneway: bool) -> tuple[list[Position], list[list[int]]]:
    """Positions every at most ``step`` metres along every edge (at least two steps an edge; vertices shared) and
    each node's moves to its neighbours.

    Parameters
    ----------
    tr : GraphTrack
    step : float
        Largest spacing of the nodes along an edge (m).
    oneway : bool
        Keep the layout's one-way rule: on a one-way edge only moves from tail to head.

    Returns
    -------
    nodes : list of (int, float)
        ``(edge, offset)`` of every node.
    moves : list of list of int
        ``moves[i]``: the nodes one step from node ``i``.
    """
    nodes: list[Position] = []
    index: dict[Any, int] = {}
    moves: list[list[int]] = []
    for e in range(tr.n_edges):
        length = float(tr.lengths[e])
        k = max(2, math.ceil(length / step))
        ids = []
        for i in range(k + 1):
            o = length * i / k
            w = tr.vertex_at(e, o)
            key = ("v", w) if w is not None else ("e", e, i)
            if key not in index:
                index[key] = len(nodes)
                nodes.append((e, o))
                moves.append([])
            ids.append(index[key])
        for a, b in itertools.pairwise(ids):
            moves[a].append(b)
            if not (oneway and tr.oneway[e]):
                moves[b].append(a)
    return nodes, moves


def plane_free(tr: GraphTrack, nodes: list[Position], fp: Disc | Rectangle, step: float) -> np.ndarray:
    """The grid's configurations kept: bodies ``fp`` at least ``step + 0.02`` m apart. Shape (n, n), bool; the
    diagonal False."""
    dr = drawn_of(tr)
    c = np.array([dr.point(*q) for q in nodes])
    hs = [dr.headings(*q) for q in nodes]
    turn = np.array([max((abs(math.remainder(x - y, math.pi)) for x in h for y in h), default=0.0) > 1e-9 for h in hs])
    h = np.array([x[0] for x in hs])
    dx = c[None, :, :] - c[:, None, :]
    if isinstance(fp, Disc):
        g = np.hypot(dx[..., 0], dx[..., 1]) - 2 * fp.radius
    else:
        g = np.full(dx.shape[:2], -np.inf)
        hl, hw = fp.length / 2, fp.width / 2
        for hh in (h[:, None] + 0 * h[None, :], h[None, :] + 0 * h[:, None]):
            for ax in (hh, hh + math.pi / 2):
                ux, uy = np.cos(ax), np.sin(ax)
                cen = np.abs(dx[..., 0] * ux + dx[..., 1] * uy)
                ra = hl * np.abs(np.cos(ax - h[:, None])) + hw * np.abs(np.sin(ax - h[:, None]))
                rb = hl * np.abs(np.cos(ax - h[None, :])) + hw * np.abs(np.sin(ax - h[None, :]))
                g = np.maximum(g, cen - ra - rb)
        reach = math.hypot(fp.length, fp.width) / 2
        dist = np.hypot(dx[..., 0], dx[..., 1])
        g = np.where(turn[:, None] | turn[None, :], np.minimum(g, dist - 2 * reach), g)
    free = g >= step + 0.02
    np.fill_diagonal(free, False)
    return free


def grid_reaches(moves: list[list[int]], free: Any, s: tuple[int, int], g: tuple[int, int]) -> bool:
    """Whether the grid leads from configuration ``s`` to ``g`` (node indices), one robot one step at a time."""
    seen = {s}
    todo = [s]
    while todo:
        i, j = todo.pop()
        if (i, j) == g:
            return True
        for a, b in [(x, j) for x in moves[i]] + [(i, y) for y in moves[j]]:
            if (a, b) not in seen and free[a, b]:
                seen.add((a, b))
                todo.append((a, b))
    return False


def grid_queries(
    rng: np.random.Generator, nodes: list[Position], moves: list[list[int]], free: Any, draws: int
) -> Iterator[tuple[bool, tuple[Position, Position], tuple[Position, Position]]]:
    """Seeded queries between kept configurations of the grid: ``draws`` random draws of four nodes, each pair of
    kept configurations yielded as (whether the grid leads from start to goal, start, goal)."""
    for _ in range(draws):
        i, j, k, m = (int(x) for x in rng.integers(0, len(nodes), size=4))
        if not (free[i, j] and free[k, m]):
            continue
        yield grid_reaches(moves, free, (i, j), (k, m)), (nodes[i], nodes[j]), (nodes[k], nodes[m])
