"""Animations of two robots moving on a graph track, from generic timed motions on their routes.

A motion is given as times ``t`` (shape (N,)) and route coordinates ``s`` (shape (N, 2), robot A in column 0): the
distance each robot has travelled along its route (:class:`mpa.geometry.DirectedRoute`), so plans of the complete
graph planner (:func:`graph_plan_motion`) and jerk-limited trajectories on graph tracks animate the same way.

The figure is laid out once (the layout, both routes faintly, start and goal; labels that would overlap moved
apart, :func:`trajopt.viz.labels.separate_labels`) and drawn once as a background; each frame restores that
background and draws only the moving artists (each robot's body and label, the time readout) on it (blitting), and
is streamed to the writer: memory does not grow with the number of frames, and a frame costs a few milliseconds
plus the encoder's time. A progress bar goes to stderr when it is a terminal. GIF files are written by
:class:`StreamingGifWriter` (frame by frame, one shared 256-colour palette taken from the first frame); MP4 files
by matplotlib's ``FFMpegWriter``, which needs an ffmpeg executable
(:func:`trajopt.viz.animation.ffmpeg_executable`). Files are written under a temporary name and renamed, so a failed
run leaves no file behind.
"""

from __future__ import annotations

import os
from pathlib import Path
from typing import Any

import numpy as np
from matplotlib.animation import AbstractMovieWriter
from matplotlib.backends.backend_agg import FigureCanvasAgg
from matplotlib.figure import Figure
from matplotlib.lines import Line2D
from numpy.typing import ArrayLike, NDArray

from mpa._arrays import FloatArray
from mpa.errors import InvalidInputError
from mpa.geometry import DirectedRoute
from mpa.graph_track import GraphTrack, as_graph_track
from mpa.planners.graph import GraphPlan
from trajopt.viz.drawing import ROBOT_COLORS
from trajopt.viz.labels import separate_labels
from trajopt.viz.layout import ROUTE_STYLES, LayoutGeometry, draw_layout, draw_routes, layout_geometry
from trajopt.viz.movie import (
    StreamingGifWriter,
    _Progress,
    _save_streaming,
    frame_times,
    movie_writer,
    validate_movie_options,
    validate_number,
)

__all__ = ["StreamingGifWriter", "animate_graph_plan", "animate_layout", "graph_plan_motion"]

#: Points along a robot's body.
BODY_POINTS = 15
#: Default figure width (inches): 800 px at the default 80 dpi.
DEFAULT_WIDTH = 10.0
#: Legend font size (points): 10.5 px at 80 dpi.
LEGEND_SIZE = 9.5
#: Vertex label size (points; edge labels one point smaller).
LABEL_SIZE = 10.0
#: Space kept free along the figure's border (inches).
BORDER_PAD = 0.15


def _validate_motion(t: ArrayLike, s: ArrayLike) -> tuple[FloatArray, FloatArray]:
    tt = np.asarray(t, dtype=float)
    ss = np.asarray(s, dtype=float)
    if tt.ndim != 1 or len(tt) < 1:
        raise InvalidInputError(f"t has shape {tt.shape}, expected (N,) with N >= 1 (seconds)")
    if ss.shape != (len(tt), 2):
        raise InvalidInputError(f"s has shape {ss.shape}, expected ({len(tt)}, 2): route coordinates of A and B (m)")
    if not (np.all(np.isfinite(tt)) and np.all(np.isfinite(ss))):
        raise InvalidInputError("t or s has a value that is not finite, expected finite times (s) and coordinates (m)")
    if np.any(np.diff(tt) < 0):
        raise InvalidInputError("t decreases somewhere, expected non-decreasing times (s)")
    return tt, ss


def graph_plan_motion(plan: GraphPlan, samples: int = 400) -> tuple[FloatArray, FloatArray]:
    """The raw plan as a timed motion: ``(t, s)`` at the plan's speed limits (no acceleration limits).

    Parameters
    ----------
    plan : GraphPlan
    samples : int
        Number of samples (>= 2).

    Returns
    -------
    t : ndarray, shape (samples,)
        Times (s), from 0 to ``plan.makespan``.
    s : ndarray, shape (samples, 2)
        Route coordinates of A and B (m).
    """
    validate_number("samples", samples, 2, integer=True)
    u, s = plan.sample(int(samples))
    return u * plan.makespan, s


