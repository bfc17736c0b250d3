"""The hard path, continuous in the query: a strictly convex QP in a corridor fixed by the plan, a spline, a filter.

Why. The plan of :mod:`mpa` depends continuously on (start, goal) inside a domain: its path ``α(u)``, written in
route coordinates and parametrized by ``u ∈ [0, 1]``, moves continuously. Every step here is a continuous function
of ``α``, with no discrete choice that could flip on a hair (no shortcut, no de-duplication, no collision-checked
halving, no corner passed at rest, a fixed number of nodes and pieces):

1. *Corridor.* ``n + 1`` plan samples ``P_k = α(k/n)`` (a fixed count, whatever the plan's steps). The separation
   ``d`` is 1-Lipschitz in the L1 norm of route coordinates (each robot moves along the track by ``|Δσ_r|``). For
   every four consecutive samples, :func:`hull_clearance` is the exact minimum ``E`` of ``d`` over their convex
   hull (continuous in the samples); a node may move within the L1 ball ``|n_k − P_k|₁ ≤ R_k``, ``R_k`` the
   smallest ``max(E − sep, 0)`` of the windows that contain ``k``. The hull of four consecutive nodes then stays
   within ``R`` of the hull of their samples, hence keeps ``d ≥ sep``, and the motion stays homotopic to the plan.
2. *QP* (:class:`CorridorProblem`): an elastic band with a bending term in the time-like metric ``σ_r / vmax_r``;
   the Hessian is fixed and positive definite, so the solution is unique and a continuous function of the query.
   Solved exactly by the dual active-set solver DAQP through CasADi's ``conic`` (built once per generator, called
   through a buffer) when a guess fails: the previous solve's active set (the empty set for the first solve), then
   up to five one-row repairs of it, is tried first: its equality-constrained solution is accepted only if every
   KKT condition holds to DAQP's tolerances, and then it *is* the unique solution, so the answer does not depend on
   how it was found (up to rounding).
3. *Path*: the uniform cubic B-spline of the nodes (:func:`trajopt.timing.spline_path`), each span inside the hull
   of four consecutive nodes, C² with a fixed number of pieces.
4. *Timing*: :func:`trajopt.timing.filtered_scaling`, a v/a-limited profile with eroded per-piece limits on a grid
   that moves with the path, then a box filter for the jerk: continuous in the path, exact limits.
"""

from __future__ import annotations

import threading
import time
from dataclasses import dataclass
from functools import lru_cache
from typing import Any, NamedTuple

import numpy as np
from numpy.typing import ArrayLike, NDArray

from mpa._arrays import FloatArray
from mpa.errors import PlanningError
from mpa.geometry import RouteGeometry
from mpa.plans import MotionPlan
from trajopt.path.planview import plan_view

__all__ = [
    "CORRIDOR_SEGMENTS",
    "CorridorProblem",
    "CorridorResult",
    "corridor_nodes",
    "corridor_radii",
]

IntArray = NDArray[np.intp]
#: Number of segments of the hard path (nodes ``n + 1``), the same for every query.
CORRIDOR_SEGMENTS = 32
#: Corridor solves: each re-centres the balls on the previous solution (a fixed count: continuous).
CORRIDOR_ITERATIONS = 8
#: Primal and dual tolerance of a known active set's KKT check (DAQP's own tolerances).
KKT_TOL = 1e-12
#: Repairs of a wrong active-set guess tried before DAQP is called.
ACTIVE_SET_REPAIRS = 5
#: Control points of one span of the cubic B-spline.
SPAN_POINTS = 4
#: Weight of the bending term relative to the elastic band.
SMOOTH_WEIGHT = 10


@dataclass(frozen=True)
class CorridorResult:
    """Output of the corridor QP.

    Attributes
    ----------
    nodes : ndarray, shape (n+1, 2)
        The optimised polyline in route coordinates (metres), first = start, last = goal.
    centers : ndarray, shape (n+1, 2)
        The plan samples ``P_k``.
    free : ndarray, shape (n+1,)
        ``R_k``: radius (L1, metres) of the free ball around every plan sample.
    stats : dict
    """

    nodes: FloatArray
    centers: FloatArray
    free: FloatArray
    stats: dict[str, Any]


