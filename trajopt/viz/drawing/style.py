"""Colours, figures and the track's embedding shared by every drawing.

Track coordinates to the plane, normals, loop periods, and the breaks of polylines at wraps.
"""

from __future__ import annotations

from itertools import pairwise

import numpy as np
from matplotlib.figure import Figure
from numpy.typing import ArrayLike, NDArray

from mpa._arrays import FloatArray
from mpa.errors import InvalidInputError
from mpa.tracks import Circle, Interval, Lollipop, Track

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
