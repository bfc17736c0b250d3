"""Drawing graph tracks (:class:`mpa.GraphTrack`) and plans of the complete graph planner with matplotlib.

Everything is drawn in the layout's own plane, in metres, with equal aspect:

- :func:`layout_geometry` (:mod:`trajopt.viz.layout_geometry`, re-exported here) turns a track into drawable
  polylines: the layout's coordinates, or an automatic layout when some vertex has none.
- :func:`draw_layout` draws the edges, a subtle arrowhead on each (``from`` -> ``to``), vertex names and (optionally)
  edge names.
- :func:`draw_routes` draws two robots' routes (:class:`mpa.geometry.DirectedRoute`) beside the track, robot A
  on the left of each edge's orientation (solid, blue), robot B on the right (dashed, orange), so that routes that
  share a stretch both show; the switches used (a robot changes edges at a vertex) are marked with a diamond and
  listed in the legend ("A: switch at J: b_left → b_short").
- :func:`draw_graph_plan` draws a plan (:class:`mpa.MotionPlan`; a paper plan on its track's graph form): layout,
  routes, start and goal markers labelled "A start", "B goal", and a title with clearance, objective and makespan
  (a paper plan: its domain).
- :func:`draw_configuration_cells` draws the cells ``A's edge × B's edge`` a plan crosses, side by side in offsets,
  with their exact free polygons (:mod:`mpa.freespace`) and the plan's path in them.

Robot colours and the start/goal icons (filled triangle = start, empty = goal) follow :mod:`trajopt.viz.drawing`.
Nothing in :mod:`mpa` or the trajectory pipeline imports this module.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any, TypedDict

import numpy as np
from matplotlib.axes import Axes
from matplotlib.figure import Figure
from matplotlib.lines import Line2D

from mpa._arrays import FloatArray
from mpa.errors import InvalidInputError
from mpa.freespace import free_space
from mpa.geometry import DirectedRoute
from mpa.graph_track import GraphTrack, Position, as_graph_track
from mpa.planners.graph import GraphPlan
from mpa.plans import MotionPlan
from trajopt.viz.drawing import ROBOT_COLORS
from trajopt.viz.layout_cells import draw_configuration_cells
from trajopt.viz.layout_geometry import LayoutGeometry, _fractions, layout_geometry

__all__ = [
    "ROUTE_STYLES",
    "LayoutGeometry",
    "Switch",
    "draw_configuration_cells",
    "draw_graph_plan",
    "draw_layout",
    "draw_routes",
    "graph_plan_figure",
    "layout_geometry",
    "plan_title",
    "route_switches",
]


class RouteStyle(TypedDict):
    """How one robot's route is drawn: matplotlib line style, and the side of the edge (+1 left, -1 right)."""

    ls: str | tuple[float, tuple[float, float]]
    side: float


#: Line styles of the robots' routes (A solid on the left of each edge, B dashed on the right).
ROUTE_STYLES: dict[str, RouteStyle] = {"A": {"ls": "-", "side": 1.0}, "B": {"ls": (0, (4.0, 2.0)), "side": -1.0}}
EDGE_COLOR = "0.35"
SWITCH_COLOR = "#2ca02c"


# ------------------------------------------------------------------------------------------------- layout
def label_beside(ax: Axes, text: str, p: Any, direction: Any, points: float, size: float, **style: Any) -> None:
    """A label centred ``points`` typographic points from the data point ``p`` along the unit vector
    ``direction`` (shape (2,) each); ``style`` goes to :meth:`matplotlib.axes.Axes.annotate` (colour, box, ...)."""
    ax.annotate(
        text,
        xy=(float(p[0]), float(p[1])),
        xytext=(float(direction[0] * points), float(direction[1] * points)),
        textcoords="offset points",
        ha="center",
        va="center",
        fontsize=size,
        **style,
    )