def _body_points(tr: GraphTrack, route: DirectedRoute, r: float, half: float) -> tuple[NDArray[np.int64], FloatArray]:
    """Positions along a robot's body: route coordinates ``r ± half`` clipped to the route; a robot that stands
    (route of length 0) gets its body along its edge, clipped to the edge."""
    if route.length > 0:
        rr = np.clip(r + np.linspace(-half, half, BODY_POINTS), route.breaks[0], route.breaks[-1])
        return route.positions(rr)
    e, o = route.positions(np.array([r]))
    off = np.clip(o[0] + np.linspace(-half, half, BODY_POINTS), 0.0, float(tr.lengths[int(e[0])]))
    return np.full(BODY_POINTS, int(e[0])), off


def animate_layout(
    track: object,
    route_a: DirectedRoute,
    route_b: DirectedRoute,
    t: ArrayLike,
    s: ArrayLike,
    out: str | os.PathLike[str],
    *,
    clearance: float | None = None,
    fps: float = 20.0,
    dpi: float = 80.0,
    max_frames: int | None = 300,
    fmt: str | None = None,
    title: str | None = None,
    bodies: bool = True,
    size: tuple[float, float] | None = None,
    progress: bool | None = None,
    footprint: object = None,
) -> Path:
    """Write an animation of two robots moving along their routes on a graph track.

    Parameters
    ----------
    track : GraphTrack or anything :func:`mpa.graph_track.as_graph_track` accepts
    route_a, route_b : DirectedRoute
        The robots' routes; ``s`` is measured along them.
    t : array_like, shape (N,)
        Times (s), non-decreasing.
    s : array_like, shape (N, 2)
        Route coordinates of A (column 0) and B (m) at those times; linearly interpolated between samples.
    out : path
        Output file; its suffix (``.gif`` or ``.mp4``) chooses the format unless ``fmt`` is given.
    clearance : float, optional
        D (m). With ``bodies``, each robot is drawn as a thick segment along its route of length D/2 on each side of
        its position (clipped to the route), so that touching bodies mean distance D.
    fps : float
        Frames per second (>= 1); the animation plays in real time unless ``max_frames`` caps the frames (then it
        plays faster, which the title says).
    dpi : float
        Resolution (>= 10).
    max_frames : int, optional
        Upper bound on the number of frames (>= 2; None: no bound).
    fmt : {"gif", "mp4"}, optional
    title : str, optional
        Figure title (a second line gives the speed-up when frames are capped).
    bodies : bool
        Draw bodies (needs ``clearance`` > 0); otherwise only a dot per robot.
    size : (float, float), optional
        Figure size in inches (default: 10 inches wide, the height from the layout's aspect ratio; at the default
        dpi the legend's text is 10.5 px high).
    progress : bool, optional
        A progress bar on stderr (default: when stderr is a terminal; silent otherwise).
    footprint : None, Footprints, Disc, Rectangle, pair or spec
        The robots' bodies in the plane, drawn to scale in every frame (:mod:`trajopt.viz.bodies`: a disc as a
        circle, a rectangle turned along the track's tangent), at the poses the gate checks; needs vertex
        coordinates.

    Returns
    -------
    Path
        The file written.

    Raises
    ------
    InvalidInputError
        Bad shapes or values of ``t``/``s``, fps, dpi, frame count or format; mp4 without an ffmpeg executable.
    """
    tr = as_graph_track(track)
    tt, ss = _validate_motion(t, s)
    out = Path(out)
    fmt, fps, dpi, max_frames = validate_movie_options(out, fmt, fps, dpi, max_frames)
    half = 0.0
    if clearance is not None:
        half = 0.5 * validate_number("clearance", clearance, 0.0)
    writer: AbstractMovieWriter = movie_writer(fmt, fps, round(fps))
    times, speedup = frame_times(float(tt[0]), float(tt[-1]), fps, max_frames)

    geo = layout_geometry(tr)
    fig = _static_figure(tr, geo, route_a, route_b, title, speedup, size)
    ax = fig.axes[0]
    moving = _moving_artists(ax)
    artists = [a for name in ("A", "B") for a in moving[name]] + [moving["clock"]]
    fps_ = None
    if footprint is not None:
        from mpa.footprint import drawing_of, footprints
        from trajopt.viz.bodies import draw_bodies

        fps_ = footprints(footprint)
        drawing = drawing_of(tr)
        moving["plane"] = draw_bodies(
            ax, fps_, np.zeros((2, 2)), np.zeros(2), (ROBOT_COLORS["A"], ROBOT_COLORS["B"]), alpha=0.45, zorder=8
        )
        artists = moving["plane"] + artists
    canvas, background = _freeze_background(fig, dpi, artists)
    bar = _Progress(len(times), "animate", progress)
    routes = (route_a, route_b)
    r_all = np.stack([np.interp(times, tt, ss[:, 0]), np.interp(times, tt, ss[:, 1])], axis=1)

    def frames() -> Any:
        for k, now in enumerate(times):
            canvas.restore_region(background)
            _update(tr, geo, routes, moving, r_all[k], half if bodies else 0.0, now - tt[0], tt[-1] - tt[0])
            if fps_ is not None:
                _place_bodies(drawing, routes, moving["plane"], fps_, r_all[k])
            for a in artists:
                fig.draw_artist(a)
            yield k

    try:
        _save_streaming(fig, frames(), out, fmt, writer, dpi, bar)
    finally:
        bar.close()
    return out


