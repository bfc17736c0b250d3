"""Stage 1, smoothing: a shorter collision-free polyline in the plan's homotopy class (CasADi + IPOPT).

Geometry. Every robot of a :class:`~mpa.plan.Plan` moves along its own :class:`~mpa.routes.Route`, so a joint
motion is a curve in the plane of route coordinates ``σ = (σ_A, σ_B)`` (metres). The separation
``d(σ) = track.distance(route_A.position(σ_A), route_B.position(σ_B))`` is piecewise affine there
(:class:`RouteGeometry`): cut the plane into *rectangles* at every σ where a robot passes the pole P
(:meth:`mpa.routes.Route.junctions`); inside a rectangle each robot stays on one edge and, with ``x`` the depth
below P on a stick and ``U`` the unrolled loop coordinate (both affine in σ with slope ±1),

- both on the stick: ``d = |x_A − x_B|``;
- one on the stick, one on the loop between the lifts ``m·c`` and ``(m+1)·c``:
  ``d = x + min(U − m·c, (m+1)·c − U)``;
- both on the loop (and the circle): ``d = min_k |U_A − U_B − k·c|``;
- interval: ``d = |p_A − p_B|``.

The free set ``d ≥ D`` of a rectangle is a union of convex polygons, one per sign choice; a *cell* is one of
them (the rectangle's box and one or two half-planes ``g·σ + h ≥ D``).

Optimisation. The plan's polyline is cut at every junction crossing, so every piece lies in one cell, and
resampled to ``N`` segments. The NLP (:class:`SmoothingProblem`, built once per ``N`` and re-solved with the
query as parameters) moves the nodes; segment ``k`` keeps *both* its end nodes in the cell of the plan's piece
it came from, so every straight segment is exactly collision-free (convexity) and the sequence of cells -- hence
the homotopy class -- is the plan's. Variables: nodes and per-segment durations ``dt_k ≥ |Δσ_r,k| / vmax_r``;
objective ``Σ dt_k`` plus a small weight times the squared second differences of the nodes. Afterwards
:func:`shortcut` replaces runs of nodes by single straight segments where that stays exactly collision-free
(:meth:`RouteGeometry.polyline_min_distance`) and keeps the skeleton word.
"""

from __future__ import annotations

import time
from dataclasses import dataclass, field
from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from mpa.errors import PlanningError
from mpa.homotopy import path_word
from mpa.plan import Plan
from mpa.routes import Route
from mpa.tracks import Interval, Track

__all__ = [
    "SIZE_CLASSES",
    "RouteGeometry",
    "SmoothingProblem",
    "SmoothingResult",
    "densify",
    "polyline_word",
    "shortcut",
    "smooth_plan",
]

FloatArray = NDArray[np.float64]
#: Node counts (segments) of the NLPs that are built; a query uses the smallest that fits its plan.
SIZE_CLASSES = (8, 16, 32, 64, 128)
#: Padding rows of the cell constraints: ``0·σ ≥ −BIG``.
_BIG = 1e19
#: Nodes closer than this (metres) are merged.
NODE_TOL = 1e-10


