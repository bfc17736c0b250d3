"""The track in the plane: the track itself, the robots on it, arrows and lanes of a motion, geodesics."""

from __future__ import annotations

from collections.abc import Sequence
from itertools import pairwise

import numpy as np
from matplotlib.axes import Axes
from numpy.typing import ArrayLike

from mpa.errors import PlanningError
from mpa.tracks import Circle, Interval, Lollipop, Track
from trajopt.viz.drawing.style import (
    ROBOT_COLORS,
    TRACK_COLOR,
    FloatArray,
    _loop_centre,
    _scale,
    _xy,
    coordinate_extent,
    embed_offset,
    lane_unit,
    loop_period,
    track_normal,
)


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
