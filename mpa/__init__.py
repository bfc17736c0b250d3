"""mpa: the topological motion planning algorithms of Boughrira & Colman for two robots on a graph track.

Layout follows the paper: :mod:`mpa.tracks` (physical spaces), :mod:`mpa.cspace` (configuration spaces),
:mod:`mpa.skeleton` and :mod:`mpa.retraction` (the deformation onto the skeleton), :mod:`mpa.planners`
(the algorithms and their domains of continuity; the function ``mpa.plan`` plans one query), :mod:`mpa.plans`
(``MotionPlan``, the interface every plan satisfies, and the paper planner's result ``Plan``),
:mod:`mpa.homotopy` (classes of paths as skeleton words), :mod:`mpa.topology`
(topological complexity of the tracks; homology and TC of two robots on any graph); shared pieces:
:mod:`mpa.graph` (metric graphs), :mod:`mpa.routes` (a robot's route in unwrapped coordinates), :mod:`mpa.errors`
(the error family). numpy only.
"""

import importlib
import importlib.util
from typing import TYPE_CHECKING, Any

from mpa.errors import InvalidInputError, MPAError, NoMotionError, PlanningError

if TYPE_CHECKING:  # the names as type checkers see them
    from mpa._version import __version__
    from mpa.batch import BatchPlans, plan_many
    from mpa.cspace import ConfigurationSpace
    from mpa.footprint import Disc, Footprints, Rectangle, parse_footprint
    from mpa.freespace import FreeSpace, free_space
    from mpa.graph import Edge, MetricGraph, farber_tc_of_graph
    from mpa.graph_track import GraphTrack
    from mpa.homotopy import path_word, reduce_word
    from mpa.planar import PlanarFreeSpace, planar_free_space
    from mpa.planners import CirclePlanner, IntervalPlanner, LollipopPlanner, Planner, make_planner, plan
    from mpa.planners.graph import GraphPlan, plan_graph
    from mpa.plans import MotionPlan, Plan, PlanStep
    from mpa.retraction import retract
    from mpa.routes import Route
    from mpa.skeleton import CircleSkeleton, IntervalSkeleton, LollipopSkeleton, Skeleton, skeleton_of
    from mpa.topology import (
        ConfigurationSpaceTopology,
        configuration_space_topology,
        load_graph_json,
        rules_needed,
        topological_complexity,
    )
    from mpa.tracks import Circle, Interval, Lollipop, Track, make_track

# The rest of the public names are imported on first use (PEP 562): ``import mpa`` (and so every ``mpa``
# command's start-up, and ``mpa --help``) does not import numpy and the planners until they are needed.
# ``__version__`` too: reading the package metadata imports ``importlib.metadata`` and ``email`` (about 30 ms).
_LAZY = {
    "__version__": "mpa._version",
    "BatchPlans": "mpa.batch",
    "plan_many": "mpa.batch",
    "ConfigurationSpace": "mpa.cspace",
    "FreeSpace": "mpa.freespace",
    "Disc": "mpa.footprint",
    "Footprints": "mpa.footprint",
    "Rectangle": "mpa.footprint",
    "parse_footprint": "mpa.footprint",
    "PlanarFreeSpace": "mpa.planar",
    "planar_free_space": "mpa.planar",
    "free_space": "mpa.freespace",
    "Edge": "mpa.graph",
    "MetricGraph": "mpa.graph",
    "farber_tc_of_graph": "mpa.graph",
    "GraphTrack": "mpa.graph_track",
    "path_word": "mpa.homotopy",
    "reduce_word": "mpa.homotopy",
    "MotionPlan": "mpa.plans",
    "Plan": "mpa.plans",
    "PlanStep": "mpa.plans",
    "CirclePlanner": "mpa.planners",
    "IntervalPlanner": "mpa.planners",
    "LollipopPlanner": "mpa.planners",
    "Planner": "mpa.planners",
    "make_planner": "mpa.planners",
    "plan": "mpa.planners",
    "GraphPlan": "mpa.planners.graph",
    "plan_graph": "mpa.planners.graph",
    "retract": "mpa.retraction",
    "Route": "mpa.routes",
    "CircleSkeleton": "mpa.skeleton",
    "IntervalSkeleton": "mpa.skeleton",
    "LollipopSkeleton": "mpa.skeleton",
    "Skeleton": "mpa.skeleton",
    "skeleton_of": "mpa.skeleton",
    "ConfigurationSpaceTopology": "mpa.topology",
    "configuration_space_topology": "mpa.topology",
    "load_graph_json": "mpa.topology",
    "rules_needed": "mpa.topology",
    "topological_complexity": "mpa.topology",
    "Circle": "mpa.tracks",
    "Interval": "mpa.tracks",
    "Lollipop": "mpa.tracks",
    "Track": "mpa.tracks",
    "make_track": "mpa.tracks",
}


def __getattr__(name: str) -> Any:
    """Import a public name (or a submodule, as ``import mpa; mpa.tracks``) on first use."""
    mod = _LAZY.get(name)
    if mod is None:
        if name.startswith("_") or importlib.util.find_spec(f"{__name__}.{name}") is None:
            raise AttributeError(f"module {__name__!r} has no attribute {name!r}")
        return importlib.import_module(f"{__name__}.{name}")
    value = getattr(importlib.import_module(mod), name)
    globals()[name] = value
    return value


def __dir__() -> list[str]:
    return sorted(set(globals()) | set(_LAZY))


__all__ = [
    "BatchPlans",
    "Circle",
    "CirclePlanner",
    "CircleSkeleton",
    "ConfigurationSpace",
    "ConfigurationSpaceTopology",
    "Disc",
    "Edge",
    "Footprints",
    "FreeSpace",
    "GraphPlan",
    "GraphTrack",
    "Interval",
    "IntervalPlanner",
    "IntervalSkeleton",
    "InvalidInputError",
    "Lollipop",
    "LollipopPlanner",
    "LollipopSkeleton",
    "MPAError",
    "MetricGraph",
    "MotionPlan",
    "NoMotionError",
    "Plan",
    "PlanStep",
    "PlanarFreeSpace",
    "Planner",
    "PlanningError",
    "Rectangle",
    "Route",
    "Skeleton",
    "Track",
    "__version__",
    "configuration_space_topology",
    "farber_tc_of_graph",
    "free_space",
    "load_graph_json",
    "make_planner",
    "make_track",
    "parse_footprint",
    "path_word",
    "plan",
    "plan_graph",
    "plan_many",
    "planar_free_space",
    "reduce_word",
    "retract",
    "rules_needed",
    "skeleton_of",
    "topological_complexity",
]
