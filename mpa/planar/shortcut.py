"""The independent motion in the planar model: both robots drive their shortest routes at once, checked exactly
against the free pieces (:func:`independent_motion`), before any search."""

from __future__ import annotations

import bisect
import math
from typing import TYPE_CHECKING, Any

import numpy as np
from numpy.typing import NDArray

from mpa.footprint import Disc
from mpa.planar.corners import corner_sweep
from mpa.planar.polygons import Coords, FloatArray, _area, _halfplanes
from mpa.planners.graph.base import TIED_ROUTES, Piece
from mpa.planners.graph.mesh import _mesh
from mpa.planners.graph.shortcut import _shortest_routes, _straight_motion

if TYPE_CHECKING:
    from mpa.graph_track import Position
    from mpa.planar.space import PlanarFreeSpace


def independent_motion(
    space: PlanarFreeSpace, start: tuple[Position, Position], goal: tuple[Position, Position]
) -> list[list[Any]] | None:
    """The two robots' shortest routes driven at once, when that motion is free in the planar model.

    Each robot follows one of its shortest routes (up to :data:`~mpa.planners.graph.base.TIED_ROUTES` of equally
    short ones each, in the order of :func:`~mpa.planners.graph.shortcut._shortest_routes`): a straight line in
    route coordinates from ``(0, 0)`` to ``(dA, dB)`` (metres), cut into segments where either robot changes edge
    (:func:`~mpa.planners.graph.shortcut._straight_motion`, which also keeps the along-track clearance exactly). In
    the planar model the motion is free when every segment lies in the union of its cell's free pieces
    (:func:`_covered`: closed convex pieces, the segment's parameter intervals inside them cover it) and, for a
    rectangle, at every instant it passes a corner where its body turns, the disc of its reach clears the other body
    (:func:`~mpa.planar.corners.corner_sweep`, the rule the gluing applies to shared points). A robot that stays on
    a turning corner throughout (no travel) is left to the search.

    Its cost (the time ``max(dA/vA, dB/vB)`` with the tie-break terms, or the length ``hypot(dA, dB)``) is the bound
    no motion undercuts: when it is free it is an optimum of the objective, never dearer than the search's path
    over the shared points. Only without lane rules (one-way edges and speed limits make the robots' own routes no
    bound of the time).

    Parameters
    ----------
    space : PlanarFreeSpace
    start, goal : ((int, float), (int, float))
        Positions ``(edge, offset)`` of robots A and B (metres), free in the planar model.

    Returns
    -------
    list of [cell, (s, t), (s, t)] or None
        The straight segments in cells (the along-track free space's polygon ids, offsets in metres), as
        :func:`mpa.planar.search._search` returns them; None when no pair of routes tried is free, the robots are
        already at the goal, or the layout has lane rules.
    """
    tr = space.track
    if tr.has_rules:
        return None
    mesh = _mesh(space.base)
    tol = 1e-9 * mesh.scale
    routes_a = _shortest_routes(mesh, start[0], goal[0], tol, max(2, TIED_ROUTES))
    routes_b = _shortest_routes(mesh, start[1], goal[1], tol, max(2, TIED_ROUTES))
    for ra in routes_a:
        for rb in routes_b:
            segs = _straight_motion(mesh, ra, rb)
            if segs is None:
                continue
            if all(_covered(space, s[0], s[1], s[2]) for s in segs) and _turns_clear(space, ra, rb):
                return segs
    return None


_Planes = tuple[FloatArray, FloatArray, FloatArray, NDArray[np.int64]]


def _cell_planes(space: PlanarFreeSpace, cell: tuple[int, int, int]) -> _Planes | None:
    """The half-planes ``a*s + b*t >= c`` (exact, no slack) of the free pieces of ``cell`` with an interior:
    ``(a, b, c, starts)``, each piece's half-planes contiguous from ``starts[k]`` (remembered per cell); None when
    the cell has no such piece."""
    memo: dict[tuple[int, int, int], _Planes | None] = space.__dict__.setdefault("_cell_planes", {})
    if cell in memo:
        return memo[cell]
    rows: list[tuple[float, float, float]] = []
    starts: list[int] = []
    eps = space.tol * space.tol
    for i in space._by_cell().get((cell[0], cell[1]), []):
        p = space.pieces[i]
        if p.cell != cell or len(p.poly) <= 2:
            continue
        pts = [(float(x), float(y)) for x, y in p.poly]
        if abs(_area(pts)) <= eps:
            continue
        hp = _halfplanes(pts, 0.0)
        if hp:
            starts.append(len(rows))
            rows.extend(hp)
    out: _Planes | None = None
    if rows:
        arr = np.array(rows, dtype=float)
        out = (arr[:, 0].copy(), arr[:, 1].copy(), arr[:, 2].copy(), np.array(starts, dtype=np.int64))
    memo[cell] = out
    return out


