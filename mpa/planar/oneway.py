"""The complete search under one-way lanes: reach sets of the pieces' shared segments (:func:`_search_sets`), the
robots a state holds on a corner, and the reason when only the one-way rule forbids a motion."""

from __future__ import annotations

import math
from typing import TYPE_CHECKING, Any

from mpa.errors import PlanningError
from mpa.footprint import Disc
from mpa.graph_track import Position
from mpa.planar.polygons import Coords, _area

if TYPE_CHECKING:
    from mpa.planar.space import PlanarFreeSpace


def _parts(pi: list[Coords], pj: list[Coords]) -> list[tuple[Coords, Coords, Coords, Coords]]:
    """The shared sets of a glued pair of pieces, as segments ``(p0, p1, q0, q1)`` (``p`` in the first piece's
    offsets, ``q`` in the second's; one parameter ``λ`` maps ``p0 + λ(p1 - p0)`` to ``q0 + λ(q1 - q0)``; a point has
    ``p0 == p1``). The shared points come as the two ends and the middle of each segment, or a single point."""
    out: list[tuple[Coords, Coords, Coords, Coords]] = []
    k, n = 0, len(pi)
    while k < n:
        if k + 2 < n:
            a, m, b = pi[k], pi[k + 1], pi[k + 2]
            span = max(abs(b[0] - a[0]), abs(b[1] - a[1]))
            mid = (0.5 * (a[0] + b[0]), 0.5 * (a[1] + b[1]))
            if span > 0.0 and max(abs(m[0] - mid[0]), abs(m[1] - mid[1])) <= 1e-9 * max(1.0, span):
                out.append((a, b, pj[k], pj[k + 2]))
                k += 3
                continue
        out.append((pi[k], pi[k], pj[k], pj[k]))
        k += 1
    return out


def _cone(ow: tuple[bool, bool], ends: tuple[Coords, Coords]) -> list[tuple[float, float, float]]:
    """Half-planes ``a*s + b*t >= c`` of ``S ⊕ K``: the configurations a monotone move reaches from the segment
    ``S`` (its two ends) when ``K`` is the forward cone of the one-way axes ``ow`` (a quadrant, a half-plane, or the
    plane: no half-plane)."""
    p, q = ends
    out = []
    if ow[0]:
        out.append((1.0, 0.0, min(p[0], q[0])))
    if ow[1]:
        out.append((0.0, 1.0, min(p[1], q[1])))
    ds, dt = q[0] - p[0], q[1] - p[1]
    if ow[0] and ow[1] and ds * dt < 0.0:  # a falling segment: nothing below its line is reached
        a, b = abs(dt), abs(ds)
        nrm = math.hypot(a, b)
        out.append((a / nrm, b / nrm, (a * p[0] + b * p[1]) / nrm))
    return out


def _lam_range(p0: Coords, p1: Coords, hp: list[tuple[float, float, float]], tol: float) -> tuple[float, float] | None:
    """The parameters ``λ ∈ [0, 1]`` where ``p0 + λ(p1 - p0)`` satisfies every half-plane: exactly when some do,
    else within ``tol`` (a segment that only touches the half-planes, where rounding decides)."""
    exact = _lam_range_tol(p0, p1, hp, 0.0)
    return exact if exact is not None else _lam_range_tol(p0, p1, hp, tol)


def _lam_range_tol(
    p0: Coords, p1: Coords, hp: list[tuple[float, float, float]], tol: float
) -> tuple[float, float] | None:
    lo, hi = 0.0, 1.0
    for a, b, c in hp:
        f0 = a * p0[0] + b * p0[1] - c + tol
        df = a * (p1[0] - p0[0]) + b * (p1[1] - p0[1])
        if abs(df) <= 1e-15:
            if f0 < 0.0:
                return None
            continue
        r = -f0 / df
        if df > 0:
            lo = max(lo, r)
        else:
            hi = min(hi, r)
    return (lo, hi) if lo <= hi else None


def _at(p0: Coords, p1: Coords, lam: float) -> Coords:
    return (p0[0] + lam * (p1[0] - p0[0]), p0[1] + lam * (p1[1] - p0[1]))


