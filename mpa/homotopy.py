"""Homotopy classes of paths as reduced edge words in the skeleton graph.

The class of a path α in the configuration space (rel endpoints) is read off ``H₁∘α``, a path in the skeleton
graph: the sequence of edges it runs along, each with a direction (``"+S1a"`` along the edge's orientation,
``"-S1a"`` against it; the first and last step may cover part of an edge), freely reduced in the universal cover:
consecutive runs along the same edge merge into their net run (a back-and-forth through a vertex cancels,
leaving any remainder). A path that never reaches a vertex has the one-step word of its net run (or the empty
word if it returns to its start). Because the skeleton is a graph, two paths with the same endpoints are
homotopic iff their reduced words agree.
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np
from numpy.typing import ArrayLike

from mpa.errors import PlanningError
from mpa.graph import MetricGraph
from mpa.retraction import retract
from mpa.skeleton import CircleSkeleton, IntervalSkeleton, LollipopSkeleton, Skeleton, skeleton_of
from mpa.tracks import Track

__all__ = ["path_word", "reduce_word", "word_from_points", "word_from_samples"]

#: Skeleton points within this arc length (model metres) of an edge's end count as at that vertex.
END_TOL = 1e-9


def reduce_word(tokens: Sequence[str]) -> tuple[str, ...]:
    """Free reduction: cancel adjacent ``+e`` / ``-e`` pairs.

    Examples
    --------
    >>> reduce_word(["+S1a", "+S2a", "-S2a", "+S2b"])
    ('+S1a', '+S2b')
    """
    out: list[str] = []
    for tok in tokens:
        if out and out[-1][1:] == tok[1:] and out[-1][0] != tok[0]:
            out.pop()
        else:
            out.append(tok)
    return tuple(out)


def word_from_points(graph: MetricGraph, edges: ArrayLike, ts: ArrayLike) -> tuple[str, ...]:
    """Reduced edge word of a densely sampled path in a skeleton graph.

    Parameters
    ----------
    graph : MetricGraph
        The skeleton graph (no loop edges).
    edges : array_like of int, shape (N,)
        Index into ``graph.edges`` of every sample.
    ts : array_like of float, shape (N,)
        Arc length of every sample along its edge.

    Returns
    -------
    tuple of str

    Raises
    ------
    PlanningError
        If two consecutive samples lie on edges without a common vertex (the sampling is too coarse).
    """
    e_idx = np.asarray(edges, dtype=np.int64)
    t_arr = np.asarray(ts, dtype=float)
    if len(e_idx) == 0:
        return ()
    change = (np.flatnonzero(e_idx[1:] != e_idx[:-1]) + 1).tolist()
    # only the samples around edge changes matter, plus the first and the last
    keep = sorted({0, len(e_idx) - 1, *change, *(k - 1 for k in change)})
    return word_from_samples(graph, e_idx[keep].tolist(), t_arr[keep].tolist())


def word_from_samples(graph: MetricGraph, edges: list[int], ts: list[float]) -> tuple[str, ...]:
    """Pure-Python core of :func:`word_from_points` (edge indices and arc lengths as lists).

    The path is cut into *steps*, one per visit of an edge, each with its extent along the edge (from where it
    entered to where it left). Consecutive steps on the same edge meet at a vertex and form a back-and-forth:
    they merge into their net displacement (dropped if zero). This is free reduction in the universal cover, so a
    full traversal followed by a partial return leaves the partial remainder (a plain token cancellation would
    lose it). The word lists the remaining steps' edges with the direction of their displacement.
    """
    E = graph.edges
    n = len(edges)
    if n == 0:
        return ()
    steps: list[tuple[int, float, float]] = []  # (edge index, t_from, t_to)

    def push(e: int, t0: float, t1: float) -> None:
        while True:
            if abs(t1 - t0) <= END_TOL:
                return
            if steps and steps[-1][0] == e:
                top = steps.pop()
                t0 = top[1]
                continue
            steps.append((e, t0, t1))
            return

    cur = edges[0]
    t_from = ts[0]
    for k in range(1, n):
        nxt = edges[k]
        if nxt == cur:
            continue
        prev_t, t_next = ts[k - 1], ts[k]
        ends_cur = {str(E[cur].tail): prev_t, str(E[cur].head): E[cur].length - prev_t}
        ends_nxt = {str(E[nxt].tail): t_next, str(E[nxt].head): E[nxt].length - t_next}
        shared = [v for v in ends_cur if v in ends_nxt]
        if not shared:
            raise PlanningError(f"path jumps from edge {E[cur].name} to {E[nxt].name}: sample it more densely")
        v = min(shared, key=lambda s: ends_cur[s] + ends_nxt[s])
        push(cur, t_from, 0.0 if v == str(E[cur].tail) else E[cur].length)
        cur = nxt
        t_from = 0.0 if v == str(E[nxt].tail) else E[nxt].length
    push(cur, t_from, ts[-1])
    return tuple(("+" if st[2] > st[1] else "-") + E[st[0]].name for st in steps)


def skeleton_points(skeleton: Skeleton, states: ArrayLike) -> tuple[np.ndarray, np.ndarray]:
    """Edge indices and arc lengths of ``H₁`` of the given states. Shapes (N,)."""
    st = np.atleast_2d(np.asarray(states, dtype=float))
    on_s = retract(skeleton.track, st, 1.0)
    if isinstance(skeleton, LollipopSkeleton):
        edge, t = skeleton.points_of_model_states(skeleton.to_model(on_s))
        if skeleton.graph.edges[0].length <= END_TOL:  # ℓ = h: I1 and I2 are single points
            on_i = (edge == 0) | (edge == 7)
            t = np.where(on_i, 0.0, t)  # v1 = S1a(0), v4 = S3a(0)
            edge = np.where(edge == 0, 1, np.where(edge == 7, 5, edge))
        return edge, t
    if isinstance(skeleton, CircleSkeleton):
        return skeleton.points_of_states(on_s)
    raise PlanningError(f"no skeleton words for {type(skeleton).__name__}")


def _jumps(sk: Skeleton, edge: np.ndarray, t: np.ndarray) -> np.ndarray:
    """Indices i where samples i and i+1 lie on skeleton edges without a common vertex."""
    idx = np.flatnonzero(edge[1:] != edge[:-1])
    return idx[~sk.graph.adjacent_edges[edge[idx], edge[idx + 1]]]


#: Where a gap between two samples is refined (16 inner points).
_REFINE_FRACTIONS = np.linspace(0.0, 1.0, 18)[1:-1]


def path_word(track: Track, states: ArrayLike, refine: int = 6) -> tuple[str, ...]:
    """Reduced skeleton word of a densely sampled path of states (track coordinates, shape (N, 2)).

    Near a collision (d → 0) the retraction H₁ moves fast, so two consecutive samples can retract to skeleton
    edges without a common vertex; such gaps are refined (up to ``refine`` times, 16 sub-samples each) along
    the shortest motion between the two samples, which is the motion itself when the samples are close.
    The interval's skeleton has no edges: every path there has the empty word.
    """
    sk = skeleton_of(track)
    if isinstance(sk, IntervalSkeleton):
        return ()
    st = np.atleast_2d(np.asarray(states, dtype=float))
    edge, t = skeleton_points(sk, st)
    f = _REFINE_FRACTIONS
    for _ in range(refine):
        gaps = _jumps(sk, edge, t)
        if len(gaps) == 0:
            break
        parts, last = [], 0
        for i in gaps:
            a = track.interpolate(st[i, 0], st[i + 1, 0], f)
            b = track.interpolate(st[i, 1], st[i + 1, 1], f)
            parts += [st[last : i + 1], np.stack([a, b], axis=-1)]
            last = i + 1
        parts.append(st[last:])
        st = np.vstack(parts)
        edge, t = skeleton_points(sk, st)
    return word_from_points(sk.graph, edge, t)
