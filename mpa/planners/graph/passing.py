"""The passing segments of ``φ = d(x, ·)`` in a free space: where the two robots are at equal graph distance from a
vertex ``x`` and at least the clearance apart (:mod:`mpa.planners.graph.bounds`, module docstring).

In a cell ``e × f`` (robot A on edge e at offset u, robot B on f at v) ``φ`` is a tent on each edge, so ``φ(p) =
φ(q)`` is at most four straight pieces ``v = ±u + β``; the clearance keeps an interval of each. The segments are built
with numpy, a block of cells at a time, only from the cells whose two edges' ranges of ``φ`` meet, cut in pieces of at
most ``PIECE_LENGTH`` times the longest edge, and kept with the free space's mesh per vertex (they do not depend on
the query beyond ``x``).
"""

from __future__ import annotations

from collections.abc import Callable, Iterator
from typing import Any

import numpy as np
from numpy.typing import NDArray

from mpa._arrays import FloatArray
from mpa.freespace import CELL_BLOCK
from mpa.planners.graph.mesh import _Mesh

__all__ = ["GEOMETRY_CACHE", "PIECE_LENGTH", "passing_geometry"]

#: The passing segments are cut in pieces of at most this fraction of the longest edge: the bound at a search node,
#: relaxed per segment (each robot to the nearest point of the segment's stretch of its edge), then loses at most
#: about a piece's length over the speed. None: whole segments (up to an edge's length each).
PIECE_LENGTH: float | None = 0.1

#: Passing segments kept with a free space's mesh, over all the vertices cached (:func:`passing_geometry`; 48 bytes
#: each, so at most 24 MB a free space, and the free-space cache keeps up to 16); 0: none.
GEOMETRY_CACHE = 500_000

_SLOPES = ((1.0, 1.0), (1.0, -1.0), (-1.0, 1.0), (-1.0, -1.0))  # the cell terms' slopes, as in mpa.freespace


def _keep(
    lo: FloatArray, hi: FloatArray, ok: NDArray[np.bool_], k: float, rhs: FloatArray
) -> tuple[FloatArray, FloatArray, NDArray[np.bool_]]:
    """The interval ``[lo, hi]`` of u cut by ``k u >= rhs`` per row (``k`` one number); rows where ``k = 0`` and
    ``rhs > 0`` are dropped from ``ok``."""
    if k > 0:
        return np.maximum(lo, rhs / k), hi, ok
    if k < 0:
        return lo, np.minimum(hi, rhs / k), ok
    return lo, hi, ok & (rhs <= 0.0)


def passing_geometry(mesh: _Mesh, x: int) -> tuple[Any, ...] | None:
    """The passing segments of ``φ = d(x, ·)`` in the free space (module docstring): arrays ``(e, u0, u1, f, alpha,
    beta)`` over the segments (robot A on edge ``e`` at ``u`` in ``[u0, u1]``, robot B on edge ``f`` at ``v = alpha u
    + beta``, metres), cut in pieces of at most ``PIECE_LENGTH`` times the longest edge; None when there are none.

    They depend on the query only through ``x``, so they are kept with the mesh, per vertex, up to
    ``GEOMETRY_CACHE`` segments in all (the oldest vertices dropped first)."""
    cache: dict[tuple[int, float | None], tuple[Any, ...] | None] | None = getattr(mesh, "_passing_geometry", None)
    if cache is None:
        cache = {}
        mesh._passing_geometry = cache  # type: ignore[attr-defined]
    key = (x, PIECE_LENGTH)
    if key in cache:
        return cache[key]
    out = _build_passing_geometry(mesh, x)
    n = 0 if out is None else len(out[0])
    if n <= GEOMETRY_CACHE:
        held = sum(0 if v is None else len(v[0]) for v in cache.values())
        while cache and held + n > GEOMETRY_CACHE:
            old = cache.pop(next(iter(cache)))
            held -= 0 if old is None else len(old[0])
        cache[key] = out
    return out