# ---------------------------------------------------------------------------------------------------
@dataclass(frozen=True)
class RouteGeometry:
    """The separation of two robots on their routes as a piecewise-affine function of ``σ = (σ_A, σ_B)``.

    Parameters
    ----------
    track : Track
    routes : tuple of Route
        Route of A and of B (from a plan).

    Attributes
    ----------
    breaks : tuple of ndarray
        Per robot, the sorted rectangle boundaries ``[σ_min, junctions…, σ_max]`` (metres).
    is_stick, slope, intercept : tuple of ndarray
        Per robot and interval between breaks: whether the robot is on a stick, and ``v = intercept + slope·σ``
        (``v`` = depth ``x`` below P on a stick, else the unrolled loop coordinate ``U``; the interval's ``p``).
    """

    track: Track
    routes: tuple[Route, Route]
    breaks: tuple[FloatArray, FloatArray] = field(init=False)
    is_stick: tuple[NDArray[np.bool_], NDArray[np.bool_]] = field(init=False)
    slope: tuple[FloatArray, FloatArray] = field(init=False)
    intercept: tuple[FloatArray, FloatArray] = field(init=False)

    def __post_init__(self) -> None:
        brs, sts, sls, ics = [], [], [], []
        for rt in self.routes:
            j = rt.junctions()
            b = np.unique(np.concatenate([[rt.sigma_min], j[(j > rt.sigma_min) & (j < rt.sigma_max)], [rt.sigma_max]]))
            lo, hi = b[:-1], b[1:]
            s1, s3 = lo + 0.25 * (hi - lo), lo + 0.75 * (hi - lo)
            st1, _k1, v1 = rt.lift_at(s1)
            _st3, _k3, v3 = rt.lift_at(s3)
            sl = np.sign(np.round((v3 - v1) / (s3 - s1)))
            brs.append(b)
            sts.append(np.asarray(st1, dtype=bool))
            sls.append(sl.astype(float))
            ics.append(v1 - sl * s1)
        object.__setattr__(self, "breaks", (brs[0], brs[1]))
        object.__setattr__(self, "is_stick", (sts[0], sts[1]))
        object.__setattr__(self, "slope", (sls[0], sls[1]))
        object.__setattr__(self, "intercept", (ics[0], ics[1]))

    @property
    def junctions(self) -> tuple[FloatArray, FloatArray]:
        """Interior rectangle boundaries of each robot (where it passes P)."""
        return self.breaks[0][1:-1], self.breaks[1][1:-1]

    def interval(self, robot: int, sigma: ArrayLike) -> NDArray[np.intp]:
        """Index of the interval between breaks that contains ``σ`` (the upper one at a break)."""
        b = self.breaks[robot]
        return np.clip(np.searchsorted(b, np.asarray(sigma, dtype=float), side="right") - 1, 0, len(b) - 2)

    def box(self, ia: int, ib: int) -> FloatArray:
        """The rectangle ``[[σA_lo, σA_hi], [σB_lo, σB_hi]]`` of intervals ``(ia, ib)``."""
        ba, bb = self.breaks
        return np.array([[ba[ia], ba[ia + 1]], [bb[ib], bb[ib + 1]]])

    def distance(self, sigma: ArrayLike) -> FloatArray:
        """Exact separation at route coordinates ``σ`` (shape (..., 2)), via the track metric (metres)."""
        s = np.asarray(sigma, dtype=float)
        pa = self.routes[0].position(s[..., 0])
        pb = self.routes[1].position(s[..., 1])
        return self.track.distance(pa, pb)

    def positions(self, sigma: ArrayLike) -> FloatArray:
        """Track coordinates of both robots at route coordinates ``σ``. Shape (..., 2)."""
        s = np.asarray(sigma, dtype=float)
        return np.stack([self.routes[0].position(s[..., 0]), self.routes[1].position(s[..., 1])], axis=-1)

    # --- cells -------------------------------------------------------------------------------------
    def cell_rows(self, mid: ArrayLike) -> tuple[tuple[int, int], list[tuple[float, float, float]]]:
        """The cell of the free set that contains the point ``mid``.

        Returns
        -------
        (ia, ib) : tuple of int
            The rectangle (interval of each robot).
        rows : list of (gA, gB, h)
            Half-planes ``gA·σ_A + gB·σ_B + h ≥ D`` (one or two) that, inside the rectangle, imply ``d ≥ D``.
        """
        m_ = np.asarray(mid, dtype=float)
        ia, ib = int(self.interval(0, m_[0])), int(self.interval(1, m_[1]))
        sa, sb = float(self.slope[0][ia]), float(self.slope[1][ib])
        ca_, cb_ = float(self.intercept[0][ia]), float(self.intercept[1][ib])
        va, vb = ca_ + sa * m_[0], cb_ + sb * m_[1]
        tr = self.track
        rows: list[tuple[float, float, float]] = []
        if isinstance(tr, Interval):
            sg = 1.0 if va - vb >= 0 else -1.0
            rows.append((sg * sa, -sg * sb, sg * (ca_ - cb_)))
            return (ia, ib), rows
        c = tr.loop  # type: ignore[attr-defined]
        st_a, st_b = bool(self.is_stick[0][ia]), bool(self.is_stick[1][ib])
        if st_a and st_b:
            sg = 1.0 if va - vb >= 0 else -1.0
            rows.append((sg * sa, -sg * sb, sg * (ca_ - cb_)))
        elif st_a or st_b:
            # x on the stick robot, U on the loop robot: x + (U − m c) ≥ D and x + ((m+1) c − U) ≥ D
            if st_a:
                gx, hx, gu, hu, u = (sa, 0.0), ca_, (0.0, sb), cb_, vb
            else:
                gx, hx, gu, hu, u = (0.0, sb), cb_, (sa, 0.0), ca_, va
            m = float(np.floor(u / c))
            rows.append((gx[0] + gu[0], gx[1] + gu[1], hx + hu - m * c))
            rows.append((gx[0] - gu[0], gx[1] - gu[1], hx + (m + 1) * c - hu))
        else:
            w = va - vb
            m = float(np.floor(w / c))
            rows.append((sa, -sb, ca_ - cb_ - m * c))
            rows.append((-sa, sb, (m + 1) * c - ca_ + cb_))
        return (ia, ib), rows

    # --- exact minimum along straight segments ---------------------------------------------------------
    def polyline_min_distance(self, pts: ArrayLike) -> float:
        """Exact minimum of the separation along the polyline through ``pts`` (shape (n, 2), route coordinates).

        Every chord is cut where a robot passes P; on the pieces the separation is the minimum of a few
        absolute values of affine functions, whose minimum over a segment is attained at an end or is 0 where
        the function changes sign.
        """
        p = np.atleast_2d(np.asarray(pts, dtype=float))
        if len(p) == 1:
            return float(self.distance(p)[0])
        return float(np.min(self.segment_min_distances(p)))

    def segment_min_distances(self, pts: ArrayLike) -> FloatArray:
        """Exact minimum of the separation along every chord of the polyline ``pts`` (shape (n, 2)). Shape (n−1,).

        A continuous function of the chord ends (the separation is continuous and piecewise affine).
        """
        p = np.atleast_2d(np.asarray(pts, dtype=float))
        if len(p) < 2:
            return np.zeros(0)
        q, owner = self._split_at_junctions(p, with_owner=True)
        a, b = q[:-1], q[1:]
        mid = 0.5 * (a + b)
        ia, ib = self.interval(0, mid[:, 0]), self.interval(1, mid[:, 1])
        sa, sb = self.slope[0][ia], self.slope[1][ib]
        va0, va1 = self.intercept[0][ia] + sa * a[:, 0], self.intercept[0][ia] + sa * b[:, 0]
        vb0, vb1 = self.intercept[1][ib] + sb * a[:, 1], self.intercept[1][ib] + sb * b[:, 1]
        tr = self.track
        if isinstance(tr, Interval):
            out = _abs_affine_min(va0 - vb0, va1 - vb1)
        else:
            c = tr.loop  # type: ignore[attr-defined]
            st_a, st_b = self.is_stick[0][ia], self.is_stick[1][ib]
            out = np.full(len(a), np.inf)
            ss = st_a & st_b
            out[ss] = _abs_affine_min((va0 - vb0)[ss], (va1 - vb1)[ss])
            sl = st_a ^ st_b
            if np.any(sl):
                x0 = np.where(st_a, va0, vb0)[sl]
                x1 = np.where(st_a, va1, vb1)[sl]
                u0 = np.where(st_a, vb0, va0)[sl]
                u1 = np.where(st_a, vb1, va1)[sl]
                um = 0.5 * (u0 + u1)
                m = np.floor(um / c)
                th0, th1 = u0 - m * c, u1 - m * c
                out[sl] = np.minimum.reduce([x0 + th0, x1 + th1, x0 + c - th0, x1 + c - th1])
            ll = ~(st_a | st_b)
            if np.any(ll):
                w0, w1 = (va0 - vb0)[ll], (va1 - vb1)[ll]
                m0, m1 = np.floor(w0 / c), np.floor(w1 / c)
                m = m0
                r0, r1 = w0 - m * c, w1 - m * c
                dd = np.minimum.reduce([r0, c - r0, r1, c - r1])
                out[ll] = np.where(m0 != m1, 0.0, dd)
        res = np.full(len(p) - 1, np.inf)
        np.minimum.at(res, owner, out)
        return res

    def _split_at_junctions(self, p: FloatArray, with_owner: bool = False) -> Any:
        """Insert the points where a chord crosses a junction (so every chord lies in one rectangle).

        With ``with_owner`` also returns, for every piece of the result, the index of the chord it comes from.
        """
        ts = [np.zeros(len(p) - 1)]
        idx = [np.arange(len(p) - 1)]
        for r in (0, 1):
            j = self.junctions[r]
            if len(j) == 0:
                continue
            s0, s1 = p[:-1, r], p[1:, r]
            ds = s1 - s0
            with np.errstate(divide="ignore", invalid="ignore"):
                t = (j[None, :] - s0[:, None]) / ds[:, None]
            ok = np.isfinite(t) & (t > 0.0) & (t < 1.0)
            kk, jj = np.nonzero(ok)
            ts.append(t[kk, jj])
            idx.append(kk)
        t_all = np.concatenate(ts)
        i_all = np.concatenate(idx)
        order = np.lexsort((t_all, i_all))
        t_all, i_all = t_all[order], i_all[order]
        q = p[i_all] + t_all[:, None] * (p[i_all + 1] - p[i_all])
        if with_owner:
            return np.vstack([q, p[-1:]]), i_all
        return np.vstack([q, p[-1:]])


