"""The robots' bodies drawn to scale: discs as circles, rectangles turned along the track's tangent.

A body is a matplotlib patch in data units (metres of the layout's drawing): a :class:`matplotlib.patches.Circle`
of the disc's radius, or a :class:`matplotlib.patches.Polygon` with the rectangle's four corners
(:func:`mpa.footprint.body_polygon`: ``length`` along the heading, ``width`` across). Centres and headings are those
of the planner and the gate (:meth:`mpa.footprint.Drawing.pose`: the point at the same fraction of the drawn
polyline as of the edge, the heading of its straight piece), so a picture shows the bodies the gate checked.
"""

from __future__ import annotations

from typing import Any

import numpy as np
from matplotlib.axes import Axes
from matplotlib.patches import Circle, Patch, Polygon
from numpy.typing import ArrayLike

from mpa._arrays import FloatArray
from mpa.footprint import Disc, Footprint, Footprints, body_polygon, drawing_of, footprints

__all__ = ["body_patch", "body_poses", "draw_bodies", "move_body"]


def body_patch(fp: Footprint, xy: ArrayLike, heading: float, **style: Any) -> Patch:
    """A patch of one body at ``xy`` (metres, shape (2,)) with ``heading`` (radians).

    Parameters
    ----------
    fp : Disc or Rectangle
    xy : array_like, shape (2,)
        The body's centre in the drawing (metres).
    heading : float
        Direction of the track's tangent there (radians); a disc ignores it.
    **style
        Patch keywords (``facecolor``, ``edgecolor``, ``alpha``, ``zorder``, ...).

    Returns
    -------
    Circle or Polygon
        In data units: a circle of radius ``fp.radius``, or the rectangle's four corners.
    """
    c = np.asarray(xy, dtype=float)
    if isinstance(fp, Disc):
        return Circle((float(c[0]), float(c[1])), fp.radius, **style)
    return Polygon(body_polygon(fp, c, float(heading)), closed=True, **style)


def move_body(patch: Patch, fp: Footprint, xy: ArrayLike, heading: float) -> None:
    """Place a patch of :func:`body_patch` at a new centre ``xy`` (metres) and ``heading`` (radians)."""
    c = np.asarray(xy, dtype=float)
    if isinstance(patch, Circle):
        patch.set_center((float(c[0]), float(c[1])))
    elif isinstance(patch, Polygon):
        patch.set_xy(body_polygon(fp, c, float(heading)))


def body_poses(track: object, edge: ArrayLike, offset: ArrayLike) -> tuple[FloatArray, FloatArray]:
    """Centres ``(..., 2)`` (metres) and headings ``(...)`` (radians) of positions ``(edge, offset)`` in the drawing.

    Raises
    ------
    InvalidInputError
        A layout without vertex coordinates (bodies need the drawing in metres).
    """
    return drawing_of(track).pose(edge, offset)


def draw_bodies(
    ax: Axes,
    footprint: object,
    xy: ArrayLike,
    heading: ArrayLike,
    colors: tuple[str, str],
    **style: Any,
) -> list[Patch]:
    """Draw robot A's and robot B's bodies and return their patches ``[A, B]``.

    Parameters
    ----------
    ax : Axes
    footprint : Footprints, Disc, Rectangle, pair or spec
        Anything :func:`mpa.footprint.footprints` accepts.
    xy : array_like, shape (2, 2)
        Centres of A and B (metres).
    heading : array_like, shape (2,)
        Headings of A and B (radians).
    colors : (str, str)
        Colours of A and B.
    **style
        Further patch keywords (default: translucent face, solid edge).
    """
    fps = footprints(footprint)
    assert fps is not None
    p = np.asarray(xy, dtype=float).reshape(2, 2)
    h = np.asarray(heading, dtype=float).reshape(2)
    out: list[Patch] = []
    for k, fp in enumerate(_pair(fps)):
        kw = {"facecolor": colors[k], "edgecolor": colors[k], "alpha": 0.35, "lw": 1.2, "zorder": 6} | style
        patch = body_patch(fp, p[k], float(h[k]), **kw)
        ax.add_patch(patch)
        out.append(patch)
    return out


def _pair(fps: Footprints) -> tuple[Footprint, Footprint]:
    return fps.a, fps.b
