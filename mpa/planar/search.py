"""The planar search over the pieces' shared points: scipy's Dijkstra over the moves as one sparse graph
(:class:`_Moves`) in growing regions bounded by the robots' own distances and a few landmarks (and, with
:data:`ASTAR_BUDGET` > 0, A* with the robots' own distances as the bound before it)."""

from __future__ import annotations

import heapq
import math
from typing import TYPE_CHECKING, Any

import numpy as np
from numpy.typing import NDArray

from mpa.footprint import Disc
from mpa.graph_track import GraphTrack, Position
from mpa.planar.polygons import Coords, FloatArray
from mpa.planners.search_common import SearchQuery
from mpa.planners.search_common import cell_speeds as _cell_speeds
from mpa.planners.search_common import move_cost as _move_cost

if TYPE_CHECKING:
    from mpa.planar.space import PlanarFreeSpace


def _forward(tr: GraphTrack, cell: tuple[int, int, int], p: Coords, q: Coords) -> bool:
    """Whether the straight move ``p -> q`` in ``cell`` keeps the one-way rule (no robot backs along a one-way
    edge; standing still is allowed)."""
    return (not tr.oneway[cell[0]] or q[0] >= p[0]) and (not tr.oneway[cell[1]] or q[1] >= p[1])


def _from_ends(tr: GraphTrack, pos: Position) -> tuple[FloatArray, FloatArray]:
    """Per edge the graph distance (metres) from its tail and from its head to the position ``pos``, shape
    ``(E,)`` each: a position ``(e, x)`` is ``min(x + tail[e], (L_e - x) + head[e])`` from it (and ``|x - offset|``
    on ``pos``'s own edge)."""
    geo = tr.geometry
    g, gs = pos
    back = float(geo.lengths[g]) - gs
    tg, hg = int(geo.tails[g]), int(geo.heads[g])
    dv = geo.dv
    tail = np.minimum(dv[geo.tails, tg] + gs, dv[geo.tails, hg] + back)
    head = np.minimum(dv[geo.heads, tg] + gs, dv[geo.heads, hg] + back)
    return tail, head


