"""The free configuration space of two robots on a graph track with clearance D, exactly, as convex polygons.

For robot A on edge ``e`` (offset ``s``) and robot B on edge ``f`` (offset ``t``) the graph distance is the minimum
of four affine terms (and ``|s - t|`` when ``e == f``; see :mod:`mpa.geometry`). The free set ``{d >= D}`` in the
cell ``e × f`` is therefore one convex polygon (``e != f``) or two (``e == f``: piece 0 where ``s - t >= D``,
piece 1 where ``t - s >= D``). Polygons are stored with their vertices in offsets ``(s, t)`` (metres),
counter-clockwise; a cell that is entirely free is not clipped (its polygon is the box).

Gluing. A robot standing on a vertex ``w`` belongs to every edge at ``w``. The *face* ``A at w, B on f`` is the set
``{t : d(w, (f, t)) >= D}``, one closed interval ``[lo, hi]`` (``d`` is a minimum of affine functions of ``t``, so its
super-level set is convex); every free polygon of a cell ``e × f`` with ``w`` an end of ``e`` restricts to exactly
this interval on its side ``s = 0`` (``w`` the tail of ``e``) or ``s = L_e`` (``w`` the head). Faces ``A on e, B at
w`` likewise. Polygons sharing a face are adjacent (a face that is a single point still connects: point contacts
count). Corners, where both robots stand on vertices, lie on faces and need no extra gluing. Path components of the
free set are the connected components of the polygon–face incidence graph (by size: a union-find, label
jumping in numpy, scipy's csgraph).

Storage. Every pair of edges is a cell, but a cell entirely free (most pairs on a large layout: farther apart than
the clearance everywhere) is its box and holds no vertices; only clipped cells keep their polygons. The polygons'
edges, pieces, numbers and components are integer arrays (:attr:`FreeSpace.polygon_ids` is a sequence read from
them), so the memory per cell is a few tens of bytes (:data:`MAX_CELLS`).

Tolerances. Membership uses ``d >= D - tol`` with ``tol = 1e-12 · max(1, total length)``, so thresholds that are met
exactly (a siding exactly as long as the clearance) count as free. A clearance of 0 (the paper's ``C²``, only the
diagonal removed), and any clearance below it, is replaced internally by ``1e-9 · max(1, total length)`` metres
(:attr:`FreeSpace.clearance_used`): with a clearance under the tolerance the robots could pass through each other.

Swapping. :meth:`FreeSpace.can_swap` with two positions answers whether ``(x, y)`` and ``(y, x)`` are in one path
component (the robots can exchange these places); without arguments, whether any configuration can be exchanged,
i.e. some component is mapped to itself by the swap ``(x, y) -> (y, x)``.
"""

from __future__ import annotations

from collections.abc import Iterable, Iterator, Mapping, Sequence
from dataclasses import dataclass
from functools import cached_property, lru_cache
from typing import overload

import numpy as np
from numpy.typing import NDArray

from mpa import tolerance
from mpa._arrays import FloatArray
from mpa._deprecation import deprecated_alias
from mpa.errors import InvalidInputError
from mpa.graph_track import GraphTrack, Position, as_graph_track

__all__ = ["MAX_CELLS", "FreeSpace", "PolygonId", "free_space", "validate_size"]

#: ``(e, f, k)``: robot A's edge, robot B's edge, piece (0 unless ``e == f``; then 0: ``s > t``, 1: ``t > s``).
PolygonId = tuple[int, int, int]

ZERO_CLEARANCE = 1e-9  # times max(1, total length): the clearance used for D = 0
TOL = tolerance.PLAN_REL  # times max(1, total length): membership tolerance (mpa.tolerance)

_EMPTY, _FULL, _PARTIAL = 0, 1, 2
_SLOPES = ((1.0, 1.0), (1.0, -1.0), (-1.0, 1.0), (-1.0, -1.0))