def _arrowhead(
    ax: Axes, pts: FloatArray, frac: FloatArray, at: float, color: str, size: float, alpha: float = 1.0, **kw: Any
) -> None:
    """A small arrowhead on a polyline at fraction ``at`` of its length, pointing along it."""
    f0, f1 = max(at - 0.02, 0.0), min(at + 0.02, 1.0)
    p0 = np.array([np.interp(f0, frac, pts[:, 0]), np.interp(f0, frac, pts[:, 1])])
    p1 = np.array([np.interp(f1, frac, pts[:, 0]), np.interp(f1, frac, pts[:, 1])])
    if np.allclose(p0, p1):
        return
    ax.annotate(
        "",
        xy=(float(p1[0]), float(p1[1])),
        xytext=(float(p0[0]), float(p0[1])),
        arrowprops={
            "arrowstyle": "-|>",
            "color": color,
            "lw": 0.0,
            "mutation_scale": size,
            "shrinkA": 0,
            "shrinkB": 0,
            "alpha": alpha,
        },
        **kw,
    )


def draw_layout(
    ax: Axes,
    track: object,
    *,
    geometry: LayoutGeometry | None = None,
    vertex_labels: bool | None = None,
    edge_labels: bool | None = None,
    arrows: bool = True,
    color: str = EDGE_COLOR,
    lw: float = 2.2,
    label_size: float = 8.0,
) -> LayoutGeometry:
    """Draw a graph track: edges as polylines, direction arrowheads, vertex and edge names.

    Parameters
    ----------
    ax : Axes
    track : GraphTrack, paper track, layout dict or path to a JSON layout
    geometry : LayoutGeometry, optional
        Precomputed :func:`layout_geometry` (computed when omitted).
    vertex_labels : bool, optional
        Write vertex names (bold, beside the vertex); default: all when the track has at most 20 vertices, else only
        the vertices of degree 1 or 2 (ends of sidings, docks), so that large grids stay readable.
    edge_labels : bool, optional
        Write edge names (small, grey italics, at the middle of each edge); default: when the track has at most 30
        edges.
    arrows : bool
        A subtle arrowhead at the middle of each edge, from its ``from`` to its ``to`` vertex.
    color : str
    lw : float
        Edge line width (points).
    label_size : float
        Font size of the names (points).

    Returns
    -------
    LayoutGeometry
        The geometry drawn (pass it on to :func:`draw_routes`).
    """
    tr = as_graph_track(track)
    geo = geometry if geometry is not None else layout_geometry(tr)
    if edge_labels is None:
        edge_labels = tr.n_edges <= 30
    _draw_edges(ax, tr, geo, color=color, lw=lw, arrows=arrows, labels=edge_labels, label_size=label_size)
    _draw_vertices(ax, tr, geo, color=color, labels=vertex_labels, label_size=label_size)
    _pad(ax, geo)
    ax.set_aspect("equal", adjustable="box")
    ax.set_xlabel("x (m)" if not geo.automatic else "x (m, automatic layout)")
    ax.set_ylabel("y (m)" if not geo.automatic else "y (m, automatic layout)")
    return geo


def _draw_edges(
    ax: Axes,
    tr: GraphTrack,
    geo: LayoutGeometry,
    *,
    color: str,
    lw: float,
    arrows: bool,
    labels: bool,
    label_size: float,
) -> None:
    """The edges as polylines, with an arrowhead at mid-length (their direction) and their names if asked."""
    lengths = tr.lengths
    for i, pts in enumerate(geo.polylines):
        ax.plot(pts[:, 0], pts[:, 1], color=color, lw=lw, solid_capstyle="round", zorder=1)
        if arrows:
            _arrowhead(ax, pts, geo.fractions[i], 0.5, "0.6", 15.0, zorder=1.5)
        if labels:
            at = 0.5 * lengths[i]
            p = geo.embed(i, at, lengths)
            n = geo.normal(i, at, lengths)
            ax.annotate(
                tr.edge_names[i],
                xy=(float(p[0]), float(p[1])),
                xytext=(float(-n[0] * 15.0), float(-n[1] * 15.0)),
                textcoords="offset points",
                ha="center",
                va="center",
                fontsize=label_size - 1.0,
                fontstyle="italic",
                color="0.4",
                zorder=2,
            )