class _Moves:
    """The moves between the pieces' shared points as one sparse graph (built once per objective and speeds).

    A node is a piece with a shared point where a motion enters it (:meth:`PlanarFreeSpace.moves`: the point in
    that piece's offsets); its arcs are the straight moves inside the piece to each of its shared points, landing
    in the neighbour, at the move's cost (:func:`_move_cost`). Moves that back along a one-way edge are left out;
    a move that would keep a rectangle still on a corner while the other body passes its turning disc goes by
    :meth:`PlanarFreeSpace.detour` (or is left out when there is none). ``arc_to``, ``arc_via`` give each arc's end
    point in the piece's offsets and its detour point (NaN: straight).
    """

    SLOTS = 1024  # the most arcs the source may have (the start's moves in all its pieces)

    def __init__(self, space: PlanarFreeSpace, objective: str, spa: list[float], spb: list[float]) -> None:
        mv = space.moves()
        pieces = space.pieces
        node: dict[tuple[int, Coords], int] = {}
        for row in mv:
            for _, nk in row:
                if nk not in node:
                    node[nk] = len(node)
        n = len(node)
        self.n = n
        self.node_piece = np.array([k[0] for k in node], dtype=np.int64)
        self.node_xy = np.array([k[1] for k in node], dtype=float).reshape(-1, 2)
        # the moves flattened, grouped by piece
        counts = np.array([len(r) for r in mv], dtype=np.int64)
        m_start = np.concatenate([[0], np.cumsum(counts)[:-1]]).astype(np.int64)
        m_xy = np.array([pi for r in mv for pi, _ in r], dtype=float).reshape(-1, 2)
        m_to = np.array([node[nk] for r in mv for _, nk in r], dtype=np.int64)
        # arcs: every node times every move of its piece
        per = counts[self.node_piece]
        rows = np.repeat(np.arange(n, dtype=np.int64), per)
        first = np.repeat(np.cumsum(per) - per, per)
        mi = np.arange(int(per.sum()), dtype=np.int64) - first + np.repeat(m_start[self.node_piece], per)
        src = self.node_xy[rows]
        dst = m_xy[mi]
        cols = m_to[mi]
        piece = self.node_piece[rows]
        cells = np.array([p.cell[:2] for p in pieces], dtype=np.int64).reshape(-1, 2)
        ea, eb = cells[piece, 0], cells[piece, 1]
        va = np.asarray(spa, dtype=float)[ea]
        vb = np.asarray(spb, dtype=float)[eb]
        w = _move_cost(objective, np.abs(dst[:, 0] - src[:, 0]), np.abs(dst[:, 1] - src[:, 1]), va, vb)
        keep = np.ones(len(w), dtype=bool)
        ow = np.asarray(space.track.oneway, dtype=bool)
        if ow.any():
            keep &= (~ow[ea] | (dst[:, 0] >= src[:, 0])) & (~ow[eb] | (dst[:, 1] >= src[:, 1]))
        via = np.full((len(w), 2), np.nan)
        if not (isinstance(space.footprints.a, Disc) and isinstance(space.footprints.b, Disc)):
            near = 10.0 * space.tol
            still = keep & ((np.abs(dst[:, 0] - src[:, 0]) <= near) | (np.abs(dst[:, 1] - src[:, 1]) <= near))
            for k in np.flatnonzero(still).tolist():
                i, c0, c1 = int(piece[k]), (float(src[k, 0]), float(src[k, 1])), (float(dst[k, 0]), float(dst[k, 1]))
                if space.segment_ok(i, c0, c1):
                    continue
                wp = space.detour(i, c0, c1)
                if wp is None:
                    keep[k] = False
                    continue
                cell = pieces[i].cell
                w[k] = _move_cost(objective, abs(wp[0] - c0[0]), abs(wp[1] - c0[1]), spa[cell[0]], spb[cell[1]])
                w[k] += _move_cost(objective, abs(c1[0] - wp[0]), abs(c1[1] - wp[1]), spa[cell[0]], spb[cell[1]])
                via[k] = wp
        rows, cols, w, dst, via = rows[keep], cols[keep], w[keep], dst[keep], via[keep]
        # rows already in order; zero costs kept as arcs (the smallest positive float); two arcs between the same
        # nodes are both kept (the search takes the cheaper, and so does the path read back)
        self.indptr = np.concatenate([[0], np.cumsum(np.bincount(rows, minlength=n))]).astype(np.int32)
        self.indices = cols.astype(np.int32)
        self.weights = np.maximum(w, 5e-324)
        self.arc_to = dst
        self.arc_via = via
        self.widen(self.SLOTS)
        self.by_piece: dict[int, NDArray[np.int64]] = {}
        order_p = np.argsort(self.node_piece, kind="stable")
        bounds = np.searchsorted(self.node_piece[order_p], np.arange(len(pieces) + 1))
        for i in range(len(pieces)):
            if bounds[i + 1] > bounds[i]:
                self.by_piece[i] = order_p[bounds[i] : bounds[i + 1]]
        self.node_of = node
        self.node_edges = cells[self.node_piece].T.copy()  # (2, n): robot A's and robot B's edge at each node
        self.node_room = space.track.lengths[self.node_edges] - self.node_xy.T  # (2, n): metres to the edges' heads
        # the nodes grouped by piece (those of piece i: piece_nodes[piece_start[i] : piece_start[i + 1]]), and per
        # piece and robot the range of its nodes' offsets, shape (2, P) (+inf, -inf: a piece without nodes)
        self.piece_nodes, self.piece_start = order_p, bounds
        self.piece_edges = cells.T.copy()
        self.piece_lo = np.full((2, len(pieces)), np.inf)
        self.piece_hi = np.full((2, len(pieces)), -np.inf)
        np.minimum.at(self.piece_lo.T, self.node_piece, self.node_xy)
        np.maximum.at(self.piece_hi.T, self.node_piece, self.node_xy)

    def near(self, query: SearchQuery, ub: float) -> NDArray[np.bool_]:
        """The region of the nodes whose :meth:`lower` bounds from the query's start and to its goal sum to at most
        ``ub``, shape ``(n,)``; the bounds computed only in the pieces whose nodes could be in it: per piece and
        robot the least distance to a position over the range of its nodes' offsets (the nearer end of the range
        through the edge's tail or head, or the range's distance to the position on its own edge), a bound that
        no node of the piece undercuts."""
        tr = query.track
        lengths = tr.lengths
        per_piece = np.zeros(self.piece_lo.shape[1])
        for pos in (query.start, query.goal):
            d = []
            for r in (0, 1):
                tail, head = _from_ends(tr, pos[r])
                e, lo, hi = self.piece_edges[r], self.piece_lo[r], self.piece_hi[r]
                dr = np.minimum(lo + tail[e], (lengths[e] - hi) + head[e])
                same = e == pos[r][0]
                gs = pos[r][1]
                dr[same] = np.minimum(dr[same], np.maximum(np.maximum(lo[same] - gs, gs - hi[same]), 0.0))
                d.append(dr)
            per_piece += _move_cost(query.objective, d[0], d[1], query.va, query.vb)
        pieces = np.flatnonzero(per_piece * (1.0 - 2e-9) <= ub)
        lo_i, hi_i = self.piece_start[pieces], self.piece_start[pieces + 1]
        cnt = hi_i - lo_i
        stop = np.cumsum(cnt)
        total = int(stop[-1]) if len(stop) else 0
        nodes = self.piece_nodes[np.repeat(lo_i - (stop - cnt), cnt) + np.arange(total)]
        region = np.zeros(self.n, dtype=bool)
        if total:
            through = self.lower(query, query.start, nodes)
            through += self.lower(query, query.goal, nodes)
            region[nodes[through <= ub]] = True
        return region

    def lower(
        self, query: SearchQuery, pos: tuple[Position, Position], nodes: NDArray[np.int64] | None = None
    ) -> FloatArray:
        """A lower bound of the cost between every node (or the ``nodes``) and the configuration ``pos`` (the query's
        start or goal), shape ``(n,)`` (or ``nodes.shape``): the cost (:func:`_move_cost` of the query's objective at
        the robots' own limits, m/s) of the robots' graph distances to it, shrunk by 1e-9 of itself (rounding). Every
        move costs at least the cost of what it changes the two distances (the cost is a monotone norm of the two
        travels, and the edges' speed limits only make a move dearer), so a path between a node and ``pos`` in either
        direction costs at least this."""
        d = []
        for r in (0, 1):
            g, gs = pos[r]
            from_tail, from_head = _from_ends(query.track, pos[r])
            e, x, room = self.node_edges[r], self.node_xy[:, r], self.node_room[r]
            if nodes is not None:
                e, x, room = e[nodes], x[nodes], room[nodes]
            dr = np.minimum(x + from_tail[e], room + from_head[e])
            same = e == g
            dr[same] = np.minimum(dr[same], np.abs(x[same] - gs))
            d.append(dr)
        return _move_cost(query.objective, d[0], d[1], query.va, query.vb) * (1.0 - 1e-9)

    LANDMARKS = 6  # nodes whose distances to and from every node bound the cost of a query (:meth:`landmarks`)

    def landmarks(self) -> tuple[FloatArray, FloatArray]:
        """Costs from and to a few *landmark* nodes (built once): ``(out, back)``, shape ``(LANDMARKS, n)`` each,
        ``out[l, u]`` the least cost from landmark ``l`` to node ``u``, ``back[l, u]`` from ``u`` to ``l`` (inf:
        not reached). Landmarks are picked farthest first (each the node farthest from those before it). By the
        triangle inequality a path from ``u`` to ``v`` costs at least ``out[l, v] - out[l, u]`` and
        ``back[l, u] - back[l, v]``: bounds that see the detours a motion must make (one body stepping aside)."""
        lm = self.__dict__.get("_landmarks")
        if lm is None:
            from scipy.sparse import csr_matrix
            from scipy.sparse.csgraph import dijkstra

            n = self.n
            g = csr_matrix((self.weights, self.indices, self.indptr), shape=(n, n))
            gt = g.T.tocsr()
            out, back = [], []
            near = np.full(n, np.inf)
            node = 0
            for _ in range(min(self.LANDMARKS, n)):
                d = dijkstra(g, directed=True, indices=node)
                out.append(d)
                back.append(dijkstra(gt, directed=True, indices=node))
                near = np.minimum(near, d)
                far = np.where(np.isfinite(near), near, -1.0)
                if far.max() <= 0.0:
                    break
                node = int(np.argmax(far))
            lm = self._landmarks = (np.array(out).reshape(-1, n), np.array(back).reshape(-1, n))
        return lm

    def widen(self, slots: int) -> None:
        """The graph with the source, node ``n``: its row has ``slots`` arcs, rewritten per query (unused arcs
        loop to the source itself)."""
        from scipy.sparse import csr_matrix

        self.SLOTS = slots
        m, n = len(self.weights), self.n
        self.graph = csr_matrix(
            (
                np.concatenate([self.weights, np.ones(slots)]),
                np.concatenate([self.indices, np.full(slots, n, dtype=np.int32)]),
                np.concatenate([self.indptr, [m + slots]]).astype(np.int32),
            ),
            shape=(n + 1, n + 1),
        )