def _abs_affine_min(f0: FloatArray, f1: FloatArray) -> FloatArray:
    """Minimum of ``|f|`` over a segment for affine ``f`` with end values ``f0, f1``."""
    return np.where(f0 * f1 <= 0.0, 0.0, np.minimum(np.abs(f0), np.abs(f1)))


# ---------------------------------------------------------------------------------------------------
def densify(pts: ArrayLike, step: float) -> FloatArray:
    """Points along a polyline (shape (n, 2)) with at most ``step`` between consecutive ones (max-norm)."""
    p = np.atleast_2d(np.asarray(pts, dtype=float))
    if len(p) < 2:
        return p.copy()
    seg = np.max(np.abs(np.diff(p, axis=0)), axis=1)
    n = np.maximum(1, np.ceil(seg / step).astype(int))
    out = [p[i] + np.linspace(0.0, 1.0, n[i], endpoint=False)[:, None] * (p[i + 1] - p[i]) for i in range(len(p) - 1)]
    out.append(p[-1:])
    return np.vstack(out)


def polyline_word(geom: RouteGeometry, pts: ArrayLike) -> tuple[str, ...]:
    """Reduced skeleton word (homotopy class) of the polyline ``pts`` in route coordinates."""
    step = 0.004 * geom.track.total_length
    return path_word(geom.track, geom.positions(densify(pts, step)))


