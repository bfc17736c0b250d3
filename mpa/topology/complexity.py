"""Topological complexity (paper §4; Farber).

TC is a homotopy invariant, and the configuration space of each track deformation-retracts onto its skeleton
(a graph), so TC is read off the skeleton's *computed* Betti numbers with Farber's formula for graphs,
one value per path component.
"""

from __future__ import annotations

from mpa.graph import MetricGraph, farber_tc_of_graph
from mpa.skeleton import skeleton_of
from mpa.tracks import Track

__all__ = ["component_betti_numbers", "rules_needed", "topological_complexity"]


def component_betti_numbers(graph: MetricGraph) -> list[int]:
    """First Betti number of every connected component of ``graph`` (``E − V + 1`` per component)."""
    out = []
    for comp in graph.components():
        n_e = sum(1 for e in graph.edges if e.tail in comp)
        out.append(n_e - len(comp) + 1)
    return out


def topological_complexity(track: Track) -> tuple[int, ...]:
    """TC of every component of the configuration space of two robots on ``track``, from its skeleton.

    Returns
    -------
    tuple of int
        ``(1, 1)`` for the interval (two contractible components), ``(2,)`` for the circle, ``(3,)`` for the
        lollipop.

    Examples
    --------
    >>> from mpa.tracks import Circle, Interval, Lollipop
    >>> topological_complexity(Interval(1.0)), topological_complexity(Circle(1.0)), topological_complexity(Lollipop())
    ((1, 1), (2,), (3,))
    """
    return tuple(farber_tc_of_graph(b1) for b1 in component_betti_numbers(skeleton_of(track).graph))


def rules_needed(track: Track) -> int:
    """The least number of continuous rules a motion planner on ``track`` needs (max TC over components)."""
    return max(topological_complexity(track))