#: Nodes A* expands before the search goes over to the sparse graph of moves (:func:`_dijkstra`); 0: no A*. The
#: queries A* finished within 100 nodes are the ones the independent motion now answers before any search
#: (:func:`mpa.planar.shortcut.independent_motion`); on the others it rarely finishes and its nodes cost more than
#: the first region's Dijkstra (docs/performance.md, "Footprints in the plane, third pass").
ASTAR_BUDGET = 0


class _QueryMoves:
    """One query's moves in the planar free space: the robots' speeds per edge, the start's and the goal's
    placements, and the rule and cost of a straight move inside a piece (:meth:`move`).

    Parameters
    ----------
    space : PlanarFreeSpace
    query : SearchQuery
        Its start and goal (free in ``space``), objective and the robots' speed limits.
    """

    __slots__ = ("bodies_turn", "g_pl", "objective", "query", "rules", "s_pl", "spa", "space", "spb")

    def __init__(self, space: PlanarFreeSpace, query: SearchQuery) -> None:
        tr = space.track
        self.space, self.query, self.objective = space, query, query.objective
        self.spa, self.spb = _cell_speeds(tr, query.va, query.vb)
        self.rules = any(tr.oneway)
        self.bodies_turn = not (isinstance(space.footprints.a, Disc) and isinstance(space.footprints.b, Disc))
        self.s_pl = space.placements(*query.start)
        self.g_pl = space.placements(*query.goal)

    def cost(self, cell: tuple[int, int, int], p: Coords, q: Coords) -> float:
        """The cost of the straight move ``p -> q`` in ``cell`` at the cell's speeds (:func:`_move_cost`)."""
        return float(
            _move_cost(self.objective, abs(q[0] - p[0]), abs(q[1] - p[1]), self.spa[cell[0]], self.spb[cell[1]])
        )

    def move(self, i: int, c: Coords, q: Coords) -> tuple[float, Coords | None] | None:
        """The cost of the move ``c -> q`` inside piece ``i`` and its detour point, None if it is not allowed."""
        space = self.space
        cell = space.pieces[i].cell
        if self.rules and not _forward(space.track, cell, c, q):
            return None
        if not self.bodies_turn or space.segment_ok(i, c, q):
            return self.cost(cell, c, q), None
        w = space.detour(i, c, q)
        if w is None:
            return None
        return self.cost(cell, c, w) + self.cost(cell, w, q), w


