"""The configuration cells a layout plan crosses, drawn side by side in offsets (``A's edge × B's edge``) with
the free polygons, the clearance set and the plan's segments; re-exported by :mod:`trajopt.viz.layout`.
"""

from __future__ import annotations

import numpy as np
from matplotlib.axes import Axes
from matplotlib.patches import Polygon, Rectangle

from mpa.freespace import FreeSpace
from mpa.graph_track import GraphTrack
from mpa.planners.graph import GraphPlan
from trajopt.viz.drawing import COLLISION_COLOR


def draw_configuration_cells(
    ax: Axes, space: FreeSpace, plan: GraphPlan, *, max_cells: int = 6, gap: float | None = None
) -> list[tuple[int, int, int]]:
    """The cells ``A's edge × B's edge`` a plan crosses, side by side in offsets, with the free polygons and the path.

    Each cell is a box of size ``L_e × L_f`` (x: robot A's offset on its edge, y: robot B's, metres), the set closer
    than the clearance shaded red, the free polygon(s) white, the plan's segments in the cell drawn in black with
    arrowheads and numbered in the order the plan passes them. Boxes are placed left to right in the order the plan
    first enters them.

    Parameters
    ----------
    ax : Axes
    space : FreeSpace
        Free space of the plan's track and clearance (:func:`mpa.free_space`).
    plan : GraphPlan
    max_cells : int
        Draw at most this many cells (the first ones entered); the rest is mentioned in the title.
    gap : float, optional
        Horizontal gap between boxes (metres); default a fifth of the largest edge.

    Returns
    -------
    list of (e, f, k)
        The cells drawn (polygon ids of :mod:`mpa.freespace`).
    """
    tr = plan.track
    lengths = tr.lengths
    order: list[tuple[int, int]] = []
    for e, f, _ in plan.corner_cells:
        if (e, f) not in order:
            order.append((e, f))
    shown = order[:max_cells]
    gap = 0.2 * float(lengths.max()) if gap is None else float(gap)
    x0: dict[tuple[int, int], float] = {}
    x = 0.0
    for e, f in shown:
        x0[(e, f)] = x
        x += float(lengths[e]) + gap
    drawn = _draw_cell_boxes(ax, space, tr, x0)
    _draw_path_in_cells(ax, plan, x0)
    _draw_ends_in_cells(ax, plan, x0)
    more = f" (first {len(shown)} of {len(order)})" if len(order) > len(shown) else ""
    ax.set_title(
        f"configuration cells crossed{more}: x = offset of A, y = offset of B (m); "
        f"red: closer than D = {plan.clearance:g} m; ■ start, ☆ goal",
        fontsize=8,
    )
    ax.set_aspect("equal", adjustable="box")
    ax.set_xticks([])
    ax.set_xlim(-0.05 * gap, x - gap + 0.05 * gap)
    ax.set_ylim(-0.05 * float(lengths.max()), float(max(lengths[f] for _, f in shown)) + 0.4 * float(lengths.max()))
    return drawn


def _draw_cell_boxes(
    ax: Axes, space: FreeSpace, tr: GraphTrack, x0: dict[tuple[int, int], float]
) -> list[tuple[int, int, int]]:
    """Each product of edges ``(e, f)`` as a box at ``x0[(e, f)]``: shaded where the robots are too close, its free
    polygons white, labelled with the edges; returns the polygons drawn."""
    names = tr.edge_names
    lengths = tr.lengths
    drawn: list[tuple[int, int, int]] = []
    for e, f in x0:
        le, lf = float(lengths[e]), float(lengths[f])
        ox = x0[(e, f)]
        ax.add_patch(Rectangle((ox, 0.0), le, lf, fc=COLLISION_COLOR, alpha=0.25, ec="none", zorder=1))
        for k in (0, 1):
            pid = (e, f, k)
            if pid in space._index:
                v = space.vertices(pid)
                ax.add_patch(Polygon(v + np.array([ox, 0.0]), closed=True, fc="white", ec="0.5", lw=0.8, zorder=2))
                drawn.append(pid)
        ax.add_patch(Rectangle((ox, 0.0), le, lf, fc="none", ec="0.2", lw=1.0, zorder=3))
        top = lf + 0.06 * float(lengths.max())
        ax.text(
            ox + le / 2, top, f"A on {names[e]}\nB on {names[f]}", ha="center", va="bottom", fontsize=7, color="0.2"
        )
    return drawn


def _draw_path_in_cells(ax: Axes, plan: GraphPlan, x0: dict[tuple[int, int], float]) -> None:
    """The plan's straight segments inside the boxes drawn at ``x0``, arrowed and numbered in order."""
    for j, ((e, f, _), seg) in enumerate(zip(plan.segment_cells, plan.segment_offsets)):
        if (e, f) not in x0:
            continue
        p = seg + np.array([x0[(e, f)], 0.0])
        ax.plot(p[:, 0], p[:, 1], color="black", lw=1.6, zorder=4)
        ax.plot(p[:, 0], p[:, 1], "o", color="black", ms=2.5, zorder=4)
        if np.hypot(*(p[1] - p[0])) > 1e-9:
            ax.annotate(
                "",
                xy=(float(p[1, 0]), float(p[1, 1])),
                xytext=(float(0.5 * (p[0, 0] + p[1, 0])), float(0.5 * (p[0, 1] + p[1, 1]))),
                arrowprops={"arrowstyle": "-|>", "color": "black", "lw": 0.0, "mutation_scale": 9},
                zorder=4,
            )
        mid = 0.5 * (p[0] + p[1])
        ax.annotate(
            str(j + 1), xy=(float(mid[0]), float(mid[1])), xytext=(4, 4), textcoords="offset points", fontsize=7
        )


def _draw_ends_in_cells(ax: Axes, plan: GraphPlan, x0: dict[tuple[int, int], float]) -> None:
    """The start (filled square) and the goal (empty star), where their cells are drawn."""
    for what, corner in (("start", 0), ("goal", -1)):
        e, f, _ = plan.corner_cells[corner]
        if (e, f) in x0:
            s, t = plan.corner_offsets[corner]
            ax.plot(
                [x0[(e, f)] + s],
                [t],
                "s" if what == "start" else "*",
                color="black",
                ms=7 if what == "start" else 10,
                mfc="black" if what == "start" else "white",
                zorder=5,
                clip_on=False,
            )
