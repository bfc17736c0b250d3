"""Animations of two robots on a track: the raw plan of :mod:`mpa` beside the jerk-limited trajectory of the same query.

Each motion gets one row of three panels: the robots on the track, the moving state in the flat configuration space
with the skeleton, and both robots' speeds over time with a cursor. Rows share one clock, so the difference between
the raw plan (corners, piecewise-constant speed, infinite acceleration) and the optimised trajectory (smooth, within
v/a/j limits) is visible side by side.

The figure is laid out once (the static panels drawn once and kept as a background); each frame restores that
background and draws only the moving artists, and is handed to the writer at once, so memory does not grow with
the number of frames. GIF files are written by :class:`~trajopt.viz.movie.StreamingGifWriter` (frame by
frame); MP4 files by matplotlib's ``FFMpegWriter``, which needs an ffmpeg executable: one on the ``PATH``, or the
one shipped inside the ``imageio-ffmpeg`` wheel (``pip install imageio-ffmpeg``), found automatically. A progress
bar goes to stderr when it is a terminal. Files are written to a temporary name and renamed, so a failed run
leaves no file behind.
"""

from __future__ import annotations

import os
from collections.abc import Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np
from matplotlib.backends.backend_agg import FigureCanvasAgg
from matplotlib.figure import Figure

from mpa import defaults
from mpa._arrays import FloatArray
from mpa.errors import InvalidInputError
from mpa.plans import Plan
from mpa.skeleton import skeleton_of
from mpa.tracks import Track
from trajopt.viz import drawing as dr
from trajopt.viz.movie import (
    FORMATS,
    _Progress,
    _save_streaming,
    ffmpeg_executable,
    frame_times,
    movie_writer,
    validate_movie_options,
)

if TYPE_CHECKING:
    from trajopt.result import Trajectory

__all__ = [
    "FORMATS",
    "Motion",
    "animate_motions",
    "animate_query",
    "ffmpeg_executable",
    "plan_motion",
    "query_title",
    "trajectory_motion",
]


@dataclass(frozen=True)
class Motion:
    """A timed motion of both robots.

    Attributes
    ----------
    label : str
        Title of the motion's row.
    t : ndarray, shape (N,)
        Times (s), increasing from 0.
    states : ndarray, shape (N, 2)
        Track coordinates of A and B (m).
    speed : ndarray, shape (N, 2)
        Signed speed of each robot along its route (m/s).
    """

    label: str
    t: FloatArray
    states: FloatArray
    speed: FloatArray

    @property
    def duration(self) -> float:
        """Time of the last sample (s)."""
        return float(self.t[-1])

    def at(self, time: float) -> tuple[FloatArray, FloatArray]:
        """State and speed at ``time`` (the last sample at or before it; held after the end)."""
        i = int(np.clip(np.searchsorted(self.t, time, side="right") - 1, 0, len(self.t) - 1))
        return self.states[i], self.speed[i]

    def upto(self, time: float) -> FloatArray:
        """The states from the start up to ``time``. Shape (K, 2)."""
        i = int(np.clip(np.searchsorted(self.t, time, side="right"), 1, len(self.t)))
        return self.states[:i]


def plan_motion(plan: Plan, vmax: float, *, samples: int = 2000) -> Motion:
    """The raw plan executed as the paper describes it: along α(u), ``u`` uniform in time, at constant speed.

    The plan's parameter ``u`` grows in proportion to the larger of the two robots' travel, so timing ``u``
    uniformly over ``T = (total larger travel) / vmax`` moves the faster robot at exactly ``vmax`` and the other
    proportionally slower: speeds jump at every corner (infinite acceleration).

    Parameters
    ----------
    plan : Plan
    vmax : float
        Speed of the faster robot (m/s, > 0).
    samples : int
        Number of time samples.

    Returns
    -------
    Motion
    """
    if not np.isfinite(vmax) or vmax <= 0:
        raise InvalidInputError(f"vmax is {vmax!r}, expected a positive finite speed (m/s)")
    inc = np.max(np.abs(np.diff(plan.waypoints_s, axis=0)), axis=1) if len(plan.waypoints_s) > 1 else np.zeros(1)
    total = float(np.sum(inc))
    duration = total / vmax
    u = np.linspace(0.0, 1.0, max(int(samples), 2))
    t = u * duration
    s = plan.path_s(u)
    speed = np.gradient(s, t, axis=0) if duration > 0 else np.zeros_like(s)
    label = f"raw plan: α(u) with u uniform in time\n(faster robot at vmax = {vmax:g} m/s), T = {duration:.2f} s"
    return Motion(label, t, plan.path(u), speed)