def _search(space: PlanarFreeSpace, query: SearchQuery) -> list[list[Any]] | None:
    """The cheapest path over the pieces' shared points of ``space`` from the query's start to its goal: its straight
    segments ``[cell, from, to]``.

    Every move keeps the one-way rule and costs its time at the cell's speeds (the edges' speed limits), or its
    length; a move that would keep a rectangle still on a corner while the other body passes its turning disc
    goes by a point inside the piece (:meth:`PlanarFreeSpace.detour`). With :data:`ASTAR_BUDGET` > 0, A* with the
    robots' own distances to the goal as the bound first; then (or when A* expands more than its budget) the same
    graph is searched by scipy's Dijkstra (:class:`_Moves`, compiled) in growing regions, which finds a path of the
    least cost over the whole graph.
    None when no path through the shared points keeps the one-way rule (:func:`_search_sets` decides).
    """
    moves = _QueryMoves(space, query)
    found = None
    if ASTAR_BUDGET > 0:
        found = _astar(moves, budget=ASTAR_BUDGET)
    if found is None:
        (ea, sa), (eb, sb) = query.start
        (fa, ta), (fb, tb) = query.goal
        geo = space.track.geometry
        da = geo.distance_scalar(ea, sa, fa, ta)
        db = geo.distance_scalar(eb, sb, fb, tb)
        lower = math.hypot(da, db) if query.objective == "shortest" else max(da / query.va, db / query.vb)
        found = _dijkstra(moves, lower)
    if found is None:
        return None
    return [[space.pieces[i].cell, a, b] for i, a, b in found]


