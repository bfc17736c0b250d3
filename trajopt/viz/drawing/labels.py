"""Placing labels where they do not cover what is drawn."""

from __future__ import annotations

from collections.abc import Sequence

import matplotlib as mpl
import numpy as np
from matplotlib.axes import Axes
from numpy.typing import ArrayLike

from mpa.tracks import Track
from trajopt.viz.drawing.style import FloatArray


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