def _clip(poly: list[tuple[float, float]], a: float, b: float, c: float) -> list[tuple[float, float]]:
    """Sutherland–Hodgman: keep ``a*s + b*t >= c`` of a convex polygon (list of (s, t))."""
    out: list[tuple[float, float]] = []
    n = len(poly)
    if n == 0:
        return out
    prev = poly[-1]
    fp = a * prev[0] + b * prev[1] - c
    for cur in poly:
        fc = a * cur[0] + b * cur[1] - c
        if fc >= 0.0:
            if fp < 0.0:
                lam = fp / (fp - fc)
                out.append((prev[0] + lam * (cur[0] - prev[0]), prev[1] + lam * (cur[1] - prev[1])))
            out.append(cur)
        elif fp >= 0.0:
            lam = fp / (fp - fc)
            out.append((prev[0] + lam * (cur[0] - prev[0]), prev[1] + lam * (cur[1] - prev[1])))
        prev, fp = cur, fc
    return out


def _dedupe(poly: list[tuple[float, float]], eps: float) -> list[tuple[float, float]]:
    out: list[tuple[float, float]] = []
    for p in poly:
        if not out or abs(p[0] - out[-1][0]) > eps or abs(p[1] - out[-1][1]) > eps:
            out.append(p)
    while len(out) > 1 and abs(out[0][0] - out[-1][0]) <= eps and abs(out[0][1] - out[-1][1]) <= eps:
        out.pop()
    return out


#: Up to this many polygons their numbers are kept in a dictionary (about 150 bytes each), above it in nested lists.
INDEX_DICT_POLYGONS = 250_000

#: Cells classified at once when the free space is built (a block of rows of the E × E cells).
CELL_BLOCK = 1 << 18

#: Up to this many polygons the components are found by a union-find in Python, above it by label jumping in numpy
#: (:func:`_label_components`): at 19 460 polygons (the airport terminal's 139 lanes) a few ms instead of the
#: union-find's 100 ms.
SMALL_POLYGONS = 1_000

#: Above this many polygons the components are found by scipy's csgraph (its import, 0.4 s, is then a small part of
#: the build; small layouts do without it).
SCIPY_POLYGONS = 200_000


def _union_find(n: int, rows: list[int], cols: list[int]) -> list[int]:
    """The root of each of ``n`` nodes after joining ``rows[i]`` with ``cols[i]`` for every ``i``."""
    parent = list(range(n))

    def find(x: int) -> int:
        while parent[x] != x:
            parent[x] = parent[parent[x]]
            x = parent[x]
        return x

    for a, b in zip(rows, cols):
        ra, rb = find(a), find(b)
        if ra != rb:
            parent[ra] = rb
    return [find(i) for i in range(n)]


def _label_components(n: int, rows: NDArray[np.int64], cols: NDArray[np.int64]) -> NDArray[np.int64]:
    """Per node of an undirected graph of ``n`` nodes (edges ``rows[i] -- cols[i]``) the least node of its component.

    Label jumping: every label is the number of a node of the same component, never above the node's own; each round
    hooks the larger label of every edge whose ends disagree onto the smaller and then follows the labels to their
    roots, until every edge's ends agree (a few rounds: the hooked trees are flattened each time).
    """
    lab = np.arange(n, dtype=np.int64)
    while True:
        lu, lv = lab[rows], lab[cols]
        diff = lu != lv
        if not diff.any():
            return lab
        lu, lv = lu[diff], lv[diff]
        hi = np.maximum(lu, lv)
        np.minimum.at(lab, hi, np.minimum(lu, lv))  # each root hooked below itself: no cycles
        while True:
            nxt = lab[lab]
            if np.array_equal(nxt, lab):
                break
            lab = nxt
        rows, cols = rows[diff], cols[diff]


#: Polygons whose incidences are joined at once by :func:`_merged_components` (memory: about 100 bytes each).
COMPONENT_BLOCK = 1 << 18