def _dedupe(pts: FloatArray) -> FloatArray:
    keep = np.concatenate([[True], np.max(np.abs(np.diff(pts, axis=0)), axis=1) > NODE_TOL])
    out = pts[keep]
    out[-1] = pts[-1]
    return out


# ---------------------------------------------------------------------------------------------------
@dataclass(frozen=True)
class CellSequence:
    """The plan's polyline cut at junction crossings, with the cell of every piece.

    Attributes
    ----------
    points : ndarray, shape (P+1, 2)
        Piece ends (route coordinates).
    boxes : ndarray, shape (P, 2, 2)
        Rectangle of every piece.
    rows : ndarray, shape (P, 2, 3)
        Half-planes ``(gA, gB, h)`` of every piece's cell (unused rows are zeros with ``h = −inf``).
    """

    points: FloatArray
    boxes: FloatArray
    rows: FloatArray


def plan_cells(geom: RouteGeometry, waypoints_s: ArrayLike) -> CellSequence:
    """Cut the plan's polyline at junction crossings and find the cell of every piece."""
    p = _dedupe(np.atleast_2d(np.asarray(waypoints_s, dtype=float)))
    q = _dedupe(geom._split_at_junctions(p)) if len(p) > 1 else p
    n = len(q) - 1
    boxes = np.zeros((n, 2, 2))
    rows = np.zeros((n, 2, 3))
    rows[:, :, 2] = -np.inf
    for k in range(n):
        (ia, ib), rr = geom.cell_rows(0.5 * (q[k] + q[k + 1]))
        boxes[k] = geom.box(ia, ib)
        for r, row in enumerate(rr):
            rows[k, r] = row
    return CellSequence(q, boxes, rows)


