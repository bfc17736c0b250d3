"""The lollipop: the paper's algorithm with three domains of continuity (TC = 3, §6.3), and the choices it leaves open.

Every planner follows the paper's three steps: the *preliminary step* ``H(x_i, ·)`` moves the start onto the
skeleton, the *main step* moves inside the skeleton by the rule of the query's domain, the *final step* is
``H(x_f, ·)`` reversed. Domain numbering: docs/conventions.md, "Domains of continuity"; departures from
the paper, with their reasons: docs/paper.md.

Choices the paper leaves open (all explicit here):

- **Neighbourhoods.** ``ε = neighbourhood · h`` (default 0.1, i.e. ε = c/20), measured as arc length in the
  skeleton (= travel of either robot). Domains are assigned in order 1, 2, 3: a query goes to the first whose
  condition holds, and each rule is continuous on the set of queries assigned to it.
- **Circle.** Domain 1: B's ccw offset Δ from its initial to its final position satisfies ``|Δ − h| < ε``
  (B's positions antipodal, within ε): both robots move ccw by Δ. Domain 2: both move by B's shortest
  signed offset (unique there).
- **Lollipop.** The extended vertices ``Ṽ = I1 ∪ I2 ∪ {v2, v3}``; ``N`` is their ε-neighbourhood in S.
  The ccw orientation of every circle ``S_j`` is the direction in which its loop robot moves ccw.

  * Domain 1 (generalized vertex position): ``x', y' ∈ N``. Project each onto its nearest extended vertex,
    join those along the chain crossing every circle ccw (same order: slide along the stick; reverse order:
    go round the loop), and leave the projections to ``y'``; two points near the same extended vertex are
    joined by the geodesic of its (tree) neighbourhood.
  * Domain 2 (generalized swapped states): otherwise, if ``x'`` and ``y'`` lie on a common circle ``S_j``
    with ccw offset ``|Δ − h| < ε``; or if they lie on different blocks of the chain and the start (goal) is,
    within ε, antipodal in its circle to the vertex where the path leaves (enters) that circle. Rule: ccw in
    that circle, shortest elsewhere, ccw across intermediate circles. (The second kind is needed: with a goal
    in the middle of S3 and the start running once round S1 no single continuous rule exists, because S1 is
    not contractible in S, so the paper's "all other pairs" cannot all share one continuous rule.)
  * Domain 3: all other pairs: shortest path in S (unique there), ccw whenever crossing a circle.
- **Short stick.** For ``ℓ < h`` the planner runs in the model lollipop ``(ℓ, 2ℓ)`` and is conjugated back
  (:class:`~mpa.skeleton.LollipopSkeleton`); plans keep ``d ≥ min(d_start, d_goal, ℓ, h)``.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np
from numpy.typing import ArrayLike

from mpa.errors import InvalidInputError, PlanningError
from mpa.planners.base import (
    FINAL,
    PRELIM,
    RULES,
    Planner,
    circle_distance,
    circle_pieces,
    pieces_word,
    reverse_moves,
)
from mpa.plans import JointMove, Plan, build_plan
from mpa.retraction import lollipop_trace_scalar
from mpa.routes import RobotMove
from mpa.skeleton import (
    CIRCLE_ENDS,
    LollipopSkeleton,
    SkeletonPoint,
    skeleton_of,
)
from mpa.tracks import Lollipop

__all__ = ["LollipopPlanner"]

# ---------------------------------------------------------------------------------------------------
# lollipop
_COMP_ORDER = {"I1": 0, "v2": 1, "v3": 2, "I2": 3}
# extended-vertex component of the vertex at φ = 0 and φ = h of each circle
_CIRCLE_COMPS = {1: ("I1", "v2"), 2: ("v2", "v3"), 3: ("I2", "v3")}


@dataclass(frozen=True)
class LollipopPlanner(Planner):
    """Two robots on a lollipop: the paper's algorithm with TC = 3 rules (§6.3), see the module docstring."""

    skeleton: LollipopSkeleton = field(init=False)

    def __post_init__(self) -> None:
        super().__post_init__()
        if not isinstance(self.track, Lollipop):
            raise InvalidInputError(f"track is {self.track!r}, expected a Lollipop")
        sk = skeleton_of(self.track)
        if not isinstance(sk, LollipopSkeleton):
            raise PlanningError(f"internal: sk is a {type(sk).__name__}, expected a LollipopSkeleton")
        object.__setattr__(self, "skeleton", sk)

    # --- geometry of the chain (model units) ---------------------------------------------------
    @property
    def _h(self) -> float:
        return self.skeleton.half

    @property
    def _eps(self) -> float:
        return self.neighbourhood * self._h

    def _vertex_phi(self, j: int, v: str) -> float:
        (lv, lp), (_rv, rp) = CIRCLE_ENDS[j]
        return (lp if v == lv else rp) * self._h

    def _near(self, pt: SkeletonPoint) -> tuple[str, float]:
        """Nearest extended-vertex component and the distance to it."""
        e = pt.edge
        if e in ("I1", "I2"):
            return e, 0.0
        j = int(e[1])
        phi = self.skeleton.circle_phi(pt)
        c = 2 * self._h
        d0 = min(phi, c - phi)
        dh = abs(phi - self._h)
        comp0, comph = _CIRCLE_COMPS[j]
        return (comp0, d0) if d0 <= dh else (comph, dh)

    def _phi_in(self, j: int, pt: SkeletonPoint) -> float:
        v = self.skeleton.vertex_at(pt)
        if v is not None and v in (CIRCLE_ENDS[j][0][0], CIRCLE_ENDS[j][1][0]):
            return self._vertex_phi(j, v)
        return self.skeleton.circle_phi(pt)

    def _circle_run(self, j: int, phi0: float, delta: float) -> list[tuple[str, float, float]]:
        return circle_pieces(phi0, delta, self._h, lambda a: f"S{j}{'ab'[a]}")

    def _to_comp_vertex(self, pt: SkeletonPoint, comp: str) -> list[tuple[str, float, float]]:
        """Pieces from ``pt`` (within ε of component ``comp``) to that component (I1/I2: stay on the stick)."""
        if pt.edge in ("I1", "I2"):
            return []
        j = int(pt.edge[1])
        phi = self.skeleton.circle_phi(pt)
        target = 0.0 if _CIRCLE_COMPS[j][0] == comp else self._h
        c = 2 * self._h
        d = (target - phi) % c
        if d > self._h:
            d -= c
        return self._circle_run(j, phi, d)

    def _slide(self, edge: str, t0: float, t1: float) -> list[tuple[str, float, float]]:
        return [(edge, t0, t1)] if abs(t1 - t0) > 1e-15 else []

    def _chain(self, c_from: str, t_from: float, c_to: str, t_to: float) -> list[tuple[str, float, float]]:
        """From extended vertex component ``c_from`` (I1/I2 position ``t_from``) to ``c_to``, ccw across circles."""
        ell_h = self.skeleton.graph.edge("I1").length
        h = self._h
        i, k = _COMP_ORDER[c_from], _COMP_ORDER[c_to]
        out: list[tuple[str, float, float]] = []
        if i < k:
            if c_from == "I1":
                out += self._slide("I1", t_from, ell_h)
            for j in range(i + 1, k + 1):  # cross circle S_j left to right
                entry = CIRCLE_ENDS[j][0][1] * h
                out += self._circle_run(j, entry, h)
            if c_to == "I2":
                out += self._slide("I2", ell_h, t_to)
        else:
            if c_from == "I2":
                out += self._slide("I2", t_from, ell_h)
            for j in range(i, k, -1):  # cross circle S_j right to left
                entry = CIRCLE_ENDS[j][1][1] * h
                out += self._circle_run(j, entry, h)
            if c_to == "I1":
                out += self._slide("I1", ell_h, t_to)
        return out

    def _reverse_pieces(self, pieces: list[tuple[str, float, float]]) -> list[tuple[str, float, float]]:
        return [(e, t1, t0) for e, t0, t1 in reversed(pieces)]

    def route_in_skeleton(self, x: SkeletonPoint, y: SkeletonPoint) -> tuple[int, list[tuple[str, float, float]]]:
        """The main step: domain and the path in S from ``x`` to ``y`` as pieces ``(edge, t_from, t_to)``."""
        sk, eps = self.skeleton, self._eps
        cx, dx = self._near(x)
        cy, dy = self._near(y)
        # ---- domain 1: both in the ε-neighbourhood of the extended vertices ----------------------
        if dx < eps and dy < eps:
            return 1, self._between_extended_vertices(x, y, cx, cy)
        # ---- same circle -------------------------------------------------------------------------
        bx, by = sk.blocks_of(x), sk.blocks_of(y)
        common = [j for j in bx if j in by and j in (1, 2, 3)]
        if common:
            return self._on_common_circle(common[0], x, y)
        # ---- different blocks ------------------------------------------------------------------
        return self._across_blocks(x, y, bx, by)

    def _between_extended_vertices(
        self, x: SkeletonPoint, y: SkeletonPoint, cx: str, cy: str
    ) -> list[tuple[str, float, float]]:
        """Domain 1: both points near extended vertices (components ``cx`` and ``cy``): along the chain."""
        ell_h = self.skeleton.graph.edge("I1").length
        if cx == cy:
            if x.edge == y.edge:
                return self._slide(x.edge, x.t, y.t)
            return self._same_comp(x, y, cx)
        tx = x.t if x.edge in ("I1", "I2") else ell_h
        ty = y.t if y.edge in ("I1", "I2") else ell_h
        return (
            self._to_comp_vertex(x, cx)
            + self._chain(cx, tx, cy, ty)
            + self._reverse_pieces(self._to_comp_vertex(y, cy))
        )

    def _on_common_circle(
        self, j: int, x: SkeletonPoint, y: SkeletonPoint
    ) -> tuple[int, list[tuple[str, float, float]]]:
        """Both points on circle ``j``: counterclockwise when antipodal within ε (domain 2), else the shorter way
        (domain 3)."""
        h, eps = self._h, self._eps
        c = 2 * h
        px, py = self._phi_in(j, x), self._phi_in(j, y)
        dccw = (py - px) % c
        if dccw >= c - 1e-15:
            dccw = 0.0
        if abs(dccw - h) < eps:
            return 2, self._circle_run(j, px, dccw)
        return 3, self._circle_run(j, px, dccw if dccw <= h else dccw - c)

    def _across_blocks(
        self, x: SkeletonPoint, y: SkeletonPoint, bx: tuple[int, ...], by: tuple[int, ...]
    ) -> tuple[int, list[tuple[str, float, float]]]:
        """Points in different blocks (``bx``, ``by``): the start's own run to its exit vertex, the circles between
        counterclockwise, the goal's own run from its entry vertex; domain 2 if an own run is ambiguous, else 3."""
        h = self._h
        ell_h = self.skeleton.graph.edge("I1").length
        right = max(bx) < min(by)
        if not right and not (min(bx) > max(by)):  # pragma: no cover - blocks always ordered here
            raise PlanningError(f"cannot order skeleton blocks {bx} and {by}")
        jx = max(bx) if right else min(bx)
        jy = min(by) if right else max(by)
        pieces: list[tuple[str, float, float]] = []
        amb = False
        # start: to the exit vertex of its block
        if jx in (0, 4):
            pieces += self._slide(x.edge, x.t, ell_h) if x.edge in ("I1", "I2") else []
        else:
            (_, lp), (_, rp) = CIRCLE_ENDS[jx]
            a_x, run = self._own_circle_run(jx, (rp if right else lp) * h, self._phi_in(jx, x), towards_vertex=True)
            amb |= a_x
            pieces += run
        # intermediate circles: counterclockwise
        for j in range(jx + 1, jy) if right else range(jx - 1, jy, -1):
            (_, lp), (_, rp) = CIRCLE_ENDS[j]
            pieces += self._circle_run(j, (lp if right else rp) * h, h)
        # goal: from the entry vertex of its block
        if jy in (0, 4):
            pieces += self._slide(y.edge, ell_h, y.t) if y.edge in ("I1", "I2") else []
        else:
            (_, lp), (_, rp) = CIRCLE_ENDS[jy]
            a_y, run = self._own_circle_run(jy, (lp if right else rp) * h, self._phi_in(jy, y), towards_vertex=False)
            amb |= a_y
            pieces += run
        return (2 if amb else 3), pieces

    def _own_circle_run(
        self, j: int, vertex_phi: float, phi: float, towards_vertex: bool
    ) -> tuple[bool, list[tuple[str, float, float]]]:
        """Run inside the start's (goal's) own circle between the point φ and the exit (entry) vertex.

        Ambiguous (returned flag) when the point is within ε of the antipode of that vertex: then ccw (domain 2),
        otherwise the shorter way.
        """
        h, c = self._h, 2 * self._h
        amb = circle_distance(phi, vertex_phi + h, c) < self._eps
        frm, to = (phi, vertex_phi) if towards_vertex else (vertex_phi, phi)
        dccw = (to - frm) % c
        return amb, self._circle_run(j, frm, dccw if (amb or dccw <= h) else dccw - c)

    def _same_comp(self, x: SkeletonPoint, y: SkeletonPoint, comp: str) -> list[tuple[str, float, float]]:
        ell_h = self.skeleton.graph.edge("I1").length
        if comp in ("I1", "I2"):
            tx = x.t if x.edge == comp else ell_h
            ty = y.t if y.edge == comp else ell_h
            return (
                self._to_comp_vertex(x, comp)
                + self._slide(comp, tx, ty)
                + self._reverse_pieces(self._to_comp_vertex(y, comp))
            )
        return self._to_comp_vertex(x, comp) + self._reverse_pieces(self._to_comp_vertex(y, comp))

    # --- clearances above min(ℓ, h): outside the paper -----------------------------------------
    def _plan_retreat(self, s: np.ndarray, g: np.ndarray) -> Plan:
        """D > h: the robots keep their order; the rear robot waits at the free end while the front one moves."""
        tr = self.track
        if not isinstance(tr, Lollipop):
            raise InvalidInputError(f"track is {tr!r}, expected a Lollipop")
        D = self.clearance
        r = 0 if self.cspace.order(s) > 0 else 1  # the rear robot (nearer the free end)
        f = 1 - r

        def joint(mr: RobotMove, mf: RobotMove) -> JointMove:
            return (mr, mf) if r == 0 else (mf, mr)

        rear_s, rear_g, fs, fg = s[r], g[r], s[f], g[f]
        prelim = [joint(RobotMove("stick", rear_s, -rear_s), RobotMove.stay(tr, fs))]
        final = [joint(RobotMove("stick", 0.0, rear_g), RobotMove.stay(tr, fg))]
        domain, rule, front = self._front_robot_moves(tr, fs, fg)
        rest = RobotMove("stick", 0.0, 0.0)
        main: list[JointMove] = [joint(rest, m) for m in front]
        xi = s.copy()
        xi[r] = 0.0
        xf = g.copy()
        xf[r] = 0.0
        return build_plan(
            tr,
            s,
            g,
            D,
            domain,
            rule,
            [
                ("the rear robot retreats to the free end; the other waits", prelim),
                (rule, main),
                ("the rear robot advances to its goal; the other waits", final),
            ],
            self.skeleton,
            xi,
            xf,
            None,
            regime="retreat",
        )

    def _front_robot_moves(self, tr: Lollipop, fs: float, fg: float) -> tuple[int, str, list[RobotMove]]:
        """D > h, the rear robot at the free end: the front robot's moves from ``fs`` to ``fg`` (track coordinates),
        with the domain and the rule that chose them."""
        ell, c, h, D = tr.stick, tr.loop, tr.half, self.clearance
        moves: list[RobotMove] = []
        th_s = fs - ell if fs > ell else 0.0
        th_g = fg - ell if fg > ell else 0.0
        if fs < ell:
            moves.append(RobotMove("stick", fs, ell - fs))
        if ell >= D:
            domain, delta = _loop_rule(c, self._eps / self._h * h, th_s, th_g)
            rule = (
                "clearance above half the loop, order kept: the rear robot waits at the free end; the front robot's "
                + (
                    "start and goal are antipodal on the loop: it goes counterclockwise"
                    if domain == 1
                    else "shortest route"
                )
            )
        else:  # the front robot can only use an arc of the loop around the antipode of P
            domain, delta = 1, th_g - th_s
            rule = "clearance above the stick and half the loop: the front robot moves within its arc of the loop"
        if abs(delta) > 0:
            moves.append(RobotMove("loop", th_s, delta))
        if fg < ell:
            moves.append(RobotMove("stick", ell, fg - ell))
        return domain, rule, moves

    def _loop_trace(self, st: np.ndarray) -> tuple[RobotMove, RobotMove]:
        tr = self.track
        if not isinstance(tr, Lollipop):
            raise InvalidInputError(f"track is {tr!r}, expected a Lollipop")
        ell, c, h = tr.stick, tr.loop, tr.half
        a, b = float(st[0]), float(st[1])
        if a > ell and b > ell:
            da, db = lollipop_trace_scalar(ell, c, a, b)  # both on the loop: the paper's loop trace
            return RobotMove("loop", a - ell, da), RobotMove("loop", b - ell, db)
        ps, pl = (a, b) if a <= ell else (b, a)
        th = pl - ell
        w = min(th, c - th)
        ms = RobotMove("stick", ps, ell - ps)  # the stick robot goes to P
        ml = RobotMove("loop", th, (h - w) if th <= h else -(h - w))  # the loop robot to the antipode of P
        return (ms, ml) if a <= ell else (ml, ms)

    def _plan_loop(self, s: np.ndarray, g: np.ndarray) -> Plan:
        """ℓ < D ≤ h: the stick is too short to pass; retract onto the antipodal circle S2 and plan there."""
        tr = self.track
        if not isinstance(tr, Lollipop):
            raise InvalidInputError(f"track is {tr!r}, expected a Lollipop")
        ell, c = tr.stick, tr.loop
        ti, tf = self._loop_trace(s), self._loop_trace(g)
        ends = []
        for mv in (*ti, *tf):
            th = ((mv.start + mv.delta) % c) if mv.edge == "loop" else 0.0
            ends.append(th)
        domain, delta = _loop_rule(c, self.neighbourhood * tr.half, ends[0], ends[2])
        main = [(RobotMove("loop", ends[0], delta), RobotMove("loop", ends[1], delta))]
        rule = "clearance above the stick length: both robots to antipodal positions on the loop, then " + (
            "counterclockwise (A's positions antipodal)" if domain == 1 else "A's shortest way round, together"
        )
        return build_plan(
            tr,
            s,
            g,
            self.clearance,
            domain,
            rule,
            [
                (
                    "the stick robot moves to P and the loop robot to the antipode of P; on the loop both move apart",
                    [ti],
                ),
                (rule, main),
                ("the reversed trace of the goal", [reverse_moves(tf)]),
            ],
            self.skeleton,
            np.array([ell + ends[0], ell + ends[1]]),
            np.array([ell + ends[2], ell + ends[3]]),
            None,
            regime="loop",
        )

    # --- the plan ---------------------------------------------------------------------------------
    def plan(self, start: ArrayLike, goal: ArrayLike) -> Plan:
        s, g = self.cspace.validate_query(start, goal)
        tr = self.track
        if not isinstance(tr, Lollipop):
            raise InvalidInputError(f"track is {tr!r}, expected a Lollipop")
        D = self.clearance
        if D > tr.half:
            return self._plan_retreat(s, g)
        if D > tr.stick:
            return self._plan_loop(s, g)
        sk = self.skeleton
        ell, c_model, kappa = sk.model.stick, sk.model.loop, sk.kappa

        def real_move(p: float, dp: float) -> RobotMove:  # a move of the model lollipop on the real one
            return RobotMove("stick", p, dp) if p <= ell else RobotMove("loop", (p - ell) / kappa, dp / kappa)

        ends = []
        traces: list[JointMove] = []
        for st in (s, g):
            ma = st[0] if st[0] <= ell else ell + (st[0] - ell) * kappa
            mb = st[1] if st[1] <= ell else ell + (st[1] - ell) * kappa
            da, db = lollipop_trace_scalar(ell, c_model, ma, mb)
            ends.append(_wrap_model(ell, c_model, ma, ma + da, mb, mb + db))
            traces.append((real_move(ma, da), real_move(mb, db)))
        (mxa, mxb), (mya, myb) = ends
        xi = np.array([v if v <= ell else ell + (v - ell) / kappa for v in (mxa, mxb)])
        xf = np.array([v if v <= ell else ell + (v - ell) / kappa for v in (mya, myb)])
        px, py = sk.point_of_model_state(mxa, mxb), sk.point_of_model_state(mya, myb)
        domain, pieces = self.route_in_skeleton(px, py)
        main: list[JointMove] = []
        for e, t0, t1 in pieces:
            ma_, mb_ = sk.edge_moves(e, t0, t1)
            main.append((sk.move_from_model(ma_), sk.move_from_model(mb_)))
        word = pieces_word(sk.graph, _drop_zero_edges(sk, pieces))
        return build_plan(
            tr,
            s,
            g,
            self.clearance,
            domain,
            RULES[("lollipop", domain)],
            [
                (PRELIM["lollipop"], [traces[0]]),
                (RULES[("lollipop", domain)], main),
                (FINAL["lollipop"], [reverse_moves(traces[1])]),
            ],
            sk,
            xi,
            xf,
            word,
        )


def _loop_rule(c: float, eps: float, th0: float, th1: float) -> tuple[int, float]:
    """One robot on a circle from θ0 to θ1 (paper §4 example): ccw if antipodal within ε (1), else shortest (2)."""
    d = (th1 - th0) % c
    if d >= c - 1e-15:
        d = 0.0
    if abs(d - 0.5 * c) < eps:
        return 1, d
    return 2, (d if d <= 0.5 * c else d - c)


def _wrap_model(ell: float, c: float, a0: float, a1: float, b0: float, b1: float) -> tuple[float, float]:
    """Model positions after a trace: loop coordinates wrapped into [ℓ, ℓ + c)."""
    out = []
    for p0, p1 in ((a0, a1), (b0, b1)):
        if p0 > ell:
            p1 = ell + (p1 - ell) % c
            if p1 >= ell + c - 1e-12:
                p1 = ell
        out.append(p1)
    return out[0], out[1]


def _drop_zero_edges(sk: LollipopSkeleton, pieces: list[tuple[str, float, float]]) -> list[tuple[str, float, float]]:
    if sk.graph.edge("I1").length > 1e-9:
        return pieces
    return [p for p in pieces if p[0] not in ("I1", "I2")]