def _astar(moves: _QueryMoves, budget: int) -> list[tuple[int, Coords, Coords]] | None:
    """A* over the shared points of one query's ``moves``; the moves ``(piece, from, to)``, or None when it expands
    more than ``budget`` nodes or the goal is not reached."""
    space, query, move = moves.space, moves.query, moves.move
    tr, rules = space.track, moves.rules
    s_pl, g_pl, spa, spb = moves.s_pl, moves.g_pl, moves.spa, moves.spb
    goal, (va, vb) = query.goal, query.speeds
    (ga_e, ga_s), (gb_e, gb_s) = goal
    pieces = space.pieces
    shortest = query.objective == "shortest"
    hcache: dict[tuple[int, Coords], float] = {}
    # per edge the robots' distances from its tail and head to their goal positions (metres), per robot
    (ta_l, ha_l), (tb_l, hb_l) = (tuple(x.tolist() for x in _from_ends(tr, goal[r])) for r in (0, 1))
    lens = tr.lengths.tolist()
    cells = space.cells()
    slack = 1.0 - 1e-12

    def bound(i: int, c: Coords) -> float:
        """The cost of the robots' own distances to the goal (:func:`_move_cost`, inlined): each move costs at least
        what it takes off each of them."""
        key = (i, c)
        h = hcache.get(key)
        if h is None:
            e, f = cells[i]
            x, y = c
            da = min(x + ta_l[e], (lens[e] - x) + ha_l[e])
            if e == ga_e:
                da = min(da, abs(x - ga_s))
            db = min(y + tb_l[f], (lens[f] - y) + hb_l[f])
            if f == gb_e:
                db = min(db, abs(y - gb_s))
            if shortest:
                h = math.hypot(da, db) * slack
            else:
                ta, tb = da / va, db / vb
                h = (max(ta, tb) + 1e-6 * (ta + tb) + 1e-9 * math.hypot(ta, tb)) * slack
            hcache[key] = h
        return h

    bodies_turn = moves.bodies_turn
    near = 10.0 * space.tol  # a robot this close to standing still may stand on a corner (segment_ok decides)
    flat = space.moves()
    goal_in: dict[int, list[Coords]] = {}
    for i, c in g_pl:
        goal_in.setdefault(i, []).append(c)
    # a node: (piece, coords in that piece); entering a neighbour through a shared point switches piece
    best: dict[tuple[int, Coords], float] = {}
    prev: dict[tuple[int, Coords], tuple[Any, ...] | None] = {}
    heap: list[tuple[float, int, tuple[int, Coords]]] = []
    counter = 0
    for i, c in s_pl:
        key = (i, c)
        best[key] = 0.0
        prev[key] = None
        heap.append((bound(i, c), counter, key))
        counter += 1
    heapq.heapify(heap)
    done: set[tuple[int, Coords]] = set()
    found: tuple[int, Coords] | None = None
    while heap:
        _, _, key = heapq.heappop(heap)
        if key in done:
            continue
        if len(done) >= budget:
            return None
        g = best[key]
        done.add(key)
        if key[0] < 0:
            found = key
            break
        i, c = key
        cell = pieces[i].cell
        # to the goal inside this piece
        for gc in goal_in.get(i, ()):
            mv = move(i, c, gc)
            if mv is None:
                continue
            gk = (-1 - i, gc)
            ng = g + mv[0]
            if ng < best.get(gk, math.inf):
                best[gk] = ng
                prev[gk] = (key, i, c, gc, mv[1])
                heapq.heappush(heap, (ng, counter, gk))  # the goal's bound is 0
                counter += 1
        # the moves to the shared points (cost inlined: the same expression as _move_cost)
        c0, c1 = c
        va_i, vb_i = spa[cell[0]], spb[cell[1]]
        for pi, nk in flat[i]:
            if rules and not _forward(tr, cell, c, pi):
                continue
            ds, dt = abs(pi[0] - c0), abs(pi[1] - c1)
            if shortest:
                ng = g + math.hypot(ds, dt)
            else:
                ta, tb = ds / va_i, dt / vb_i
                ng = g + (max(ta, tb) + 1e-6 * (ta + tb) + 1e-9 * math.hypot(ta, tb))
            if ng >= best.get(nk, math.inf) - 1e-15:
                continue
            via = None
            # a move that keeps a robot still may turn its body on a corner (discs never need the check)
            if bodies_turn and (abs(pi[0] - c0) <= near or abs(pi[1] - c1) <= near) and not space.segment_ok(i, c, pi):
                mv = move(i, c, pi)
                if mv is None:
                    continue
                ng, via = g + mv[0], mv[1]
                if ng >= best.get(nk, math.inf) - 1e-15:
                    continue
            best[nk] = ng
            prev[nk] = (key, i, c, pi, via)
            heapq.heappush(heap, (ng + bound(nk[0], nk[1]), counter, nk))
            counter += 1
    if found is None:
        return None
    segs: list[tuple[int, Coords, Coords]] = []
    key_: tuple[int, Coords] | None = found
    while key_ is not None:
        pv = prev[key_]
        if pv is None:
            break
        pkey, i, a, b, via = pv
        if via is not None:
            segs += [(i, via, b), (i, a, via)]
        elif a != b:
            segs.append((i, a, b))
        key_ = pkey
    return _in_order(segs, s_pl)