def _search_sets(
    space: PlanarFreeSpace,
    start: tuple[Position, Position],
    goal: tuple[Position, Position],
    budget: int = 400_000,
) -> list[list[Any]] | None:
    """A motion that keeps the one-way rule, or None when none exists in the model (complete).

    **Reach.** In a convex free piece the moves allowed from a point ``r`` are the straight moves to the points of
    its forward cone ``C(r)`` (the one-way coordinates do not decrease); from a segment ``S`` they reach
    ``R(S) = piece ∩ (S ⊕ K)``: the piece cut by ``s >= min_S s`` and ``t >= min_S t`` on one-way axes and, when both
    axes are one-way and ``S`` falls, by ``S``'s line (:func:`_cone`). A state is a piece with the segment ``S``
    where the motion may enter it; its successors are the shared segments with the glued pieces cut to ``R(S)``
    (again segments: a convex set meets a segment in a segment), and the goal is reached when it lies in ``R(S)``.

    **Complete.** Every motion under the rule passes through a sequence of pieces and shared sets; by induction
    its crossing points lie in the successive states' segments (a monotone move from a point of ``S`` stays in
    ``R(S)``), so the search reaches the goal whenever such a motion exists. A state whose segment lies in the reach
    of a state already expanded in the same piece adds nothing (``S' ⊆ R(S)`` implies ``R(S') ⊆ R(S)``) and is
    skipped, which also ends the search.

    **Path.** Back from the goal: in each state the point of its segment from which the next point is forward
    (closest to it), a straight move inside the piece. ``budget`` bounds the expanded states.
    """
    from collections import deque

    tr = space.track
    pieces = space.pieces
    tol = 10.0 * space.tol
    dom = 100.0 * tol  # a state within this of an expanded one's reach adds nothing (rounding never loops)
    ow_of = [(bool(tr.oneway[p.cell[0]]), bool(tr.oneway[p.cell[1]])) for p in pieces]
    goal_in: dict[int, list[Coords]] = {}
    for i, c in space.placements(*goal):
        goal_in.setdefault(i, []).append(c)
    # a state: (piece, ends of S, parent state, (p0, p1, q0, q1, lo, hi) of the shared segment it came through)
    states: list[tuple[int, tuple[Coords, Coords], int, Any]] = []
    todo: deque[int] = deque()
    for i, c in space.placements(*start):
        states.append((i, (c, c), -1, None))
        todo.append(len(states) - 1)
    expanded: dict[int, list[list[tuple[float, float, float]]]] = {}
    parts_memo: dict[int, list[tuple[int, list[tuple[Coords, Coords, Coords, Coords]]]]] = {}
    found: tuple[int, Coords] | None = None
    steps = 0
    seen_pinned: set[tuple[int, tuple[Coords, Coords]]] = set()
    while todo and found is None:
        sid = todo.popleft()
        i, ends, _, _ = states[sid]
        done = expanded.setdefault(i, [])
        if any(all(a * x[0] + b * x[1] >= c - dom for x in ends for a, b, c in hp) for hp in done):
            continue
        pins = _pins(space, i, ends, ow_of[i])
        if pins:  # a smaller reach: never used to drop other states, and each such state expanded once
            if (i, ends) in seen_pinned:
                continue
            seen_pinned.add((i, ends))
        steps += 1
        if steps > budget:
            raise PlanningError(f"the one-way search expanded more than {budget} states without deciding")
        hp = _cone(ow_of[i], ends)
        if not pins:
            done.append(hp)
        for gc in goal_in.get(i, ()):
            if all(a * gc[0] + b * gc[1] >= c - tol for a, b, c in hp) and _pinned_ok(pins, gc, ends, tol):
                found = (sid, gc)
                break
        if found is not None:
            break
        if i not in parts_memo:
            parts_memo[i] = [(j, _parts(pi, pj)) for j, pi, pj in space.adjacent[i]]
        for j, parts in parts_memo[i]:
            for p0, p1, q0, q1 in parts:
                rng = _lam_range(p0, p1, hp, tol)
                if rng is None:
                    continue
                for lo, hi in _pinned_ranges(pins, p0, p1, rng, ends, tol):
                    x = (_at(q0, q1, lo), _at(q0, q1, hi))
                    if any(
                        all(a * y[0] + b * y[1] >= c - dom for y in x for a, b, c in h2) for h2 in expanded.get(j, ())
                    ):
                        continue
                    states.append((j, x, sid, (p0, p1, q0, q1, lo, hi)))
                    todo.append(len(states) - 1)
    if found is None:
        return None
    sid, y = found
    segs: list[list[Any]] = []
    lam = 0.0
    while True:
        i, ends, parent, via = states[sid]
        cell = pieces[i].cell
        ow = ow_of[i]
        if via is None:
            xp = ends[0]
        else:
            p0, p1, q0, q1, lo, hi = via
            # the parameters in [lo, hi] whose point is behind y on the one-way axes (and, where a robot is pinned
            # to a corner, on y's side of its turning block), then the closest to y
            hp = [(-1.0, 0.0, -y[0])] if ow[0] else []
            hp += [(0.0, -1.0, -y[1])] if ow[1] else []
            for ax, corner, b0, b1 in _pins(space, i, (_at(q0, q1, lo), _at(q0, q1, hi)), ow):
                if abs(y[ax] - corner) <= tol:
                    o = 1 - ax
                    if y[o] <= b0:
                        hp.append((-1.0, 0.0, -b0) if o == 0 else (0.0, -1.0, -b0))
                    elif y[o] >= b1:
                        hp.append((1.0, 0.0, b1) if o == 0 else (0.0, 1.0, b1))
            a0, a1 = _at(q0, q1, lo), _at(q0, q1, hi)
            rng = _lam_range(a0, a1, hp, tol)
            u0, u1 = rng if rng is not None else (0.0, 1.0)
            d = (a1[0] - a0[0], a1[1] - a0[1])
            den = d[0] * d[0] + d[1] * d[1]
            mu = 0.0 if den <= 0.0 else ((y[0] - a0[0]) * d[0] + (y[1] - a0[1]) * d[1]) / den
            mu = min(max(mu, u0), u1)
            # the closest point first; where its move would hold a robot on a corner through the other's block,
            # a point of the allowed range off that corner (the middle, then the ends)
            cands = [mu, 0.5 * (u0 + u1), u0, u1]
        chosen: tuple[Coords, Coords | None] | None = None
        for m_ in cands if via is not None else [0.0]:
            if via is not None:
                lam = lo + m_ * (hi - lo)
                xp = _at(q0, q1, lam)
            # a move within the tolerances of a shared point: never backwards on a one-way axis
            xp = (min(xp[0], y[0]) if ow[0] else xp[0], min(xp[1], y[1]) if ow[1] else xp[1])
            if xp == y or space.segment_ok(i, xp, y):
                chosen = (xp, None)
                break
            w = space.detour(i, xp, y)  # a robot kept still on a corner: by a point inside the piece
            if w is not None:
                chosen = (xp, w)
                break
        if chosen is None:
            raise PlanningError(
                "the one-way search found a motion whose move turns a body on a corner into the other one"
            )
        xp, w = chosen
        if xp != y:
            segs += [[cell, xp, y]] if w is None else [[cell, w, y], [cell, xp, w]]  # reversed below
        if via is None:
            break
        y = _at(via[0], via[1], lam)
        sid = parent
    segs.reverse()
    return segs


