"""The figure of a run on a layout (``mpa trajectory --graph ... --plot``, ``mpa plot DIR`` of a layout run).

Left: the layout (:func:`trajopt.viz.layout.draw_layout`) with both carts' routes beside the track
(:func:`~trajopt.viz.layout.draw_routes`: A solid on the left of each edge, B dashed on the right), start and goal
markers, and the carts' positions at a few times (:data:`SNAPSHOTS` times evenly spaced inside the motion,
numbered circles beside each cart's lane, the times in the legend). Right: each cart's speed and acceleration
over time with the limits (A solid, B dashed), and the distance between the carts with the clearance. A layout
has no domains of continuity: the title names the query, clearance, makespan and closest approach, and each
cart's motion in words.

:func:`layout_run_figure` draws from plain arrays (a :class:`~trajopt.result.Trajectory`, or the columns of a
``setpoints.csv`` with the routes of its ``summary.json``: :func:`routes_from_summary`);
:func:`trajectory_figure` draws any trajectory (a layout run here, a paper track's with
:func:`trajopt.viz.plotting.plot_trajectory`).
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from typing import TYPE_CHECKING, Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from mpa._arrays import FloatArray
from mpa.errors import InvalidInputError
from mpa.geometry import DirectedRoute
from mpa.graph_track import GraphTrack

if TYPE_CHECKING:  # pragma: no cover
    from matplotlib.figure import Figure

    from trajopt.result import Trajectory

__all__ = ["SNAPSHOTS", "layout_run_figure", "routes_from_summary", "trajectory_figure"]

#: Number of times inside the motion at which the carts are drawn on the layout (start and goal have markers).
SNAPSHOTS = 4


def routes_from_summary(track: GraphTrack, routes: Mapping[str, Sequence[Mapping[str, Any]]]) -> tuple[Any, Any]:
    """The carts' routes from ``summary.json``'s ``routes`` (``{"a": [{"edge", "dir", "entry", "from_s", "to_s"},
    ...], "b": [...]}``) as :class:`~mpa.geometry.DirectedRoute` on ``track``.

    Raises
    ------
    InvalidInputError
        Missing or malformed routes, an edge not on the layout.
    """
    out = []
    for r in "ab":
        pieces = routes.get(r) if isinstance(routes, Mapping) else None
        if not pieces:
            raise InvalidInputError(f"summary.json has no route of robot {r.upper()}, expected one written by mpa")
        try:
            edges = [track.edge_index(str(p["edge"])) for p in pieces]
            dirs = [int(p["dir"]) for p in pieces]
            entry = [float(p["entry"]) for p in pieces]
            lengths = [float(p["to_s"]) - float(p["from_s"]) for p in pieces]
            origin = float(pieces[0]["from_s"])
        except (KeyError, TypeError, ValueError) as exc:
            raise InvalidInputError(f"summary.json's route of robot {r.upper()} is malformed ({exc})") from None
        out.append(DirectedRoute.from_pieces(edges, dirs, entry, lengths, origin))
    return out[0], out[1]


def _positions(route: DirectedRoute, s: FloatArray) -> tuple[NDArray[np.int64], FloatArray]:
    e, o = route.positions(s)
    return np.asarray(e, dtype=np.int64), np.asarray(o, dtype=float)


def layout_run_figure(
    track: GraphTrack,
    routes: tuple[DirectedRoute, DirectedRoute],
    t: ArrayLike,
    s: ArrayLike,
    *,
    v: ArrayLike | None = None,
    a: ArrayLike | None = None,
    clearance: float | None = None,
    limits: Mapping[str, Sequence[float]] | None = None,
    title: str = "",
    words: Mapping[str, str] | None = None,
    snapshots: int = SNAPSHOTS,
    footprint: object = None,
    poses: tuple[ArrayLike, ArrayLike] | None = None,
) -> Figure:
    """The figure of a layout run (see the module docstring).

    Parameters
    ----------
    track : GraphTrack
    routes : (DirectedRoute, DirectedRoute)
        A's and B's routes; ``s`` are coordinates along them.
    t : array_like, shape (N,)
        Row times (s).
    s : array_like, shape (N, 2)
        Route coordinates of A and B (m).
    v, a : array_like, shape (N, 2), optional
        Speeds (m/s) and accelerations (m/s²) along the routes; the panels are left out when missing.
    clearance : float, optional
        D (m), drawn in the distance panel.
    limits : mapping, optional
        ``{"vmax": (A, B), "amax": (A, B)}`` drawn as dotted lines.
    title : str
    words : mapping, optional
        Each cart's motion in words (``{"A": ..., "B": ...}``).
    snapshots : int
        Number of times inside the motion the carts are drawn at (>= 1).
    footprint : None, Footprints, Disc, Rectangle, pair or spec
        The robots' bodies, drawn to scale (:mod:`trajopt.viz.bodies`) at the start, the goal and the snapshot
        times; needs vertex coordinates.
    poses : (array_like, array_like), optional
        With ``footprint``: the bodies' centres, shape (N, 2, 2) (row, robot, x/y; metres), and headings, shape
        (N, 2) (radians), e.g. the CSV's ``a_x, a_y, b_x, b_y, a_heading, b_heading``; by default computed from
        the routes (:meth:`mpa.footprint.Drawing.pose`).

    Returns
    -------
    Figure
        Not attached to pyplot.
    """
    from matplotlib.figure import Figure
    from matplotlib.lines import Line2D

    from trajopt.viz import plotting as pl
    from trajopt.viz.drawing import ROBOT_COLORS
    from trajopt.viz.layout import _marker, _pad, draw_layout, draw_routes, layout_geometry

    tt = np.asarray(t, dtype=float)
    ss = np.atleast_2d(np.asarray(s, dtype=float))
    if tt.ndim != 1 or ss.shape != (len(tt), 2) or len(tt) == 0:
        raise InvalidInputError(f"rows have shapes t {tt.shape}, s {ss.shape}, expected (N,) and (N, 2), N >= 1")
    panels = [("v", v, "speed (m/s)", "vmax"), ("a", a, "acceleration (m/s²)", "amax")]
    panels = [p for p in panels if p[1] is not None]
    geo = layout_geometry(track)
    pts = np.vstack(geo.polylines)
    span = np.maximum(pts.max(axis=0) - pts.min(axis=0), 1e-9 * geo.size)
    aspect = float(np.clip(span[1] / span[0], 0.35, 1.4))
    fig = Figure(figsize=(13.0, max(5.2, 6.2 * aspect + 1.6)), layout="constrained")
    gs = fig.add_gridspec(len(panels) + 1, 2, width_ratios=[1.35, 1.0])
    ax = fig.add_subplot(gs[:, 0])
    draw_layout(ax, track, geometry=geo)
    lane = 0.015 * geo.size
    draw_routes(ax, track, routes[0], routes[1], geometry=geo, lane=lane, switches=False)
    e_a, o_a = _positions(routes[0], ss[:, 0])
    e_b, o_b = _positions(routes[1], ss[:, 1])
    ends = {"start": 0, "goal": len(tt) - 1}
    for robot, (e, o) in (("A", (e_a, o_a)), ("B", (e_b, o_b))):
        for what, k in ends.items():
            _marker(ax, geo, track, (int(e[k]), float(o[k])), robot, what, lane)
    # the carts at a few times: numbered circles on their lanes
    n = max(int(snapshots), 1)
    idx = np.unique(np.round(np.linspace(0, len(tt) - 1, n + 2)[1:-1]).astype(int))
    handles: list[Any] = []
    for j, k in enumerate(idx):
        for robot, (e, o), side in (("A", (e_a, o_a), 1.0), ("B", (e_b, o_b), -1.0)):
            p = geo.embed(e[k], o[k], track.lengths) + side * 2.2 * lane * geo.normal(e[k], o[k], track.lengths)
            ax.plot(*p, "o", ms=13, mfc="white", mec=ROBOT_COLORS[robot], mew=1.8, zorder=9)
            xy = (float(p[0]), float(p[1]))
            ax.annotate(str(j + 1), xy, ha="center", va="center", fontsize=7.5, color=ROBOT_COLORS[robot], zorder=10)
        handles.append(Line2D([], [], ls="none", marker=f"${j + 1}$", color="0.2", label=f"t = {tt[k]:.2f} s"))
    if footprint is not None:
        _draw_run_bodies(ax, track, footprint, poses, (e_a, o_a, e_b, o_b), [0, *idx.tolist(), len(tt) - 1])
    h0: list[Any]
    h0, l0 = ax.get_legend_handles_labels()
    ax.legend(
        [*h0, *handles],
        [*l0, *(h.get_label() for h in handles)],
        loc="upper center",
        bbox_to_anchor=(0.5, -0.16),
        ncol=4,
        fontsize=9,
        frameon=False,
    )
    _pad(ax, geo)
    ax.set_title("layout, routes and the carts at a few times", fontsize=10)
    # the profiles and the distance between the carts
    axes = [fig.add_subplot(gs[i, 1]) for i in range(len(panels) + 1)]
    for axp, (_key, val, label, lim_key) in zip(axes, panels):
        arr = np.asarray(val, dtype=float)
        for r in (0, 1):
            axp.plot(tt, arr[:, r], color=pl.COLORS[r], ls=pl.LINESTYLES[r], lw=pl.LINEWIDTHS[r], label="AB"[r])
        if limits and lim_key in limits:
            for r in (0, 1):
                lv = float(limits[lim_key][r])
                axp.axhline(lv, color=pl.COLORS[r], ls=":", lw=0.9)
                axp.axhline(-lv, color=pl.COLORS[r], ls=":", lw=0.9)
        axp.set_ylabel(label)
        axp.grid(alpha=0.3)
        axp.legend(fontsize=9, loc="best")
    axd = axes[-1]
    d = track.geometry.distance(e_a, o_a, e_b, o_b)
    axd.plot(tt, d, color="0.15", lw=1.6, label="distance")
    if clearance is not None:
        axd.axhline(clearance, color="#d62728", ls="--", lw=1.2, label=f"clearance {clearance:g} m")
    axd.set_ylabel("distance A–B (m)")
    axd.set_xlabel("t (s)")
    axd.grid(alpha=0.3)
    axd.legend(fontsize=9, loc="best")
    pl.title_with_words(fig, title, words)
    return fig


def _draw_run_bodies(
    ax: Any, track: GraphTrack, footprint: object, poses: Any, pos: tuple[Any, ...], rows: list[int]
) -> None:
    """The bodies to scale at the given rows: filled at the start and the snapshots, outlined at the goal."""
    from trajopt.viz.bodies import body_poses, draw_bodies
    from trajopt.viz.drawing import ROBOT_COLORS

    if poses is not None:
        xy = np.asarray(poses[0], dtype=float).reshape(-1, 2, 2)
        hd = np.asarray(poses[1], dtype=float).reshape(-1, 2)
    else:
        e_a, o_a, e_b, o_b = pos
        at = np.asarray(rows)
        xa, ha = body_poses(track, e_a[at], o_a[at])
        xb, hb = body_poses(track, e_b[at], o_b[at])
        xy = np.full((len(e_a), 2, 2), np.nan)
        hd = np.full((len(e_a), 2), np.nan)
        xy[at, 0], xy[at, 1], hd[at, 0], hd[at, 1] = xa, xb, ha, hb
    colors = (ROBOT_COLORS["A"], ROBOT_COLORS["B"])
    last = rows[-1]
    for k in rows:
        style = {"alpha": 0.8, "facecolor": "none", "ls": "--"} if k == last else {"alpha": 0.25}
        draw_bodies(ax, footprint, xy[k], hd[k], colors, **style)


def trajectory_figure(traj: Trajectory, name: str | None = None) -> Figure:
    """The figure of any trajectory: a layout run (:func:`layout_run_figure`) or a paper track's
    (:func:`trajopt.viz.plotting.plot_trajectory`)."""
    if not traj.is_graph:
        from trajopt.viz.plotting import plot_trajectory

        return plot_trajectory(traj)
    from trajopt.path.planview import plan_view

    view = plan_view(traj.plan)
    tr = view.graph
    plan = traj.plan
    a0, b0 = (tr.position_name(*p) for p in plan.layout_start)
    a1, b1 = (tr.position_name(*p) for p in plan.layout_goal)
    head = f"{name}: " if name else ""
    title = (
        f"{head}A {a0} → {a1}, B {b0} → {b1} · clearance {traj.clearance:g} m · makespan {traj.makespan:.2f} s · "
        f"closest {traj.min_separation:.3f} m"
    )
    lim = traj.limits
    return layout_run_figure(
        tr,
        view.routes,
        traj.t,
        traj.s,
        v=traj.v,
        a=traj.a,
        clearance=traj.clearance,
        limits={"vmax": tuple(lim.v), "amax": tuple(lim.a)},
        title=title,
        words=traj.description(),
        footprint=getattr(traj, "footprint", None),
    )
