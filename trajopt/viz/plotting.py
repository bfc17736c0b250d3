"""The demo figure of a :class:`~trajopt.export.Trajectory` (matplotlib, Agg; imported only by the CLI).

One figure, three views: the track with both robots' routes, the path in the flat configuration space
(track coordinates of A and B) with the skeleton and the forbidden band ``d < D``, and ``s, v, a, j`` of both
robots over time with the limits. Kept small on purpose; richer drawings belong to ``trajopt.viz.drawing``.
"""

from __future__ import annotations

import io
import os
from typing import TYPE_CHECKING, Any

import numpy as np
from numpy.typing import NDArray

from mpa.skeleton import IntervalSkeleton, SkeletonPoint, skeleton_of
from mpa.tracks import Track

if TYPE_CHECKING:  # pragma: no cover
    from matplotlib.axes import Axes
    from matplotlib.figure import Figure

    from trajopt.export import Trajectory

__all__ = ["draw_cspace", "draw_profiles", "draw_track", "figure_png", "plot_trajectory"]

COLORS = ("tab:blue", "tab:orange")


def _split_jumps(pts: NDArray[np.float64], jump: float) -> list[NDArray[np.float64]]:
    """Split a polyline where consecutive points jump (wrap of a coordinate) by more than ``jump``."""
    if len(pts) < 2:
        return [pts]
    cut = np.flatnonzero(np.max(np.abs(np.diff(pts, axis=0)), axis=1) > jump) + 1
    return np.split(pts, cut)


def draw_track(ax: Axes, track: Track, track_pos: NDArray[np.float64] | None = None) -> None:
    """The track in its planar embedding, with the robots' motion (track coordinates, shape (N, 2))."""
    p = np.linspace(0.0, track.total_length, 800, endpoint=False)
    xy = track.embed(p)
    for part in _split_jumps(xy, 0.05 * track.total_length):
        ax.plot(part[:, 0], part[:, 1], color="0.75", lw=6, solid_capstyle="round", zorder=1)
    if track_pos is not None:
        for r, name in enumerate("AB"):
            pts = track.embed(track_pos[:, r])
            off = (0.012 if r else -0.012) * track.total_length
            for part in _split_jumps(pts, 0.05 * track.total_length):
                ax.plot(part[:, 0], part[:, 1] + off, color=COLORS[r], lw=1.5, zorder=2)
            ax.plot(*pts[0], "o", color=COLORS[r], ms=7, zorder=3, label=f"{name} start")
            ax.plot(*pts[-1], "s", color=COLORS[r], ms=7, zorder=3, mfc="white", label=f"{name} goal")
    ax.set_aspect("equal")
    ax.set_title("track and routes")
    ax.legend(fontsize=7, loc="best")
    ax.set_xticks([])
    ax.set_yticks([])


def draw_cspace(ax: Axes, track: Track, clearance: float, paths: dict[str, NDArray[np.float64]]) -> None:
    """The flat configuration space ``(a, b)`` with the band ``d < D``, the skeleton and some paths."""
    L = track.total_length
    g = np.linspace(0.0, L, 301)
    A, B = np.meshgrid(g, g, indexing="xy")
    d = track.distance(A, B)
    ax.contourf(A, B, d, levels=[-1.0, clearance], colors=["0.85"])
    sk = skeleton_of(track)
    if not isinstance(sk, IntervalSkeleton):
        for e in sk.graph.edges:
            ts = np.linspace(0.0, e.length, 60)
            pts = np.array([sk.state(SkeletonPoint(e.name, float(t))) for t in ts])
            for part in _split_jumps(pts, 0.25 * L):
                ax.plot(part[:, 0], part[:, 1], color="tab:green", lw=1, alpha=0.8)
        ax.plot([], [], color="tab:green", lw=1, label="skeleton")
    styles = ("k--", "tab:red")
    for (name, pts), st in zip(paths.items(), styles):
        for i, part in enumerate(_split_jumps(pts, 0.25 * L)):
            if st.startswith("k"):
                ax.plot(part[:, 0], part[:, 1], st, lw=1, label=name if i == 0 else None)
            else:
                ax.plot(part[:, 0], part[:, 1], color=st, lw=1.8, label=name if i == 0 else None)
    any_pts = next(iter(paths.values()))
    ax.plot(*any_pts[0], "ko", ms=5)
    ax.plot(*any_pts[-1], "ks", ms=5, mfc="white")
    ax.set_xlim(0, L)
    ax.set_ylim(0, L)
    ax.set_aspect("equal")
    ax.set_xlabel("a (track coordinate of A, m)")
    ax.set_ylabel("b (m)")
    ax.set_title(f"configuration space (grey: d < {clearance:g} m)")
    ax.legend(fontsize=7, loc="upper left")