def _freeze_background(fig: Figure, dpi: float, artists: list[Any]) -> tuple[FigureCanvasAgg, Any]:
    """Fix the figure's pixel size (even, as h264 needs) and layout, move overlapping labels apart, and draw
    everything but the moving ``artists`` once: returns the canvas and that background (restored every frame)."""
    fig.set_dpi(dpi)
    w, h = (np.asarray(fig.get_size_inches()) * dpi).astype(int) // 2 * 2
    fig.set_size_inches(w / dpi, h / dpi)
    canvas = FigureCanvasAgg(fig)
    for a in artists:
        a.set_animated(True)  # left out of the background
    canvas.draw()
    fig.set_layout_engine("none")  # freeze the layout: frames differ only in the moving artists
    _fit_inside(fig, fig.axes[0], BORDER_PAD)
    if separate_labels(fig.axes[0]):
        canvas.draw()
    return canvas, canvas.copy_from_bbox(fig.bbox)


def _fit_inside(fig: Figure, ax: Any, pad: float) -> None:
    """Move and shrink ``ax`` until everything drawn keeps ``pad`` inches from the figure's border (the layout
    engine does not always manage with an equal-aspect axes and a legend beside it). Draws the figure."""
    w, h = fig.get_size_inches()
    for _ in range(3):
        fig.canvas.draw()
        bb = fig.get_tightbbox(fig.canvas.get_renderer())  # type: ignore[attr-defined]
        if bb.x0 >= pad - 1e-3 and bb.y0 >= pad - 1e-3 and bb.x1 <= w - pad + 1e-3 and bb.y1 <= h - pad + 1e-3:
            return
        pos = ax.get_position()
        sx = (w - 2 * pad) / max(bb.width, 1e-9)
        sy = (h - 2 * pad) / max(bb.height, 1e-9)
        s = min(sx, sy, 1.0)
        x0 = (pad + (pos.x0 * w - bb.x0) * s) / w
        y0 = (pad + (pos.y0 * h - bb.y0) * s) / h
        ax.set_position([x0, y0, pos.width * s, pos.height * s])


def _static_figure(
    tr: GraphTrack,
    geo: LayoutGeometry,
    route_a: DirectedRoute,
    route_b: DirectedRoute,
    title: str | None,
    speedup: float,
    size: tuple[float, float] | None,
) -> Figure:
    pts = np.vstack(geo.polylines)
    span = np.maximum(pts.max(axis=0) - pts.min(axis=0), 1e-9 * geo.size)
    aspect = float(np.clip(span[1] / span[0], 0.3, 1.5))
    figsize = size if size is not None else (DEFAULT_WIDTH, 0.62 * DEFAULT_WIDTH * aspect + 1.6)
    fig = Figure(figsize=figsize, layout="constrained", facecolor="white")
    FigureCanvasAgg(fig)  # frames are rendered with Agg
    ax = fig.subplots()
    draw_layout(ax, tr, geometry=geo, label_size=LABEL_SIZE)
    draw_routes(ax, tr, route_a, route_b, geometry=geo, alpha=0.35, lw=1.6)
    handles, labels = ax.get_legend_handles_labels()
    rows = max(int((figsize[1] - 1.0) * 72.0 / (LEGEND_SIZE * 2.0)), 3)  # legend rows that fit the height
    if len(handles) > rows:  # the routes, the first switches, and how many more
        more = len(handles) - (rows - 1)
        handles = [*handles[: rows - 1], Line2D([], [], ls="none")]
        labels = [*labels[: rows - 1], f"… and {more} more switches"]
    ax.legend(
        handles,
        labels,
        loc="upper left",
        bbox_to_anchor=(1.01, 1.0),
        fontsize=LEGEND_SIZE,
        frameon=False,
        borderaxespad=0.0,
    )
    m = 0.08 * geo.size
    lo, hi = pts.min(axis=0), pts.max(axis=0)
    ax.set_xlim(lo[0] - m, hi[0] + m)
    ax.set_ylim(lo[1] - m, hi[1] + m)
    head = title or "two robots on a graph track"
    if speedup > 1.0:
        head += f"\n(played {speedup:.1f}× faster than real time)"
    ax.set_title(head, fontsize=10)
    return fig


