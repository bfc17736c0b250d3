"""From the search's segments to a plan: merging, routes, the cell word and the :class:`GraphPlan`."""

from __future__ import annotations

from typing import Any

import numpy as np

from mpa.freespace import PolygonId
from mpa.geometry import DirectedRoute
from mpa.graph_track import GraphTrack, Position
from mpa.planners.graph.result import GraphPlan
from mpa.planners.search_common import SearchQuery


def _merge_same_polygon(segs: list[list[Any]]) -> list[list[Any]]:
    """Join consecutive segments inside one convex polygon into one straight segment (never longer, still free)."""
    out: list[list[Any]] = []
    for x in segs:
        if out and out[-1][0] == x[0] and out[-1][2] == x[1]:
            out[-1] = [x[0], out[-1][1], x[2]]
            if out[-1][1] == out[-1][2]:
                out.pop()
        else:
            out.append(list(x))
    return out


def _route(moves: list[tuple[int, float, float]], start: Position) -> tuple[DirectedRoute, list[float]]:
    """A robot's route from its per-segment moves ``(edge, from, to)``; also the route coordinate at each corner."""
    edges: list[int] = []
    dirs: list[int] = []
    entry: list[float] = []
    lengths: list[float] = []
    exit_off: float | None = None
    at = [0.0]
    for e, a, b in moves:
        ds = b - a
        if ds != 0.0:
            d = 1 if ds > 0 else -1
            if edges and edges[-1] == e and dirs[-1] == d and exit_off == a:
                lengths[-1] += abs(ds)
            else:
                edges.append(e)
                dirs.append(d)
                entry.append(a)
                lengths.append(abs(ds))
            exit_off = b
        at.append(at[-1] + abs(ds))
    if not edges:
        return DirectedRoute.standing(*start), at
    breaks = np.concatenate([[0.0], np.cumsum(lengths)])
    return DirectedRoute(np.array(edges), np.array(dirs), np.array(entry), breaks), at


def _word(track: GraphTrack, cells: list[PolygonId]) -> tuple[str, ...]:
    names = track.edge_names
    out: list[str] = []
    for e, f, k in cells:
        label = f"{names[e]}×{names[f]}" + (f"/{k}" if e == f else "")
        if out and out[-1] == label:
            continue
        if len(out) >= 2 and out[-2] == label:
            out.pop()
            continue
        out.append(label)
    return tuple(out)


def _assemble(query: SearchQuery, segs: list[list[Any]]) -> GraphPlan:
    """The :class:`GraphPlan` of ``query`` along the search's straight segments ``segs`` ``[polygon, from, to]``
    (offsets in the polygon's cell, metres), timed at the robots' speeds."""
    start = query.start
    va, vb = query.speeds
    cells = [tuple(x[0]) for x in segs]
    offs = np.array([[x[1], x[2]] for x in segs], dtype=float).reshape(-1, 2, 2)
    route_a, at_a = _route([(c[0], o[0, 0], o[1, 0]) for c, o in zip(cells, offs)], start[0])
    route_b, at_b = _route([(c[1], o[0, 1], o[1, 1]) for c, o in zip(cells, offs)], start[1])
    waypoints = np.stack([at_a, at_b], axis=1)
    d = np.abs(offs[:, 1] - offs[:, 0]) if len(offs) else np.zeros((0, 2))
    seg_t = np.maximum(d[:, 0] / va, d[:, 1] / vb)
    times = np.concatenate([[0.0], np.cumsum(seg_t)])
    return GraphPlan(
        track=query.track,
        start=start,
        goal=query.goal,
        clearance=query.free_space.clearance,
        clearance_used=query.free_space.clearance_used,
        objective=query.objective,
        speeds=query.speeds,
        segment_cells=tuple(cells),
        segment_offsets=offs,
        waypoints=waypoints,
        route_a=route_a,
        route_b=route_b,
        word=_word(query.track, cells),
        makespan=float(times[-1]),
        length=float(np.hypot(d[:, 0], d[:, 1]).sum()),
        _times=times,
    )
