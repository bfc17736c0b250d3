"""The demo figure of a :class:`~trajopt.result.Trajectory` (matplotlib, Agg; imported only by the CLI).

One figure, three views: the track with both robots' routes, the path in the flat configuration space
(track coordinates of A and B) with the skeleton and the forbidden band ``d < D``, and ``s, v, a, j`` of both
robots over time with the limits (A solid, B dashed, so that equal curves of a symmetric swap both show). The
track and configuration-space panels are drawn with :mod:`trajopt.viz.drawing`.
"""

from __future__ import annotations

import io
import os
from collections.abc import Mapping
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np
from numpy.typing import NDArray

from mpa.skeleton import skeleton_of
from mpa.tracks import Track

if TYPE_CHECKING:  # pragma: no cover
    from matplotlib.axes import Axes
    from matplotlib.figure import Figure

    from trajopt.export import Trajectory

__all__ = [
    "draw_cspace",
    "draw_profiles",
    "draw_track",
    "figure_png",
    "plot_trajectory",
    "save_and_close",
    "save_figure",
]

COLORS = ("tab:blue", "tab:orange")
#: Line styles of robots A and B in the profiles: B dashed on top of A, so equal curves (a symmetric swap) show both.
LINESTYLES = ("-", (0, (4, 2)))
LINEWIDTHS = (2.2, 1.4)


def draw_track(ax: Axes, track: Track, track_pos: NDArray[np.float64] | None = None) -> None:
    """The track in its planar embedding, with the robots' motion (track coordinates, shape (N, 2)).

    Each robot's route is drawn beside the track on its own side (A outside the loop and above the stick, B inside
    and below), with its start (filled triangle) and goal (empty triangle) labelled "A start", "B goal", ...
    """
    from trajopt.viz import drawing as dr

    dr.draw_track(ax, track, labels=True, ccw_arrow=False)
    if track_pos is not None:
        for r, name in enumerate("AB"):
            dr.draw_motion(ax, track, track_pos[:, r], name, arrows=(0.5,), lw=1.8)
        dr.draw_robots(ax, track, track_pos[-1], final=True, labels=("A goal", "B goal"))
        dr.draw_robots(ax, track, track_pos[0], labels=("A start", "B start"))
    ax.set_title("track and routes (A: outer side, B: inner side)")


def draw_cspace(ax: Axes, track: Track, clearance: float, paths: dict[str, NDArray[np.float64]]) -> None:
    """The flat configuration space ``(a, b)`` with the band ``d < D``, the skeleton and some paths.

    The first path is drawn dashed black, the second solid in :data:`trajopt.viz.drawing.TRAJECTORY_COLOR` (dark
    indigo, apart from the band's red); the start (filled) and goal (empty) are labelled.
    """
    from trajopt.viz import drawing as dr

    dr.draw_flat_cspace(ax, track, clearance=clearance, axis_labels=False)
    dr.draw_skeleton(ax, skeleton_of(track), labels=False, arrows=False, lw=1.2, alpha=0.6, vertices=False)
    ax.plot([], [], color=dr.BLOCK_COLORS["S1"], lw=1.2, alpha=0.6, label="skeleton")
    styles = (("k", "--", 1.2, 7.0), (dr.TRAJECTORY_COLOR, "-", 1.8, 6.0))  # colour, line style, width, zorder
    for (name, pts), (color, ls, lw, zorder) in zip(paths.items(), styles):
        dr.draw_flat_path(ax, track, pts, arrows=(), color=color, ls=ls, lw=lw, zorder=zorder)
        ax.plot([], [], label=name, color=color, ls=ls, lw=lw)
    any_pts = next(iter(paths.values()))
    dr.draw_state(ax, any_pts[0], "start", size=6, offset=(6, -14))
    dr.draw_state(ax, any_pts[-1], "goal", size=6, filled=False, offset=(6, 6))
    ax.set_xlabel("a (track coordinate of A, m)")
    ax.set_ylabel("b (track coordinate of B, m)")
    ax.set_title(f"configuration space (red: d < {clearance:g} m)")
    ax.legend(fontsize=7, loc="upper left", framealpha=0.9)