def _draw_vertices(
    ax: Axes, tr: GraphTrack, geo: LayoutGeometry, *, color: str, labels: bool | None, label_size: float
) -> None:
    """The vertices that edges use as small circles, named (``labels`` None: all if at most 20, else the ends and
    the vertices of degree 2)."""
    used = sorted(set(tr.tails.tolist()) | set(tr.heads.tolist()))
    vx = geo.vertices[used]
    ax.plot(vx[:, 0], vx[:, 1], "o", color="white", mec=color, mew=1.4, ms=5.5, zorder=3)
    named = used
    if labels is None:
        named = used if len(used) <= 20 else [w for w in used if tr.degree(w) <= 2]
    elif not labels:
        named = []
    if named:
        centre = np.nanmean(vx, axis=0)
        for w in named:
            p = geo.vertices[w]
            d = p - centre
            nd = float(np.hypot(*d))
            d = d / nd if nd > 1e-9 * geo.size else np.array([0.0, 1.0])
            box = {"boxstyle": "round,pad=0.15", "fc": "white", "ec": "none", "alpha": 0.8}
            label_beside(
                ax,
                str(tr.graph.vertices[w]),
                p,
                d,
                10.0,
                label_size,
                fontweight="bold",
                color="0.15",
                bbox=box,
                zorder=6,
            )


# ------------------------------------------------------------------------------------------------- routes
@dataclass(frozen=True)
class Switch:
    """A robot changing edges at a vertex along its route.

    Attributes
    ----------
    robot : str
        ``"A"`` or ``"B"``.
    vertex : int
        Vertex index.
    from_edge, to_edge : int
        Edge indices before and after.
    r : float
        Route coordinate where it happens (metres).
    """

    robot: str
    vertex: int
    from_edge: int
    to_edge: int
    r: float

    def text(self, track: GraphTrack) -> str:
        """E.g. ``"A: switch at J: b_left → b_short"``."""
        names = track.edge_names
        vertex = track.graph.vertices[self.vertex]
        return f"{self.robot}: switch at {vertex}: {names[self.from_edge]} → {names[self.to_edge]}"


def _piece_end(route: DirectedRoute, i: int) -> float:
    return float(route.entry[i] + route.dirs[i] * (route.breaks[i + 1] - route.breaks[i]))


def route_switches(track: GraphTrack, route: DirectedRoute, robot: str) -> list[Switch]:
    """The switches a route uses: where it leaves one edge for another at a vertex.

    Parameters
    ----------
    track : GraphTrack
    route : DirectedRoute
    robot : str
        ``"A"`` or ``"B"`` (copied into each :class:`Switch`).

    Returns
    -------
    list of Switch
        In route order. A reversal on the same edge is not a switch.
    """
    out: list[Switch] = []
    for i in range(len(route.edges) - 1):
        e, f = int(route.edges[i]), int(route.edges[i + 1])
        if e == f:
            continue
        w = track.vertex_at(e, _piece_end(route, i))
        if w is None:  # numerically not exactly at the end: take the nearer end
            end = _piece_end(route, i)
            w = int(track.tails[e]) if end < 0.5 * track.lengths[e] else int(track.heads[e])
        out.append(Switch(robot, int(w), e, f, float(route.breaks[i + 1])))
    return out


