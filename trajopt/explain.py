"""Why a query gets no verified setpoints, in words the caller can act on: a rate too low (and the lowest that
works), a clearance at the threshold of the motion (and a lower one that works), ends too close, bodies too close
in the plane; and the ladder of round rates such messages name (:data:`RATE_LADDER`)."""

from __future__ import annotations

from typing import TYPE_CHECKING, Any, cast

import numpy as np

from mpa.errors import MPAError, PlanningError
from mpa.planners.graph import GraphPlan
from mpa.plans import Plan
from trajopt.path.planview import densify, plan_view

if TYPE_CHECKING:
    from trajopt.generator import TrajectoryGenerator

__all__ = ["RATE_LADDER", "explain_plane", "explain_rejection", "explain_threshold"]


def _ladder(lo: float, hi: float) -> list[float]:
    """Round rates (Hz) from below ``lo`` up to ``hi``: 1, 1.2, 1.5, 2, 2.5, 3, 4, 5, 6, 8 per decade."""
    out: list[float] = []
    e = int(np.floor(np.log10(max(lo, 1e-3))))
    while True:
        for m in RATE_LADDER:
            r = float(f"{m * 10.0**e:.6g}")
            if r > hi:
                return out
            out.append(r)
        e += 1


#: Mantissas of the round rates tried when a rate is too low (see :meth:`TrajectoryGenerator.lowest_rate`).
RATE_LADDER = (1.0, 1.2, 1.5, 2.0, 2.5, 3.0, 4.0, 5.0, 6.0, 8.0)


class _RejectedError(PlanningError):
    """Neither the optimised motion nor the re-timed plan passes the gate (the caller may be told why)."""


def _decimal_at_most(x: float) -> str:
    """The shortest decimal (6 to 17 significant digits) whose value is at most ``x``: the number a message names
    is the number that was tried, and reading it back never gives more than ``x``."""
    for digits in range(6, 18):
        text = f"{x:.{digits}g}"
        if float(text) <= x:
            return text
    return repr(x)


def explain_threshold(gen: TrajectoryGenerator, plan: Plan | GraphPlan) -> str:
    """At a threshold clearance (the plan keeps exactly D somewhere while the robots move) no rate can be
    verified: the gate's bound between rows loses ``a·Δt²/8``. Names a slightly lower clearance that gives
    verified setpoints (tried here, at most three), or "" if the plan is not at a threshold or none works."""
    margin = gen.separation_margin()
    if gen.clearance <= 0 or float(plan.min_distance()) - gen.clearance >= margin:
        return ""
    for drop in (2.0 * margin, 1e-3 * gen.clearance, 1e-2 * gen.clearance):
        text = _decimal_at_most(gen.clearance - drop)
        lower = float(text)
        if lower <= 0 or lower >= gen.clearance:
            continue
        try:
            gen = type(gen)(gen.track, clearance=lower, limits=gen.limits, rate=gen.rate)
            gen._generate(gen.plan(plan.start, plan.goal), None)  # no explanation of its own (no recursion)
        except (MPAError, _RejectedError):
            continue
        return (
            f"clearance {gen.clearance!r} m is at the threshold of this motion: the robots must pass exactly "
            f"{gen.clearance!r} m apart while moving, which setpoints at no rate can verify (between rows they "
            f"may come closer); expected a clearance below it: {text} m works at {gen.rate:g} Hz"
        )
    return ""


def explain_rejection(gen: TrajectoryGenerator, plan: Plan | GraphPlan) -> str:
    """Why every candidate of ``plan`` fails the gate at this rate, if the caller can fix it ("" if not)."""
    if gen.footprint is not None:  # bodies are planned on layouts only: a graph plan
        why = explain_plane(gen, cast(GraphPlan, plan))
        if why:
            return why
    best = gen.lowest_rate(plan)
    margin = gen.separation_margin()
    if best is not None:
        slack = float(plan.min_distance()) - gen.clearance
        tight = ""
        if slack < margin:  # the layout itself leaves (almost) no room: say so, and what clearance would do
            lower = gen.clearance + slack - 2.0 * margin
            tight = (
                f" (the motion's closest approach keeps only {max(slack, 0.0):.3g} m beyond the clearance, the "
                f"most this track allows here, and setpoints at {gen.rate:g} Hz need {margin:.3g} m"
                + (f"; or lower the clearance to about {lower:.6g} m)" if lower > 0.0 else ")")
            )
        return (
            f"rate is {gen.rate!r} Hz, too low for this motion: between rows the robots could come closer "
            f"than the clearance {gen.clearance!r} m; the lowest usable rate is {best:g} Hz{tight}"
        )
    view = plan_view(plan)
    ends: tuple[Any, Any] = (plan.start, plan.goal)
    for name, st in zip(("start", "goal"), ends):
        d = view.separation(name)
        if d < gen.clearance + margin:
            where = (
                f"({view.graph.position_name(*st[0])}, {view.graph.position_name(*st[1])})"
                if view.is_graph
                else f"({float(st[0])!r}, {float(st[1])!r})"
            )
            return (
                f"{name} {where} has the robots {d!r} apart, expected more than "
                f"the clearance {gen.clearance!r} plus {margin:.3g} m: the gate cannot verify setpoints that "
                f"leave robots at rest exactly at the clearance (at {gen.rate:g} Hz); lower the clearance "
                f"or move the {name} apart"
            )
    return ""


def explain_plane(gen: TrajectoryGenerator, plan: GraphPlan) -> str:
    """The bodies pass closer than the gate's between-rows margin at this rate ("" if they do not)."""
    from mpa.planar import corner_sweep
    from trajopt.verify.planar import row_gaps

    assert gen.footprint is not None
    view = plan_view(plan)
    e, o = view.positions(densify(view.waypoints, 0.01))
    g = row_gaps(view.graph, gen.footprint, e, o)
    need = 0.5 * gen._plane_margin(gen.rate)
    # a rectangle at rest on a corner at the start or goal: the gate bounds its turn by the disc of its reach
    swept = ""
    for (pa, pb), k in ((plan.start, 0), (plan.goal, len(g) - 1)):
        _, depth = corner_sweep(view.graph, gen.footprint, pa, pb)
        if -depth < min(g[k], need):
            g[k] = -depth
            swept = " (a rectangle on a corner: the disc it sweeps turning there)"
    low = float(np.min(g))
    if low >= need:
        return ""
    where = "at the start" if g[0] < need else ("at the goal" if g[-1] < need else "on the only way there")
    return (
        f"footprint {gen.footprint.spec()}: the bodies come within {max(low, 0.0):.3g} m of each other "
        f"{where}{swept}, "
        f"and setpoints at {gen.rate:g} Hz are verified between rows only with {need:.3g} m between them; "
        "use smaller bodies, start or goal further apart, or a higher rate"
    )
