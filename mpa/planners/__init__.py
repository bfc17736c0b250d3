"""The motion planning algorithms of the paper, one module per track, with their domains of continuity.

:mod:`mpa.planners.base` holds the shared :class:`Planner` and the rules in words; :mod:`mpa.planners.interval`,
:mod:`mpa.planners.circle` and :mod:`mpa.planners.lollipop` the algorithms of the paper's §3, §4 and §6;
:mod:`mpa.planners.factory` picks the planner of a track.
"""

from mpa.planners.base import DEFAULT_NEIGHBOURHOOD, RULES, Planner
from mpa.planners.circle import CirclePlanner
from mpa.planners.factory import make_planner, plan
from mpa.planners.interval import IntervalPlanner
from mpa.planners.lollipop import LollipopPlanner

__all__ = [
    "DEFAULT_NEIGHBOURHOOD",
    "RULES",
    "CirclePlanner",
    "IntervalPlanner",
    "LollipopPlanner",
    "Planner",
    "make_planner",
    "plan",
]