def hull_clearance(geom: RouteGeometry, centers: FloatArray, width: int = 4) -> FloatArray:
    """Exact minimum separation over the convex hull of every ``width`` consecutive plan samples. Shape (n+2−width,).

    It is the minimum over the chords between all pairs of the points: the separation has no local minimum
    above 0 (one robot can always move towards the other along its route) and no obstacle fits inside such a
    small hull, so the minimum over the hull is on its boundary, which those chords cover. Continuous in the points.
    """
    n1 = len(centers)
    if n1 - width + 1 < 1:
        return np.zeros(0)
    first, second, windows = _hull_chords(n1, width)
    chords = geom.chord_min_distances(centers[first], centers[second])
    return np.asarray(np.min(chords[windows], axis=0))


@lru_cache(maxsize=16)
def _hull_chords(n1: int, width: int) -> tuple[IntArray, IntArray, IntArray]:
    """Every chord ``(i, i + g)`` (``1 <= g < width``) of ``n1`` points once (a chord is shared by up to
    ``width − g`` windows): its first and second point, and for every window its chords (shape (pairs, windows))."""
    nw = n1 - width + 1
    first: list[int] = []
    second: list[int] = []
    index: dict[tuple[int, int], int] = {}
    for g in range(1, width):
        for i in range(n1 - g):
            index[i, i + g] = len(first)
            first.append(i)
            second.append(i + g)
    pairs = [(i, j) for i in range(width) for j in range(i + 1, width)]
    windows = np.array([[index[w + i, w + j] for w in range(nw)] for i, j in pairs], dtype=np.intp)
    return np.array(first, dtype=np.intp), np.array(second, dtype=np.intp), windows


def corridor_radii(geom: RouteGeometry, centers: FloatArray, separation: float) -> FloatArray:
    """L1 radius of every node's ball: the minimum, over the spline spans that use the node, of ``max(E − sep, 0)``.

    ``E`` is :func:`hull_clearance` of the span's four plan samples. Shape (n+1,).
    """
    n1 = len(centers)
    if n1 < SPAN_POINTS:
        return np.full(n1, np.inf)
    ends, table = _node_chords(n1)
    a, b = centers.take(ends, axis=0)
    chords = geom.chord_min_distances(a, b)
    # min over windows of max(E − sep, 0) = max(min over the windows' chords − sep, 0) (monotone, also rounded)
    return np.maximum(np.minimum.reduce(chords.take(table), axis=1) - separation, 0.0)


@lru_cache(maxsize=8)
def _node_chords(n1: int) -> tuple[IntArray, IntArray]:
    """The chords of :func:`hull_clearance` (windows of :data:`SPAN_POINTS` of ``n1`` points): their ends (shape
    (2, C)) and, for every point, the chords of all the windows that contain it (shape (n1, M), repeats padding the
    rows of the points near the ends, which are in fewer windows)."""
    first, second, windows = _hull_chords(n1, SPAN_POINTS)
    nw = n1 - SPAN_POINTS + 1
    rows = []
    for k in range(n1):
        ws = range(max(k - SPAN_POINTS + 1, 0), min(k, nw - 1) + 1)
        rows.append(sorted({int(c) for w in ws for c in windows[:, w]}))
    m = max(len(r) for r in rows)
    table = np.array([r + [r[0]] * (m - len(r)) for r in rows], dtype=np.intp)
    return np.stack([first, second]), table