def trajectory_motion(traj: Trajectory) -> Motion:
    """The jerk-limited :class:`trajopt.Trajectory` as a motion (its own time stamps and speeds)."""
    kind = "fallback: re-timed plan" if bool(getattr(traj, "fallback", False)) else "optimised"
    label = f"jerk-limited trajectory\n({kind}), makespan {float(traj.makespan):.2f} s"
    return Motion(label, np.asarray(traj.t, dtype=float), np.asarray(traj.track, dtype=float), np.asarray(traj.v))


def animate_motions(
    track: Track,
    motions: Sequence[Motion],
    out: str | os.PathLike[str],
    *,
    plan: Plan | None = None,
    fps: float = 20.0,
    dpi: float = 80.0,
    max_frames: int | None = None,
    fmt: str | None = None,
    title: str | None = None,
    progress: bool | None = None,
) -> Path:
    """Write an animation of one or more motions of the same query, one row each, on a shared clock.

    Parameters
    ----------
    track : Track
    motions : sequence of Motion
        The motions (e.g. :func:`plan_motion` and :func:`trajectory_motion`).
    out : path
        Output file; its suffix (``.gif`` or ``.mp4``) chooses the format unless ``fmt`` is given.
    plan : Plan, optional
        Drawn faintly in the configuration space (the whole path), with the start and goal.
    fps : float
        Frames per second of the file; the animation plays in real time unless ``max_frames`` caps the frames
        (then it plays faster, which the title says).
    dpi : float
        Resolution.
    max_frames : int, optional
        Upper bound on the number of frames (>= 2).
    fmt : {"gif", "mp4"}, optional
    title : str, optional
        Figure title (default: the track and its size, e.g. "lollipop ℓ = 1 m, c = 1 m").
    progress : bool, optional
        Show a progress bar on stderr (default: when stderr is a terminal).

    Returns
    -------
    Path
        The file written.

    Raises
    ------
    InvalidInputError
        Bad fps, dpi, frame count or format; mp4 without an ffmpeg executable.
    """
    out = Path(out)
    fmt, fps, dpi, max_frames = validate_movie_options(out, fmt, fps, dpi, max_frames)
    if not motions:
        raise InvalidInputError("motions is empty, expected at least one motion to animate")
    writer = movie_writer(fmt, fps)
    times, speedup = frame_times(0.0, max(max(m.duration for m in motions), 1e-9), fps, max_frames)
    fig, artists = _motions_figure(track, motions, plan, float(times[-1]), title, speedup)
    canvas, background = _freeze_background(fig, dpi, artists)
    bar = _Progress(len(times), "animate", progress)

    def frames() -> Any:
        for k, now in enumerate(times):
            canvas.restore_region(background)
            for a in _update_frame(track, motions, artists, float(now)):
                fig.draw_artist(a)
            yield k

    try:
        _save_streaming(fig, frames(), out, fmt, writer, dpi, bar)
    finally:
        bar.close()
    return out


def _artist_list(art: dict[str, Any]) -> list[Any]:
    return [art["trail"], art["dot"], *art["marks"].values(), *art["names"].values(), art["cursor"], art["clock"]]


def _motions_figure(
    track: Track, motions: Sequence[Motion], plan: Plan | None, duration: float, title: str | None, speedup: float
) -> tuple[Figure, list[dict[str, Any]]]:
    """The figure of :func:`animate_motions` (one row of three panels per motion, a title) and each row's moving
    artists; ``duration`` (s) is the shared clock's length."""
    fig = Figure(figsize=(11.0, 3.3 * len(motions) + 0.5), layout="constrained")
    axes = fig.subplots(len(motions), 3, squeeze=False, width_ratios=[1.35, 1.0, 1.1])
    sk = plan.skeleton if plan is not None else skeleton_of(track)
    vlim = max(float(np.max(np.abs(m.speed))) for m in motions) * 1.1 + 1e-9
    artists = [
        _draw_motion_row(axes[row], track, sk, m, duration=duration, vlim=vlim, last=row == len(motions) - 1)
        for row, m in enumerate(motions)
    ]
    head = title or dr.track_title(track)
    if speedup > 1.0:
        head += f"  (played {speedup:.1f}× faster than real time)"
    fig.suptitle(head, fontsize=12)
    return fig, artists


