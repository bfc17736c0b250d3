"""mpa: the topological motion planning algorithms of Boughrira & Colman for two robots on a graph track.

Layout follows the paper: :mod:`mpa.tracks` (physical spaces), :mod:`mpa.cspace` (configuration spaces),
:mod:`mpa.skeleton` and :mod:`mpa.retraction` (the deformation onto the skeleton), :mod:`mpa.planners`
(the algorithms and their domains of continuity), :mod:`mpa.plan` (results), :mod:`mpa.homotopy` (classes of
paths as skeleton words), :mod:`mpa.topology` (topological complexity of the tracks; homology and TC of two
robots on any graph); shared pieces: :mod:`mpa.graph` (metric graphs), :mod:`mpa.routes` (a robot's route in
unwrapped coordinates), :mod:`mpa.errors` (the error family). numpy only.
"""

from mpa._version import __version__
from mpa.batch import BatchPlans, plan_many
from mpa.cspace import ConfigurationSpace
from mpa.errors import InvalidInputError, MPAError, NoMotionError, PlanningError
from mpa.freespace import FreeSpace, free_space
from mpa.graph import Edge, MetricGraph, farber_tc_of_graph
from mpa.graph_track import GraphTrack
from mpa.homotopy import path_word, reduce_word
from mpa.plan import Plan, PlanStep
from mpa.planners import CirclePlanner, IntervalPlanner, LollipopPlanner, Planner, make_planner, plan
from mpa.planners.graph import GraphPlan, plan_graph
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

__all__ = [
    "BatchPlans",
    "Circle",
    "CirclePlanner",
    "CircleSkeleton",
    "ConfigurationSpace",
    "ConfigurationSpaceTopology",
    "Edge",
    "Interval",
    "IntervalPlanner",
    "IntervalSkeleton",
    "InvalidInputError",
    "Lollipop",
    "LollipopPlanner",
    "LollipopSkeleton",
    "MPAError",
    "MetricGraph",
    "NoMotionError",
    "Plan",
    "PlanStep",
    "Planner",
    "PlanningError",
    "Route",
    "Skeleton",
    "Track",
    "__version__",
    "configuration_space_topology",
    "farber_tc_of_graph",
    "load_graph_json",
    "make_planner",
    "make_track",
    "path_word",
    "plan",
    "plan_many",
    "reduce_word",
    "retract",
    "rules_needed",
    "skeleton_of",
    "topological_complexity",
]
__all__ += ["FreeSpace", "GraphPlan", "GraphTrack", "free_space", "plan_graph"]
