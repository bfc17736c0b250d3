"""The free space with bodies in the plane (:class:`PlanarFreeSpace`: built, glued, asked where a configuration
lies) and its cache (:func:`planar_free_space`)."""

from __future__ import annotations

from functools import lru_cache
from typing import TYPE_CHECKING, Any

import numpy as np

from mpa.errors import InvalidInputError
from mpa.footprint import Footprints, drawing_of, footprints
from mpa.freespace import free_space
from mpa.graph_track import GraphTrack, Position, as_graph_track
from mpa.planar.corners import start_refusal
from mpa.planar.glue import _Glue
from mpa.planar.polygons import TOUCH, Coords, _area, _halfplanes, _inside

if TYPE_CHECKING:
    from mpa.planar.search import _Moves


class PlanarFreeSpace(_Glue):
    """Free configuration space of two robots with footprints in the plane and the along-track clearance D.

    Parameters
    ----------
    track : GraphTrack or paper track or layout
        Needs coordinates for every vertex (the drawing, :class:`mpa.footprint.Drawing`).
    clearance : float
        D (metres, >= 0), the along-track clearance as in :class:`mpa.freespace.FreeSpace`.
    footprint : Footprints or anything :func:`mpa.footprint.footprints` accepts

    Attributes
    ----------
    base : FreeSpace
        The along-track free space.
    pieces : list
        Closed convex free pieces (cell, sub-cell, polygon in offsets).
    component : ndarray of int, shape (len(pieces),)
        Path component of each piece.
    n_components : int
    """

    def __init__(self, track: object, clearance: float, footprint: object) -> None:
        fps = footprints(footprint)
        if fps is None:
            raise InvalidInputError("footprint is None, expected a footprint for the planar free space")
        self.track = as_graph_track(track)
        self.footprints = fps
        self.drawing = drawing_of(self.track)
        self.base = free_space(self.track, clearance)
        self.clearance = self.base.clearance
        self.tol = TOUCH * max(1.0, self.track.total_length)
        self._build()
        self._glue()

    def moves(self) -> list[list[tuple[Coords, tuple[int, Coords]]]]:
        """Per piece its shared points with the glued pieces, flattened: ``(point in this piece, (neighbour, the
        point in the neighbour's offsets))`` in the order of :attr:`adjacent` (built once; a repeated move relaxes
        nothing the first one did not and is kept once)."""
        mv = self.__dict__.get("_moves")
        if mv is None:
            mv = self._moves = [
                list(dict.fromkeys((pi, (j, pj)) for j, pts_i, pts_j in row for pi, pj in zip(pts_i, pts_j)))
                for row in self.adjacent
            ]
        return mv

    def search_graph(self, objective: str, spa: list[float], spb: list[float]) -> _Moves:
        """The moves between shared points as a sparse graph (:class:`_Moves`), built once per objective and the
        robots' speeds per edge (m/s)."""
        memo: dict[tuple[Any, ...], _Moves] = self.__dict__.setdefault("_graphs", {})
        key = (objective, tuple(spa), tuple(spb))
        g = memo.get(key)
        if g is None:
            from mpa.planar.search import _Moves

            g = memo[key] = _Moves(self, objective, spa, spb)
        return g

    def names(self, pos: Position) -> list[Position]:
        """All ``(edge, offset)`` names of a position (several on a vertex)."""
        tr = self.track
        e, s = pos
        w = tr.vertex_at(e, s)
        if w is None:
            return [pos]
        out = []
        for f in range(tr.n_edges):
            if tr.tails[f] == w:
                out.append((f, 0.0))
            if tr.heads[f] == w:
                out.append((f, float(tr.lengths[f])))
        return out

    def placements(self, pa: Position, pb: Position) -> list[tuple[int, Coords]]:
        """The free pieces holding the configuration, with its offsets in each (empty if it is not free; the last
        few configurations asked remembered: a query asks for its start and goal several times)."""
        memo: dict[tuple[Position, Position], list[tuple[int, Coords]]] = self.__dict__.setdefault("_placed", {})
        key = ((int(pa[0]), float(pa[1])), (int(pb[0]), float(pb[1])))
        out = memo.get(key)
        if out is None:
            out = []
            for ea, sa in self.names(pa):
                for eb, sb in self.names(pb):
                    for i in self._inside_cell((ea, eb), sa, sb):
                        out.append((i, (sa, sb)))
            if len(memo) >= 64:
                memo.clear()
            memo[key] = out
        return list(out)

    def _inside_cell(self, cell: tuple[int, int], s: float, t: float) -> list[int]:
        """The pieces of ``cell`` (in :meth:`_by_cell` order) holding ``(s, t)``: :func:`_inside` with tolerance
        ``10 * tol``, the half-planes of every piece of the cell tested at once (the same expression)."""
        memo = self.__dict__.setdefault("_cell_tests", {})
        tol = 10.0 * self.tol
        data = memo.get(cell)
        if data is None:
            idx = self._by_cell().get(cell, [])
            rows: list[tuple[float, float, float]] = []
            owner: list[int] = []
            degenerate = []
            for k, i in enumerate(idx):
                poly = self.pieces[i].poly
                pts = [tuple(x) for x in poly]
                if len(poly) <= 2 or abs(_area(pts)) <= tol * tol:
                    degenerate.append(k)
                    continue
                hp = _halfplanes(pts, tol)
                rows.extend(hp)
                owner.extend([k] * len(hp))
            arr = np.array(rows, dtype=float).reshape(-1, 3)
            data = memo[cell] = (idx, arr[:, 0], arr[:, 1], arr[:, 2], np.array(owner, dtype=np.int64), degenerate)
        idx, a, b, c, own, degenerate = data
        if not idx:
            return []
        outside = np.bincount(own[a * s + b * t < c], minlength=len(idx)) > 0
        for k in degenerate:
            outside[k] = not _inside(self.pieces[idx[k]].poly, s, t, tol)
        return [idx[k] for k in np.flatnonzero(~outside).tolist()]

    def cells(self) -> list[tuple[int, int]]:
        """Per piece its cell's two edges ``(edge of A, edge of B)`` (built once)."""
        cl = self.__dict__.get("_cells")
        if cl is None:
            cl = self._cells = [(p.cell[0], p.cell[1]) for p in self.pieces]
        return cl

    def _by_cell(self) -> dict[tuple[int, int], list[int]]:
        bc = getattr(self, "_bc", None)
        if bc is None:
            bc = {}
            for i, p in enumerate(self.pieces):
                bc.setdefault((p.cell[0], p.cell[1]), []).append(i)
            self._bc = bc
        return bc

    def component_of(self, pos_a: object, pos_b: object) -> int | None:
        """Path component of a configuration (None if the bodies overlap or the robots are closer than D)."""
        a = self.track.position(pos_a, "position of robot A")
        b = self.track.position(pos_b, "position of robot B")
        pl = self.placements(a, b)
        return None if not pl else int(self.component[pl[0][0]])

    def is_free(self, pos_a: Position, pos_b: Position) -> bool:
        """Whether the configuration is free in the planar model: the robots keep the clearance along the track and
        it lies in a free piece (the bodies apart in the plane, every orientation at a corner)."""
        if not self.base.is_free(pos_a, pos_b):
            return False
        return not start_refusal(self.track, self, "", pos_a, pos_b)

    def can_swap(self, pos_a: object | None = None, pos_b: object | None = None) -> bool:
        """Whether the robots can exchange places (two positions: these; none: some free configuration)."""
        if pos_a is None and pos_b is None:
            for i, p in enumerate(self.pieces):
                e, f, _ = p.cell
                s, t = p.poly.mean(axis=0)
                other = self.placements((f, float(t)), (e, float(s)))
                if any(self.component[j] == self.component[i] for j, _ in other):
                    return True
            return False
        if pos_a is None or pos_b is None:
            raise InvalidInputError("can_swap takes two positions or none")
        a = self.track.position(pos_a, "position of robot A")
        b = self.track.position(pos_b, "position of robot B")
        c1 = self.component_of(a, b)
        why = start_refusal(self.track, self, "configuration", a, b) if c1 is not None else ""
        if c1 is None or why:
            raise InvalidInputError(
                why
                or f"configuration {pos_a!r}, {pos_b!r} has the bodies overlapping or the robots closer than the "
                f"clearance {self.clearance:g}"
            )
        if start_refusal(self.track, self, "configuration", b, a):
            return False
        return c1 == self.component_of(b, a)


@lru_cache(maxsize=16)
def _cached(track: GraphTrack, clearance: float, fps: Footprints) -> PlanarFreeSpace:
    return PlanarFreeSpace(track, clearance, fps)


def planar_free_space(track: object, clearance: float, footprint: object) -> PlanarFreeSpace:
    """The :class:`PlanarFreeSpace` of ``(track, clearance, footprint)``, built once and cached."""
    fps = footprints(footprint)
    if fps is None:
        raise InvalidInputError("footprint is None, expected a footprint for the planar free space")
    tr = as_graph_track(track)
    if isinstance(clearance, bool) or not isinstance(clearance, (int, float, np.integer, np.floating)):
        raise InvalidInputError(f"clearance is {clearance!r}, expected a finite number >= 0 (metres)")
    return _cached(tr, float(clearance), fps)