def _route_lane_points(
    tr: GraphTrack, geo: LayoutGeometry, route: DirectedRoute, side: float, lane: float, per_metre: float
) -> list[FloatArray]:
    """Polylines of a route drawn beside the track (one per piece, offset further on each revisit of an edge)."""
    visits: dict[int, int] = {}
    out: list[FloatArray] = []
    for i in range(len(route.edges)):
        r0, r1 = float(route.breaks[i]), float(route.breaks[i + 1])
        if r1 <= r0:
            continue
        e = int(route.edges[i])
        k = visits.get(e, 0)
        visits[e] = k + 1
        n = max(math.ceil((r1 - r0) * per_metre), 2)
        r = np.linspace(r0, r1, n + 1)
        off = route.entry[i] + route.dirs[i] * (r - r0)
        p = geo.embed(np.full(r.shape, e), off, tr.lengths)
        nrm = geo.normal(np.full(r.shape, e), off, tr.lengths)
        out.append(p + side * lane * (1.0 + 0.9 * k) * nrm)
    return out


def draw_routes(
    ax: Axes,
    track: object,
    route_a: DirectedRoute,
    route_b: DirectedRoute,
    *,
    geometry: LayoutGeometry | None = None,
    lane: float | None = None,
    switches: bool = True,
    lw: float = 2.0,
    alpha: float = 0.9,
) -> list[Switch]:
    """Draw both robots' routes beside the track, with arrowheads along them and the switches they use.

    Parameters
    ----------
    ax : Axes
    track : GraphTrack or anything :func:`mpa.graph_track.as_graph_track` accepts
    route_a, route_b : DirectedRoute
        Robot A's and robot B's routes.
    geometry : LayoutGeometry, optional
    lane : float, optional
        Distance of a route from the track (metres); default 1.5 % of the drawing's size. A is drawn on the left of
        each edge's orientation, B on the right; a robot that travels an edge again is drawn further out.
    switches : bool
        Mark the switches (diamonds at the vertex) and add legend entries "A: switch at J: e1 → e2".
    lw : float
        Line width (points).
    alpha : float
        Opacity of the routes.

    Returns
    -------
    list of Switch
        The switches of A, then B.
    """
    tr = as_graph_track(track)
    geo = geometry if geometry is not None else layout_geometry(tr)
    lane = 0.015 * geo.size if lane is None else float(lane)
    per_metre = 200.0 / max(tr.total_length, 1e-9)
    found: list[Switch] = []
    for name, route in (("A", route_a), ("B", route_b)):
        st = ROUTE_STYLES[name]
        color = ROBOT_COLORS[name]
        pieces = _route_lane_points(tr, geo, route, st["side"], lane, per_metre)
        if pieces:
            pts = np.vstack(pieces)
            ax.plot(pts[:, 0], pts[:, 1], color=color, lw=lw, ls=st["ls"], alpha=alpha, zorder=4, label=f"route {name}")
            for p in pieces:
                _arrowhead(ax, p, _fractions(p), 0.6, color, 15.0, zorder=4.5, alpha=alpha)
        else:
            ax.plot([], [], color=color, lw=lw, ls=st["ls"], label=f"route {name} (stays)")
        if switches:
            sw = route_switches(tr, route, name)
            found.extend(sw)
    if switches and found:
        used = sorted({s.vertex for s in found})
        vx = geo.vertices[used]
        ax.plot(vx[:, 0], vx[:, 1], "D", ms=9, mfc="none", mec=SWITCH_COLOR, mew=2.0, zorder=5)
        for s in found:
            ax.plot(
                [], [], "D", ms=7, mfc="none", mec=SWITCH_COLOR, mew=1.5, color=ROBOT_COLORS[s.robot], label=s.text(tr)
            )
    return found


