"""Choosing the planner of a track: :func:`make_planner` (built once) and :func:`plan` (one query).

The paper's tracks (:class:`~mpa.tracks.Interval`, :class:`~mpa.tracks.Circle`, :class:`~mpa.tracks.Lollipop`) are
planned by the paper's algorithm unless ``planner="graph"`` asks for the complete graph planner
(:mod:`mpa.planners.graph`); a :class:`~mpa.graph_track.GraphTrack` (or a layout) is always planned by the graph
planner.
"""

from __future__ import annotations

from typing import Any

import numpy as np

from mpa.errors import InvalidInputError
from mpa.graph_track import GraphTrack
from mpa.planners.base import (
    DEFAULT_NEIGHBOURHOOD,
    Planner,
)
from mpa.planners.circle import CirclePlanner
from mpa.planners.graph import GraphPlan, plan_graph
from mpa.planners.interval import IntervalPlanner
from mpa.planners.lollipop import LollipopPlanner
from mpa.plans import Plan
from mpa.tracks import Circle, Interval, Lollipop, Track

__all__ = ["OBJECTIVES", "PLANNERS", "make_planner", "plan"]

#: Values of ``plan(..., planner=)``: the paper's algorithm or the complete graph planner (``auto``: the paper's on
#: the paper's tracks, the graph planner on any other layout).
PLANNERS = ("auto", "paper", "graph")
#: Values of ``plan(..., objective=)`` for the graph planner.
OBJECTIVES = ("fastest", "shortest")


def make_planner(track: Track, clearance: float = 0.0, neighbourhood: float = DEFAULT_NEIGHBOURHOOD) -> Planner:
    """The planner of ``track`` (built once; call ``.plan(start, goal)`` for every query)."""
    if isinstance(track, Interval):
        return IntervalPlanner(track, clearance, neighbourhood)
    if isinstance(track, Circle):
        return CirclePlanner(track, clearance, neighbourhood)
    if isinstance(track, Lollipop):
        return LollipopPlanner(track, clearance, neighbourhood)
    raise InvalidInputError(f"track is {track!r}, expected an Interval, Circle or Lollipop")


def plan(
    track: Track | GraphTrack,
    start: Any,
    goal: Any,
    clearance: float = 0.0,
    neighbourhood: float = DEFAULT_NEIGHBOURHOOD,
    *,
    planner: str = "auto",
    objective: str = "fastest",
    speeds: Any = (1.0, 1.0),
    footprint: Any = None,
) -> Plan | GraphPlan:
    """Plan a collision-free motion of two robots from ``start`` to ``goal``.

    On the paper's tracks the paper's algorithm answers (a :class:`~mpa.plans.Plan` with its domain of continuity);
    with ``planner="graph"``, or on any other track graph, the complete graph planner answers (a
    :class:`~mpa.planners.graph.GraphPlan`: it finds a motion whenever one exists).

    Parameters
    ----------
    track : Track or GraphTrack
    start, goal : pair
        Robots A and B: track coordinates on the paper's tracks (floats, m); on a graph track positions
        ``(edge, offset)``, ``"EDGE:OFFSET"`` or vertex names.
    clearance : float
        Required clearance D >= 0 (metres).
    neighbourhood : float
        Neighbourhood size of the paper planner's domains, as a fraction of half the loop.
    planner : {"auto", "paper", "graph"}
        ``auto``: the paper's algorithm on the paper's tracks, the graph planner otherwise.
    objective : {"fastest", "shortest"}
        Graph planner only: minimum time for the per-robot ``speeds`` over all homotopy classes, or minimum length.
    speeds : (float, float)
        Graph planner only: per-robot speed limits for ``objective="fastest"`` (m/s).
    footprint : None, mpa.Disc, mpa.Rectangle, pair or spec string
        The robots' bodies in the plane (:mod:`mpa.footprint`, :mod:`mpa.planar`): the graph planner then keeps
        them apart in the layout's drawing too (on the paper's tracks it answers, with their drawing).

    Returns
    -------
    Plan or GraphPlan

    Raises
    ------
    InvalidInputError
        Bad start, goal, clearance, track, planner or objective.
    NoMotionError
        No collision-free motion exists (the message says why).

    Examples
    --------
    >>> from mpa import Lollipop, plan
    >>> p = plan(Lollipop(1.0, 1.0), (0.1, 0.6), (0.8, 0.3))
    >>> p.domain, p.word
    (1, ('+I1', '+S1a', '+S2a', '+S3b', '-I2'))
    >>> g = plan(Lollipop(1.0, 1.0), (0.2, 0.5), (0.5, 0.2), clearance=0.05, planner="graph")
    >>> round(g.min_distance(), 9) >= 0.05
    True
    """
    if planner not in PLANNERS:
        raise InvalidInputError(f"planner is {planner!r}, expected one of {', '.join(PLANNERS)}")
    if objective not in OBJECTIVES:
        raise InvalidInputError(f"objective is {objective!r}, expected one of {', '.join(OBJECTIVES)}")
    if isinstance(track, (Interval, Circle, Lollipop)):
        if footprint is not None:
            if planner == "paper":
                raise InvalidInputError("planner is 'paper' with a footprint, expected 'graph' or 'auto'")
            planner = "graph"
        if planner != "graph":
            return make_planner(track, clearance, neighbourhood).plan(start, goal)
        return plan_graph(
            track.as_graph_track(),
            _paper_positions(track, start, "start"),
            _paper_positions(track, goal, "goal"),
            clearance,
            objective,
            speeds,
            footprint,
        )
    if planner == "paper":
        raise InvalidInputError(f"planner is 'paper' for {track!r}, expected an Interval, Circle or Lollipop track")
    return plan_graph(track, start, goal, clearance, objective, speeds, footprint)


def _paper_positions(track: Track, pair: Any, name: str) -> tuple[tuple[int, float], tuple[int, float]]:
    """Track coordinates ``(a, b)`` of a paper track as graph positions on :meth:`Track.as_graph_track`."""
    p = np.asarray(track.validate(pair, name), dtype=float)
    if p.shape != (2,):
        raise InvalidInputError(f"{name} has shape {p.shape}, expected two track coordinates (robot A, robot B)")
    edges, offsets = track.to_graph_position(p)
    return (int(edges[0]), float(offsets[0])), (int(edges[1]), float(offsets[1]))