def _covered(space: PlanarFreeSpace, cell: tuple[int, int, int], p0: Coords, p1: Coords) -> bool:
    """Whether the segment ``p0 -> p1`` (offsets in ``cell``, metres) lies in the union of the cell's free pieces.

    Per piece the parameters ``λ ∈ [0, 1]`` of ``p0 + λ (p1 - p0)`` inside it form one interval (the piece is
    convex: the intersection of its half-planes' intervals); the segment is covered when those intervals, sorted,
    leave no gap longer than the touching tolerance (:data:`mpa.planar.polygons.TOUCH` times the layout's scale,
    in metres along the segment)."""
    planes = _cell_planes(space, cell)
    if planes is None:
        return False
    a, b, c, starts = planes
    dx, dy = p1[0] - p0[0], p1[1] - p0[1]
    v0 = a * p0[0] + b * p0[1] - c  # >= 0 inside at λ = 0
    slope = a * dx + b * dy
    with np.errstate(divide="ignore", invalid="ignore"):
        r = -v0 / slope
    lo = np.maximum.reduceat(np.where(slope > 0.0, r, -np.inf), starts)
    hi = np.minimum.reduceat(np.where(slope < 0.0, r, np.inf), starts)
    never = np.logical_or.reduceat((slope == 0.0) & (v0 < 0.0), starts)
    lo, hi = np.maximum(lo, 0.0), np.minimum(hi, 1.0)
    keep = ~never & (lo <= hi)
    if not keep.any():
        return False
    lo, hi = lo[keep], hi[keep]
    order = np.argsort(lo, kind="stable")
    gap = space.tol / max(math.hypot(dx, dy), 1e-300)
    reach = 0.0
    for x, y in zip(lo[order].tolist(), hi[order].tolist(), strict=True):
        if x > reach + gap:
            return False
        reach = max(reach, y)
    return reach >= 1.0 - gap


def _turns_clear(space: PlanarFreeSpace, ra: list[Piece], rb: list[Piece]) -> bool:
    """Whether, along the straight motion on routes ``ra`` and ``rb``, every rectangle that passes a corner where
    its body turns (:meth:`~mpa.planar.corners._Corners._corner_lists`, polyline corners and vertices) has the disc
    of its reach clear of the other body at that instant (:func:`~mpa.planar.corners.corner_sweep` within the
    touching tolerance); False when a rectangle stands on such a corner throughout (no travel)."""
    fps = space.footprints
    if isinstance(fps.a, Disc) and isinstance(fps.b, Disc):
        return True
    routes = (ra, rb)
    cums = []
    for route in routes:
        cum = [0.0]
        for _, x0, x1 in route:
            cum.append(cum[-1] + abs(x1 - x0))
        cums.append(cum)
    totals = (cums[0][-1], cums[1][-1])
    corners = space._corner_lists()
    near = 10.0 * space.tol

    def where(r: int, lam: float) -> Position:
        """Robot ``r``'s position at ``lam`` of the motion."""
        route, cum, total = routes[r], cums[r], totals[r]
        d = lam * total
        k = min(max(bisect.bisect_right(cum, d) - 1, 0), len(route) - 1)
        e, x0, x1 = route[k]
        length = cum[k + 1] - cum[k]
        if length <= 0.0:
            return e, x0
        u = min(max((d - cum[k]) / length, 0.0), 1.0)
        return e, x0 + (x1 - x0) * u

    instants: set[float] = set()
    for r, fp in enumerate((fps.a, fps.b)):
        if isinstance(fp, Disc):
            continue
        for k, (e, x0, x1) in enumerate(routes[r]):
            lo_x, hi_x = min(x0, x1), max(x0, x1)
            arr = corners[e]
            for x in arr[bisect.bisect_left(arr, lo_x - near) : bisect.bisect_right(arr, hi_x + near)]:
                if totals[r] <= 0.0:
                    return False  # standing on a turning corner while the other body moves: the search decides
                along = cums[r][k] + min(abs(x - x0), abs(x1 - x0))
                instants.add(min(max(along / totals[r], 0.0), 1.0))
    tr = space.track
    for lam in sorted(instants):
        _, depth = corner_sweep(tr, fps, where(0, lam), where(1, lam), near)
        if depth > space.tol:
            return False
    return True
