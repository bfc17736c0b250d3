"""The free polygons as the search sees them: sides, faces and their pages, names of points on faces."""

from __future__ import annotations

from typing import Any, cast

from numpy.typing import NDArray

from mpa.freespace import FreeSpace, PolygonId
from mpa.graph_track import Position
from mpa.planners.graph.base import Coords, FaceKey, Key, Side

#: A side with its ends (:meth:`_Mesh.side_ends`): axis, side value, face, lo, hi, the ends' keys and offsets.
SideEnds = tuple[int, float, FaceKey, float, float, Key, Coords, Key, Coords]


class _Rows:
    """The rows of a ``(V, E)`` array of faces as Python lists, each made when it is first read (a large layout's
    search reads the faces of the few vertices near its robots, not ``V × E`` Python floats)."""

    def __init__(self, a: NDArray[Any]) -> None:
        self._a = a
        self._rows: list[list[Any] | None] = [None] * a.shape[0]

    def __getitem__(self, w: int) -> list[Any]:
        row = self._rows[w]
        if row is None:
            row = self._rows[w] = self._a[w].tolist()
        return row


class _Mesh:
    """What the search needs of one free space, built lazily and kept with it: per polygon its sides that are faces,
    per face its *pages* (the polygons glued along it, each with its side value), per face end the polygons holding it.
    """

    def __init__(self, fs: FreeSpace) -> None:
        self.fs = fs
        g = fs.geometry
        self.g = g
        self.inc: list[list[tuple[int, float]]] = [[] for _ in range(g.n_vertices)]
        for e in range(g.n_edges):
            self.inc[g._t[e]].append((e, 0.0))
            self.inc[g._h[e]].append((e, g._L[e]))
        self.lo = _Rows(fs.faces.lo)
        self.hi = _Rows(fs.faces.hi)
        self.ok = _Rows(fs.faces.ok)
        self.scale = max(1.0, float(g.lengths.max()))
        self.eps = 1e-12 * self.scale
        self._sides: dict[PolygonId, list[Side]] = {}
        self._side_ends: dict[PolygonId, tuple[SideEnds, ...]] = {}
        self._pages: dict[FaceKey, list[tuple[PolygonId, float]]] = {}
        self._members: dict[Key, list[tuple[PolygonId, Coords]]] = {}

    def sides(self, pid: PolygonId) -> list[Side]:
        out = self._sides.get(pid)
        if out is None:
            e, f, k = pid
            out = []
            for s, w in self.fs._sides_a(e, f, k):
                if self.ok[w][f]:
                    out.append((0, s, (0, w, f), self.lo[w][f], self.hi[w][f]))
            for t, w in self.fs._sides_b(e, f, k):
                if self.ok[w][e]:
                    out.append((1, t, (1, w, e), self.lo[w][e], self.hi[w][e]))
            self._sides[pid] = out
        return out

    def side_ends(self, pid: PolygonId) -> tuple[SideEnds, ...]:
        """The sides of the polygon ``pid`` that are faces (:meth:`sides`, in the same order), each with its two ends
        named and placed: ``(ax, a, face, lo, hi, key_lo, pt_lo, key_hi, pt_hi)``, ``key_*`` the end's
        :meth:`point_key`, ``pt_*`` its offsets in the polygon's cell (m); made once per polygon."""
        out = self._side_ends.get(pid)
        if out is None:
            out = self._side_ends[pid] = tuple(
                (
                    ax,
                    a,
                    face,
                    lo,
                    hi,
                    self.point_key(face, lo),
                    (a, lo) if ax == 0 else (lo, a),
                    self.point_key(face, hi),
                    (a, hi) if ax == 0 else (hi, a),
                )
                for ax, a, face, lo, hi in self.sides(pid)
            )
        return out

    def pages(self, face: FaceKey) -> list[tuple[PolygonId, float]]:
        out = self._pages.get(face)
        if out is None:
            ax, w, other = face
            index = self.fs._index
            out = []
            for e2, x in self.inc[w]:
                if ax == 0:
                    pid = (e2, other, 0 if e2 != other else (1 if x == 0.0 else 0))
                else:
                    pid = (other, e2, 0 if e2 != other else (0 if x == 0.0 else 1))
                if pid in index:
                    out.append((pid, x))
            self._pages[face] = out
        return out

    def point_key(self, face: FaceKey, y: float) -> Key:
        """Canonical name of the point at coordinate ``y`` along a face (a corner when ``y`` is an end of the edge)."""
        ax, w, other = face
        g = self.g
        if y == 0.0:
            w2 = g._t[other]
        elif y == g._L[other]:
            w2 = g._h[other]
        else:
            return ("F", ax, w, other, y)
        return ("C", w, w2) if ax == 0 else ("C", w2, w)

    def members(self, key: Key) -> list[tuple[PolygonId, Coords]]:
        """The polygons holding a face end or corner, with its coordinates in each."""
        out = self._members.get(key)
        if out is not None:
            return out
        out = []
        if key[0] == "F":
            _, ax, w, other, y = key
            for pid, x in self.pages((ax, w, other)):
                out.append((pid, (x, y) if ax == 0 else (y, x)))
        else:
            _, w, w2 = key
            index = self.fs._index
            for e, s in self.inc[w]:
                for f, t in self.inc[w2]:
                    if e == f and s == t:
                        continue
                    pid = (e, f, 0 if e != f or s > t else 1)
                    if pid in index:
                        out.append((pid, (s, t)))
        self._members[key] = out
        return out

    def names(self, pos: Position) -> list[tuple[int, float]]:
        """All (edge, offset) names of a position (several at a vertex)."""
        e, s = pos
        if s == 0.0:
            return list(self.inc[self.g._t[e]])
        if s == self.g._L[e]:
            return list(self.inc[self.g._h[e]])
        return [pos]

    def placements(self, pa: Position, pb: Position) -> list[tuple[PolygonId, Coords]]:
        out = []
        for ea, sa in self.names(pa):
            for eb, sb in self.names(pb):
                pid = self.fs.polygon_of((ea, sa), (eb, sb))
                if pid is not None:
                    out.append((pid, (sa, sb)))
        return out


def _mesh(fs: FreeSpace) -> _Mesh:
    m = getattr(fs, "_plan_mesh", None)
    if m is None:
        m = _Mesh(fs)
        fs._plan_mesh = m  # type: ignore[attr-defined]
    return cast("_Mesh", m)