class CorridorProblem:
    """The corridor QP for ``n`` segments and speed limits ``vmax``, built once and re-solved.

    Parameters
    ----------
    n : int
        Number of segments.
    vmax : array_like, shape (2,)
        Speed limits of A and B (m/s): route coordinates are divided by them (a time-like metric).
    solver : str
        A CasADi ``conic`` plugin that ships with CasADi (default ``"daqp"``, a dual active-set method: exact
        and deterministic, no warm start kept between queries; an active set passed to :meth:`solve` is checked
        with ``H⁻¹`` precomputed here, see there).

    Notes
    -----
    Variables: the interior nodes ``x = [σ_A(1..n−1), σ_B(1..n−1)]`` (the ends are the query). Objective
    ``Σ_k Σ_r (Δσ_r,k / vmax_r)² + w·Σ_k Σ_r (Δ²σ_r,k / vmax_r)²``: an elastic band (evenly spaced, pulled taut)
    with a bending term; the Hessian is positive definite and fixed, so the solution is unique and a continuous
    (piecewise affine) function of the bounds. Rows: ``σ_A,k ± σ_B,k`` of every interior node (the L1 ball is a
    box in these rotated coordinates); the route extents are bounds of the variables.
    """

    def __init__(self, n: int = CORRIDOR_SEGMENTS, vmax: ArrayLike = (0.5, 0.5), solver: str = "daqp") -> None:
        import casadi as ca

        t0 = time.perf_counter()
        self.n = n = int(n)
        if n < 3:
            raise PlanningError(f"the corridor needs at least 3 segments, got {n}")
        v = np.asarray(vmax, dtype=float)
        self.vmax = v
        d1 = np.zeros((n, n + 1))
        for k in range(n):
            d1[k, k : k + 2] = (-1.0, 1.0)
        d2 = np.zeros((n - 1, n + 1))
        for k in range(n - 1):
            d2[k, k : k + 3] = (1.0, -2.0, 1.0)
        q = 2.0 * (d1.T @ d1 + SMOOTH_WEIGHT * d2.T @ d2)  # per robot, on all nodes
        inner = slice(1, n)
        m = n - 1
        self.nx = 2 * m
        h = np.zeros((2 * m, 2 * m))
        self._g_ends = []  # per robot: (m, 2) coupling of the interior to the two ends
        for r in range(2):
            h[r * m : (r + 1) * m, r * m : (r + 1) * m] = q[inner, inner] / v[r] ** 2
            self._g_ends.append(q[inner][:, [0, n]] / v[r] ** 2)
        self.h = h
        a = np.zeros((2 * m, 2 * m))
        for k in range(m):
            a[2 * k, k], a[2 * k, m + k] = 1.0, 1.0
            a[2 * k + 1, k], a[2 * k + 1, m + k] = 1.0, -1.0
        self.a = a
        opts: dict[str, Any] = {"error_on_fail": False}
        if solver == "qpoases":
            opts.update({"printLevel": "none"})
        if solver == "daqp":
            opts.update({"daqp": {"primal_tol": 1e-12, "dual_tol": 1e-12}})
        self.solver_name = solver
        self.solver = ca.conic(f"corridor{n}", solver, {"h": ca.DM(h).sparsity(), "a": ca.DM(a).sparsity()}, opts)
        # One call per solve through a buffer: the fixed H and A are constants of a wrapping function whose one
        # input is [g, lba, uba, lbx, ubx] and one output [x, λ_A, λ_x] (numpy memory, no DM conversion per call).
        nx = self.nx
        p = ca.MX.sym("p", 5 * nx)
        g_, lba_, uba_, lbx_, ubx_ = ca.vertsplit(p, [0, nx, 2 * nx, 3 * nx, 4 * nx, 5 * nx])
        out = self.solver(h=ca.DM(h), g=g_, a=ca.DM(a), lba=lba_, uba=uba_, lbx=lbx_, ubx=ubx_)
        self._function = ca.Function(f"corridor{n}_packed", [p], [ca.vertcat(out["x"], out["lam_a"], out["lam_x"])])
        self._in = np.zeros(5 * nx)
        self._out = np.zeros(3 * nx)
        self._buffer, self._eval = self._function.buffer()
        buf: Any = self._buffer  # (CasADi's stubs ask for a size that its Python binding does not take)
        buf.set_arg(0, self._in.data)
        buf.set_res(0, self._out.data)
        self._lock = threading.Lock()
        # For a known active set (the previous solve's): all constraints as rows C = [A; I], G = C·H⁻¹, K = G·Cᵀ
        self._c = np.vstack([a, np.eye(nx)])
        self._hinv = np.linalg.inv(h)
        self._hinv = 0.5 * (self._hinv + self._hinv.T)
        self._gmat = self._c @ self._hinv
        self._k = self._gmat @ self._c.T
        # g = E·[σ_A(start), σ_A(goal), σ_B(start), σ_B(goal)]; the unconstrained solution is −H⁻¹·g
        self._e = np.zeros((nx, 4))
        self._e[:m, 0:2], self._e[m:, 2:4] = self._g_ends[0], self._g_ends[1]
        self._x_free = -(self._hinv @ self._e)
        self.build_time = time.perf_counter() - t0

    def solve(
        self,
        centers: FloatArray,
        radius: FloatArray,
        lower: FloatArray,
        upper: FloatArray,
        active: tuple[IntArray, FloatArray] | None = None,
        query: _Query | None = None,
    ) -> tuple[FloatArray, dict[str, Any]]:
        """Solve for one query.

        Parameters
        ----------
        centers : ndarray, shape (n+1, 2)
            Plan samples (route coordinates, metres); the first and last are the start and the goal.
        radius : ndarray, shape (n+1,)
            L1 radius of every node's ball (metres).
        lower, upper : ndarray, shape (2,)
            Extent of each robot's route (metres).
        active : (ndarray of int, ndarray of float), optional
            A guess of the active set (constraint rows of ``[A; I]`` and their sides, +1 upper, −1 lower), e.g.
            ``stats["active"]`` of the previous solve. If the equality-constrained solution for it satisfies
            every KKT condition (primal and dual feasibility to 1e-12, the solver's tolerances) it *is* the unique
            solution and DAQP is not called; otherwise DAQP solves the QP.
        query : optional
            :meth:`query` of the same ends and bounds, shared by the solves of one query.

        Returns
        -------
        nodes : ndarray, shape (n+1, 2)
        stats : dict
            Also ``active``: the active set of the solution (for the next solve).
        """
        n, m = self.n, self.n - 1
        t0 = time.perf_counter()
        if query is None:
            query = self.query(centers[0], centers[-1], lower, upper)
        xs, act, status, success = self._solve(query, centers, radius, active)
        elapsed = time.perf_counter() - t0
        nodes = np.empty((n + 1, 2))
        nodes[0], nodes[-1] = centers[0], centers[-1]
        nodes[1:-1, 0], nodes[1:-1, 1] = xs[:m], xs[m:]
        stats = {
            "n_segments": n,
            "qp_solver": self.solver_name,
            "qp_status": status,
            "qp_success": success,
            "qp_time": elapsed,
            "active": act,
        }
        return nodes, stats

    def query(self, start: FloatArray, goal: FloatArray, lower: FloatArray, upper: FloatArray) -> _Query:
        """What the solves of one query share: the ends, the unconstrained solution, the bound rows."""
        nx, m = self.nx, self.n - 1
        e4 = np.array([start[0], goal[0], start[1], goal[1]], dtype=float)
        lohi = np.empty(4 * nx)  # bounds of the rows of C = [A; I], lower then upper; ball rows set per solve
        lo, hi = lohi[: 2 * nx], lohi[2 * nx :]
        lo[nx : nx + m], lo[nx + m :] = lower[0], lower[1]
        hi[nx : nx + m], hi[nx + m :] = upper[0], upper[1]
        return _Query(e4, self._x_free @ e4, self._e @ e4, lo, hi, lohi, {})

    def _solve(
        self, q: _Query, centers: FloatArray, radius: FloatArray, active: tuple[IntArray, FloatArray] | None
    ) -> tuple[FloatArray, tuple[IntArray, FloatArray], str, bool]:
        """The interior nodes ``x`` (shape (nx,)), the active set, the status and success of one solve."""
        nx = self.nx
        lo, hi = q.lo, q.hi
        # ball rows of node k: σ_A ± σ_B within (P_A ± P_B) ∓ R_k, interleaved (2k: +, 2k+1: −)
        rot = centers[1:-1] @ _ROTATE  # (m, 2): [σ_A + σ_B, σ_A − σ_B] (exact: products by ±1, one sum)
        rr = radius[1:-1, None]
        np.subtract(rot, rr, out=lo[:nx].reshape(-1, 2))
        np.add(rot, rr, out=hi[:nx].reshape(-1, 2))
        if active is not None:
            known = self._known_active_set(q, active)
            if known is not None:
                return known[0], known[1], "KKT_VERIFIED", True
        with self._lock:
            buf_in = self._in
            buf_in[:nx] = q.g
            buf_in[nx : 2 * nx], buf_in[2 * nx : 3 * nx] = lo[:nx], hi[:nx]
            buf_in[3 * nx : 4 * nx], buf_in[4 * nx :] = lo[nx:], hi[nx:]
            self._eval()
            st = self._buffer.stats()
            out = self._out.copy()
        lam = out[nx:]
        w = (lam != 0.0).nonzero()[0]
        return out[:nx], (w, np.sign(lam[w])), str(st.get("return_status", "")), bool(st.get("success", False))

    def _known_active_set(
        self, q: _Query, active: tuple[IntArray, FloatArray]
    ) -> tuple[FloatArray, tuple[IntArray, FloatArray]] | None:
        """The solution and its active set if ``active``, or one of up to :data:`ACTIVE_SET_REPAIRS` repairs of
        it, is the optimal active set (all KKT conditions hold), else None.

        ``q``: the query (its bounds ``lo, hi`` of the rows ``[A; I]`` set for this solve). A repair drops the
        row whose multiplier is the most negative and adds the most violated row (a guess only: whatever set is
        tried, the answer is accepted only if every KKT condition holds, and then it is the unique solution).
        """
        with np.errstate(all="ignore"):  # a singular set gives NaN multipliers (rejected below)
            return self._repaired(q, *active)

    def _repaired(
        self, q: _Query, w: IntArray, side: FloatArray
    ) -> tuple[FloatArray, tuple[IntArray, FloatArray]] | None:
        """:meth:`_known_active_set` (within its error state)."""
        x_free, lo, hi = q.x_free, q.lo, q.hi
        for _ in range(ACTIVE_SET_REPAIRS + 1):
            x: FloatArray = x_free
            nu: FloatArray = _EMPTY
            dual: FloatArray = _EMPTY
            dmin = 0.0
            if len(w):
                key = w.tobytes() + side.tobytes()
                sub = q.sets.get(key)
                if sub is None:  # K restricted to the set, C·x_free on it, H⁻¹·C of its rows, its sides' bounds
                    sub = q.sets[key] = (
                        self._k.take(w, 0).take(w, 1),
                        self._c.take(w, 0) @ x_free,
                        self._gmat.take(w, 0),
                        w + np.where(side > 0, len(lo), 0),
                    )
                b = q.lohi.take(sub[3])
                try:
                    nu = _solve_vector(sub[0], sub[1] - b)
                except np.linalg.LinAlgError:
                    return None
                x = x_free - nu @ sub[2]
                dual = nu * side  # upper rows ν ≥ 0, lower rows ν ≤ 0
                dmin = dual.min()
            cx = self._c @ x
            up, down = cx - hi, lo - cx
            viol = np.maximum(up, down)
            j = int(viol.argmax())  # (the first NaN if any)
            if dmin >= -KKT_TOL and viol[j] <= KKT_TOL:
                return x, (w, side)  # (NaN fails both tests)
            if not np.isfinite(viol[j]):  # (cx not finite)
                return None
            # one active-set step: drop the row with the most negative multiplier, add the most violated row
            if dmin < -KKT_TOL:
                drop = int(dual.argmin())
                w = np.concatenate((w[:drop], w[drop + 1 :]))
                side = np.concatenate((side[:drop], side[drop + 1 :]))
            if viol[j] > KKT_TOL:
                w = np.concatenate((w, (j,)))
                side = np.concatenate((side, (1.0 if up[j] > down[j] else -1.0,)))
        return None