@dataclass(frozen=True)
class SmoothingResult:
    """Output of the smoothing stage.

    Attributes
    ----------
    nodes : ndarray, shape (M, 2)
        The smoothed, shortcut polyline in route coordinates (metres), first = start, last = goal.
    optimized : ndarray, shape (N+1, 2)
        The IPOPT solution before shortcutting.
    stats : dict
        ``n_segments``, ``ipopt_iterations``, ``ipopt_status``, ``solve_time``, ``build_time`` (s), …
    """

    nodes: FloatArray
    optimized: FloatArray
    stats: dict[str, Any]


class SmoothingProblem:
    """The smoothing NLP for ``n`` segments, built once (CasADi SX, IPOPT with MUMPS) and re-solved.

    Parameters
    ----------
    n : int
        Number of segments (nodes ``n + 1``).

    Notes
    -----
    Variables ``x = [σ_A(0..n), σ_B(0..n), dt(0..n−1)]``. Parameters: the cell half-plane coefficients
    ``(gA, gB)`` of two rows per segment, the inverse speed limits and the smoothness weight; right-hand sides
    and the rectangles enter as the numeric bounds ``lbg``, ``lbx``, ``ubx`` of each call.
    """

    def __init__(self, n: int) -> None:
        import casadi as ca

        t0 = time.perf_counter()
        self.n = int(n)
        n = self.n
        x = ca.SX.sym("x", 3 * n + 2)
        sa, sb, dt = x[0 : n + 1], x[n + 1 : 2 * n + 2], x[2 * n + 2 :]
        coef = ca.SX.sym("coef", 4 * n)  # per segment k, row r: (gA, gB) at 4k + 2r
        inv_v = ca.SX.sym("inv_v", 2)
        w = ca.SX.sym("w", 1)
        ga = ca.reshape(coef[0::2], 2, n).T  # (n, 2): row r of segment k
        gb = ca.reshape(coef[1::2], 2, n).T
        g_cells = []
        for r in range(2):
            for off in (0, 1):
                g_cells.append(ga[:, r] * sa[off : n + off] + gb[:, r] * sb[off : n + off])
        da, db = ca.diff(sa), ca.diff(sb)
        g_vel = [da * inv_v[0] - dt, -da * inv_v[0] - dt, db * inv_v[1] - dt, -db * inv_v[1] - dt]
        g = ca.vertcat(*g_cells, *g_vel)
        smooth = ca.sumsqr(ca.diff(da)) + ca.sumsqr(ca.diff(db)) if n > 1 else ca.SX(0)
        f = ca.sum1(dt) + w * smooth
        opts: dict[str, Any] = {
            "ipopt.print_level": 0,
            "ipopt.sb": "yes",
            "print_time": False,
            "ipopt.linear_solver": "mumps",
            "ipopt.tol": 1e-9,
            "ipopt.constr_viol_tol": 1e-10,
            "ipopt.max_iter": 300,
            "ipopt.bound_push": 1e-9,
            "ipopt.bound_frac": 1e-9,
            "ipopt.mu_init": 1e-4,
            "ipopt.warm_start_init_point": "yes",
        }
        self.solver = ca.nlpsol(f"smooth{n}", "ipopt", {"x": x, "p": ca.vertcat(coef, inv_v, w), "f": f, "g": g}, opts)
        self.n_g = 8 * n
        self.build_time = time.perf_counter() - t0

    def solve(
        self,
        cells: CellSequence,
        separation: float,
        vmax: ArrayLike,
        *,
        floor_values: FloatArray | None = None,
    ) -> tuple[FloatArray, dict[str, Any]]:
        """Solve for one query.

        Parameters
        ----------
        cells : CellSequence
            The plan's pieces and cells (at most ``n`` pieces).
        separation : float
            Required separation inside the optimizer (clearance plus margins; metres).
        vmax : array_like, shape (2,)
            Speed limits of A and B (m/s).

        Returns
        -------
        nodes : ndarray, shape (n+1, 2)
        stats : dict
        """
        n = self.n
        pcs = len(cells.points) - 1
        if pcs > n or pcs < 1:
            raise PlanningError(f"plan has {pcs} pieces, the NLP has {n} segments")
        # distribute the segments over the pieces (at least one each, the rest by length)
        ln = np.max(np.abs(np.diff(cells.points, axis=0)), axis=1)
        cnt = np.ones(pcs, dtype=int)
        extra = n - pcs
        if extra > 0:
            share = ln / max(float(ln.sum()), 1e-300) * extra
            add = np.floor(share).astype(int)
            cnt += add
            rest = extra - int(add.sum())
            if rest > 0:
                cnt[np.argsort(-(share - add))[:rest]] += 1
        piece = np.repeat(np.arange(pcs), cnt)  # piece of every segment
        first = np.concatenate([[0], np.cumsum(cnt)[:-1]])
        frac = (np.arange(n) - first[piece]) / cnt[piece]
        x0n = cells.points[piece] + frac[:, None] * (cells.points[piece + 1] - cells.points[piece])
        x0n = np.vstack([x0n, cells.points[-1:]])
        # bounds of the nodes: intersection of the boxes of the adjacent segments
        boxes = cells.boxes[piece]
        lo = np.full((n + 1, 2), -np.inf)
        hi = np.full((n + 1, 2), np.inf)
        for off in (0, 1):
            lo[off : n + off] = np.maximum(lo[off : n + off], boxes[:, :, 0])
            hi[off : n + off] = np.minimum(hi[off : n + off], boxes[:, :, 1])
        lo[0] = hi[0] = cells.points[0]
        lo[-1] = hi[-1] = cells.points[-1]
        x0n = np.clip(x0n, lo, hi)
        rows = cells.rows[piece]  # (n, 2, 3)
        used = np.isfinite(rows[:, :, 2])
        coef = np.where(used[:, :, None], rows[:, :, :2], 0.0)
        rhs = np.where(used, separation - np.where(used, rows[:, :, 2], 0.0), -_BIG)
        # never ask for more than the plan itself has where the plan is tighter (start or goal near D)
        for off in (0, 1):
            val = np.einsum("krc,kc->kr", coef, x0n[off : n + off])
            rhs = np.where(used, np.minimum(rhs, val), rhs)
        lbg_cells = np.concatenate([rhs[:, r] for r in range(2) for _off in (0, 1)])
        v = np.asarray(vmax, dtype=float)
        dt0 = np.max(np.abs(np.diff(x0n, axis=0)) / v[None, :], axis=1)
        total = float(dt0.sum())
        scale = float(np.sum(np.max(np.abs(np.diff(x0n, axis=0)), axis=1)))
        weight = 0.05 * n / max(scale * float(np.mean(v)), 1e-12)
        p = np.concatenate([coef.reshape(-1), 1.0 / v, [weight]])
        x0 = np.concatenate([x0n[:, 0], x0n[:, 1], dt0])
        lbx = np.concatenate([lo[:, 0], lo[:, 1], np.zeros(n)])
        ubx = np.concatenate([hi[:, 0], hi[:, 1], np.full(n, np.inf)])
        lbg = np.concatenate([lbg_cells, np.full(4 * n, -np.inf)])
        ubg = np.concatenate([np.full(4 * n, np.inf), np.zeros(4 * n)])
        t0 = time.perf_counter()
        sol = self.solver(x0=x0, p=p, lbx=lbx, ubx=ubx, lbg=lbg, ubg=ubg)
        st = self.solver.stats()
        elapsed = time.perf_counter() - t0
        xs = np.asarray(sol["x"], dtype=float).ravel()
        nodes = np.stack([xs[: n + 1], xs[n + 1 : 2 * n + 2]], axis=1)
        nodes = np.clip(nodes, lo, hi)
        stats = {
            "n_segments": n,
            "n_pieces": pcs,
            "ipopt_status": str(st.get("return_status", "")),
            "ipopt_success": bool(st.get("success", False)),
            "ipopt_iterations": int(st.get("iter_count", -1)),
            "solve_time": elapsed,
            "plan_time_bound": total,
            "optimized_time_bound": float(np.sum(xs[2 * n + 2 :])),
        }
        return nodes, stats


