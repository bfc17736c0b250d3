"""The drawable shape of a layout: polylines of its edges in the layout's plane (metres).

:func:`layout_geometry` turns a track into drawable polylines: the layout's coordinates and ``points`` when every
vertex has coordinates, else an automatic layout (classical multidimensional scaling of the graph distances between
vertices, refined by stress majorization; numpy only and deterministic). A loop without ``points`` is drawn as a
circle through its vertex, of circumference equal to its length; parallel edges without ``points`` are bent apart.
:mod:`trajopt.viz.layout` draws with it (and re-exports its names).
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike

from mpa._arrays import FloatArray
from mpa.graph_track import GraphTrack, as_graph_track

__all__ = ["CIRCLE_POINTS", "LayoutGeometry", "layout_geometry"]

#: Points per circle drawn for a loop without ``points``.
CIRCLE_POINTS = 64


@dataclass(frozen=True)
class LayoutGeometry:
    """Drawable polylines of a track's edges (metres).

    Attributes
    ----------
    vertices : ndarray, shape (V, 2)
        Vertex coordinates (the layout's, or the automatic layout's).
    polylines : tuple of ndarray
        Per edge, shape (n_i, 2), from its tail to its head.
    fractions : tuple of ndarray
        Per edge, shape (n_i,): cumulative drawn length of the polyline divided by its total (0 ... 1).
    automatic : bool
        Whether the vertex coordinates were computed (the layout has none or not all).
    size : float
        Diagonal of the bounding box of everything drawn (metres), a scale for offsets and markers.
    """

    vertices: FloatArray
    polylines: tuple[FloatArray, ...]
    fractions: tuple[FloatArray, ...]
    automatic: bool
    size: float

    def embed(self, edge: ArrayLike, offset: ArrayLike, lengths: ArrayLike) -> FloatArray:
        """Points of positions ``(edge, offset)``: at the same fraction of the drawn polyline as of the edge.

        Parameters
        ----------
        edge : array_like of int
        offset : array_like of float
            Metres from the edge's tail.
        lengths : array_like of float, shape (E,)
            Edge lengths (metres).

        Returns
        -------
        ndarray, shape ``broadcast(edge, offset).shape + (2,)``
        """
        return self._along_polylines(edge, offset, lengths, _point_at)

    def normal(self, edge: ArrayLike, offset: ArrayLike, lengths: ArrayLike) -> FloatArray:
        """Unit normals on the left of each edge's orientation at positions ``(edge, offset)``. Same shape as
        :meth:`embed`."""
        return self._along_polylines(edge, offset, lengths, _normal_at)

    def _along_polylines(
        self,
        edge: ArrayLike,
        offset: ArrayLike,
        lengths: ArrayLike,
        value: Callable[[FloatArray, FloatArray, FloatArray], FloatArray],
    ) -> FloatArray:
        """``value(polyline, fractions, f)`` (shape ``(k, 2)``) of each edge's drawn polyline at the fractions ``f``
        (shape ``(k,)``) of its length, for positions ``(edge, offset)``; shape
        ``broadcast(edge, offset).shape + (2,)``."""
        e, o = np.broadcast_arrays(np.asarray(edge, dtype=np.int64), np.asarray(offset, dtype=float))
        ln = np.asarray(lengths, dtype=float)
        out = np.empty((*e.shape, 2))
        for i in np.unique(e):
            m = e == i
            out[m] = value(self.polylines[int(i)], self.fractions[int(i)], np.clip(o[m] / ln[i], 0.0, 1.0))
        return out


def _point_at(pts: FloatArray, frac: FloatArray, f: FloatArray) -> FloatArray:
    """Points at the fractions ``f`` of a polyline ``pts`` (shape ``(n, 2)``) whose vertices lie at ``frac``."""
    return np.stack([np.interp(f, frac, pts[:, 0]), np.interp(f, frac, pts[:, 1])], axis=-1)


def _normal_at(pts: FloatArray, frac: FloatArray, f: FloatArray) -> FloatArray:
    """Unit normals on the left of a polyline ``pts`` (shape ``(n, 2)``) at the fractions ``f``."""
    seg = np.diff(pts, axis=0)
    d = seg[np.clip(np.searchsorted(frac, f, side="right") - 1, 0, len(seg) - 1)]
    nrm = np.hypot(d[:, 0], d[:, 1])
    nrm[nrm == 0] = 1.0
    return np.stack([-d[:, 1] / nrm, d[:, 0] / nrm], axis=-1)


def _fractions(pts: FloatArray) -> FloatArray:
    seg = np.hypot(*np.diff(pts, axis=0).T)
    cum = np.concatenate([[0.0], np.cumsum(seg)])
    return cum / cum[-1] if cum[-1] > 0 else np.linspace(0.0, 1.0, len(pts))


def _auto_vertices(track: GraphTrack) -> FloatArray:
    """Deterministic planar-ish vertex coordinates from the graph distances (classical MDS + stress majorization)."""
    n = track.graph.n_vertices
    if n == 1:
        return np.zeros((1, 2))
    dv = np.array(track.geometry.dv, dtype=float)
    finite = np.isfinite(dv)
    big = float(dv[finite].max()) if np.any(finite & (dv > 0)) else 1.0
    dv = np.where(finite, dv, 1.5 * big + 1.0)
    # classical MDS
    j = np.eye(n) - 1.0 / n
    b = -0.5 * j @ (dv**2) @ j
    w, v = np.linalg.eigh(b)
    order = np.argsort(w)[::-1][:2]
    x = v[:, order] * np.sqrt(np.maximum(w[order], 1e-12))
    if x.shape[1] < 2:  # pragma: no cover - n >= 2 gives two eigenvectors
        x = np.column_stack([x, np.zeros(n)])
    # break ties of collinear layouts (a path) a little, deterministically
    x = x + 1e-3 * big * np.column_stack([np.zeros(n), np.cos(np.arange(n))])
    # stress majorization (SMACOF) with weights 1/d^2
    with np.errstate(divide="ignore"):
        wts = np.where(dv > 0, 1.0 / dv**2, 0.0)
    lap = -wts.copy()
    np.fill_diagonal(lap, wts.sum(axis=1))
    lap_pinv = np.linalg.pinv(lap)
    for _ in range(200):
        diff = x[:, None, :] - x[None, :, :]
        dist = np.hypot(diff[..., 0], diff[..., 1])
        with np.errstate(divide="ignore", invalid="ignore"):
            ratio = np.where(dist > 0, wts * dv / dist, 0.0)
        bz = -ratio
        np.fill_diagonal(bz, ratio.sum(axis=1))
        x_new = lap_pinv @ (bz @ x)
        if np.max(np.abs(x_new - x)) < 1e-9 * big:
            x = x_new
            break
        x = x_new
    x -= x.mean(axis=0)
    # canonical orientation: principal axis horizontal, signs fixed by the first vertex that is off an axis
    _, _, vt = np.linalg.svd(x, full_matrices=False)
    x = x @ vt.T
    for k in range(2):
        col = x[:, k]
        i = int(np.argmax(np.abs(col) > 1e-9 * big)) if np.any(np.abs(col) > 1e-9 * big) else 0
        if col[i] < 0:
            x[:, k] = -col
    return x


def _loop_circle(centre_dir: FloatArray, at: FloatArray, length: float) -> FloatArray:
    r = length / (2 * math.pi)
    c = at + r * centre_dir
    phase = math.atan2(-centre_dir[1], -centre_dir[0])
    ang = phase + 2 * math.pi * np.linspace(0.0, 1.0, CIRCLE_POINTS + 1)
    pts = np.column_stack([c[0] + r * np.cos(ang), c[1] + r * np.sin(ang)])
    pts[0] = pts[-1] = at
    return pts


def layout_geometry(track: object) -> LayoutGeometry:
    """Drawable polylines of a track: its coordinates, or an automatic layout when some vertex has none.

    Parameters
    ----------
    track : GraphTrack, paper track, layout dict or path to a JSON layout

    Returns
    -------
    LayoutGeometry
    """
    tr = as_graph_track(track)
    automatic = not tr.has_coordinates
    if automatic:
        xy = _auto_vertices(tr)
    else:
        xy = np.array([c if c is not None else (np.nan, np.nan) for c in tr.coords], dtype=float)
    tails, heads, lengths = tr.tails, tr.heads, tr.lengths
    polys: list[FloatArray | None] = [None] * tr.n_edges
    pair_count: dict[tuple[int, int], int] = {}
    loops_at: dict[int, list[int]] = {}
    for i in range(tr.n_edges):
        u, v = int(tails[i]), int(heads[i])
        if tr.points[i] and not automatic:
            polys[i] = np.array([xy[u], *tr.points[i], xy[v]], dtype=float)
        elif u == v:
            loops_at.setdefault(u, []).append(i)
        else:
            key = (min(u, v), max(u, v))
            k = pair_count.get(key, 0)
            pair_count[key] = k + 1
            a, b = xy[u], xy[v]
            if k == 0:
                polys[i] = np.array([a, b])
            else:  # bend the k-th parallel edge: alternate sides, growing sagitta
                side = 1.0 if k % 2 else -1.0
                sag = side * 0.22 * ((k + 1) // 2) * float(np.hypot(*(b - a)))
                lo, hi = (a, b) if u < v else (b, a)
                nrm = np.array([-(hi - lo)[1], (hi - lo)[0]]) / max(float(np.hypot(*(hi - lo))), 1e-300)
                q = np.linspace(0.0, 1.0, 25)[:, None]
                mid = 0.5 * (lo + hi) + 2 * sag * nrm
                curve = (1 - q) ** 2 * lo + 2 * q * (1 - q) * mid + q**2 * hi
                polys[i] = curve if u < v else curve[::-1]
    # loops: circles pointing away from the vertex's other edges, spread if several
    for w, idx in loops_at.items():
        away = np.zeros(2)
        for i in range(tr.n_edges):
            p = polys[i]
            if p is None or tails[i] == heads[i]:
                continue
            if int(tails[i]) == w:
                away -= (p[1] - p[0]) / max(float(np.hypot(*(p[1] - p[0]))), 1e-300)
            if int(heads[i]) == w:
                away -= (p[-2] - p[-1]) / max(float(np.hypot(*(p[-2] - p[-1]))), 1e-300)
        alone = float(np.hypot(*away)) <= 1e-9
        base = math.pi / 2 if alone else math.atan2(away[1], away[0])
        n = len(idx)
        for k, i in enumerate(idx):
            # alone: spread evenly round the vertex (two loops: a figure eight); else fanned out away from its edges
            ang = base + 2 * math.pi * k / n if alone else base + (k - (n - 1) / 2) * (math.pi / 2) / max(n - 1, 1)
            polys[i] = _loop_circle(np.array([math.cos(ang), math.sin(ang)]), xy[w], float(lengths[i]))
    done = tuple(np.asarray(p, dtype=float) for p in polys)
    allpts = np.vstack([*done, xy[np.isfinite(xy[:, 0])]])
    span = allpts.max(axis=0) - allpts.min(axis=0)
    size = float(np.hypot(*span)) or 1.0
    return LayoutGeometry(xy, done, tuple(_fractions(p) for p in done), automatic, size)
