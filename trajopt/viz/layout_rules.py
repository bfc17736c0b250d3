"""Drawing a layout with its lane rules: vertex names, one-way arrows and speed limits (``mpa layout show``).

matplotlib only here (and in the rest of :mod:`trajopt.viz`); nothing in :mod:`mpa` or the pipeline imports it.
"""

from __future__ import annotations

from typing import Any

import numpy as np
from matplotlib.axes import Axes
from matplotlib.figure import Figure

from mpa.graph_track import GraphTrack, as_graph_track
from trajopt.viz.layout import LayoutGeometry, _arrowhead, _pad, draw_layout, label_beside, layout_geometry

__all__ = ["ONEWAY_COLOR", "SPEED_COLOR", "draw_lane_rules", "layout_figure"]

#: Colour of the one-way arrows.
ONEWAY_COLOR = "#d62728"
#: Colour of the speed-limit labels.
SPEED_COLOR = "#1f77b4"


def draw_lane_rules(ax: Axes, track: GraphTrack, geo: LayoutGeometry, *, label_size: float = 7.0) -> None:
    """Overlay the lane rules on a drawn layout: one-way edges red with arrowheads at a quarter, half and three
    quarters of their length (from ``from`` to ``to``), speed limits as blue labels ``≤ v m/s`` at mid-edge.

    Parameters
    ----------
    ax : Axes
        Axes holding :func:`trajopt.viz.layout.draw_layout` of ``track``.
    track : GraphTrack
    geo : LayoutGeometry
        The geometry it was drawn with.
    label_size : float
        Font size of the limits (points).
    """
    lengths = track.lengths
    for i, pts in enumerate(geo.polylines):
        if track.oneway[i]:
            ax.plot(pts[:, 0], pts[:, 1], color=ONEWAY_COLOR, lw=2.4, solid_capstyle="round", zorder=1.2)
            for at in (0.25, 0.5, 0.75):
                _arrowhead(ax, pts, geo.fractions[i], at, ONEWAY_COLOR, 16.0, zorder=1.6)
        limit = track.speed_limits[i]
        if limit is not None:
            p = geo.embed(i, 0.5 * lengths[i], lengths)
            n = geo.normal(i, 0.5 * lengths[i], lengths)
            box = {"boxstyle": "round,pad=0.12", "fc": "white", "ec": SPEED_COLOR, "lw": 0.6, "alpha": 0.85}
            label_beside(ax, f"≤ {limit:g} m/s", p, n, 14.0, label_size, color=SPEED_COLOR, bbox=box, zorder=5)


def layout_figure(track: object, *, name: str | None = None, width: float = 9.0, **draw_kw: Any) -> Figure:
    """A figure of a layout: edges, vertex names, one-way arrows and speed limits, with a legend of the rules.

    Parameters
    ----------
    track : GraphTrack, paper track, layout dict or path to a JSON layout
    name : str, optional
        Title (with the edge count and total length).
    width : float
        Figure width (inches).
    **draw_kw
        Passed to :func:`trajopt.viz.layout.draw_layout` (e.g. ``vertex_labels=True``).

    Returns
    -------
    Figure
        Not attached to pyplot (save with ``fig.savefig``).
    """
    tr = as_graph_track(track)
    geo = layout_geometry(tr)
    pts = np.vstack(geo.polylines)
    span = np.maximum(pts.max(axis=0) - pts.min(axis=0), 1e-9 * geo.size)
    aspect = float(np.clip(span[1] / span[0], 0.3, 1.6))
    fig = Figure(figsize=(width, 0.8 * width * aspect + 1.0), layout="constrained")
    ax = fig.subplots(1, 1)
    draw_kw.setdefault("vertex_labels", True)
    draw_layout(ax, tr, geometry=geo, **draw_kw)
    draw_lane_rules(ax, tr, geo)
    _pad(ax, geo)
    n_one = sum(tr.oneway)
    n_lim = sum(v is not None for v in tr.speed_limits)
    title = f"{name + ': ' if name else ''}{tr.n_edges} edges, {tr.total_length:.4g} m"
    rules = []
    if n_one:
        rules.append(f"{n_one} one-way (red arrows)")
    if n_lim:
        rules.append(f"{n_lim} with a speed limit (blue)")
    ax.set_title(title + ("; " + ", ".join(rules) if rules else ""), fontsize=10)
    return fig