def _freeze_background(fig: Figure, dpi: float, artists: Sequence[dict[str, Any]]) -> tuple[FigureCanvasAgg, Any]:
    """Fix the figure's pixel size (even, as h264 needs) and layout, and draw everything but the moving artists
    once: returns the canvas and that background (restored before each frame)."""
    fig.set_dpi(dpi)
    w, h = (np.asarray(fig.get_size_inches()) * dpi).astype(int) // 2 * 2  # even pixel sizes (what h264 needs)
    fig.set_size_inches(w / dpi, h / dpi)
    canvas = FigureCanvasAgg(fig)
    moving = [a for art in artists for a in _artist_list(art)]
    for a in moving:
        a.set_animated(True)  # left out of the background
    canvas.draw()
    fig.set_layout_engine("none")  # freeze the layout: frames differ only in the moving artists
    return canvas, canvas.copy_from_bbox(fig.bbox)


def _draw_motion_row(
    row_axes: Sequence[Any], track: Track, sk: Any, m: Motion, *, duration: float, vlim: float, last: bool
) -> dict[str, Any]:
    """Draw the static part of one motion's row (track, flat space, speeds); returns the artists that move."""
    ax_p, ax_f, ax_v = row_axes
    dr.draw_track(ax_p, track, labels=True, ccw_arrow=False)
    dr.draw_robots(ax_p, track, m.states[-1], final=True, labels=("", ""))
    dr.draw_flat_cspace(ax_f, track, axis_labels=last)
    dr.draw_skeleton(ax_f, sk, alpha=0.8, lw=2.0)
    dr.draw_flat_path(ax_f, track, m.states, color="0.65", lw=1.0, arrows=())
    dr.draw_state(ax_f, m.states[0], "$x_i$", size=5)
    dr.draw_state(ax_f, m.states[-1], "$x_f$", size=5, filled=False)
    ax_p.set_title(m.label, fontsize=10, loc="left")
    ax_p.text(0.98, 0.02, "filled ▲: now, empty △: goal", transform=ax_p.transAxes, fontsize=9, ha="right")
    for k, name in enumerate("AB"):
        ax_v.plot(
            m.t,
            m.speed[:, k],
            color=dr.ROBOT_COLORS[name],
            ls=dr.ROBOT_LINESTYLES[name],
            lw=2.2 if name == "A" else 1.6,
            label=f"robot {name}",
        )
    ax_v.set_xlim(0.0, duration)
    ax_v.set_ylim(-vlim, vlim)
    ax_v.axhline(0.0, color="0.7", lw=0.8)
    ax_v.set_ylabel("speed along route (m/s)", fontsize=10)
    ax_v.legend(loc="upper right", fontsize=9)
    ax_v.grid(alpha=0.3)
    if last:
        ax_v.set_xlabel("time (s)")
    return _moving_artists(ax_p, ax_f, ax_v)


def _moving_artists(ax_p: Any, ax_f: Any, ax_v: Any) -> dict[str, Any]:
    """The artists of one row that each frame moves: the trail and dot in the flat space, the robots (triangles
    with their names) on the track, the time cursor and the clock."""
    (trail,) = ax_f.plot([], [], color="k", lw=2.2, zorder=6)
    (dot,) = ax_f.plot([], [], "o", color="k", ms=7, zorder=9)
    marks, names = {}, {}
    for name in "AB":
        color = dr.ROBOT_COLORS[name]
        (marks[name],) = ax_p.plot([], [], marker="^", ms=13, color=color, ls="none", zorder=8)
        names[name] = ax_p.annotate(
            name,
            (0.0, 0.0),
            xytext=(0.0, 0.0),
            textcoords="offset points",
            color=color,
            fontsize=12,
            fontweight="bold",
            ha="center",
            va="center",
            zorder=9,
        )
    cursor = ax_v.axvline(0.0, color="k", lw=1.0)
    clock = ax_p.text(0.02, 0.02, "", transform=ax_p.transAxes, fontsize=11)
    return {"trail": trail, "dot": dot, "marks": marks, "names": names, "cursor": cursor, "clock": clock}


