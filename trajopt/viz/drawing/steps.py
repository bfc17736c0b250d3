"""One step of a plan (preliminary, main, final) drawn on the track and in the flat configuration space."""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np
from matplotlib.axes import Axes
from numpy.typing import ArrayLike

from mpa.plans import Plan
from mpa.skeleton import skeleton_of
from trajopt.viz.drawing.cspace import draw_flat_cspace, draw_flat_path, draw_state
from trajopt.viz.drawing.labels import free_offset
from trajopt.viz.drawing.skeleton import draw_skeleton
from trajopt.viz.drawing.style import STEP_COLORS, FloatArray
from trajopt.viz.drawing.track import draw_motion, draw_robots, draw_track


# ---------------------------------------------------------------------------------------------------
# a plan, step by step
@dataclass(frozen=True)
class StepStyle:
    """What :func:`draw_plan_step` shows: which step (None: the initial and final states) and the labels."""

    step: str | None = None
    samples: int = 1500
    show_traces: bool = True


def _step_range(p: Plan, name: str) -> tuple[float, float]:
    st = next(s for s in p.steps if s.name == name)
    return st.u_start, st.u_end


def draw_plan_step(axes: Sequence[Axes], p: Plan, style: StepStyle = StepStyle()) -> None:
    """One step of a plan in the paper's two pictures: the robots on the track, the state in the flat space.

    Left: the track; the robots at the beginning (filled triangles) and end (empty) of the step and each robot's
    motion during the step. Right: the flat configuration space with the skeleton, the whole plan faint, the step
    in its colour, and the states ``x_i, x_i', x_f', x_f``.

    Parameters
    ----------
    axes : (Axes, Axes)
        Physical and configuration-space axes.
    p : Plan
    style : StepStyle
        ``style.step`` is ``"preliminary"``, ``"main"``, ``"final"`` or None (the query: initial and final states,
        with the traces of H that take them to the skeleton).
    """
    ax_phys, ax_flat = axes
    track = p.track
    sk = p.skeleton if p.skeleton is not None else skeleton_of(track)
    draw_track(ax_phys, track, ccw_arrow=style.step is None)
    draw_flat_cspace(ax_flat, track, clearance=p.clearance)
    sk_samples = draw_skeleton(ax_flat, sk, alpha=0.9)
    u = np.linspace(0.0, 1.0, style.samples)
    whole = p.path(u)
    draw_flat_path(ax_flat, track, whole, color="0.6", lw=1.2, arrows=(), alpha=0.8)
    xi, xf = p.skeleton_start, p.skeleton_goal
    if style.step is None:
        draw_robots(ax_phys, track, p.start, final=False, labels=("$A_i$", "$B_i$"))
        draw_robots(ax_phys, track, p.goal, final=True, labels=("$A_f$", "$B_f$"))
        if style.show_traces:
            for nm in ("preliminary", "final"):
                u0, u1 = _step_range(p, nm)
                if u1 > u0:
                    seg = p.path(np.linspace(u0, u1, 300))
                    draw_flat_path(ax_flat, track, seg, color=STEP_COLORS[nm], lw=2.0, arrows=(1.0,), ls="-")
    else:
        u0, u1 = _step_range(p, style.step)
        seg = p.path(np.linspace(u0, u1, max(2, int(style.samples * max(u1 - u0, 0.05)))))
        if u1 > u0:
            draw_motion(ax_phys, track, seg[:, 0], "A")
            draw_motion(ax_phys, track, seg[:, 1], "B")
            draw_flat_path(ax_flat, track, seg, color=STEP_COLORS[style.step], lw=2.6, arrows=(0.5, 1.0))
        else:
            ax_phys.text(
                0.5,
                0.02,
                "(empty step: the state is already on the skeleton)",
                transform=ax_phys.transAxes,
                ha="center",
                fontsize=9,
                color="0.3",
            )
        draw_robots(ax_phys, track, seg[-1], final=True, labels=("", ""))
        draw_robots(ax_phys, track, seg[0], final=False)  # on top: a robot that waits shows filled
    lines = np.vstack([whole[::5], *sk_samples.values()]) if sk_samples else whole[::5]
    _draw_query_states(ax_flat, p.start, xi, "i", STEP_COLORS["preliminary"], filled=True, lines=lines)
    _draw_query_states(ax_flat, p.goal, xf, "f", STEP_COLORS["final"], filled=False, lines=lines)


def _draw_query_states(
    ax: Axes, state: ArrayLike, on_skeleton: ArrayLike, index: str, color: str, *, filled: bool, lines: FloatArray
) -> None:
    """A state ``x`` and its retraction ``x'``, each label placed where it covers the least (:func:`free_offset`).

    When ``x = x'`` only ``x`` is drawn.
    """
    x = np.asarray(state, dtype=float)
    xs = np.asarray(on_skeleton, dtype=float)
    both = np.vstack([lines, x, xs])
    label = f"$x_{index}$"
    draw_state(ax, x, label, color="k", filled=filled, offset=free_offset(ax, x, both), ha="center", va="center")
    if float(np.max(np.abs(xs - x))) > 1e-9 * max(1.0, float(np.max(np.abs(x)))):
        off = free_offset(ax, xs, both)
        draw_state(ax, xs, f"$x_{index}'$", color=color, filled=filled, size=6, offset=off, ha="center", va="center")