def draw_profiles(axes: Any, traj: Trajectory) -> None:
    """``s, v, a, j`` of both robots over time on four axes, with the limits dotted (A solid, B dashed)."""
    lims = {"v": traj.limits.v, "a": traj.limits.a, "j": traj.limits.j}
    for ax, (key, unit) in zip(axes, (("s", "m"), ("v", "m/s"), ("a", "m/s²"), ("j", "m/s³"))):
        val = getattr(traj, key)
        for r, name in enumerate("AB"):
            ax.plot(traj.t, val[:, r], color=COLORS[r], ls=LINESTYLES[r], lw=LINEWIDTHS[r], label=name, zorder=3 + r)
        if key in lims:
            same = lims[key][0] == lims[key][1]
            for r in (0,) if same else (0, 1):
                col = "0.4" if same else COLORS[r]
                ax.axhline(lims[key][r], color=col, ls=":", lw=0.9)
                ax.axhline(-lims[key][r], color=col, ls=":", lw=0.9)
        ax.set_ylabel(f"{key} ({unit})")
        ax.grid(alpha=0.3)
    axes[0].legend(fontsize=8, loc="upper left")
    axes[-1].set_xlabel("t (s)")


def plot_trajectory(traj: Trajectory) -> Figure:
    """The demo figure (track, configuration space, profiles) of a trajectory."""
    from matplotlib.figure import Figure

    from trajopt.viz.drawing import track_title

    fig = Figure(figsize=(12, 8), constrained_layout=True)
    gs = fig.add_gridspec(4, 2, width_ratios=[1.0, 1.2])
    ax_track = fig.add_subplot(gs[0:2, 0])
    ax_cs = fig.add_subplot(gs[2:4, 0])
    prof = [fig.add_subplot(gs[i, 1]) for i in range(4)]
    plan: Any = traj.plan  # a paper plan (graph trajectories are drawn by trajopt.viz.layout_animation)
    draw_track(ax_track, plan.track, traj.track)
    plan_pts = plan.sample(max(400, plan.samples_needed(0.005)))
    draw_cspace(ax_cs, plan.track, traj.clearance, {"plan": plan_pts, "trajectory": traj.track})
    draw_profiles(prof, traj)
    what = "fallback: plan re-timed" if traj.fallback else "optimized"
    fig.suptitle(
        f"{track_title(plan.track)}: ({plan.start[0]:g}, {plan.start[1]:g}) → "
        f"({plan.goal[0]:g}, {plan.goal[1]:g}), domain {traj.domain}, makespan {traj.makespan:.2f} s ({what})"
    )
    return fig


def save_figure(fig: Figure, path: str | os.PathLike[str], dpi: float, **savefig_kwargs: Any) -> Path:
    """Write ``fig`` to ``path`` atomically (a temporary file beside it, then a rename; nothing left on failure).

    The format is the suffix of ``path`` (PNG without one); the parent folders are made. ``savefig_kwargs`` go to
    :meth:`matplotlib.figure.Figure.savefig` (e.g. ``facecolor``). Returns the path written.
    """
    out = Path(path)
    out.parent.mkdir(parents=True, exist_ok=True)
    from trajopt.io.atomic import atomic_path

    with atomic_path(out) as tmp:
        fig.savefig(tmp, dpi=dpi, format=out.suffix.lstrip(".").lower() or "png", **savefig_kwargs)
    return out


def title_with_words(fig: Figure, title: str, words: Mapping[str, str] | None) -> None:
    """Give ``fig`` the title ``title`` with each cart's motion in words (``{"A": ..., "B": ...}``) on a line of its
    own below it; no title when both are empty."""
    text = title
    if words:
        text += "".join(f"\n{k}: {w}" for k, w in words.items())
    if text:
        fig.suptitle(text, fontsize=10)


def save_and_close(fig: Figure, path: str | os.PathLike[str], dpi: float) -> Path:
    """Lay ``fig`` out tightly, write it with :func:`save_figure` and close it (pyplot forgets it).

    Returns the path written.
    """
    import matplotlib.pyplot as plt

    fig.tight_layout()
    try:
        return save_figure(fig, path, dpi)
    finally:
        plt.close(fig)


def figure_png(fig: Figure) -> bytes:
    """PNG bytes of a figure (Agg canvas, no display needed)."""
    from matplotlib.backends.backend_agg import FigureCanvasAgg

    FigureCanvasAgg(fig)
    buf = io.BytesIO()
    fig.savefig(buf, format="png", dpi=110)
    return buf.getvalue()
