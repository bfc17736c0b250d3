"""What the OMPL baselines share: the joint state space of two robots and the vertex-only path simplification.

OMPL is imported by the callers (it is an optional dependency) and passed in as its ``base`` module.
"""

from __future__ import annotations

from typing import Any

__all__ = ["joint_state_space", "simplify_vertices"]


def joint_state_space(ob: Any, high: float, *, circle: bool = False) -> Any:
    """The joint configuration space of two robots.

    Parameters
    ----------
    ob : module
        ``ompl.base``.
    high : float
        Upper bound of each robot's coordinate (m) on a box ``[0, high]²``.
    circle : bool
        Two angles (``SO2 × SO2``, weight 1 each) instead of the box (``high`` unused).
    """
    if circle:
        space = ob.CompoundStateSpace()
        space.addSubspace(ob.SO2StateSpace(), 1.0)
        space.addSubspace(ob.SO2StateSpace(), 1.0)
        return space
    space = ob.RealVectorStateSpace(2)
    bounds = ob.RealVectorBounds(2)
    bounds.setLow(0.0)
    bounds.setHigh(high)
    space.setBounds(bounds)
    return space


def simplify_vertices(simp: Any, path: Any) -> None:
    """Simplify ``path`` in place by vertex-to-vertex steps only (they call nothing but the motion validator):
    ``reduceVertices``, ``collapseCloseVertices``, then ``reduceVertices`` while it improves (at most 5 more)."""
    more = simp.reduceVertices(path)
    simp.collapseCloseVertices(path)
    k = 0
    while more and k < 5:
        more = simp.reduceVertices(path)
        k += 1