def _in_order(
    segs: list[tuple[int, Coords, Coords]], s_pl: list[tuple[int, Coords]]
) -> list[tuple[int, Coords, Coords]]:
    """The moves read back from the goal, in order from the start (a move that stays at the start when none)."""
    segs.reverse()
    if not segs:
        i, c = s_pl[0]
        segs.append((i, c, c))
    return segs


#: Node counts of the regions the planar search tries after the first (:func:`_dijkstra`).
_REGIONS = (2_000, 6_000, 18_000)


def _dijkstra(moves: _QueryMoves, lower: float) -> list[tuple[int, Coords, Coords]] | None:
    """Dijkstra (scipy, compiled) over :class:`_Moves` from a source node joined to the start's moves; the moves
    ``(piece, from, to)`` of a cheapest path, or None when the goal is not reached.

    ``moves``: the query's moves, ``lower``: a lower bound of the cost (the cost of the robots' own distances). First
    in growing *regions*: the nodes whose bounds from the start and to the goal (:meth:`_Moves.lower`) sum to at
    most ``ub``; every node of a path that costs at most ``ub`` lies in that region, so a goal reached there at a cost
    within ``ub`` is reached at its least cost over the whole graph. Then, when no region reaches it, the whole
    graph.
    """
    from scipy.sparse.csgraph import dijkstra

    space, query, move = moves.space, moves.query, moves.move
    s_pl, g_pl, spa, spb = moves.s_pl, moves.g_pl, moves.spa, moves.spb
    objective = query.objective
    G = space.search_graph(objective, spa, spb)
    flat = space.moves()
    n = G.n
    # the source's arcs: from the start in each of its pieces to that piece's shared points
    first: dict[int, tuple[float, int, Coords, Coords, Coords | None]] = {}
    direct: list[tuple[float, int, Coords, Coords, Coords | None]] = []
    goal_in: dict[int, list[Coords]] = {}
    for i, c in g_pl:
        goal_in.setdefault(i, []).append(c)
    for i, c in s_pl:
        for pi, nk in flat[i]:
            mv = move(i, c, pi)
            if mv is None:
                continue
            k = G.node_of[nk]
            if k not in first or mv[0] < first[k][0]:
                first[k] = (mv[0], i, c, pi, mv[1])
        for gc in goal_in.get(i, ()):
            mv = move(i, c, gc)
            if mv is not None:
                direct.append((mv[0], i, c, gc, mv[1]))
    fk = np.array(sorted(first), dtype=np.int64)
    fw = np.maximum(np.array([first[int(k)][0] for k in fk], dtype=float), 5e-324)

    def arrival(dist: FloatArray) -> tuple[float, int, int, Coords, Coords, Coords | None] | None:
        """The cheapest arrival at the goal: cost, node (-1: from the start), piece, its point, goal point, detour."""
        best: tuple[float, int, int, Coords, Coords, Coords | None] | None = None
        for cost, i, c, gc, via in direct:
            if best is None or cost < best[0]:
                best = (cost, -1, i, c, gc, via)
        for i, gcs in goal_in.items():
            nodes = G.by_piece.get(i)
            if nodes is None:
                continue
            reached = nodes[np.isfinite(dist[nodes])]
            for k in reached.tolist():
                xy = (float(G.node_xy[k, 0]), float(G.node_xy[k, 1]))
                for gc in gcs:
                    if best is not None and dist[k] >= best[0]:
                        break
                    mv = move(i, xy, gc)
                    if mv is not None and (best is None or dist[k] + mv[0] < best[0]):
                        best = (float(dist[k] + mv[0]), k, i, xy, gc, mv[1])
        return best

    # first the region just above the robots' own bound: most queries end there
    ub = lower * (1.0 + 1e-3) + 1e-9 * (1.0 + lower)
    dist, pred = _region_search(G, G.near(query, ub), fk, fw)
    best = arrival(dist)
    if best is not None and best[0] <= ub:
        return _read_back(G, first, best, pred, s_pl)
    from_start, to_goal = G.lower(query, query.start), G.lower(query, query.goal)
    # the landmarks' bounds (Goldberg and Harrelson's ALT): to the goal out[l, T] - out[l, u] with out[l, T]
    # through the goal pieces' nodes and a straight last move (never dearer than the move taken), from the start
    # back[l, S] - back[l, u] with back[l, S] through the source's arcs; 1e-9 of the larger term kept for rounding
    out, back = G.landmarks()
    to_t = np.full(len(out), np.inf)
    for i, gcs in goal_in.items():
        nodes = G.by_piece.get(i)
        if nodes is None:
            continue
        e, f = space.cells()[i]
        for gc in gcs:
            last = _move_cost(
                objective,
                np.abs(G.node_xy[nodes, 0] - gc[0]),
                np.abs(G.node_xy[nodes, 1] - gc[1]),
                spa[e],
                spb[f],
            )
            to_t = np.minimum(to_t, np.min(out[:, nodes] + last, axis=1))
    from_s = np.min(back[:, fk] + fw, axis=1) if len(fk) else np.full(len(back), np.inf)
    with np.errstate(invalid="ignore"):
        for l_ in range(len(out)):
            to_goal = np.fmax(to_goal, to_t[l_] - out[l_] - 1e-9 * to_t[l_])
            from_start = np.fmax(from_start, from_s[l_] - back[l_] - 1e-9 * from_s[l_])
    through = from_start + to_goal
    if len(fk):
        lower = max(lower, float(np.min(fw + to_goal[fk])))
    # then just above the landmarks' lower bound, the sums that take in about 2 000, 6 000 and 18 000 nodes (each
    # region about three times the last), and the whole graph
    finite = through[np.isfinite(through)]
    ubs = [lower * (1.0 + 1e-3) + 1e-9 * (1.0 + lower)]
    for size in _REGIONS:
        if size < len(finite):
            cut = float(np.partition(finite, size)[size])
            if cut > ubs[-1]:
                ubs.append(cut)
    for ub in ubs:
        dist, pred = _region_search(G, through <= ub, fk, fw)
        best = arrival(dist)
        if best is not None and best[0] <= ub:
            return _read_back(G, first, best, pred, s_pl)
    if len(first) > G.SLOTS:  # a start with more shared points than the source's row holds: a larger row
        G.widen(len(first))
    graph = G.graph
    ks = np.full(G.SLOTS, n, dtype=np.int32)
    ws = np.ones(G.SLOTS)
    ks[: len(first)] = fk
    ws[: len(first)] = fw
    graph.indices[-G.SLOTS :] = ks
    graph.data[-G.SLOTS :] = ws
    dist, pred = dijkstra(graph, directed=True, indices=n, return_predecessors=True)
    best = arrival(dist)
    return None if best is None else _read_back(G, first, best, pred, s_pl)