def draw_profiles(axes: Any, traj: Trajectory) -> None:
    """``s, v, a, j`` of both robots over time on four axes, with the limits dashed."""
    lims = {"v": traj.limits.v, "a": traj.limits.a, "j": traj.limits.j}
    for ax, (key, unit) in zip(axes, (("s", "m"), ("v", "m/s"), ("a", "m/s²"), ("j", "m/s³"))):
        val = getattr(traj, key)
        for r, name in enumerate("AB"):
            ax.plot(traj.t, val[:, r], color=COLORS[r], lw=1.2, label=name)
            if key in lims:
                ax.axhline(lims[key][r], color=COLORS[r], ls=":", lw=0.8)
                ax.axhline(-lims[key][r], color=COLORS[r], ls=":", lw=0.8)
        ax.set_ylabel(f"{key} ({unit})")
        ax.grid(alpha=0.3)
    axes[0].legend(fontsize=7)
    axes[-1].set_xlabel("t (s)")


def plot_trajectory(traj: Trajectory) -> Figure:
    """The demo figure (track, configuration space, profiles) of a trajectory."""
    from matplotlib.figure import Figure

    fig = Figure(figsize=(12, 8), constrained_layout=True)
    gs = fig.add_gridspec(4, 2, width_ratios=[1.0, 1.2])
    ax_track = fig.add_subplot(gs[0:2, 0])
    ax_cs = fig.add_subplot(gs[2:4, 0])
    prof = [fig.add_subplot(gs[i, 1]) for i in range(4)]
    plan = traj.plan
    draw_track(ax_track, plan.track, traj.track)
    plan_pts = plan.sample(max(400, plan.samples_needed(0.005)))
    draw_cspace(ax_cs, plan.track, traj.clearance, {"plan": plan_pts, "trajectory": traj.track})
    draw_profiles(prof, traj)
    what = "fallback: plan re-timed" if traj.fallback else "optimized"
    fig.suptitle(
        f"{_track_label(plan.track)}: ({plan.start[0]:g}, {plan.start[1]:g}) → "
        f"({plan.goal[0]:g}, {plan.goal[1]:g}), domain {traj.domain}, makespan {traj.makespan:.2f} s ({what})"
    )
    return fig


def figure_png(fig: Figure) -> bytes:
    """PNG bytes of a figure (Agg canvas, no display needed)."""
    from matplotlib.backends.backend_agg import FigureCanvasAgg

    FigureCanvasAgg(fig)
    buf = io.BytesIO()
    fig.savefig(buf, format="png", dpi=110)
    return buf.getvalue()


def save_png(traj: Trajectory, path: str | os.PathLike[str]) -> None:
    """Write the demo figure of ``traj`` to ``path``."""
    with open(path, "wb") as fh:
        fh.write(figure_png(plot_trajectory(traj)))


def _track_label(track) -> str:  # type: ignore[no-untyped-def]
    """``"lollipop (stick 1 m, loop 1 m)"``."""
    params = ", ".join(f"{k} {v:g} m" for k, v in track.to_dict().items() if k != "track")
    return f"{track.kind} ({params})"