def _pins(
    space: PlanarFreeSpace, i: int, ends: tuple[Coords, Coords], ow: tuple[bool, bool]
) -> list[tuple[int, float, float, float]]:
    """The robots a state of the one-way search holds on a corner: ``(axis, corner offset, block start, block
    end)`` where its segment ``S`` lies on the corner's line, the robot is a rectangle that cannot step off the
    line and back (its edge is one-way, or the piece has no interior) and the other body passes its turning disc
    over the open interval ``(block start, block end)`` of the other robot's offsets. From ``S`` the points of that
    line are then reached only on the side of the block where ``S`` reaches it."""
    out = []
    sub = space.pieces[i].sub
    flat = None
    for ax, corner in space.still_on_corner(i, ends[0], ends[1]):
        fp = space.footprints.a if ax == 0 else space.footprints.b
        if isinstance(fp, Disc):
            continue
        if not ow[ax]:
            if flat is None:
                poly = space.pieces[i].poly
                t = 10.0 * space.tol
                flat = len(poly) < 3 or abs(_area([tuple(x) for x in poly])) <= t * t
            if not flat:
                continue  # it may step into the piece and back (PlanarFreeSpace.detour)
        blk = space._turn_block(ax, sub[ax], corner, sub[1 - ax])
        if blk is not None:
            out.append((ax, corner, blk[0], blk[1]))
    return out


