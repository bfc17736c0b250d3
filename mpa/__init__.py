"""mpa: the topological motion planning algorithms of Boughrira & Colman for two robots on a graph track."""

from mpa.errors import InvalidInputError, MPAError, NoMotionError, PlanningError
from mpa.graph import Edge, MetricGraph, farber_tc_of_graph

__all__ = [
    "Edge",
    "InvalidInputError",
    "MPAError",
    "MetricGraph",
    "NoMotionError",
    "PlanningError",
    "farber_tc_of_graph",
]