def _build_passing_geometry(
    mesh: _Mesh,
    x: int,
    every_cell: bool = False,
    rows: NDArray[np.int64] | None = None,
    cols: NDArray[np.int64] | None = None,
    cell_ok: Callable[[NDArray[np.int64], NDArray[np.int64]], NDArray[np.bool_]] | None = None,
) -> tuple[Any, ...] | None:
    """:func:`passing_geometry` built: numpy over the free space's non-empty cells, a block at a time, only those
    whose two edges' ranges of ``φ`` meet (``every_cell``: all of them, the tests' reference).

    ``rows``, ``cols``: only the cells of these edges of robot A, of robot B (sorted edge numbers; None: every
    edge); ``cell_ok``: only the cells ``e × f`` it keeps (a mask over a block's cells). The segments of the cells
    kept are those of the whole build, in the same order."""
    g = mesh.g
    fs = mesh.fs
    lengths, tails, heads = g.lengths, g.tails, g.heads
    dmin = fs._dmin
    slack = 1e-12 * mesh.scale
    phi_t, phi_h = g.dv[x, tails], g.dv[x, heads]
    mid = np.clip(0.5 * (lengths + phi_h - phi_t), 0.0, lengths)
    # φ on an edge ranges from its smaller end value to the tent's top: a cell can hold φ(p) = φ(q) only where its
    # two edges' ranges meet (most cells of a large layout are at very different distances from x)
    phi_lo = np.minimum(phi_t, phi_h) - 1e-9 * mesh.scale
    phi_hi = np.minimum(mid + phi_t, lengths - mid + phi_h) + 1e-9 * mesh.scale
    parts: dict[tuple[int, int, int], list[tuple[FloatArray, ...]]] = {}
    blocks = fs.nonempty_cells() if every_cell else _cells_meeting(fs, phi_lo, phi_hi, lengths, rows, cols)
    for ee, ff in blocks:  # a block of cells at a time: memory bounded on large layouts
        if cell_ok is not None:
            keep = cell_ok(ee, ff)
            ee, ff = ee[keep], ff[keep]
            if not len(ee):
                continue
        c0 = g.cell_terms_array(ee, ff)
        same = ee == ff
        for pe in (0, 1):
            se = 1.0 if pe == 0 else -1.0
            ce = phi_t[ee] if pe == 0 else lengths[ee] + phi_h[ee]
            ua = np.zeros(len(ee)) if pe == 0 else mid[ee]
            ub = mid[ee] if pe == 0 else lengths[ee]
            for pf in (0, 1):
                sf = 1.0 if pf == 0 else -1.0
                cf = phi_t[ff] if pf == 0 else lengths[ff] + phi_h[ff]
                va_ = np.zeros(len(ff)) if pf == 0 else mid[ff]
                vb_ = mid[ff] if pf == 0 else lengths[ff]
                alpha = se * sf
                beta = sf * (ce - cf)  # v = alpha u + beta on the piece
                if alpha > 0:
                    lo, hi = np.maximum(ua, va_ - beta), np.minimum(ub, vb_ - beta)
                else:
                    lo, hi = np.maximum(ua, beta - vb_), np.minimum(ub, beta - va_)
                ok = np.ones(len(ee), dtype=bool)
                for j, (ca, cb) in enumerate(_SLOPES):  # c0 + ca u + cb v >= dmin
                    lo, hi, ok = _keep(lo, hi, ok, ca + cb * alpha, dmin - slack - c0[:, j] - cb * beta)
                # one edge: |u - v| >= dmin, u - v = (1 - alpha) u - beta; the two sides are two cases
                for case in (0, 1, -1):
                    m = ok & (~same if case == 0 else same)
                    lo_c, hi_c = lo, hi
                    if case != 0:
                        lo_c, hi_c, m = _keep(lo, hi, m, case * (1.0 - alpha), dmin - slack + case * beta)
                    m &= lo_c <= hi_c
                    if m.any():
                        b = beta[m]
                        row = (ee[m], lo_c[m], hi_c[m], ff[m], np.full(int(m.sum()), alpha), b)
                        parts.setdefault((pe, pf, case), []).append(row)
    found = [r for key in sorted(parts, key=lambda k: (k[0], k[1], (0, 1, -1).index(k[2]))) for r in parts[key]]
    if not found:
        return None
    e = np.concatenate([r[0] for r in found])
    u0 = np.concatenate([r[1] for r in found])
    u1 = np.concatenate([r[2] for r in found])
    f = np.concatenate([r[3] for r in found])
    al = np.concatenate([r[4] for r in found])
    be = np.concatenate([r[5] for r in found])
    if PIECE_LENGTH is not None:  # shorter pieces: the relaxation at a node loses at most a piece's length
        n = np.maximum(1, np.ceil((u1 - u0) / (PIECE_LENGTH * mesh.scale)).astype(np.int64))
        idx = np.repeat(np.arange(len(n)), n)
        j = np.arange(len(idx)) - np.repeat(np.cumsum(n) - n, n)
        step = (u1 - u0)[idx] / n[idx]
        lo = u0[idx] + j * step
        hi = np.where(j == n[idx] - 1, u1[idx], lo + step)
        e, f, al, be, u0, u1 = e[idx], f[idx], al[idx], be[idx], lo, hi
    return e, u0, u1, f, al, be