def _pinned_ok(pins: list[tuple[int, float, float, float]], y: Coords, ends: tuple[Coords, Coords], tol: float) -> bool:
    """Whether the point ``y`` is reached from the segment ``ends`` with the robots in ``pins`` held on their
    corners (a point off a pinned line is reached by moving that robot, which :func:`_cone` decides)."""
    for ax, corner, b0, b1 in pins:
        if abs(y[ax] - corner) > tol:
            continue
        o = 1 - ax
        lo, hi = min(ends[0][o], ends[1][o]), max(ends[0][o], ends[1][o])
        if not ((lo <= b0 and y[o] <= b0) or (hi >= b1 and y[o] >= b1) or lo <= y[o] <= hi):
            return False
    return True


def _pinned_ranges(
    pins: list[tuple[int, float, float, float]],
    p0: Coords,
    p1: Coords,
    rng: tuple[float, float],
    ends: tuple[Coords, Coords],
    tol: float,
) -> list[tuple[float, float]]:
    """The parameter range ``rng`` of the shared segment ``p0 -> p1`` cut to the points reached with the robots in
    ``pins`` held on their corners: on a pinned line, the parts on the reached sides of the block (and ``S``'s own
    points); an end of a segment that only touches the line is dropped when it is not reached."""
    out = [rng]
    for ax, corner, b0, b1 in pins:
        o = 1 - ax
        on0, on1 = abs(p0[ax] - corner) <= tol, abs(p1[ax] - corner) <= tol
        nxt: list[tuple[float, float]] = []
        for lo, hi in out:
            if on0 and on1:  # along the line: the other robot's offsets allowed there, as parameters
                lo_s, hi_s = min(ends[0][o], ends[1][o]), max(ends[0][o], ends[1][o])
                allowed = [(lo_s, hi_s)]
                if lo_s <= b0:
                    allowed.append((-math.inf, b0))
                if hi_s >= b1:
                    allowed.append((b1, math.inf))
                d = p1[o] - p0[o]
                for y0, y1 in allowed:
                    if abs(d) <= 1e-15:
                        if y0 - tol <= p0[o] <= y1 + tol:
                            nxt.append((lo, hi))
                        continue
                    l0, l1 = sorted(((y0 - p0[o]) / d, (y1 - p0[o]) / d))
                    a, b = max(lo, l0), min(hi, l1)
                    if a <= b:
                        nxt.append((a, b))
            elif on0 or on1:  # touches the line at one end: that end only if reached
                end = p0 if on0 else p1
                if _pinned_ok([(ax, corner, b0, b1)], end, ends, tol):
                    nxt.append((lo, hi))
                else:
                    cut = 1e-9
                    a, b = (max(lo, cut), hi) if on0 else (lo, min(hi, 1.0 - cut))
                    if a <= b:
                        nxt.append((a, b))
            else:
                nxt.append((lo, hi))
        out = nxt
    return out


def _why_one_way(space: PlanarFreeSpace, start: tuple[Position, Position], goal: tuple[Position, Position]) -> str:
    """The reason when only the one-way rule forbids the motion (start and goal share a component)."""
    tr = space.track
    names = ", ".join(tr.position_name(*p) for p in start)
    gnames = ", ".join(tr.position_name(*p) for p in goal)
    one = [tr.edge_names[i] for i, ow in enumerate(tr.oneway) if ow]
    listed = ", ".join(one[:8]) + (" ..." if len(one) > 8 else "")
    return (
        f"the one-way lanes forbid it: start ({names}) and goal ({gnames}) are connected with the bodies "
        f"({space.footprints.spec()}) apart when every lane may be driven both ways, but no such motion drives the "
        f"one-way lanes ({listed}) only from 'from' to 'to'"
    )
