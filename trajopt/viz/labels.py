"""Labels that do not overlap: :func:`separate_labels` moves annotations apart after a figure is laid out.

The texts of an axes are taken in order of decreasing ``zorder`` (vertex names before edge names on a layout);
each one that overlaps a text already placed (its drawn box, grown by :data:`GAP` pixels) is tried at other offsets
from the point it labels — further out, on the other side, at right angles — and keeps the first that overlaps
nothing placed and stays inside the axes. Only annotations with an offset (``textcoords="offset points"``) are
moved; other texts stay where they are and count as placed. Animated texts are left alone.
"""

from __future__ import annotations

from typing import Any

import numpy as np

__all__ = ["GAP", "separate_labels"]

#: Pixels kept between two labels.
GAP = 2.0
#: Offsets tried, as multiples of the label's own offset ``v`` (and of ``v`` turned by 90°).
_TRIES = (
    (1.7, 0.0),
    (-1.0, 0.0),
    (-1.7, 0.0),
    (0.0, 1.2),
    (0.0, -1.2),
    (2.5, 0.0),
    (-2.5, 0.0),
    (1.2, 1.2),
    (1.2, -1.2),
)


def _box(text: Any, renderer: Any) -> Any:
    return text.get_window_extent(renderer).expanded(1.0, 1.0).padded(GAP)


def separate_labels(ax: Any) -> bool:
    """Move the annotations of ``ax`` that overlap others (see the module docstring). The figure must have been
    drawn once (its layout fixed); returns whether any label moved (then draw again)."""
    fig = ax.figure
    renderer = fig.canvas.get_renderer()
    frame = ax.get_window_extent(renderer)
    texts = [t for t in ax.texts if t.get_visible() and not t.get_animated() and t.get_text()]
    texts.sort(key=lambda t: -t.get_zorder())
    placed: list[Any] = []
    moved = False
    for t in texts:
        box = _box(t, renderer)
        if not any(box.overlaps(b) for b in placed):
            placed.append(box)
            continue
        offset = getattr(t, "xyann", None)
        if offset is None or getattr(t, "anncoords", None) != "offset points":
            placed.append(box)
            continue
        v = np.asarray(offset, dtype=float)
        if not np.any(v):
            v = np.array([0.0, 10.0])
        w = np.array([-v[1], v[0]])
        for a, b in _TRIES:
            t.xyann = tuple(a * v + b * w)
            cand = _box(t, renderer)
            inside = frame.x0 <= cand.x0 and cand.x1 <= frame.x1 and frame.y0 <= cand.y0 and cand.y1 <= frame.y1
            if inside and not any(cand.overlaps(p) for p in placed):
                placed.append(cand)
                moved = True
                break
        else:
            t.xyann = tuple(v)
            placed.append(box)
    return moved