class _Query(NamedTuple):
    """Per query: ``[σ_A(start), σ_A(goal), σ_B(start), σ_B(goal)]``, the unconstrained solution, the linear term
    ``g``, the bounds of the rows ``[A; I]`` (ball rows rewritten by every solve) and the active sets' matrices."""

    e4: FloatArray
    x_free: FloatArray
    g: FloatArray
    lo: FloatArray
    hi: FloatArray
    lohi: FloatArray
    sets: dict[bytes, tuple[FloatArray, FloatArray, FloatArray, IntArray]]


def _solve_vector(k: FloatArray, r: FloatArray) -> FloatArray:
    """``K⁻¹·r`` for a vector ``r``: LAPACK's solve as :func:`numpy.linalg.solve` calls it (its gufunc, the same
    result bit for bit, without the wrapper's checks: a singular ``K`` gives NaN, or raises ``LinAlgError``
    where numpy's internal gufunc is not available)."""
    if _SOLVE1 is None:
        return np.asarray(np.linalg.solve(k, r), dtype=float)
    return np.asarray(_SOLVE1(k, r), dtype=float)


try:  # numpy's own gufunc behind numpy.linalg.solve for a vector right-hand side (numpy >= 1.8)
    from numpy.linalg import _umath_linalg

    _SOLVE1: Any = _umath_linalg.solve1
