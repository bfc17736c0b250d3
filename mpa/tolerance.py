"""One tolerance model for the planner and the verification gate, scaled with the layout.

Positions and distances on a track are computed from edge lengths and offsets (metres); their rounding error
grows with the size of the numbers, so every tolerance is relative to the layout's scale
``L = max(1 m, total length)`` (:func:`layout_scale`; the track metric uses no vertex coordinates, so their
magnitude does not enter). Two tolerances follow from it:

- the planner's membership tolerance ``ε_plan = 1e-12·L`` (:func:`membership_tol`): a configuration is free
  when ``d ≥ D − ε_plan``;
- the gate's separation tolerance ``ε_gate = max(1e-9 m, 8·ε_plan)`` (:func:`separation_tol`): setpoints pass
  when ``d ≥ D − ε_gate`` at every row and between rows.

``ε_gate ≥ 8·ε_plan`` on every layout, so a path the planner accepts (up to ``ε_plan``) is never refused by
the gate for rounding: at most a rate error (the motion between rows) or a threshold error naming a clearance
that works. Below 125 m of track ``ε_gate`` is 1e-9 m; on 1e6 m it is 8e-6 m (1e-6 m for the planner).
"""

from __future__ import annotations

from collections.abc import Iterable

__all__ = ["GATE_FLOOR", "PLAN_REL", "layout_scale", "membership_tol", "separation_tol"]

#: The planner's membership tolerance relative to the layout's scale.
PLAN_REL = 1e-12
#: The gate's separation tolerance on small layouts (m).
GATE_FLOOR = 1e-9
#: How many times the planner's tolerance the gate's is at least.
GATE_FACTOR = 8.0


def layout_scale(lengths: Iterable[float]) -> float:
    """``max(1, Σ lengths)`` (m): the scale of a layout's coordinates.

    Parameters
    ----------
    lengths : iterable of float
        Edge lengths (m); a numpy array is read as one list (the same sum, in the same order, without a Python
        loop over its elements).
    """
    tolist = getattr(lengths, "tolist", None)
    values = tolist() if callable(tolist) else [float(x) for x in lengths]
    return max(1.0, float(sum(values)))


def membership_tol(scale: float) -> float:
    """The planner's membership tolerance (m) on a layout of scale ``scale`` (m): ``1e-12·scale``."""
    return PLAN_REL * max(1.0, float(scale))


def separation_tol(scale: float) -> float:
    """The gate's separation tolerance (m) on a layout of scale ``scale`` (m): ``max(1e-9, 8·1e-12·scale)``."""
    return max(GATE_FLOOR, GATE_FACTOR * membership_tol(scale))