def _cells_meeting(
    fs: Any,
    phi_lo: FloatArray,
    phi_hi: FloatArray,
    lengths: FloatArray,
    row_edges: NDArray[np.int64] | None = None,
    col_edges: NDArray[np.int64] | None = None,
) -> Iterator[tuple[NDArray[np.int64], NDArray[np.int64]]]:
    """The non-empty cells ``e × f`` whose edges' ranges ``[phi_lo, phi_hi]`` meet, row-major, in blocks of at most
    ``CELL_BLOCK`` rows' worth: found by sorting the edges by ``phi_lo`` (only edges whose ``phi_lo`` lies within the
    widest range below ``e``'s can meet it), without a pass over every cell. ``row_edges``, ``col_edges``: only
    these edges ``e`` and ``f`` (sorted; None: every edge)."""
    n = len(phi_lo)
    cols_all = np.arange(n) if col_edges is None else np.asarray(col_edges, dtype=np.int64)
    rows_all = np.arange(n) if row_edges is None else np.asarray(row_edges, dtype=np.int64)
    order = cols_all[np.argsort(phi_lo[cols_all], kind="stable")]
    lo_sorted = phi_lo[order]
    reach = float(np.max(phi_hi[cols_all] - phi_lo[cols_all])) if len(cols_all) else 0.0
    first = np.zeros(n, dtype=np.int64)
    last = np.zeros(n, dtype=np.int64)
    first[rows_all] = np.searchsorted(lo_sorted, phi_lo[rows_all] - reach, side="left")
    last[rows_all] = np.searchsorted(lo_sorted, phi_hi[rows_all], side="right")
    rows_per_block = max(1, CELL_BLOCK // max(1, len(cols_all)))
    for i0 in range(0, len(rows_all), rows_per_block):
        rows = rows_all[i0 : i0 + rows_per_block]
        counts = np.maximum(0, last[rows] - first[rows])
        ee = np.repeat(rows, counts)
        offs = np.arange(len(ee)) - np.repeat(np.cumsum(counts) - counts, counts) + np.repeat(first[rows], counts)
        ff = order[offs]
        keep = (phi_lo[ff] <= phi_hi[ee]) & (phi_lo[ee] <= phi_hi[ff])
        ee, ff = ee[keep], ff[keep]
        keep = fs.status[ee, ff] != 0
        ee, ff = ee[keep], ff[keep]
        if len(ee):
            k = np.lexsort((ff, ee))  # row-major, as fs.nonempty_cells
            yield ee[k].astype(np.int64), ff[k].astype(np.int64)
