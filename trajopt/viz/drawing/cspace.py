"""The flat configuration space picture: the collision set shaded, paths, states and traces in it."""

from __future__ import annotations

from collections.abc import Sequence

import matplotlib as mpl
import numpy as np
from matplotlib.axes import Axes
from numpy.typing import ArrayLike

from mpa.retraction import retract
from mpa.tracks import Circle, Interval, Lollipop, Track
from trajopt.viz.drawing.style import COLLISION_COLOR, ROBOT_COLORS, FloatArray, coordinate_extent, split_wraps
from trajopt.viz.drawing.track import arrow_along


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