# --------------------------------------------------------------------------------------------------- plans
def plan_title(plan: MotionPlan, name: str | None = None) -> str:
    """E.g. ``"y_junction — A, B swap: left, right → right, left\\nD = 0.5 m, fastest, makespan 6.5 s at 1 m/s"``.

    A paper plan (:class:`mpa.Plan`, no objective or speeds) says its domain instead: ``"D = 0.1 m, domain 2"``.
    """
    tr = plan.layout
    a0, b0 = (tr.position_name(*p) for p in plan.layout_start)
    a1, b1 = (tr.position_name(*p) for p in plan.layout_goal)
    swap = "A, B swap: " if (a0, b0) == (b1, a1) else ""
    head = f"{name} — " if name else ""
    if not isinstance(plan, GraphPlan):  # the paper's plans have a domain, not an objective or speeds
        return f"{head}{swap}{a0}, {b0} → {a1}, {b1}\nD = {plan.clearance:g} m, domain {plan.domain}"
    speeds = (
        f"{plan.speeds[0]:g} m/s" if plan.speeds[0] == plan.speeds[1] else f"{plan.speeds[0]:g}/{plan.speeds[1]:g} m/s"
    )
    return (
        f"{head}{swap}{a0}, {b0} → {a1}, {b1}\n"
        f"D = {plan.clearance:g} m, {plan.objective}, makespan {plan.makespan:.3g} s at {speeds}"
    )


def _marker(
    ax: Axes, geo: LayoutGeometry, tr: GraphTrack, pos: tuple[int, float], robot: str, what: str, lane: float
) -> None:
    side = ROUTE_STYLES[robot]["side"]
    e, o = pos
    p = geo.embed(e, o, tr.lengths)
    n = geo.normal(e, o, tr.lengths)
    q = p + side * lane * n
    color = ROBOT_COLORS[robot]
    filled = what == "start"
    ax.plot(
        [q[0]], [q[1]], "^" if filled else "v", ms=10, color=color, mfc=color if filled else "white", mew=2.0, zorder=7
    )
    ox, oy = side * float(n[0]), side * float(n[1])
    ha = "left" if ox > 0.35 else "right" if ox < -0.35 else "center"
    va = "bottom" if oy > 0.35 else "top" if oy < -0.35 else "center"
    ax.annotate(
        f"{robot} {what}",
        xy=(float(q[0]), float(q[1])),
        xytext=(ox * 9.0, oy * 9.0),
        textcoords="offset points",
        ha=ha,
        va=va,
        fontsize=8,
        color=color,
        fontweight="bold",
        bbox={"boxstyle": "round,pad=0.15", "fc": "white", "ec": color, "lw": 0.6, "alpha": 0.9},
        zorder=8,
    )


def draw_graph_plan(
    ax: Axes,
    plan: MotionPlan,
    *,
    name: str | None = None,
    geometry: LayoutGeometry | None = None,
    edge_labels: bool | None = None,
    legend: bool = True,
    title: bool = True,
    footprint: object = None,
) -> list[Switch]:
    """Draw a plan on its layout (a paper plan on its track's graph form).

    Parameters
    ----------
    ax : Axes
    plan : MotionPlan
        A :class:`mpa.GraphPlan` or a paper :class:`mpa.Plan`.
    name : str, optional
        Layout name for the title (e.g. the file's stem).
    geometry : LayoutGeometry, optional
    edge_labels : bool, optional
        As for :func:`draw_layout`.
    legend : bool
        A legend outside the axes on the right: the routes and every switch used.
    title : bool
        Title with the query, clearance, objective and makespan (:func:`plan_title`).
    footprint : None, Footprints, Disc, Rectangle, pair or spec
        The robots' bodies, drawn to scale at start (filled) and goal (outlined) in the layout's drawing
        (:mod:`trajopt.viz.bodies`); needs vertex coordinates.

    Returns
    -------
    list of Switch
    """
    if not isinstance(plan, MotionPlan):
        raise InvalidInputError(f"plan is a {type(plan).__name__}, expected a plan (an mpa.MotionPlan, from mpa.plan)")
    tr = plan.layout
    geo = geometry if geometry is not None else layout_geometry(tr)
    draw_layout(ax, tr, geometry=geo, edge_labels=edge_labels)
    lane = 0.015 * geo.size
    sw = draw_routes(ax, tr, *plan.layout_routes, geometry=geo, lane=lane)
    for robot, k in (("A", 0), ("B", 1)):
        _marker(ax, geo, tr, plan.layout_start[k], robot, "start", lane)
        _marker(ax, geo, tr, plan.layout_goal[k], robot, "goal", lane)
    if footprint is not None:
        _draw_end_bodies(ax, tr, plan.layout_start, plan.layout_goal, footprint)
    if legend:
        h = [
            Line2D([], [], marker="^", ls="none", color="0.3", ms=8, label="start"),
            Line2D([], [], marker="v", ls="none", color="0.3", mfc="white", ms=8, label="goal"),
        ]
        handles, labels = ax.get_legend_handles_labels()
        ax.legend(
            [*handles, *h],
            [*labels, "start", "goal"],
            loc="upper left",
            bbox_to_anchor=(1.01, 1.0),
            fontsize=8,
            frameon=False,
            borderaxespad=0.0,
        )
    if title:
        text = plan_title(plan, name)
        if footprint is not None:
            from mpa.footprint import footprints

            fps = footprints(footprint)
            assert fps is not None
            text += f", bodies {fps.spec()} m to scale"
        ax.set_title(text, fontsize=10)
    _pad(ax, geo)
    return sw