def _merged_components(
    n_nodes: int, blocks: Iterable[tuple[NDArray[np.integer], NDArray[np.integer]]]
) -> NDArray[np.integer]:
    """Per node of an undirected graph given as blocks of edges ``(rows, cols)``, a node of its component.

    A forest of labels (a union-find): each block's edges are read between the roots of their ends, the components
    of those roots found by scipy's csgraph on the block alone, and every root hooked onto one root of its component;
    at the end every label is followed to its root. Memory: one integer per node and one block's edges, never the
    whole graph's; time: the block's edges times the forest's depth (at most the number of blocks).
    """
    from scipy.sparse import coo_matrix
    from scipy.sparse.csgraph import connected_components

    lab = np.arange(n_nodes, dtype=np.int32 if n_nodes < 2**31 else np.int64)

    def roots(x: NDArray[np.integer]) -> NDArray[np.integer]:
        x = lab[x]
        while True:
            y = lab[x]
            if np.array_equal(x, y):
                return x
            x = y

    mark = np.zeros(n_nodes, dtype=bool)  # the roots a block touches, numbered without sorting them
    pos = np.zeros(n_nodes, dtype=lab.dtype)
    for rows, cols in blocks:
        m = len(rows)
        if m == 0:
            continue
        ends = np.concatenate([roots(rows), roots(cols)])
        mark[ends] = True
        uniq = np.flatnonzero(mark)
        mark[uniq] = False
        k = len(uniq)
        pos[uniq] = np.arange(k, dtype=lab.dtype)
        inv = pos[ends]
        adj = coo_matrix((np.ones(m, dtype=np.float64), (inv[:m], inv[m:])), shape=(k, k)).tocsr()
        n_comp, comp = connected_components(adj, directed=False)
        one = np.empty(n_comp, dtype=np.int64)
        one[comp] = np.arange(k)  # one root of each component (whichever is written last), its own label
        lab[uniq] = uniq[one[comp]]
    while True:
        nxt = lab[lab]
        if np.array_equal(nxt, lab):
            return nxt
        lab = nxt


class _PolygonIndex:
    """The number of each free polygon ``(e, f, k)`` (a read-only mapping) without a Python object per polygon.

    Per cell ``e × f`` the number of its first polygon (-1 when empty) in an ``(E, E)`` integer array, per cell
    whether that polygon is piece 0 (a bit array), per edge the number of the second piece of its own cell; a row of
    the first array becomes a list (two list indexings per look-up) only when a look-up reads it.
    """

    def __init__(self, pe: NDArray[np.integer], pf: NDArray[np.integer], pk: NDArray[np.integer], n_e: int) -> None:
        n = len(pe)
        dt = np.int32 if n < 2**31 - 1 else np.int64
        first = np.full((n_e, n_e), -1, dtype=dt)
        head = np.ones(n, dtype=bool)
        if n > 1:
            head[1:] = (pe[1:] != pe[:-1]) | (pf[1:] != pf[:-1])
        idx = np.nonzero(head)[0]
        first[pe[idx], pf[idx]] = idx
        self._first = first
        k0 = np.zeros((n_e, n_e), dtype=bool)
        k0[pe[idx], pf[idx]] = pk[idx] == 0
        self._k0 = k0  # per cell: whether its first polygon is piece 0
        second = np.nonzero(~head)[0]  # (e, e, 1) after (e, e, 0)
        self._second = {int(pe[i]): int(i) for i in second}
        self._rows: list[list[int] | None] = [None] * n_e
        self._n = n
        self._n_e = n_e

    def get(self, pid: PolygonId, default: int | None = None) -> int | None:
        """The polygon's number, ``default`` when it is not a free polygon."""
        try:
            e, f, k = pid
        except (TypeError, ValueError):
            return default
        if not (0 <= e < self._n_e and 0 <= f < self._n_e):
            return default
        row = self._rows[e]
        if row is None:
            row = self._rows[e] = self._first[e].tolist()
        i = row[f]
        if i < 0:
            return default
        if (k == 0) == bool(self._k0[e, f]):
            return i
        if k == 1 and e == f:
            return self._second.get(e, default)
        return default

    def __contains__(self, pid: object) -> bool:
        return self.get(pid) is not None  # type: ignore[arg-type]

    def __getitem__(self, pid: PolygonId) -> int:
        i = self.get(pid)
        if i is None:
            raise KeyError(pid)
        return i

    def __len__(self) -> int:
        return self._n