except (ImportError, AttributeError):  # pragma: no cover - another numpy layout
    _SOLVE1 = None

_ROTATE = np.array([[1.0, 1.0], [1.0, -1.0]])
_EMPTY = np.zeros(0)


def corridor_nodes(
    plan: MotionPlan, geom: RouteGeometry, separation: float, problem: CorridorProblem
) -> CorridorResult:
    """The hard path's polyline and blend radii for one plan (see the module docstring).

    Parameters
    ----------
    plan : MotionPlan
    geom : RouteGeometry
        Of the plan's routes (:attr:`trajopt.path.planview.PlanView.geom`).
    separation : float
        Separation the path keeps where the plan does (metres): the clearance plus the gate's margins.
    problem : CorridorProblem

    Returns
    -------
    CorridorResult

    Raises
    ------
    PlanningError
        The QP solver failed, or the result leaves the corridor (never expected).
    """
    t0 = time.perf_counter()
    n = problem.n
    view = plan_view(plan)
    centers = view.path_s(_unit_grid(n))
    centers[0], centers[-1] = view.waypoints[0], view.waypoints[-1]
    lower, upper = view.lower, view.upper
    t1 = time.perf_counter()
    plan_centers = centers
    query = problem.query(centers[0], centers[-1], lower, upper)
    known_sets = 0
    active: tuple[IntArray, FloatArray] | None = (np.zeros(0, np.intp), np.zeros(0))
    qp_time = 0.0
    st: dict[str, Any] = {}
    for it in range(CORRIDOR_ITERATIONS):
        free = corridor_radii(geom, centers, separation)
        if it == 0:
            min_free = float(free[1:-1].min())
        # the previous solve's active set (at first the empty set: the greedy repairs find most first active sets)
        # is tried first (exact if its KKT conditions hold, else DAQP)
        nodes, st = problem.solve(centers, free, lower, upper, active, query)
        active = st.get("active")
        qp_time += st["qp_time"]
        known_sets += st["qp_status"] == "KKT_VERIFIED"
        if not st["qp_success"]:
            raise PlanningError(f"corridor QP failed: {st['qp_status']}")
        nodes[0], nodes[-1] = centers[0], centers[-1]
        nodes = np.minimum(np.maximum(nodes, lower), upper)  # (np.clip, without its overhead)
        dev = np.abs(nodes - centers)
        excess = dev[:, 0] + dev[:, 1] - free
        if excess.max() > 1e-9:
            k = int(np.argmax(excess))
            raise PlanningError(f"corridor QP node {k} leaves its ball by {excess[k]:.3g} m")
        centers = nodes
    stats: dict[str, Any] = {"qp_known_active_sets": known_sets, "min_free": min_free}
    stats.update({k: v for k, v in st.items() if k not in ("qp_time", "active")})  # the last solve's
    stats["qp_time"] = qp_time
    v = problem.vmax
    for key, pts in (("plan_time_bound", plan_centers), ("optimized_time_bound", nodes)):
        legs = np.abs(pts[1:] - pts[:-1]) / v
        stats[key] = float(np.sum(np.maximum(legs[:, 0], legs[:, 1])))
    stats["corridor_time"] = t1 - t0
    stats["corridor_iterations"] = CORRIDOR_ITERATIONS
    return CorridorResult(nodes, plan_centers, free, stats)