_PROBLEMS: dict[int, SmoothingProblem] = {}


def problem_for(pieces: int) -> SmoothingProblem:
    """The cached NLP of the smallest size class with at least ``2·pieces`` segments (built on first use)."""
    want = 2 * pieces
    n = next((s for s in SIZE_CLASSES if s >= want), None)
    if n is None:
        if pieces > SIZE_CLASSES[-1]:
            raise PlanningError(f"plan has {pieces} pieces, more than the largest NLP ({SIZE_CLASSES[-1]} segments)")
        n = SIZE_CLASSES[-1]
    if n not in _PROBLEMS:
        _PROBLEMS[n] = SmoothingProblem(n)
    return _PROBLEMS[n]


def shortcut(geom: RouteGeometry, nodes: ArrayLike, separation: float, word: tuple[str, ...]) -> FloatArray:
    """Replace runs of nodes by straight segments that stay ``≥ separation`` apart and keep the word.

    Greedy: from the current node, the farthest later node reachable by an exactly collision-free chord
    (checked by :meth:`RouteGeometry.polyline_min_distance`) whose polyline keeps the skeleton word ``word``.
    """
    p = _dedupe(np.atleast_2d(np.asarray(nodes, dtype=float)))
    out = [p[0]]
    i = 0
    n = len(p)
    while i < n - 1:
        nxt = i + 1
        for j in range(n - 1, i + 1, -1):
            if geom.polyline_min_distance(np.array([p[i], p[j]])) < separation:
                continue
            cand = np.vstack([*out, p[j:]])
            if polyline_word(geom, cand) == tuple(word):
                nxt = j
                break
        out.append(p[nxt])
        i = nxt
    return np.array(out)