def _moving_artists(ax: Any) -> dict[str, Any]:
    art: dict[str, Any] = {}
    for name in ("A", "B"):
        color = ROBOT_COLORS[name]
        (body,) = ax.plot([], [], color=color, lw=7.0, alpha=0.75, solid_capstyle="butt", zorder=9)
        (dot,) = ax.plot([], [], "o", color=color, mec="white", mew=1.5, ms=9, zorder=10)
        # the name in a disc beside the robot: two markers (drawn much faster than a text with a box)
        (disc,) = ax.plot([], [], "o", color=color, mec="none", ms=15, zorder=11)
        (letter,) = ax.plot([], [], marker=f"$\\mathbf{{{name}}}$", color="white", mec="none", ms=8, zorder=12)
        art[name] = (body, dot, disc, letter)
    art["clock"] = ax.text(
        0.01, 0.99, "", transform=ax.transAxes, ha="left", va="top", fontsize=10, family="monospace", zorder=12
    )
    return art


def _place_bodies(
    drawing: Any, routes: tuple[DirectedRoute, DirectedRoute], patches: list[Any], fps: Any, r: Any
) -> None:
    """Move the bodies' patches to the robots' poses at route coordinates ``r`` (shape (2,), metres)."""
    from trajopt.viz.bodies import move_body

    for k, fp in enumerate((fps.a, fps.b)):
        e, o = routes[k].positions(np.array([r[k]]))
        xy, hd = drawing.pose(e, o)
        move_body(patches[k], fp, xy[0], float(hd[0]))


def _update(
    tr: GraphTrack,
    geo: LayoutGeometry,
    routes: tuple[DirectedRoute, DirectedRoute],
    art: dict[str, Any],
    r: FloatArray,
    half: float,
    now: float,
    duration: float,
) -> None:
    for k, name in enumerate(("A", "B")):
        route = routes[k]
        body, dot, disc, letter = art[name]
        e, o = route.positions(np.array([r[k]]))
        p = geo.embed(e, o, tr.lengths)[0]
        n = geo.normal(e, o, tr.lengths)[0]
        dot.set_data([p[0]], [p[1]])
        if half > 0:
            be, bo = _body_points(tr, route, float(r[k]), half)
            bp = geo.embed(be, bo, tr.lengths)
            body.set_data(bp[:, 0], bp[:, 1])
        side = ROUTE_STYLES[name]["side"]
        to_px = dot.axes.transData
        px = to_px.transform(p) + side * n * 16.0 * dot.figure.dpi / 72.0  # 16 points beside the robot
        q = to_px.inverted().transform(px)
        disc.set_data([q[0]], [q[1]])
        letter.set_data([q[0]], [q[1]])
    art["clock"].set_text(f"t = {now:6.2f} s / {duration:.2f} s")


def animate_graph_plan(plan: GraphPlan, out: str | os.PathLike[str], *, name: str | None = None, **kw: Any) -> Path:
    """Animate a plan of the complete graph planner at its speed limits (see :func:`animate_layout`).

    Parameters
    ----------
    plan : GraphPlan
    out : path
    name : str, optional
        Layout name for the title.
    **kw
        Passed to :func:`animate_layout` (``fps``, ``dpi``, ``max_frames``, ``fmt``, ``bodies``).
    """
    from trajopt.viz.layout import plan_title

    t, s = graph_plan_motion(plan)
    kw.setdefault("clearance", plan.clearance)
    kw.setdefault("title", plan_title(plan, name))
    return animate_layout(plan.track, plan.route_a, plan.route_b, t, s, out, **kw)
