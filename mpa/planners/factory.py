"""Choosing the planner of a track: :func:`make_planner` (built once) and :func:`plan` (one query)."""

from __future__ import annotations

from numpy.typing import ArrayLike

from mpa.errors import InvalidInputError
from mpa.plan import Plan
from mpa.planners.base import (
    DEFAULT_NEIGHBOURHOOD,
    Planner,
)
from mpa.planners.circle import CirclePlanner
from mpa.planners.interval import IntervalPlanner
from mpa.planners.lollipop import LollipopPlanner
from mpa.tracks import Circle, Interval, Lollipop, Track

__all__ = ["make_planner", "plan"]


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
    track: Track,
    start: ArrayLike,
    goal: ArrayLike,
    clearance: float = 0.0,
    neighbourhood: float = DEFAULT_NEIGHBOURHOOD,
) -> Plan:
    """Plan a collision-free motion of two robots from ``start`` to ``goal`` with the paper's algorithm.

    Parameters
    ----------
    track : Track
    start, goal : array_like, shape (2,)
        Track coordinates of robots A and B.
    clearance : float
        Required clearance D >= 0 (metres).
    neighbourhood : float
        Neighbourhood size of the domains, as a fraction of half the loop.

    Returns
    -------
    Plan

    Raises
    ------
    InvalidInputError
        Bad start, goal, clearance or track.
    NoMotionError
        No collision-free motion exists (the message says why).

    Examples
    --------
    >>> from mpa import Lollipop, plan
    >>> p = plan(Lollipop(1.0, 1.0), (0.1, 0.6), (0.8, 0.3))
    >>> p.domain, p.word
    (1, ('+I1', '+S1a', '+S2a', '+S3b', '-I2'))
    """
    return make_planner(track, clearance, neighbourhood).plan(start, goal)