def _collinear_merge(p: FloatArray, tol: float = 1e-12) -> FloatArray:
    """Drop interior nodes that lie on the straight line through their neighbours (same direction)."""
    if len(p) <= 2:
        return p
    keep = [0]
    for i in range(1, len(p) - 1):
        a, b, c = p[keep[-1]], p[i], p[i + 1]
        u, v = b - a, c - b
        cross = u[0] * v[1] - u[1] * v[0]
        if abs(cross) <= tol * max(1.0, float(np.linalg.norm(u) * np.linalg.norm(v))) and float(u @ v) > 0:
            continue
        keep.append(i)
    keep.append(len(p) - 1)
    return p[keep]


def smooth_plan(plan: Plan, separation: float, vmax: ArrayLike, geom: RouteGeometry | None = None) -> SmoothingResult:
    """Smooth a plan: IPOPT in the plan's cells, then shortcut.

    Parameters
    ----------
    plan : Plan
    separation : float
        Separation the result must keep (clearance plus the verifier's margins; metres).
    vmax : array_like, shape (2,)
        Speed limits of A and B (m/s); they weigh the robots' travel in the objective.
    geom : RouteGeometry, optional
        Re-used if given.

    Returns
    -------
    SmoothingResult

    Raises
    ------
    PlanningError
        IPOPT failed, or its result is not collision-free or leaves the homotopy class.
    """
    geom = geom or RouteGeometry(plan.track, plan.routes)
    t0 = time.perf_counter()
    cells = plan_cells(geom, plan.waypoints_s)
    pcs = len(cells.points) - 1
    if pcs < 1:  # start == goal: nothing to do
        pt = np.asarray(plan.waypoints_s[:1], dtype=float)
        return SmoothingResult(pt, pt, {"n_segments": 0, "ipopt_iterations": 0, "ipopt_status": "trivial"})
    prob = problem_for(pcs)
    t1 = time.perf_counter()
    nodes, stats = prob.solve(cells, separation + 1e-6, vmax)
    stats["cells_time"] = t1 - t0
    if not stats["ipopt_success"]:
        raise PlanningError(f"IPOPT failed: {stats['ipopt_status']} after {stats['ipopt_iterations']} iterations")
    nodes[0], nodes[-1] = cells.points[0], cells.points[-1]
    d_start = float(geom.distance(cells.points[0]))
    d_goal = float(geom.distance(cells.points[-1]))
    need = min(separation, d_start, d_goal)
    dmin = geom.polyline_min_distance(nodes)
    if dmin < need - 1e-12:
        raise PlanningError(f"smoothed path comes {dmin:.9g} close, below the required {need:.9g}")
    t2 = time.perf_counter()
    word = polyline_word(geom, nodes)
    if word != tuple(plan.word):
        raise PlanningError(f"smoothed path has the class {word}, the plan {tuple(plan.word)}")
    short = _collinear_merge(shortcut(geom, nodes, need, plan.word))
    stats["shortcut_time"] = time.perf_counter() - t2
    stats["n_corners"] = len(short) - 2
    return SmoothingResult(short, nodes, stats)
