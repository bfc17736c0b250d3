"""Drawing the paper's objects with matplotlib: tracks, robots, flat configuration spaces, skeletons, traces of H.

Everything drawn here is computed by :mod:`mpa` (track embeddings, distances, skeleton edges, the retraction H,
plans), so a picture doubles as a visual check of the implementation. Nothing in :mod:`mpa` imports this module.

Conventions of the *flat configuration space* picture: the x axis is robot A's track coordinate, the y axis robot
B's, over ``[0, ℓ]`` (interval), ``[0, c)`` (circle) or ``[0, ℓ + c)`` (lollipop; the stick is ``[0, ℓ]``, the
loop lies beyond the dashed lines at ``ℓ``). The collision set (the diagonal, or ``d < D`` for a clearance D) is
shaded red. The loop coordinates are periodic: a path that leaves the square at ``ℓ + c`` (or ``c``) comes back at
``ℓ`` (or 0), and every polyline is broken there (:func:`split_wraps`) instead of being drawn as a long chord.

Robot A is blue, robot B orange; a filled triangle is a robot's initial position, an empty one its final position
(the paper's icons). On the track A is drawn on the outer side (outside the loop, above the stick) and B on the
inner side; where both robots' curves share axes, A is solid and B dashed (:data:`ROBOT_LINESTYLES`).
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass
from itertools import pairwise

import matplotlib as mpl
import numpy as np
from matplotlib.axes import Axes
from matplotlib.figure import Figure
from numpy.typing import ArrayLike, NDArray

from mpa.errors import InvalidInputError, PlanningError
from mpa.plans import Plan
from mpa.retraction import retract
from mpa.skeleton import CircleSkeleton, IntervalSkeleton, LollipopSkeleton, Skeleton, SkeletonPoint, skeleton_of
from mpa.tracks import Circle, Interval, Lollipop, Track

__all__ = [
    "BLOCK_COLORS",
    "ROBOT_COLORS",
    "TRAJECTORY_COLOR",
    "StepStyle",
    "arrow_along",
    "block_of_edge",
    "chain_layout",
    "coordinate_extent",
    "draw_chain",
    "draw_flat_cspace",
    "draw_flat_path",
    "draw_motion",
    "draw_plan_step",
    "draw_robot",
    "draw_robots",
    "draw_skeleton",
    "draw_state",
    "draw_traces",
    "draw_track",
    "draw_track_geodesic",
    "embed_offset",
    "free_offset",
    "lane_unit",
    "loop_period",
    "motion_lanes",
    "new_figure",
    "sample_skeleton",
    "split_wraps",
    "track_normal",
    "track_title",
]

FloatArray = NDArray[np.float64]

#: Colours of robots A and B.
ROBOT_COLORS = {"A": "#1f77b4", "B": "#ff7f0e"}
#: Colours of the blocks of the skeleton chain (lollipop) and of the antipodal circle (circle).
BLOCK_COLORS = {
    "I1": "#2ca02c",
    "S1": "#9467bd",
    "S2": "#8c564b",
    "S3": "#e377c2",
    "I2": "#17becf",
    "A": "#9467bd",
    "A<B": "#2ca02c",
    "B<A": "#17becf",
}
#: Colours of the three steps of the algorithm.
STEP_COLORS = {"preliminary": "#e6ab02", "main": "#000000", "final": "#7f7f7f"}
COLLISION_COLOR = "#d62728"
#: Colour of a trajectory's path in the configuration space: far from the collision band's red.
TRAJECTORY_COLOR = "#1a237e"
#: Line styles of robots A and B where their curves share axes (speed over time): B dashed on top of A.
ROBOT_LINESTYLES = {"A": "-", "B": (0, (4, 2))}
TRACK_COLOR = "0.35"


def new_figure(
    ncols: int = 1, nrows: int = 1, *, width: float = 4.2, height: float = 4.0
) -> tuple[Figure, NDArray[np.object_]]:
    """A figure with ``nrows × ncols`` axes (always returned as a 2-D array), without pyplot's global state.

    Parameters
    ----------
    ncols, nrows : int
        Grid of axes.
    width, height : float
        Size of one panel in inches.

    Returns
    -------
    fig : Figure
    axes : ndarray of Axes, shape (nrows, ncols)
    """
    fig = Figure(figsize=(width * ncols, height * nrows), layout="constrained")
    axes = fig.subplots(nrows, ncols, squeeze=False)
    return fig, axes


def _xy(p: ArrayLike) -> tuple[float, float]:
    """A point as a pair of floats (what matplotlib's annotations expect)."""
    x, y = np.asarray(p, dtype=float).reshape(2)
    return float(x), float(y)


def track_title(track: Track) -> str:
    """A readable name of a track and its size, e.g. ``"lollipop ℓ = 1 m, c = 1 m"``."""
    params = track.to_dict()
    sizes = [f"{sym} = {params[key]:g} m" for key, sym in (("stick", "ℓ"), ("loop", "c")) if key in params]
    return f"{track.kind} {', '.join(sizes)}".strip()


# ---------------------------------------------------------------------------------------------------
# coordinates
def coordinate_extent(track: Track) -> float:
    """Upper end of the track coordinate range: ℓ (interval), c (circle), ℓ + c (lollipop)."""
    return float(track.total_length)


def loop_period(track: Track) -> tuple[float, float] | None:
    """``(ℓ0, c)``: the loop coordinates are ``[ℓ0, ℓ0 + c)`` and periodic with period c; None for the interval."""
    if isinstance(track, Circle):
        return 0.0, track.loop
    if isinstance(track, Lollipop):
        return track.stick, track.loop
    return None


def split_wraps(track: Track, states: ArrayLike) -> FloatArray:
    """Break a densely sampled path of states where a loop coordinate wraps round (``ℓ + c → ℓ`` or ``c → 0``).

    At each wrap the segment is completed to the edge of the square on both sides and a NaN row is inserted,
    so matplotlib draws two pieces meeting the boundary instead of a chord across the square.

    Parameters
    ----------
    track : Track
    states : array_like, shape (N, 2)
        Consecutive states (track coordinates), dense enough that no real step exceeds half the loop.

    Returns
    -------
    ndarray, shape (M, 2)
        The states with the wraps opened (M ≥ N).
    """
    st = np.atleast_2d(np.asarray(states, dtype=float))
    per = loop_period(track)
    if per is None or len(st) < 2:
        return st.copy()
    lo, c = per
    hi = lo + c
    out: list[FloatArray] = [st[0]]
    for p0, p1 in pairwise(st):
        jump = p1 - p0
        wrapped = np.abs(jump) > 0.5 * c
        if np.any(wrapped):
            if np.sum(wrapped) == 1:
                k = int(np.flatnonzero(wrapped)[0])
                sgn = -np.sign(jump[k])  # +1: crossed the top edge upwards
                p1u = p1.copy()
                p1u[k] += sgn * c
                edge0 = hi if sgn > 0 else lo
                frac = (edge0 - p0[k]) / (p1u[k] - p0[k]) if p1u[k] != p0[k] else 0.0
                q0 = p0 + frac * (p1u - p0)
                q0[k] = edge0
                q1 = q0.copy()
                q1[k] = lo if sgn > 0 else hi
                out += [q0, np.array([np.nan, np.nan]), q1]
            else:
                out.append(np.array([np.nan, np.nan]))
        out.append(p1)
    return np.array(out)


# ---------------------------------------------------------------------------------------------------
# the physical track
def _loop_centre(track: Track) -> FloatArray:
    if isinstance(track, Circle):
        return np.zeros(2)
    if not isinstance(track, Lollipop):
        raise InvalidInputError(f"track is {track!r}, expected a Lollipop")
    pts = track.embed(np.linspace(track.stick, track.stick + track.loop, 65)[:-1])
    return np.asarray(pts.mean(axis=0))


def track_normal(track: Track, p: ArrayLike) -> FloatArray:
    """Unit normal of the embedded track at ``p`` (outward on the loop, +y on the stick). Shape ``p.shape + (2,)``."""
    p = np.asarray(p, dtype=float)
    xy = track.embed(p)
    if isinstance(track, Interval):
        return np.broadcast_to(np.array([0.0, 1.0]), xy.shape).copy()
    centre = _loop_centre(track)
    radial = xy - centre
    radial = radial / np.maximum(np.linalg.norm(radial, axis=-1, keepdims=True), 1e-300)
    if isinstance(track, Circle):
        return radial
    if not isinstance(track, Lollipop):
        raise InvalidInputError(f"track is {track!r}, expected a Lollipop")
    up = np.broadcast_to(np.array([0.0, 1.0]), xy.shape)
    return np.where((p < track.stick)[..., None], up, radial)


def embed_offset(track: Track, p: ArrayLike, offset: ArrayLike) -> FloatArray:
    """Embedded positions pushed ``offset`` (metres, broadcast) along :func:`track_normal`."""
    p = np.asarray(p, dtype=float)
    return track.embed(p) + np.asarray(offset, dtype=float)[..., None] * track_normal(track, p)


def lane_unit(track: Track) -> float:
    """Length unit of the offsets of drawn motions: the loop radius, or a tenth of an interval."""
    if isinstance(track, (Circle, Lollipop)):
        return float(track.loop / (2 * np.pi))
    return 0.1 * float(track.total_length)


def _scale(track: Track) -> float:
    xy = track.embed(np.linspace(0.0, coordinate_extent(track), 200))
    return float(np.max(np.ptp(xy, axis=0)))


def draw_track(
    ax: Axes,
    track: Track,
    *,
    color: str = TRACK_COLOR,
    lw: float = 3.0,
    labels: bool = True,
    ccw_arrow: bool = True,
    highlight: tuple[float, float] | None = None,
    highlight_color: str = "#2ca02c",
) -> None:
    """Draw the track from its planar embedding (:meth:`Track.embed`), with the pole P and the free end.

    Parameters
    ----------
    ax : Axes
    track : Track
    color : str
        Colour of the track.
    lw : float
        Line width.
    labels : bool
        Label the pole P (lollipop), the free end 0 and the stick/loop.
    ccw_arrow : bool
        Draw the counterclockwise orientation of the loop.
    highlight : (float, float), optional
        A coordinate range ``[p0, p1]`` drawn thick in ``highlight_color``.
    highlight_color : str
    """
    ext = coordinate_extent(track)
    closed = isinstance(track, Circle)
    p = np.linspace(0.0, ext, 721)
    xy = track.embed(p)
    if closed:
        xy = np.vstack([xy, xy[:1]])
    ax.plot(xy[:, 0], xy[:, 1], color=color, lw=lw, solid_capstyle="round", zorder=1)
    s = _scale(track)
    if highlight is not None:
        hp = np.linspace(highlight[0], highlight[1], 200)
        hxy = track.embed(hp)
        ax.plot(hxy[:, 0], hxy[:, 1], color=highlight_color, lw=2.2 * lw, alpha=0.6, zorder=1, solid_capstyle="round")
    if isinstance(track, Lollipop):
        pxy = track.embed(track.stick)
        ax.plot(*pxy, "o", color="k", ms=5, zorder=3)
        f = track.embed(0.0)
        ax.plot(*f, "o", color="k", ms=4, zorder=3)
        if labels:
            ax.annotate("P", _xy(pxy), xytext=(-10, 8), textcoords="offset points", fontsize=11)
            ax.annotate("0", _xy(f), xytext=(-4, 8), textcoords="offset points", fontsize=9, color="0.3")
    if isinstance(track, Interval):
        for q, name in ((0.0, "0"), (track.stick, f"{track.stick:g}")):
            ax.plot(*track.embed(q), "|", color="k", ms=12, zorder=3)
            if labels:
                ax.annotate(name, _xy(track.embed(q)), xytext=(-4, -16), textcoords="offset points", fontsize=9)
    if ccw_arrow and track.has_loop:
        per = loop_period(track)
        if per is None:
            raise PlanningError("internal: per is not set")
        lo, c = per
        centre = _loop_centre(track)
        r = float(np.linalg.norm(track.embed(lo + 0.25 * c) - centre))
        ang = np.linspace(0.35, 0.15, 30) * 2 * np.pi + np.arctan2(*(track.embed(lo) - centre)[::-1])
        ring = centre + 0.55 * r * np.stack([np.cos(ang), np.sin(ang)], axis=-1)[::-1]
        ax.plot(ring[:, 0], ring[:, 1], color="0.55", lw=1.0)
        arrow_along(ax, ring, frac=1.0, color="0.55", size=10)
    ax.set_aspect("equal")
    ax.axis("off")
    pad = 0.12 * s
    lo_xy, hi_xy = xy.min(axis=0), xy.max(axis=0)
    ax.set_xlim(lo_xy[0] - pad, hi_xy[0] + pad)
    ax.set_ylim(lo_xy[1] - pad, hi_xy[1] + pad)


def draw_robot(
    ax: Axes, track: Track, p: float, name: str, *, final: bool = False, label: str | None = None, size: float = 11.0
) -> None:
    """One robot as the paper's triangle: filled at its initial position, empty at its final position.

    Parameters
    ----------
    ax : Axes
    track : Track
    p : float
        Track coordinate.
    name : {"A", "B"}
        Which robot (sets the colour).
    final : bool
        Empty triangle (final position) instead of a filled one.
    label : str, optional
        Text next to the marker (default ``name``); ``""`` for none.
    size : float
        Marker size.
    """
    color = ROBOT_COLORS[name]
    side = 1.0 if name == "A" else -1.0  # A just outside the track, B just inside: never hidden by each other
    xy = embed_offset(track, float(p), side * 0.15 * lane_unit(track))
    ax.plot(*xy, marker="^", ms=size, mec=color, mfc="white" if final else color, mew=2.0, zorder=6, linestyle="none")
    text = name if label is None else label
    if text:
        off = 15.0 * side * track_normal(track, float(p))  # points, away from the track on the robot's side
        ax.annotate(
            text,
            _xy(xy),
            xytext=_xy(off),
            textcoords="offset points",
            color=color,
            fontsize=10,
            ha="center",
            va="center",
            zorder=7,
            fontweight="bold",
        )


def draw_robots(
    ax: Axes, track: Track, state: ArrayLike, *, final: bool = False, labels: tuple[str, str] | None = None
) -> None:
    """Both robots of a state ``(a, b)`` (see :func:`draw_robot`)."""
    a, b = (float(v) for v in np.asarray(state, dtype=float))
    la, lb = labels if labels is not None else ("A", "B")
    draw_robot(ax, track, a, "A", final=final, label=la)
    draw_robot(ax, track, b, "B", final=final, label=lb)


def arrow_along(
    ax: Axes, pts: ArrayLike, *, frac: float = 0.5, color: str = "k", size: float = 14.0, lw: float = 1.5
) -> None:
    """An arrowhead on a polyline at the fraction ``frac`` of its arc length, pointing forwards.

    NaN rows split the polyline into pieces (see :func:`split_wraps`); the arc length is that of the pieces, the
    gaps between them do not count.

    Parameters
    ----------
    ax : Axes
    pts : array_like, shape (N, 2)
        The polyline.
    frac : float
        Position along the polyline in [0, 1].
    color : str
    size : float
        Arrowhead size (points).
    lw : float
    """
    xy = np.asarray(pts, dtype=float)
    if len(xy) < 2:
        return
    seg = np.linalg.norm(np.diff(xy, axis=0), axis=1)
    seg = np.where(np.isfinite(seg), seg, 0.0)
    cum = np.concatenate([[0.0], np.cumsum(seg)])
    total = cum[-1]
    if total <= 0:
        return
    target = float(np.clip(frac, 0.0, 1.0)) * total
    usable = np.flatnonzero(seg > 0)
    i = int(usable[np.clip(np.searchsorted(cum[usable + 1], target), 0, len(usable) - 1)])
    t = float(np.clip((target - cum[i]) / seg[i], 0.0, 1.0))
    direction = (xy[i + 1] - xy[i]) / seg[i]
    head = xy[i] + t * (xy[i + 1] - xy[i])
    tail = head - 1e-3 * total * direction
    ax.annotate(
        "",
        xy=head,
        xytext=tail,
        arrowprops={"arrowstyle": "-|>", "color": color, "lw": lw, "mutation_scale": size, "shrinkA": 0, "shrinkB": 0},
        zorder=5,
    )


def motion_lanes(track: Track, positions: ArrayLike) -> FloatArray:
    """Lane index of every sample of a robot's motion: how many earlier passes over the same edge it has made.

    The motion is cut into passes where the robot goes through the pole P (from the stick to the loop or back) or
    reverses; a pass gets the number of earlier passes on the same edge (stick or loop), and on the loop the index
    also grows by the number of turns made within the pass, so that laps spiral outwards.

    Parameters
    ----------
    track : Track
    positions : array_like, shape (N,)
        Track coordinates over time (dense).

    Returns
    -------
    ndarray, shape (N,)
    """
    p = np.asarray(positions, dtype=float)
    n = len(p)
    per = loop_period(track)
    ell = track.stick if isinstance(track, Lollipop) else (-np.inf if isinstance(track, Circle) else np.inf)
    on_loop = p > ell + 1e-12
    at_pole = np.abs(p - ell) <= 1e-9 * max(1.0, float(track.total_length))
    for i in range(1, n):  # a sample at P belongs to the pass it ends or starts
        if at_pole[i]:
            on_loop[i] = on_loop[i - 1]
    dp = np.diff(p)
    if per is not None:
        c = per[1]
        dp = np.where(np.abs(dp) > 0.5 * c, dp - np.sign(dp) * c, dp)
    direction = np.sign(dp)
    for i in range(1, len(direction)):  # carry the last non-zero direction forwards
        if direction[i] == 0:
            direction[i] = direction[i - 1]
    near_pole = at_pole.copy()
    near_pole[1:] |= at_pole[:-1]
    near_pole[:-1] |= at_pole[1:]
    cuts = [0]
    for i in range(1, n):
        if on_loop[i] != on_loop[i - 1]:
            cuts.append(i)
        elif i >= 2 and direction[i - 1] * direction[i - 2] < 0:
            if not near_pole[i - 1] and on_loop[i - 2] == on_loop[i]:
                cuts.append(i)
    cuts.append(n)
    out = np.zeros(n)
    counts = {False: 0, True: 0}
    for start, stop in pairwise(cuts):
        if stop <= start:
            continue
        edge = bool(on_loop[start])
        lane = float(counts[edge])
        if edge and per is not None:
            travel = np.concatenate([[0.0], np.cumsum(np.abs(dp[start : stop - 1]))])
            out[start:stop] = lane + travel / per[1]
        else:
            out[start:stop] = lane
        counts[edge] += 1
    return out


def draw_motion(
    ax: Axes,
    track: Track,
    positions: ArrayLike,
    name: str,
    *,
    lane: float = 0.25,
    spread: float = 0.3,
    arrows: Sequence[float] = (0.5, 1.0),
    lw: float = 2.0,
    alpha: float = 1.0,
) -> None:
    """The motion of one robot along the track, drawn beside the track with arrowheads.

    The curve is the embedding of the robot's track coordinates pushed off the track along its normal by
    ``lane + spread · k`` (in units of the loop radius, or of a tenth of the interval), where ``k`` counts the robot's
    earlier passes over the same edge (:func:`motion_lanes`), so that a robot passing the same place twice draws
    visibly separate passes. Robot B is drawn on the other side of the track.

    Parameters
    ----------
    ax : Axes
    track : Track
    positions : array_like, shape (N,)
        The robot's track coordinates over time (dense).
    name : {"A", "B"}
    lane, spread : float
        Offset from the track at the start, and its growth to the end (see above).
    arrows : sequence of float
        Fractions of the arc length where arrowheads are drawn.
    lw, alpha : float
    """
    p = np.asarray(positions, dtype=float)
    if len(p) < 2 or (float(np.max(np.abs(np.diff(p)))) == 0.0 and float(np.ptp(p)) == 0.0):
        return
    sign = 1.0 if name == "A" else -1.0
    off = sign * lane_unit(track) * (lane + spread * motion_lanes(track, p))
    xy = embed_offset(track, p, off)
    color = ROBOT_COLORS[name]
    ax.plot(xy[:, 0], xy[:, 1], color=color, lw=lw, alpha=alpha, zorder=4, solid_capstyle="round")
    for f in arrows:
        arrow_along(ax, xy, frac=f, color=color, size=13)


def draw_track_geodesic(ax: Axes, track: Track, p: float, q: float, *, color: str = "#2ca02c", n: int = 2001) -> float:
    """Highlight the shortest path between ``p`` and ``q`` on the track, found from :meth:`Track.distance` alone.

    A point ``r`` of the track lies on a shortest path iff ``d(p, r) + d(r, q) = d(p, q)``.

    Returns
    -------
    float
        The distance ``d(p, q)``.
    """
    r = np.linspace(0.0, coordinate_extent(track), n)
    d = float(track.distance(p, q))
    on = np.abs(track.distance(p, r) + track.distance(r, q) - d) <= 1e-9 + 1e-6 * d
    xy = track.embed(r)
    xy[~on] = np.nan
    ax.plot(xy[:, 0], xy[:, 1], color=color, lw=7, alpha=0.45, zorder=2, solid_capstyle="round")
    return d


# ---------------------------------------------------------------------------------------------------
# the flat configuration space
def draw_flat_cspace(
    ax: Axes,
    track: Track,
    *,
    clearance: float = 0.0,
    grid: int = 401,
    level_h: bool = False,
    quadrant_labels: bool = False,
    components: bool = False,
    axis_labels: bool = True,
) -> None:
    """The flat configuration space: axes over the coordinate range, the collision set shaded.

    Parameters
    ----------
    ax : Axes
    track : Track
    clearance : float
        Shade ``{d < D}`` as well as the diagonal (metres).
    grid : int
        Resolution of the shading.
    level_h : bool
        Draw the level set ``d = h`` (h = half the loop) as a thin dotted contour computed from
        :meth:`Track.distance`: the skeleton must lie on it.
    quadrant_labels : bool
        Name the four products of stick and loop (lollipop).
    components : bool
        Shade the two components of the interval's configuration space in two tints.
    axis_labels : bool
        Label the axes with the robots' names.
    """
    ext = coordinate_extent(track)
    g = np.linspace(0.0, ext, grid)
    aa, bb = np.meshgrid(g, g)
    d = track.distance(aa, bb)
    if components and isinstance(track, Interval):
        _shade_interval_components(ax, aa, bb, ext)
    if clearance > 0:
        _shade_clearance_band(ax, d, clearance, ext)
    ax.plot([0, ext], [0, ext], color=COLLISION_COLOR, lw=2.0, alpha=0.85, zorder=2)
    if level_h and isinstance(track, (Circle, Lollipop)):
        h = 0.5 * float(track.loop)
        ax.contour(g, g, d, levels=[h], colors="0.5", linewidths=0.8, linestyles=":", zorder=2)
    ax.set_xlim(0, ext)
    ax.set_ylim(0, ext)
    ax.set_aspect("equal")
    if isinstance(track, Lollipop):
        _lollipop_flat_axes(ax, track, quadrant_labels=quadrant_labels)
    elif isinstance(track, Circle):
        c = track.loop
        ax.set_xticks([0, 0.5 * c, c], ["0", f"{0.5 * c:g}", f"{c:g}"])
        ax.set_yticks([0, 0.5 * c, c], ["0", f"{0.5 * c:g}", f"{c:g}"])
    if axis_labels:
        ax.set_xlabel("robot A (track coordinate)", color=ROBOT_COLORS["A"])
        ax.set_ylabel("robot B (track coordinate)", color=ROBOT_COLORS["B"])


def _shade_interval_components(ax: Axes, aa: FloatArray, bb: FloatArray, ext: float) -> None:
    """The two components of the interval's configuration space (A < B, B < A) in two tints."""
    tint = np.where(bb > aa, 1.0, 0.0)
    cmap = mpl.colors.ListedColormap(["#e6f2ff", "#fff0e0"])
    ax.imshow(tint, origin="lower", extent=(0, ext, 0, ext), cmap=cmap, vmin=0, vmax=1, zorder=0)
    ax.text(0.25 * ext, 0.8 * ext, "A < B", ha="center", fontsize=10, color="0.3")
    ax.text(0.75 * ext, 0.2 * ext, "B < A", ha="center", fontsize=10, color="0.3")


def _shade_clearance_band(ax: Axes, d: FloatArray, clearance: float, ext: float) -> None:
    """The states closer than the clearance (``d < D``), shaded in the collision colour."""
    bad = np.where(d < clearance, 1.0, np.nan)
    ax.imshow(
        bad,
        origin="lower",
        extent=(0, ext, 0, ext),
        cmap=mpl.colors.ListedColormap([COLLISION_COLOR]),
        alpha=0.22,
        zorder=1,
        interpolation="nearest",
    )


def _lollipop_flat_axes(ax: Axes, track: Lollipop, *, quadrant_labels: bool) -> None:
    """Dashed lines at the pole P, ticks at 0, P, P + h, ℓ + c, and optionally the names of the four quadrants."""
    ell, c = track.stick, track.loop
    ax.axvline(ell, color="0.4", ls="--", lw=0.9, zorder=1)
    ax.axhline(ell, color="0.4", ls="--", lw=0.9, zorder=1)
    ticks = [0.0, ell, ell + 0.5 * c, ell + c]
    names = ["0", f"P\n{ell:g}", f"{ell + 0.5 * c:g}", f"{ell + c:g}"]
    ax.set_xticks(ticks, names)
    ax.set_yticks(ticks, [n.replace("\n", " ") for n in names])
    if not quadrant_labels:
        return
    for x, y, text in (
        (0.22 * ell, 0.06 * ell, "stick × stick"),
        (0.25 * ell, ell + 0.92 * c, "stick × loop"),
        (ell + 0.78 * c, 0.1 * ell, "loop × stick"),
        (ell + 0.2 * c, ell + 0.92 * c, "loop × loop"),
    ):
        ax.text(
            x,
            y,
            text,
            ha="center",
            va="center",
            fontsize=8,
            color="0.45",
            rotation=0,
            bbox={"fc": "white", "ec": "none", "alpha": 0.7},
        )


def block_of_edge(skeleton: Skeleton, edge: str) -> str:
    """Name of the block of the chain an edge belongs to: I1, S1, S2, S3, I2 (lollipop) or A (circle)."""
    if isinstance(skeleton, CircleSkeleton):
        return "A"
    if edge in ("I1", "I2"):
        return edge
    return edge[:2]


def sample_skeleton(skeleton: Skeleton, n: int = 200) -> dict[str, FloatArray]:
    """Every edge of the skeleton graph sampled through ``skeleton.state(SkeletonPoint(edge, t))``.

    Returns
    -------
    dict
        Edge name to an array of states (track coordinates), shape (n, 2), tail first.
    """
    out: dict[str, FloatArray] = {}
    if not isinstance(skeleton, (CircleSkeleton, LollipopSkeleton)):  # the interval's skeleton has no edges
        return out
    for e in skeleton.graph.edges:
        ts = np.linspace(0.0, e.length, n)
        out[e.name] = np.array([skeleton.state(SkeletonPoint(e.name, float(t))) for t in ts])
    return out


def draw_skeleton(
    ax: Axes,
    skeleton: Skeleton,
    *,
    labels: bool = True,
    arrows: bool = True,
    lw: float = 2.6,
    vertices: bool = True,
    alpha: float = 1.0,
) -> dict[str, FloatArray]:
    """The skeleton in the flat configuration space, sampled edge by edge from the library.

    Each edge is drawn in its block's colour (:data:`BLOCK_COLORS`); circle arcs get an arrowhead in the direction
    of their orientation (counterclockwise: the loop robot moves ccw); the blocks are labelled I1, S1, S2, S3, I2
    (or 𝒜 for the antipodal circle). A label sits at its block's centroid unless the centroid is a collision
    (S2, the antipodal circle), then on each arc.

    Parameters
    ----------
    ax : Axes
    skeleton : Skeleton
    labels, arrows, vertices : bool
    lw, alpha : float

    Returns
    -------
    dict
        The sampled edges (see :func:`sample_skeleton`).
    """
    track = skeleton.track
    if isinstance(skeleton, IntervalSkeleton) and isinstance(track, Interval):
        ell = track.stick
        for (x, y), name in (((0.0, ell), "A<B"), ((ell, 0.0), "B<A")):
            ax.plot(x, y, "o", color=BLOCK_COLORS[name], ms=9, zorder=6, clip_on=False)
        return {}
    samples = sample_skeleton(skeleton)
    blocks: dict[str, list[FloatArray]] = {}
    for e in skeleton.graph.edges:
        st = samples[e.name]
        blk = block_of_edge(skeleton, e.name)
        blocks.setdefault(blk, []).append(st)
        color = BLOCK_COLORS[blk]
        xy = split_wraps(track, st)
        ax.plot(xy[:, 0], xy[:, 1], color=color, lw=lw, alpha=alpha, zorder=4, solid_capstyle="butt")
        if arrows and blk not in ("I1", "I2") and e.length > 0:
            arrow_along(ax, xy, frac=0.55, color=color, size=15)
    if vertices:
        for v in skeleton.graph.vertices:
            pts = [samples[e.name][0] for e in skeleton.graph.edges if e.tail == v] + [
                samples[e.name][-1] for e in skeleton.graph.edges if e.head == v
            ]
            if pts:
                ax.plot(*pts[0], "o", color="k", ms=3.5, zorder=5)
    if labels:
        ext = coordinate_extent(track)
        for blk, parts in blocks.items():
            name = r"$\mathcal{A}$" if blk == "A" else f"${blk[0]}_{blk[1]}$"
            for sp in _label_spots(track, [p for p in parts if np.ptp(p, axis=0).max() > 0], ext):
                ax.text(
                    float(sp[0]),
                    float(sp[1]),
                    name,
                    color=BLOCK_COLORS[blk],
                    fontsize=12,
                    ha="center",
                    va="center",
                    zorder=7,
                    fontweight="bold",
                    bbox={"fc": "white", "ec": "none", "alpha": 0.75, "pad": 1.0},
                )
    return samples


def _label_spots(track: Track, parts: Sequence[FloatArray], ext: float) -> list[FloatArray]:
    """Where to write a block's name: its centroid if that is off the block and not a collision, else beside the
    middle of each of its edges, on the side away from the diagonal."""
    if not parts:
        return []
    allp = np.vstack(parts)
    cen = allp.mean(axis=0)
    off_curve = float(np.min(np.linalg.norm(allp - cen, axis=1))) > 0.06 * ext
    if off_curve and float(track.distance(cen[0], cen[1])) > 0.05 * track.total_length:
        return [cen]
    spots = []
    for p in parts:
        k = len(p) // 2
        tangent = p[min(k + 1, len(p) - 1)] - p[max(k - 1, 0)]
        normal = np.array([-tangent[1], tangent[0]]) / max(float(np.linalg.norm(tangent)), 1e-300)
        cands = [p[k] + s * 0.055 * ext * normal for s in (1.0, -1.0)]
        spots.append(max(cands, key=lambda q: abs(float(q[1] - q[0]))))
    return spots


def draw_flat_path(
    ax: Axes,
    track: Track,
    states: ArrayLike,
    *,
    color: str = "k",
    lw: float = 2.0,
    arrows: Sequence[float] = (0.5,),
    alpha: float = 1.0,
    ls: str = "-",
    zorder: float = 5,
) -> None:
    """A path of states in the flat configuration space, broken where a loop coordinate wraps round."""
    xy = split_wraps(track, states)
    ax.plot(xy[:, 0], xy[:, 1], color=color, lw=lw, alpha=alpha, ls=ls, zorder=zorder, solid_capstyle="round")
    for f in arrows:
        arrow_along(ax, xy, frac=f, color=color, size=13)


def draw_state(
    ax: Axes,
    state: ArrayLike,
    label: str | None = None,
    *,
    color: str = "k",
    marker: str = "o",
    filled: bool = True,
    offset: tuple[float, float] = (6, 6),
    size: float = 7.0,
    ha: str = "left",
    va: str = "baseline",
) -> None:
    """A state (point) in the flat configuration space, with an optional label such as ``$x_i'$``.

    The label sits ``offset`` points from the point, aligned by ``ha``/``va``; near the top or right edge of the
    axes a positive offset is turned round so that the label stays inside.
    """
    x, y = (float(v) for v in np.asarray(state, dtype=float))
    (x0, x1), (y0, y1) = ax.get_xlim(), ax.get_ylim()
    if x > x0 + 0.85 * (x1 - x0) and offset[0] > 0:
        offset = (-offset[0] - 12, offset[1])
    if y > y0 + 0.9 * (y1 - y0) and offset[1] > 0:
        offset = (offset[0], -offset[1] - 8)
    ax.plot(
        x,
        y,
        marker=marker,
        ms=size,
        mec=color,
        mfc=color if filled else "white",
        mew=1.6,
        zorder=8,
        linestyle="none",
        clip_on=False,
    )
    if label:
        ax.annotate(
            label,
            (x, y),
            xytext=offset,
            textcoords="offset points",
            fontsize=12,
            color=color,
            zorder=9,
            ha=ha,
            va=va,
            bbox={"fc": "white", "ec": "none", "alpha": 0.7, "pad": 0.5},
        )


def draw_traces(
    ax: Axes,
    track: Track,
    *,
    n: int = 13,
    steps: int = 41,
    min_distance: float | None = None,
    color: str = "0.45",
) -> tuple[FloatArray, FloatArray]:
    """Traces ``t ↦ H(x, t)`` of the deformation for a grid of start states, computed with :func:`mpa.retract`.

    Parameters
    ----------
    ax : Axes
    track : Track
    n : int
        Grid points per axis (shifted by half a cell so that no start lies on the diagonal or the skeleton).
    steps : int
        Samples of t in [0, 1] along each trace.
    min_distance : float, optional
        Skip starts closer than this (default: 2 % of the total length).
    color : str

    Returns
    -------
    starts : ndarray, shape (K, 2)
    ends : ndarray, shape (K, 2)
        ``H(x, 1)`` of every start.
    """
    ext = coordinate_extent(track)
    g = (np.arange(n) + 0.5) / n * ext
    aa, bb = np.meshgrid(g, g)
    starts = np.stack([aa.ravel(), bb.ravel()], axis=-1)
    dmin = 0.02 * track.total_length if min_distance is None else min_distance
    starts = starts[track.distance(starts[:, 0], starts[:, 1]) > dmin]
    ts = np.linspace(0.0, 1.0, steps)
    traces = np.stack([retract(track, starts, np.full(len(starts), t)) for t in ts], axis=1)  # (K, steps, 2)
    for tr in traces:
        xy = split_wraps(track, tr)
        ax.plot(xy[:, 0], xy[:, 1], color=color, lw=0.9, zorder=3)
        if float(np.max(np.abs(tr[-1] - tr[0]))) > 1e-9:
            arrow_along(ax, xy, frac=1.0, color=color, size=7, lw=0.8)
    ax.plot(starts[:, 0], starts[:, 1], "o", ms=2.0, color="0.3", zorder=3)
    return starts, traces[:, -1]


# ---------------------------------------------------------------------------------------------------
# the abstract chain I1 — S1 — S2 — S3 — I2
def chain_layout(skeleton: LollipopSkeleton, *, radius: float = 1.0, stick: float = 1.2) -> dict[str, FloatArray]:
    """Positions of the vertices of the skeleton graph for the chain picture: a row, circles of ``radius``."""
    names = [str(v) for v in skeleton.graph.vertices]
    x = {"e1": 0.0, "v1": stick}
    x["v2"] = x["v1"] + 2 * radius
    x["v3"] = x["v2"] + 2 * radius
    x["v4"] = x["v3"] + 2 * radius
    x["e2"] = x["v4"] + stick
    return {v: np.array([x[v], 0.0]) for v in names}


def draw_chain(
    ax: Axes,
    skeleton: LollipopSkeleton,
    *,
    arrows: bool = True,
    labels: bool = True,
    vertex_names: bool = True,
    dim_edges: Sequence[str] = (),
) -> dict[str, FloatArray]:
    """The skeleton graph as the paper's chain of three circles with two intervals.

    Vertices and edges come from ``skeleton.graph``. A circle arc runs along the lower half when its tail is left
    of its head and along the upper half otherwise, so an arrow from tail to head turns counterclockwise on the
    page: the page's ccw is the library's ccw orientation of every ``S_j``.

    Parameters
    ----------
    ax : Axes
    skeleton : LollipopSkeleton
    arrows, labels, vertex_names : bool
    dim_edges : sequence of str
        Edges drawn dashed and grey (e.g. a spanning tree being contracted).

    Returns
    -------
    dict
        Vertex positions.
    """
    pos = chain_layout(skeleton)
    for e in skeleton.graph.edges:
        p0, p1 = pos[str(e.tail)], pos[str(e.head)]
        blk = block_of_edge(skeleton, e.name)
        color = BLOCK_COLORS[blk]
        dim = e.name in dim_edges
        if blk in ("I1", "I2"):
            xy = np.array([p0, p1])
        else:
            centre = 0.5 * (p0 + p1)
            r = 0.5 * float(np.linalg.norm(p1 - p0))
            a0 = np.arctan2(*(p0 - centre)[::-1])
            # lower half if tail left of head: angle from π to 2π; upper half otherwise: from 0 to π
            ang = np.linspace(a0, a0 + np.pi, 100)
            xy = centre + r * np.stack([np.cos(ang), np.sin(ang)], axis=-1)
        ax.plot(
            xy[:, 0], xy[:, 1], color="0.6" if dim else color, lw=1.5 if dim else 3.0, ls="--" if dim else "-", zorder=2
        )
        if arrows and blk not in ("I1", "I2") and not dim:
            arrow_along(ax, xy, frac=0.55, color=color, size=16)
        if (labels and e.name.endswith("a")) or (labels and blk in ("I1", "I2")):
            mid = xy.mean(axis=0) if len(xy) == 2 else xy[len(xy) // 2]
            txt = f"${blk[0]}_{blk[1]}$"
            dy = -0.28 if blk not in ("I1", "I2") else 0.25
            if blk.startswith("S") and mid[1] > 0:
                dy = 0.28
            ax.text(mid[0], mid[1] + dy, txt, color=color, ha="center", va="center", fontsize=13, fontweight="bold")
    for v, p in pos.items():
        ax.plot(*p, "o", color="k", ms=5, zorder=4)
        if vertex_names:
            ax.annotate(v, _xy(p), xytext=(0, 7), textcoords="offset points", ha="center", fontsize=8, color="0.3")
    ax.set_aspect("equal")
    ax.axis("off")
    allp = np.array(list(pos.values()))
    ax.set_xlim(allp[:, 0].min() - 0.3, allp[:, 0].max() + 0.3)
    ax.set_ylim(-1.5, 1.5)
    return pos


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


def free_offset(ax: Axes, xy: ArrayLike, obstacles: ArrayLike, *, radius: float = 15.0) -> tuple[float, float]:
    """An offset (points) for a label of the point ``xy`` that keeps it clear of lines and of the other labels.

    Tries eight directions at ``radius`` points and picks the one farthest (on screen) from the ``obstacles``
    (data points, shape (K, 2), e.g. samples of the drawn paths) and from the texts already on the axes.

    Returns
    -------
    (float, float)
        The offset in points.
    """
    to_px = ax.figure.dpi / 72.0
    centre = ax.transData.transform(np.asarray(xy, dtype=float).reshape(1, 2))[0]
    obs = ax.transData.transform(np.asarray(obstacles, dtype=float).reshape(-1, 2))
    texts = [_text_anchor_px(ax, tx) for tx in ax.texts]
    best, best_score = (radius, radius), -np.inf
    for ang in np.arange(8) * np.pi / 4 + np.pi / 4:
        off = (radius * float(np.cos(ang)), radius * float(np.sin(ang)))
        spot = centre + to_px * np.array(off)
        score = float(np.min(np.linalg.norm(obs - spot, axis=1))) if len(obs) else np.inf
        for anchor in texts:
            score = min(score, 0.5 * float(np.linalg.norm(anchor - spot)))
        if score > best_score:
            best, best_score = off, score
    return best


def _text_anchor_px(ax: Axes, text: mpl.text.Text) -> FloatArray:
    """Where a text of the axes sits, in display pixels (annotations: the point plus the offset)."""
    if isinstance(text, mpl.text.Annotation) and text.anncoords == "offset points":
        base = ax.transData.transform(np.asarray(text.xy, dtype=float).reshape(1, 2))[0]
        return np.asarray(base + np.asarray(text.xyann, dtype=float) * ax.figure.dpi / 72.0)
    return np.asarray(text.get_transform().transform(text.get_position()))