class _PolygonIds(Sequence[PolygonId]):
    """The free polygons ``(e, f, k)`` in the order of their numbers, read from three compact arrays (no tuple is
    kept per polygon: a tuple is made when an element is read)."""

    def __init__(self, pe: NDArray[np.integer], pf: NDArray[np.integer], pk: NDArray[np.integer]) -> None:
        self._pe, self._pf, self._pk = pe, pf, pk

    def __len__(self) -> int:
        return len(self._pe)

    @overload
    def __getitem__(self, i: int) -> PolygonId: ...

    @overload
    def __getitem__(self, i: slice) -> list[PolygonId]: ...

    def __getitem__(self, i: int | slice) -> PolygonId | list[PolygonId]:
        if isinstance(i, slice):
            return list(zip(self._pe[i].tolist(), self._pf[i].tolist(), self._pk[i].tolist()))
        return (int(self._pe[i]), int(self._pf[i]), int(self._pk[i]))

    def __iter__(self) -> Iterator[PolygonId]:
        step = 1 << 16
        for i0 in range(0, len(self._pe), step):
            yield from self[i0 : i0 + step]

    def __eq__(self, other: object) -> bool:
        if isinstance(other, _PolygonIds):
            return bool(
                np.array_equal(self._pe, other._pe)
                and np.array_equal(self._pf, other._pf)
                and np.array_equal(self._pk, other._pk)
            )
        if isinstance(other, Sequence):
            return len(other) == len(self) and all(a == tuple(b) for a, b in zip(self, other))
        return NotImplemented

    __hash__ = None  # type: ignore[assignment]


@dataclass(frozen=True)
class _Faces:
    lo: FloatArray  # (V, E): face "robot at vertex w, other robot on edge f", interval [lo, hi] in offsets on f
    hi: FloatArray
    ok: NDArray[np.bool_]  # lo <= hi