def _read_back(
    G: _Moves,
    first: dict[int, tuple[float, int, Coords, Coords, Coords | None]],
    best: tuple[float, int, int, Coords, Coords, Coords | None],
    pred: Any,
    s_pl: list[tuple[int, Coords]],
) -> list[tuple[int, Coords, Coords]]:
    """The moves ``(piece, from, to)`` of the path that :func:`_dijkstra` found, read back from its arrival ``best``
    over the predecessors ``pred`` (``G.n``: the source, whose arcs ``first`` are the start's moves)."""
    n = G.n
    _, k, i, c_last, gc, via = best
    segs: list[tuple[int, Coords, Coords]] = []

    def add(piece: int, a: Coords, b: Coords, w: Coords | None) -> None:
        if w is not None:
            segs.extend([(piece, w, b), (piece, a, w)])
        elif a != b:
            segs.append((piece, a, b))

    add(i, c_last, gc, via)
    while k >= 0:
        p = int(pred[k])
        if p == n:  # the source: the first move, from the start
            _, i0, c0, to, w0 = first[k]
            add(i0, c0, to, w0)
            break
        lo, hi = int(G.indptr[p]), int(G.indptr[p + 1])
        arcs = lo + np.flatnonzero(G.indices[lo:hi] == k)
        a = int(arcs[np.argmin(G.weights[arcs])])
        w = G.arc_via[a]
        add(
            int(G.node_piece[p]),
            (float(G.node_xy[p, 0]), float(G.node_xy[p, 1])),
            (float(G.arc_to[a, 0]), float(G.arc_to[a, 1])),
            None if np.isnan(w[0]) else (float(w[0]), float(w[1])),
        )
        k = p
    return _in_order(segs, s_pl)