@lru_cache(maxsize=8)
def _unit_grid(n: int) -> FloatArray:
    """``k/n`` for ``k = 0 … n`` (shape (n+1,); shared: never written to)."""
    u = np.linspace(0.0, 1.0, n + 1)
    u.flags.writeable = False
    return u


def hard_path_scaling(
    plan: MotionPlan,
    geom: RouteGeometry,
    separation: float,
    limits: Any,
    problem: CorridorProblem,
    timings: dict[str, Any] | None = None,
) -> tuple[Any, dict[str, Any]]:
    """Corridor QP, cubic B-spline and the filtered v/a-limited profile: the hard path's timing.

    Parameters
    ----------
    plan : MotionPlan
    geom : RouteGeometry
    separation : float
        Clearance plus the gate's margins (metres).
    limits : trajopt.timing.Limits
    problem : CorridorProblem
        Built for ``limits.v``.
    timings : dict, optional
        Filled with the stage times ``smooth``, ``blend``, ``jerk`` (s).

    Returns
    -------
    scaling : trajopt.timing.TimeScaling
    stats : dict
    """
    from trajopt.timing import filtered_scaling, spline_path

    timings = timings if timings is not None else {}
    t0 = time.perf_counter()
    res = corridor_nodes(plan, geom, separation, problem)
    t1 = time.perf_counter()
    timings["smooth"] = t1 - t0
    stats = dict(res.stats)
    path = spline_path(res.nodes)
    t2 = time.perf_counter()
    timings["blend"] = t2 - t1
    scaling = filtered_scaling(path, limits)
    timings["jerk"] = time.perf_counter() - t2
    stats.update(scaling.stats)
    return scaling, stats