def _update_frame(track: Track, motions: Sequence[Motion], artists: Sequence[dict[str, Any]], now: float) -> list[Any]:
    """Move every row's artists to the time ``now`` (s); returns the artists changed."""
    unit = dr.lane_unit(track)
    changed: list[Any] = []
    for m, art in zip(motions, artists):
        state, _ = m.at(now)
        path = dr.split_wraps(track, m.upto(now))
        art["trail"].set_data(path[:, 0], path[:, 1])
        art["dot"].set_data([state[0]], [state[1]])
        for name, p, side in (("A", state[0], 1.0), ("B", state[1], -1.0)):
            xy = dr.embed_offset(track, float(p), side * 0.15 * unit)
            art["marks"][name].set_data([xy[0]], [xy[1]])
            art["names"][name].xy = (float(xy[0]), float(xy[1]))
            art["names"][name].set_position(tuple(16.0 * side * dr.track_normal(track, float(p))))
        art["cursor"].set_xdata([now, now])
        art["clock"].set_text(f"t = {min(now, m.duration):5.2f} s")
        changed += [art["trail"], art["dot"], *art["marks"].values(), *art["names"].values()]
        changed += [art["cursor"], art["clock"]]
    return changed


def query_title(track: Track, plan: Plan) -> str:
    """A readable title of a query, e.g. "lollipop ℓ = 1 m, c = 1 m — A and B swap: (1.3, 1.7) → (1.7, 1.3),
    D = 0.05 m, domain 2"."""
    (a0, b0), (a1, b1) = plan.start, plan.goal
    swap = " A and B swap:" if np.allclose((a0, b0), (b1, a1)) else ""
    return (
        f"{dr.track_title(track)} —{swap} ({a0:g}, {b0:g}) → ({a1:g}, {b1:g}), "
        f"D = {plan.clearance:g} m, domain {plan.domain}"
    )


def animate_query(
    track: Track,
    start: Sequence[float],
    goal: Sequence[float],
    out: str | os.PathLike[str],
    *,
    clearance: float = defaults.CLEARANCE,
    vmax: float = defaults.VMAX,
    amax: float = defaults.AMAX,
    jmax: float = defaults.JMAX,
    rate: float = defaults.RATE,
    trajectory: bool = True,
    **kw: Any,
) -> Path:
    """Plan a query, optimise its trajectory and animate both (see :func:`animate_motions`).

    Parameters
    ----------
    track : Track
    start, goal : sequence of float, shape (2,)
        Track coordinates of A and B (m).
    out : path
        Output file (``.gif`` or ``.mp4``).
    clearance, vmax, amax, jmax, rate : float
        As for :func:`trajopt.generate_trajectory`.
    trajectory : bool
        Also animate the jerk-limited trajectory (False: the raw plan only).
    **kw
        Passed to :func:`animate_motions` (``fps``, ``dpi``, ``max_frames``, ``fmt``).

    Returns
    -------
    Path

    Raises
    ------
    InvalidInputError, NoMotionError, PlanningError
        From the planner and the trajectory generator; see also :func:`animate_motions`.
    """
    from mpa.planners import make_planner

    # fail before the (slower) planning and optimisation
    validate_movie_options(Path(out), kw.get("fmt"), kw.get("fps", 20.0), kw.get("dpi", 80.0), kw.get("max_frames"))
    if trajectory:
        from trajopt.generator import generate_trajectory

        traj = generate_trajectory(track, start, goal, clearance=clearance, vmax=vmax, amax=amax, jmax=jmax, rate=rate)
        p = traj.plan
        assert isinstance(p, Plan)  # a paper track's query: the motion is drawn in its track coordinates
        motions = [plan_motion(p, vmax), trajectory_motion(traj)]
    else:
        p = make_planner(track, clearance).plan(start, goal)
        motions = [plan_motion(p, vmax)]
    return animate_motions(track, motions, out, plan=p, title=query_title(track, p), **kw)