def _region_search(
    G: _Moves, region: NDArray[np.bool_], fk: NDArray[np.int64], fw: FloatArray
) -> tuple[FloatArray, NDArray[np.int64]]:
    """Dijkstra (scipy) over the nodes of ``region`` (shape ``(n,)``) only, from a source joined to the nodes ``fk``
    at costs ``fw``: the costs of all ``n`` nodes (inf outside the region or not reached) and their predecessors
    (``n``: the source; negative: none), in the whole graph's numbering."""
    from scipy.sparse import csr_matrix
    from scipy.sparse.csgraph import dijkstra

    n = G.n
    r = np.flatnonzero(region)
    m = len(r)
    dist = np.full(n, np.inf)
    pred = np.full(n, -9999, dtype=np.int64)
    if m == 0:
        return dist, pred
    new = np.full(n, -1, dtype=np.int64)
    new[r] = np.arange(m)
    lo = G.indptr[r].astype(np.int64)
    cnt = G.indptr[r + 1].astype(np.int64) - lo
    stop = np.cumsum(cnt)
    idx = np.repeat(lo - (stop - cnt), cnt) + np.arange(int(stop[-1]))
    cols = new[G.indices[idx]]
    keep = cols >= 0
    per_row = np.bincount(np.repeat(np.arange(m), cnt)[keep], minlength=m)
    fc = new[fk]
    fin = fc >= 0
    data = np.concatenate([G.weights[idx[keep]], fw[fin]])
    indices = np.concatenate([cols[keep], fc[fin]]).astype(np.int32)
    indptr = np.concatenate([[0], np.cumsum(per_row), [len(data)]]).astype(np.int32)
    sub = csr_matrix((data, indices, indptr), shape=(m + 1, m + 1))
    d, p = dijkstra(sub, directed=True, indices=m, return_predecessors=True)
    dist[r] = d[:m]
    ok = p[:m] >= 0
    pred[r[ok]] = np.append(r, n)[p[:m][ok]]
    return dist, pred
