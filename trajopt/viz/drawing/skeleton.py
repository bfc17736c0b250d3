"""The skeleton: its blocks coloured, drawn over the flat configuration space or as a chain of circles."""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np
from matplotlib.axes import Axes

from mpa.skeleton import CircleSkeleton, IntervalSkeleton, LollipopSkeleton, Skeleton, SkeletonPoint
from mpa.tracks import Interval
from trajopt.viz.drawing.labels import _label_spots
from trajopt.viz.drawing.style import BLOCK_COLORS, FloatArray, _xy, coordinate_extent, split_wraps
from trajopt.viz.drawing.track import arrow_along


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
