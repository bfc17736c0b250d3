"""The chains of cells that :mod:`mpa.planners.corners` re-solves a plan's corners in: the search's chain, widened
round the grid corners it turns (where both robots change edge at one corner, or one right after the other), so that
the rule's minimiser does not depend on which side of a grid corner the search's queue happened to pass."""

from __future__ import annotations

from typing import Any

from mpa.freespace import FreeSpace, PolygonId

Coords = tuple[float, float]


def _widenings(fs: FreeSpace, segs: list[list[Any]]) -> list[list[tuple[int, PolygonId, Any]]]:
    """Where the chain turns a grid corner: both robots change edge at one corner, or one right after the other.

    Returns per such place the ways round it, each ``(index, cell, how)``: ``how`` is ``"keep"`` (the search's
    way), ``"insert"`` (a cell put in between the cells ``index - 1`` and ``index``, starting as a segment of length
    zero at the corner: the two cells that turn the corner on either side; both contain the search's way through
    the corner itself) or ``"replace"`` (the cell ``index`` swapped for the one on the corner's other side).
    """
    index = fs._index
    cells = [tuple(x[0]) for x in segs]
    n = len(cells)
    out: list[list[tuple[int, PolygonId, Any]]] = []
    j = 1
    while j < n:
        (a0, b0, _), (a1, b1, _) = cells[j - 1], cells[j]
        ways: list[tuple[int, PolygonId, Any]] = []
        if a0 != a1 and b0 != b1:  # both at once, through the corner
            for x in ((a1, b0, 0), (a0, b1, 0)):
                if x[0] == x[1] or x in index:  # one edge: the piece is the robots' order there (see _widened)
                    ways.append((j, x, "insert"))
            if ways:  # each holds the corner itself (its cell's segment of length zero): no need to keep the chain
                out.append(ways)
            j += 1
            continue
        if j + 1 < n:
            a2, b2, _ = cells[j + 1]
            if (a0 != a1 and b1 == b0 and b2 != b1 and a2 == a1) or (b0 != b1 and a1 == a0 and a2 != a1 and b2 == b1):
                other = (a0, b2, 0) if a0 != a1 else (a2, b0, 0)
                if other[0] == other[1] or other in index:
                    out.append([(j, cells[j], "keep"), (j, other, "replace")])
                    j += 2
                    continue
        j += 1
    return out


def _piece(cell: PolygonId, s: float, t: float) -> PolygonId:
    """The cell with its piece: on one edge 0 when robot A is ahead (``s > t``), else 1."""
    e, f, _ = cell
    return (e, f, 0 if e != f or s > t else 1)


def _widened(fs: FreeSpace, segs: list[list[Any]], choice: list[tuple[int, PolygonId, Any]]) -> list[list[Any]] | None:
    """The chain of ``segs`` with the ways ``choice`` round its grid corners (see :func:`_widenings`); a cell put in
    or swapped in starts as a segment of length zero at the grid corner (both robots on their vertices). None when
    the cell is not free there."""
    g = fs.geometry
    lengths = g._L
    out = [list(x) for x in segs]
    for j, cell, how in sorted(choice, key=lambda c: -c[0]):
        if how == "keep":
            continue
        if how == "insert":
            prev, nxt = out[j - 1], out[j]
            # robot A: the edge of the new cell is the next cell's (or the previous one's); same for B
            sa = nxt[1][0] if cell[0] == nxt[0][0] else prev[2][0]
            sb = nxt[1][1] if cell[1] == nxt[0][1] else prev[2][1]
            cell = _piece(cell, sa, sb)
            if cell not in fs._index:
                return None
            out.insert(j, [cell, (sa, sb), (sa, sb)])
            continue
        prev, nxt = out[j - 1], out[j + 1]
        pt = _grid_corner(g, lengths, prev, nxt, cell)
        if pt is None:
            return None
        cell = _piece(cell, *pt[1])
        if cell not in fs._index:
            return None
        out[j - 1] = [prev[0], prev[1], pt[0]]
        out[j] = [cell, pt[1], pt[1]]
        out[j + 1] = [nxt[0], pt[2], nxt[2]]
    return out


def _grid_corner(
    g: Any, lengths: Any, prev: list[Any], nxt: list[Any], cell: PolygonId
) -> tuple[Coords, Coords, Coords] | None:
    """The grid corner between ``prev``'s cell and ``nxt``'s cell (each robot on the vertex where it changes edge:
    where ``prev`` ends or ``nxt`` starts at an end of the robot's edge) in the three cells' offsets: ``prev``'s,
    ``cell``'s and ``nxt``'s; None when a robot changes edge at no end of its edges."""
    res: list[list[float]] = [[0.0, 0.0], [0.0, 0.0], [0.0, 0.0]]
    for r in (0, 1):
        e0, e1, em = prev[0][r], nxt[0][r], cell[r]
        x0, x1 = float(prev[2][r]), float(nxt[1][r])
        if x0 == 0.0 or x0 == lengths[e0]:
            w = g._t[e0] if x0 == 0.0 else g._h[e0]
        elif x1 == 0.0 or x1 == lengths[e1]:
            w = g._t[e1] if x1 == 0.0 else g._h[e1]
        else:
            return None
        ends = []
        for e in (e0, e1):
            if g._t[e] == w:
                ends.append(0.0)
            elif g._h[e] == w:
                ends.append(float(lengths[e]))
            else:
                return None
        res[0][r], res[2][r] = ends
        res[1][r] = ends[0] if em == e0 else ends[1]
    return (res[0][0], res[0][1]), (res[1][0], res[1][1]), (res[2][0], res[2][1])