def _draw_end_bodies(
    ax: Axes, tr: GraphTrack, start: tuple[Position, Position], goal: tuple[Position, Position], footprint: object
) -> None:
    """The bodies at the start (filled) and at the goal (outlined, dashed), to scale."""
    from trajopt.viz.bodies import body_poses, draw_bodies

    colors = (ROBOT_COLORS["A"], ROBOT_COLORS["B"])
    for ends, style in (
        (start, {}),
        (goal, {"alpha": 0.8, "facecolor": "none", "ls": "--"}),
    ):
        xy, hd = body_poses(tr, [ends[0][0], ends[1][0]], [ends[0][1], ends[1][1]])
        draw_bodies(ax, footprint, xy, hd, colors, **style)


def _pad(ax: Axes, geo: LayoutGeometry) -> None:
    pts = np.vstack(geo.polylines)
    lo, hi = pts.min(axis=0), pts.max(axis=0)
    m = 0.1 * geo.size
    ax.set_xlim(lo[0] - m, hi[0] + m)
    ax.set_ylim(lo[1] - m, hi[1] + m)


def graph_plan_figure(
    plan: GraphPlan,
    *,
    name: str | None = None,
    cells: bool = True,
    max_cells: int = 6,
    width: float = 9.0,
    footprint: object = None,
) -> Figure:
    """A figure of a plan: the layout with the routes, and (``cells``) the configuration cells it crosses below.

    Parameters
    ----------
    plan : GraphPlan
    name : str, optional
        Layout name for the title.
    cells : bool
        Add the panel of :func:`draw_configuration_cells`.
    max_cells : int
        At most this many cells in that panel.
    width : float
        Figure width (inches).
    footprint : None, Footprints, Disc, Rectangle, pair or spec
        The robots' bodies drawn to scale at start and goal (:func:`draw_graph_plan`).

    Returns
    -------
    Figure
        Not attached to pyplot (save with ``fig.savefig``).
    """
    geo = layout_geometry(plan.track)
    pts = np.vstack(geo.polylines)
    span = np.maximum(pts.max(axis=0) - pts.min(axis=0), 1e-9 * geo.size)
    aspect = float(np.clip(span[1] / span[0], 0.3, 1.6))
    top = 0.62 * width * aspect + 1.0
    fig = Figure(figsize=(width, top + (2.6 if cells else 0.0)), layout="constrained")
    if cells:
        ax_top, ax_cells = fig.subplots(2, 1, height_ratios=[top, 2.6])
    else:
        ax_top, ax_cells = fig.subplots(1, 1), None
    draw_graph_plan(ax_top, plan, name=name, geometry=geo, footprint=footprint)
    if ax_cells is not None:
        draw_configuration_cells(ax_cells, free_space(plan.track, plan.clearance), plan, max_cells=max_cells)
    return fig