class FreeSpace:
    """Free configuration space ``{d >= D}`` of two robots on a graph track, as glued convex polygons.

    Parameters
    ----------
    track : GraphTrack or paper track or layout
        The track (paper tracks are converted with ``as_graph_track()``).
    clearance : float
        D (metres, >= 0). D = 0 uses :data:`ZERO_CLEARANCE` · max(1, total length) internally.

    Attributes
    ----------
    track : GraphTrack
    clearance : float
        The clearance asked for (metres).
    clearance_used : float
        The clearance the polygons are built with (metres).
    tol : float
        Membership tolerance (metres): free means ``d >= clearance_used - tol``.
    status : ndarray of int, shape (E, E)
        Per cell ``e × f``: 0 empty, 1 entirely free (the box), 2 clipped.
    polygon_ids : sequence of PolygonId
        The non-empty free polygons; the index in this sequence is the polygon's number.

    Notes
    -----
    Prefer :func:`free_space`, which caches one instance per ``(track, clearance)``.
    """

    def __init__(self, track: object, clearance: float) -> None:
        tr = as_graph_track(track)
        validate_size(tr)
        if isinstance(clearance, bool) or not isinstance(clearance, (int, float, np.integer, np.floating)):
            raise InvalidInputError(f"clearance is {clearance!r}, expected a finite number >= 0 (metres)")
        dd = float(clearance)
        if not np.isfinite(dd) or dd < 0:
            raise InvalidInputError(f"clearance is {clearance!r}, expected a finite number >= 0 (metres)")
        self.track: GraphTrack = tr
        self.clearance = dd
        scale = tolerance.layout_scale(tr.lengths)
        self.tol = tolerance.membership_tol(scale)
        # below the membership tolerance a clearance would let the robots pass through each other (d >= D - tol
        # holds at d = 0): every clearance is at least the one that stands for 0
        self.clearance_used = max(dd, ZERO_CLEARANCE * scale)
        self.geometry = tr.geometry
        self._build()

    # ------------------------------------------------------------------------------------------ build
    def _build(self) -> None:
        g = self.geometry
        n_e = g.n_edges
        lengths = g.lengths
        dmin = self.clearance_used - self.tol
        self._dmin = dmin
        # faces: robot at vertex w, other on edge f at offset x: d = min(x + DV[w, tail f], L_f - x + DV[w, head f])
        lo = np.maximum(0.0, dmin - g.dv[:, g.tails])
        hi = np.minimum(lengths[None, :], lengths[None, :] + g.dv[:, g.heads] - dmin)
        self.faces = _Faces(lo, hi, lo <= hi)
        # classify the cells, a block of rows at a time (memory: about 100 bytes per cell of a block, not per cell)
        status = np.full((n_e, n_e), _PARTIAL, dtype=np.int8)
        self.status = status
        self._eps = 1e-12 * max(1.0, float(lengths.max()))
        self._vertices: dict[PolygonId, FloatArray] = {}
        ca = np.array([sl[0] for sl in _SLOPES])
        cb = np.array([sl[1] for sl in _SLOPES])
        lf = lengths[None, :, None]
        rows = max(1, CELL_BLOCK // max(1, n_e))
        for i0 in range(0, n_e, rows):
            i1 = min(n_e, i0 + rows)
            ee, ff = np.meshgrid(np.arange(i0, i1), np.arange(n_e), indexing="ij")
            c0 = g.cell_terms_array(ee, ff)  # (rows, E, 4)
            le = lengths[i0:i1, None, None]
            tmin = c0 + np.minimum(0.0, ca * le) + np.minimum(0.0, cb * lf)
            tmax = c0 + np.maximum(0.0, ca * le) + np.maximum(0.0, cb * lf)
            with np.errstate(invalid="ignore"):
                empty = np.any(tmax < dmin, axis=-1)
                full = np.all(tmin >= dmin, axis=-1) & (ee != ff)
            block = status[i0:i1]
            block[full] = _FULL
            block[empty] = _EMPTY
            for r, f in zip(*np.nonzero(block == _PARTIAL)):
                self._clip_cell(i0 + int(r), int(f), c0[r, f].tolist(), tmin[r, f].tolist())
        self._polygon_arrays()
        # the number of each polygon: a dictionary when small (fastest to look up), else compact arrays per cell
        self._index: Mapping[PolygonId, int] | _PolygonIndex
        if len(self._pe) <= INDEX_DICT_POLYGONS:
            self._index = {pid: i for i, pid in enumerate(self.polygon_ids)}
        else:
            self._index = _PolygonIndex(self._pe, self._pf, self._pk, n_e)
        self._components()

    def _polygon_arrays(self) -> None:
        """The polygons' edges and pieces ``_pe, _pf, _pk`` in the order of their cells (row-major), pieces 0 then 1.

        Entirely free cells and clipped cells of two edges hold piece 0; a clipped cell of one edge the pieces that
        survived clipping. Compact: int32 edges and int8 pieces, read from :attr:`status` a block of rows at a time.
        """
        status = self.status
        n_e = status.shape[0]
        pe_parts, pf_parts = [], []
        for r, f in self.nonempty_cells():
            pe_parts.append(r.astype(np.int32))
            pf_parts.append(f.astype(np.int32))
        pe, pf = np.concatenate(pe_parts), np.concatenate(pf_parts)
        del pe_parts, pf_parts
        pk = np.zeros(len(pe), dtype=np.int8)
        # cells of one edge: where each stands, which pieces it has (the second piece inserted after the first)
        row_start = np.concatenate([[0], np.cumsum(np.count_nonzero(status, axis=1))])
        extra = []
        for e in range(n_e):
            if status[e, e] == _EMPTY:
                continue
            pos = int(row_start[e]) + int(np.count_nonzero(status[e, :e]))
            has0, has1 = (e, e, 0) in self._vertices, (e, e, 1) in self._vertices
            if has0 and has1:
                extra.append((pos + 1, e))
            elif has1:
                pk[pos] = 1
        if extra:
            at = np.array([x[0] for x in extra], dtype=np.int64)
            ex = np.array([x[1] for x in extra], dtype=np.int32)
            pe, pf, pk = np.insert(pe, at, ex), np.insert(pf, at, ex), np.insert(pk, at, np.int8(1))
        self._pe, self._pf, self._pk = pe, pf, pk

    def nonempty_cells(self) -> Iterator[tuple[NDArray[np.int64], NDArray[np.int64]]]:
        """The cells ``e × f`` holding a free polygon, a block of rows at a time, row-major.

        Yields
        ------
        (ndarray of int, ndarray of int)
            Robot A's edges and robot B's edges of the block's non-empty cells, shapes ``(n,)``; at most
            :data:`CELL_BLOCK` cells' worth of rows a block, so that work over every cell keeps its memory bounded.
        """
        n_e = self.status.shape[0]
        rows = max(1, CELL_BLOCK // max(1, n_e))
        for i0 in range(0, n_e, rows):
            r, f = np.nonzero(self.status[i0 : i0 + rows])
            yield r + i0, f

    @cached_property
    def polygon_ids(self) -> Sequence[PolygonId]:
        """The non-empty free polygons ``(e, f, k)`` (a read-only sequence, made from compact arrays); the index in
        this sequence is the polygon's number."""
        return _PolygonIds(self._pe, self._pf, self._pk)

    def _clip_cell(self, e: int, f: int, c0: list[float], tmin: list[float]) -> None:
        """The free polygons of a clipped cell ``e × f`` (into ``_vertices``); the cell is empty if none is left.

        ``c0`` and ``tmin``: the four terms' constants and their least values over the cell's box (metres).
        """
        dmin = self._dmin
        lengths = self.geometry._L
        le_, lf_ = float(lengths[e]), float(lengths[f])
        poly = [(0.0, 0.0), (le_, 0.0), (le_, lf_), (0.0, lf_)]
        for j, (a, b) in enumerate(_SLOPES):
            if tmin[j] < dmin:
                poly = _clip(poly, a, b, dmin - c0[j])
                if not poly:
                    break
        eps = self._eps
        pieces = ((0, 1.0, -1.0), (1, -1.0, 1.0)) if e == f else ((0, 0.0, 0.0),)
        for k, a, b in pieces:
            q = _clip(poly, a, b, dmin) if e == f else poly
            q = _dedupe(q, eps)
            if q:
                self._vertices[(e, f, k)] = np.asarray(q, dtype=float)
        if not any((e, f, k) in self._vertices for k in (0, 1)):
            self.status[e, f] = _EMPTY

    def _incidences(self, p0: int, p1: int) -> tuple[NDArray[np.integer], NDArray[np.integer]]:
        """The incidences of the polygons ``p0 .. p1 - 1``: pairs (polygon node, face node) as two arrays.

        Nodes: the polygons, then the faces "A at w, B on f" (``n_poly + w * E + f``) and "A on e, B at w"
        (``n_poly + V * E + e * V + w``); an incidence joins a polygon to a face on one of its sides (int32 when the
        nodes allow).
        """
        g = self.geometry
        n_e, n_v = g.n_edges, g.n_vertices
        pe, pf, pk = self._pe[p0:p1], self._pf[p0:p1], self._pk[p0:p1]
        n_poly = len(self._pe)
        tails, heads = g.tails, g.heads
        ok = self.faces.ok
        same = pe == pf
        idx = np.int32 if n_poly + 2 * n_v * n_e < 2**31 else np.int64
        rows, cols = [], []
        # A on a vertex: the tail of e (two edges, or piece 1 of one edge) and the head of e (two edges, or piece 0)
        for w_of, use in ((tails, ~same | (pk == 1)), (heads, ~same | (pk == 0))):
            w = w_of[pe]
            m = use & ok[w, pf]
            rows.append((np.nonzero(m)[0] + p0).astype(idx))
            cols.append((n_poly + w[m] * n_e + pf[m]).astype(idx))
        # B on a vertex: the tail of f (two edges, or piece 0 of one edge) and the head of f (or piece 1)
        for w_of, use in ((tails, ~same | (pk == 0)), (heads, ~same | (pk == 1))):
            w = w_of[pf]
            m = use & ok[w, pe]
            rows.append((np.nonzero(m)[0] + p0).astype(idx))
            cols.append((n_poly + n_v * n_e + pe[m].astype(np.int64) * n_v + w[m]).astype(idx))
        return np.concatenate(rows), np.concatenate(cols)

    def _components(self) -> None:
        """Path components: connected components of the graph of polygons and the faces on their sides
        (:meth:`_incidences`), numbered in the order of their first polygon."""
        g = self.geometry
        n_poly = len(self._pe)
        n_nodes = n_poly + 2 * g.n_vertices * g.n_edges
        if n_poly <= SMALL_POLYGONS:  # union-find in Python: tiny layouts
            r, c = self._incidences(0, n_poly)
            lab: NDArray[np.integer] = np.asarray(_union_find(n_nodes, r.tolist(), c.tolist()))[:n_poly]
        elif n_poly <= SCIPY_POLYGONS:
            r, c = self._incidences(0, n_poly)
            lab = _label_components(n_nodes, r.astype(np.int64), c.astype(np.int64))[:n_poly]
        else:
            blocks = (
                self._incidences(p0, min(n_poly, p0 + COMPONENT_BLOCK)) for p0 in range(0, n_poly, COMPONENT_BLOCK)
            )
            lab = _merged_components(n_nodes, blocks)[:n_poly]
        # number the components in the order of their first polygon (labels are nodes: a first polygon per label)
        dt = np.int32 if n_nodes < 2**31 else np.int64
        first: NDArray[np.integer] = np.full(n_nodes, n_poly, dtype=dt)
        np.minimum.at(first, lab, np.arange(n_poly, dtype=dt))
        roots = np.flatnonzero(first < n_poly)
        rank = np.zeros(n_nodes, dtype=dt)
        rank[roots[np.argsort(first[roots])]] = np.arange(len(roots), dtype=dt)
        self.polygon_component = rank[lab]
        self.n_components = len(roots)

    def _sides_a(self, e: int, f: int, k: int) -> list[tuple[float, int]]:
        """Sides of polygon ``(e, f, k)`` where robot A stands on a vertex: list of (s of the side, vertex)."""
        g = self.geometry
        le = g._L[e]
        if e != f:
            return [(0.0, g._t[e]), (le, g._h[e])]
        return [(0.0, g._t[e])] if k == 1 else [(le, g._h[e])]

    def _sides_b(self, e: int, f: int, k: int) -> list[tuple[float, int]]:
        """Sides of polygon ``(e, f, k)`` where robot B stands on a vertex: list of (t of the side, vertex)."""
        g = self.geometry
        lf = g._L[f]
        if e != f:
            return [(0.0, g._t[f]), (lf, g._h[f])]
        return [(0.0, g._t[f])] if k == 0 else [(lf, g._h[f])]

    # ---------------------------------------------------------------------------------------- queries
    def vertices(self, pid: PolygonId) -> FloatArray:
        """Corners of a free polygon in offsets ``(s, t)`` (metres), counter-clockwise. Shape (n, 2)."""
        e, f, _ = pid
        if pid not in self._index:
            raise InvalidInputError(f"polygon {pid!r} is not a free polygon of this space")
        if self.status[e, f] == _FULL:
            le, lf = self.geometry._L[e], self.geometry._L[f]
            return np.array([(0.0, 0.0), (le, 0.0), (le, lf), (0.0, lf)])
        return self._vertices[pid]

    def polygons(self) -> dict[PolygonId, FloatArray]:
        """All free polygons ``{(e, f, k): corners (n, 2)}`` (builds the boxes of entirely free cells)."""
        return {pid: self.vertices(pid) for pid in self.polygon_ids}

    def face_interval(self, vertex: int, edge: int) -> tuple[float, float] | None:
        """Free offsets ``[lo, hi]`` of a robot on ``edge`` while the other stands on ``vertex`` (None if empty)."""
        if not self.faces.ok[vertex, edge]:
            return None
        return float(self.faces.lo[vertex, edge]), float(self.faces.hi[vertex, edge])

    def is_free(self, pos_a: Position, pos_b: Position) -> bool:
        """Whether the robots at these positions are at least the clearance apart (within :attr:`tol`)."""
        return self.geometry.distance_scalar(pos_a[0], pos_a[1], pos_b[0], pos_b[1]) >= self._dmin

    def polygon_of(self, pos_a: Position, pos_b: Position) -> PolygonId | None:
        """The free polygon of cell ``(edge A) × (edge B)`` holding the configuration, None if it is not free."""
        (e, s), (f, t) = pos_a, pos_b
        if not self.is_free(pos_a, pos_b):
            return None
        pid = (e, f, 0 if e != f or s > t else 1)
        return pid if pid in self._index else None

    def component_of(self, pos_a: object, pos_b: object) -> int | None:
        """Path component (0 .. n_components - 1) of a configuration, None if it is not free.

        Parameters
        ----------
        pos_a, pos_b : position
            Anything :meth:`GraphTrack.position` accepts (``(edge, offset)``, ``"EDGE:OFFSET"``, a vertex name).
        """
        a = self.track.position(pos_a, "position of robot A")
        b = self.track.position(pos_b, "position of robot B")
        pid = self.polygon_of(a, b)
        return None if pid is None else int(self.polygon_component[self._index[pid]])

    def components(self) -> int:
        """Number of path components of the free space."""
        return self.n_components

    def swap_component(self, comp: int) -> int:
        """The component that the swap ``(x, y) -> (y, x)`` maps component ``comp`` to."""
        i = int(np.nonzero(self.polygon_component == comp)[0][0])
        e, f, k = self.polygon_ids[i]
        s, t = self.vertices((e, f, k)).mean(axis=0)
        pid = self.polygon_of((f, float(t)), (e, float(s)))
        if pid is None:  # pragma: no cover - the centroid of a free polygon is free
            raise InvalidInputError("internal: swapped centroid not free")
        return int(self.polygon_component[self._index[pid]])

    def can_swap(self, pos_a: object | None = None, pos_b: object | None = None) -> bool:
        """Whether the robots can exchange places.

        With positions: whether ``(pos_a, pos_b)`` and ``(pos_b, pos_a)`` lie in one path component. Without: whether
        some configuration can be exchanged (some component is mapped to itself by the swap).
        """
        if pos_a is None and pos_b is None:
            return any(self.swap_component(c) == c for c in range(self.n_components))
        if pos_a is None or pos_b is None:
            raise InvalidInputError("can_swap takes two positions or none")
        c1 = self.component_of(pos_a, pos_b)
        if c1 is None:
            raise InvalidInputError(
                f"configuration {pos_a!r}, {pos_b!r} has the robots closer than the clearance {self.clearance:g}"
            )
        return c1 == self.component_of(pos_b, pos_a)


#: Budget of the free space's size: at most this many cells (pairs of edges, E²; about 3 162 edges) are built. The
#: free space is compact (per cell an int8 status, the polygon's int32 edges and int8 piece, an int32 number and
#: component; clipped polygons only for the cells within the clearance somewhere; the components merged a block at a
#: time). Measured on the seeded warehouse grids and road maps (``tracemalloc``): 1 000 edges build in 1.0-1.3 s CPU,
#: peak 145 MB, 31 MB kept; 3 000 edges (9e6 cells) in about 10 s CPU, peak 516 MB, 262 MB kept.
MAX_CELLS = 10_000_000


def validate_size(track: GraphTrack) -> None:
    """Refuse, before any work, a layout whose free space would exceed :data:`MAX_CELLS` cells (E² edge pairs).

    Raises
    ------
    InvalidInputError
        The message names the number of edges, the estimated cells and the budget (about 3 162 edges).
    """
    e = int(track.n_edges)
    if e * e > MAX_CELLS:
        raise InvalidInputError(
            f"layout has {e} edges, a free space of {e * e} cells (edge pairs), expected at most {MAX_CELLS} cells "
            f"(about {int(MAX_CELLS**0.5)} edges): larger layouts are not supported yet (merge chains of edges "
            "between junctions into single edges, or plan on a part of the layout)"
        )


#: Deprecated name of :func:`validate_size` (warns).
check_size = deprecated_alias(validate_size, "check_size")


@lru_cache(maxsize=16)
def _cached(track: GraphTrack, clearance: float) -> FreeSpace:
    return FreeSpace(track, clearance)


def free_space(track: object, clearance: float) -> FreeSpace:
    """The :class:`FreeSpace` of ``(track, clearance)``, built once and cached (the last 16 are kept)."""
    tr = as_graph_track(track)
    if isinstance(clearance, bool) or not isinstance(clearance, (int, float, np.integer, np.floating)):
        raise InvalidInputError(f"clearance is {clearance!r}, expected a finite number >= 0 (metres)")
    return _cached(tr, float(clearance))
