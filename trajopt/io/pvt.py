"""Position-velocity-time (PVT) tables for drives that interpolate cubically (Hermite) between rows.

A PVT drive receives rows ``(t_k, s_k, v_k)`` and moves, between two rows, along the cubic Hermite polynomial
with those end positions and velocities. :func:`pvt_table` samples a verified trajectory every ``interval``
seconds and accepts the interval only if that *reconstruction* — not the trajectory itself — keeps the clearance
and the limits (:func:`check_pvt`); the row velocities are fitted when the cubics through exact samples would
break a limit (:func:`fit_row_velocities`), :func:`largest_pvt_interval` finds the largest round interval that
passes, and ``max_stretch`` may slow the same path down. The rows, the fit, the check and the intervals are
derived in docs/pvt.md.
"""

from __future__ import annotations

import io
import math
import os
from dataclasses import dataclass
from typing import Any, SupportsFloat, SupportsIndex

import numpy as np

from mpa._arrays import FloatArray, IntArray
from mpa.errors import InvalidInputError
from mpa.plans import Plan
from trajopt.export import Trajectory, atomic_write_text
from trajopt.timing import Limits
from trajopt.verify.gate import LIMIT_RTOL, VerificationReport, verify_setpoints
from trajopt.verify.rows import Setpoints

__all__ = [
    "AUTO",
    "PVT_COLUMNS",
    "PVTCheck",
    "PVTTable",
    "check_pvt",
    "fit_row_velocities",
    "hermite_eval",
    "largest_pvt_interval",
    "pvt_knots",
    "pvt_rows",
    "pvt_table",
    "smallest_pvt_stretch",
    "time_text",
    "write_pvt",
]

#: Columns of the PVT file.
PVT_COLUMNS = ("time", "a_s", "a_v", "b_s", "b_v")
#: Default interval (s); the largest ``"auto"`` takes.
DEFAULT_INTERVAL = 0.1
#: The interval value that asks for the largest round interval that works (:func:`pvt_table`).
AUTO = "auto"
#: Smallest interval tried by :func:`largest_pvt_interval` (s).
MIN_INTERVAL = 1e-3
#: Smallest dense-grid rate of the check (Hz).
DENSE_RATE = 1000.0
#: Time-stretch factors tried, in order (see :func:`pvt_table`).
STRETCHES = (1.0, 1.001, 1.002, 1.005, 1.01, 1.02, 1.05, 1.1, 1.2, 1.5, 2.0)


@dataclass(frozen=True)
class PVTTable:
    """Rows of a PVT table. ``t`` shape (M,) s; ``s``, ``v`` shape (M, 2) m, m/s (column 0 = robot A)."""

    t: FloatArray
    s: FloatArray
    v: FloatArray
    interval: float
    stretch: float = 1.0
    """Time-stretch factor k >= 1: the rows sample ``s(t/k)`` (the same path, k times slower)."""
    velocity_change: float = 0.0
    """Largest change (m/s) of a row velocity from the motion's made by :func:`fit_row_velocities` (0: the rows
    are exact samples)."""

    @property
    def motion_time(self) -> float:
        """Time of the last row (s)."""
        return float(self.t[-1])

    def csv_text(self) -> str:
        """The file's content: header ``time,a_s,a_v,b_s,b_v``; times as the shortest decimals that read back
        exactly (:func:`time_text`: ``0.3``, not ``0.30000000000000004``), the rest 12 significant digits."""
        buf = io.StringIO()
        buf.write(",".join(PVT_COLUMNS) + "\n")
        data = np.column_stack([self.s[:, 0], self.v[:, 0], self.s[:, 1], self.v[:, 1]])
        cols = [np.char.mod("%.12g", data[:, i]).astype(object) for i in range(4)]
        rows = np.asarray(time_text(self.t), dtype=object)
        for c in cols:
            rows = rows + "," + c
        if len(rows):
            buf.write("\n".join(rows.tolist()) + "\n")
        return buf.getvalue()


@dataclass(frozen=True)
class PVTCheck:
    """Outcome of :func:`check_pvt`.

    Attributes
    ----------
    ok : bool
    failures : tuple of str
        Limit failures of the pieces, then the gate's failures.
    peak_ratio : dict
        ``{"v": (A, B), "a": …, "j": …}``: largest ``|value| / limit`` of the reconstruction per robot.
    report : VerificationReport
        The gate's report on the dense grid.
    dense_rate : float
        Rate of the dense grid (Hz).
    """

    ok: bool
    failures: tuple[str, ...]
    peak_ratio: dict[str, tuple[float, float]]
    report: VerificationReport
    dense_rate: float


def time_text(t: Any) -> list[str]:
    """Times (s, shape (M,)) as the shortest decimals that read back to the same floats (no exponent): the row
    times ``k·Δ`` of :func:`pvt_knots` print as the decimal the step names (``0.3``, never
    ``0.30000000000000004``)."""
    return [np.format_float_positional(x, unique=True, trim="-") for x in np.asarray(t, dtype=float)]


def _to_float(x: object) -> float:
    """``float(x)`` for any object: TypeError or ValueError if it is no number."""
    if not isinstance(x, (SupportsFloat, SupportsIndex, str)):
        raise TypeError(f"{type(x).__name__} is not a number")
    return float(x)


def validate_interval(interval: object) -> float:
    """Validate a PVT interval: a finite number >= :data:`MIN_INTERVAL` (s).

    Raises
    ------
    InvalidInputError
    """
    try:
        d = _to_float(interval)
    except (TypeError, ValueError):
        raise InvalidInputError(
            f"PVT interval is {interval!r}, expected a number of seconds >= {MIN_INTERVAL:g}"
        ) from None
    if not math.isfinite(d) or d < MIN_INTERVAL:
        raise InvalidInputError(f"PVT interval is {d!r} s, expected a finite number >= {MIN_INTERVAL:g} s")
    return d


def pvt_knots(motion_time: float, interval: float) -> FloatArray:
    """Row times: ``k·Δ`` below ``T − Δ/100``, then ``T`` (see the module docstring). Shape (M,).

    ``k·Δ`` is rounded to 12 decimals (the float nearest the decimal multiple: ``3 × 0.1`` is 0.3, not
    0.30000000000000004), so the rows print as the multiples they are."""
    if motion_time <= 0:
        return np.zeros(1)
    k = np.arange(int(np.ceil(motion_time / interval)) + 1)
    t = np.round(k * interval, 12)
    t = t[t < motion_time - interval / 100.0]
    return np.append(t, motion_time)


def _coefficients(t: FloatArray, s: FloatArray, v: FloatArray) -> tuple[FloatArray, FloatArray, FloatArray]:
    h = np.diff(t)[:, None]
    ds = np.diff(s, axis=0)
    c2 = (3.0 * ds / h - 2.0 * v[:-1] - v[1:]) / h
    c3 = (v[:-1] + v[1:] - 2.0 * ds / h) / (h * h)
    return h, c2, c3


def hermite_eval(
    t_rows: FloatArray, s_rows: FloatArray, v_rows: FloatArray, tq: FloatArray
) -> tuple[FloatArray, FloatArray, FloatArray, FloatArray]:
    """The cubic Hermite reconstruction at times ``tq``: ``s, v, a, j``, each shape (len(tq), 2).

    Right-continuous at the rows (``a`` and ``j`` of the piece that starts there); before the first row and
    after the last the robots rest at the first/last row (``v = a = j = 0``).
    """
    tq = np.asarray(tq, dtype=float)
    n = len(tq)
    if len(t_rows) < 2:
        z = np.zeros((n, 2))
        return np.broadcast_to(s_rows[0], (n, 2)).copy(), z, z.copy(), z.copy()
    _h, c2, c3 = _coefficients(t_rows, s_rows, v_rows)
    k = np.clip(np.searchsorted(t_rows, tq, side="right") - 1, 0, len(t_rows) - 2)
    tau = (tq - t_rows[k])[:, None]
    c0, c1, q2, q3 = s_rows[k], v_rows[k], c2[k], c3[k]
    s = c0 + tau * (c1 + tau * (q2 + tau * q3))
    v = c1 + tau * (2.0 * q2 + 3.0 * tau * q3)
    a = 2.0 * q2 + 6.0 * q3 * tau
    j = np.broadcast_to(6.0 * q3, s.shape).copy()
    after = tq >= t_rows[-1]
    s[after] = s_rows[-1]
    v[after], a[after], j[after] = 0.0, 0.0, 0.0
    before = tq < t_rows[0]
    s[before] = s_rows[0]
    v[before], a[before], j[before] = 0.0, 0.0, 0.0
    return s, v, a, j


#: Factor on each limit in :func:`fit_row_velocities`: a motion may touch its limits (a cruise at ``vmax``
#: makes the mean velocity of a piece ``vmax``), and this plus the LP solver's feasibility tolerance (1e-7,
#: limits scaled to 1) stays inside :data:`trajopt.verify.gate.LIMIT_RTOL`.
FIT_SHARE = 1.0 + 1e-7
#: Rounds of velocity cuts added at the pieces' velocity vertices (:func:`fit_row_velocities`).
FIT_ROUNDS = 12


def fit_row_velocities(
    t: FloatArray, s: FloatArray, v: FloatArray, vmax: float, amax: float, jmax: float
) -> FloatArray | None:
    """Row velocities, closest in L1 to ``v``, whose Hermite cubics keep the limits, positions ``s`` fixed.

    Between two rows a PVT drive follows the cubic with the rows' positions and velocities. Through *exact*
    samples of a jerk-limited motion that uses its acceleration limit, that cubic overshoots it wherever a jerk
    phase begins inside a piece (its acceleration is linear, the motion's is not): by about ``jmax·Δ/7``, so no
    interval down to 1 ms keeps ``amax``. With the positions kept, the velocities at the inner rows are free;
    this solves the linear program

        minimise   Σ_k |w_k − v_k|
        subject to |a| ≤ amax at both ends of every piece (a is linear on a piece), |6·c3| ≤ jmax,
                   |w_k| ≤ vmax, the cubic's velocity ≤ vmax inside each piece (cuts at τ/h = 1/4, 1/2, 3/4,
                   then at and around each violated vertex, up to :data:`FIT_ROUNDS` rounds),

    with the first and last velocities fixed (at rest, or the state a re-plan starts from).

    Parameters
    ----------
    t : ndarray, shape (M,)
        Row times (s), increasing.
    s, v : ndarray, shape (M,)
        One robot's row positions (m) and the motion's velocities there (m/s).
    vmax, amax, jmax : float
        The robot's limits (m/s, m/s², m/s³).

    Returns
    -------
    ndarray, shape (M,) or None
        The velocities (m/s), or None when the program is infeasible or its solution still breaks a limit.
    """
    from scipy.optimize import linprog
    from scipy.sparse import coo_matrix, vstack

    m = len(t)
    if m < 3:
        return None
    h = np.diff(t)
    d = np.diff(s) / h
    k = np.arange(m - 1)
    vl, al, jl = vmax * FIT_SHARE, amax * FIT_SHARE, jmax * FIT_SHARE
    rows: list[tuple[FloatArray, FloatArray, FloatArray, IntArray]] = []  # (coef_k, coef_k1, rhs, piece index)
    # a at the piece's start (6d - 4w_k - 2w_k+1)/h and end (-6d + 2w_k + 4w_k+1)/h, each within ±amax, in amax units
    for ck, ck1, cd in ((-4.0, -2.0, 6.0), (2.0, 4.0, -6.0)):
        for sign in (1.0, -1.0):
            rows.append((sign * ck / (h * al), sign * ck1 / (h * al), 1.0 - sign * cd * d / (h * al), k))
    # jerk 6(w_k + w_k+1 - 2d)/h² within ±jmax, in jmax units
    for sign in (1.0, -1.0):
        g = 6.0 / (h * h * jl)
        rows.append((sign * g, sign * g, 1.0 + sign * 2.0 * d * g, k))

    def vel_rows(u: FloatArray, idx: IntArray) -> list[tuple[FloatArray, FloatArray, FloatArray, IntArray]]:
        bk, bk1, bd = 1.0 - 4.0 * u + 3.0 * u * u, -2.0 * u + 3.0 * u * u, 6.0 * u - 6.0 * u * u
        dd = d[idx]
        return [(sg * bk / vl, sg * bk1 / vl, 1.0 - sg * bd * dd / vl, idx) for sg in (1.0, -1.0)]

    for u in (0.25, 0.5, 0.75):
        rows += vel_rows(np.full(m - 1, u), k)
    bounds = np.column_stack([np.full(m, -vl), np.full(m, vl)])
    bounds[0] = v[0]
    bounds[-1] = v[-1]
    w = v.copy()
    for _ in range(FIT_ROUNDS):
        coef_k = np.concatenate([r[0] for r in rows])
        coef_k1 = np.concatenate([r[1] for r in rows])
        rhs = np.concatenate([r[2] for r in rows])
        piece = np.concatenate([r[3] for r in rows])
        nr = len(rhs)
        # variables: w (m), e (m) with e >= |w - v|
        ri = np.concatenate([np.arange(nr), np.arange(nr)])
        ci = np.concatenate([piece, piece + 1])
        a_ub = coo_matrix((np.concatenate([coef_k, coef_k1]), (ri, ci)), shape=(nr, 2 * m))
        eye = np.arange(m)
        dev = coo_matrix(
            (
                np.concatenate([np.ones(m), -np.ones(m), -np.ones(m), -np.ones(m)]),
                (np.concatenate([eye, eye, eye + m, eye + m]), np.concatenate([eye, eye + m, eye, eye + m])),
            ),
            shape=(2 * m, 2 * m),
        )
        a_all = vstack([a_ub, dev]).tocsr()
        b_all = np.concatenate([rhs, v, -v])
        cost = np.concatenate([np.zeros(m), np.ones(m)])
        bnd = np.vstack([bounds, np.column_stack([np.zeros(m), np.full(m, np.inf)])])
        res = linprog(cost, A_ub=a_all, b_ub=b_all, bounds=bnd, method="highs")
        if res.status != 0:
            return None
        w = np.asarray(res.x[:m], dtype=float)
        w[0], w[-1] = v[0], v[-1]
        c2 = (3.0 * d - 2.0 * w[:-1] - w[1:]) / h
        c3 = (w[:-1] + w[1:] - 2.0 * d) / (h * h)
        tau = np.where(c3 != 0, -c2 / np.where(c3 != 0, 3.0 * c3, 1.0), -1.0)
        inside = (tau > 0) & (tau < h)
        vv = np.where(inside, w[:-1] + tau * (2.0 * c2 + 3.0 * tau * c3), 0.0)
        bad = np.nonzero(inside & (np.abs(vv) > vmax * (1.0 + LIMIT_RTOL / 4)))[0]
        if not len(bad):
            return w
        for du in (0.0, -1 / 64, 1 / 64, -1 / 16, 1 / 16):
            rows += vel_rows(np.clip(tau[bad] / h[bad] + du, 0.0, 1.0), bad)
    return None


def pvt_rows(trajectory: Trajectory, interval: float, stretch: float = 1.0, *, fit: bool = True) -> PVTTable:
    """The PVT rows at ``interval`` (s) of the motion stretched ``stretch`` times, *unchecked* (see
    :func:`pvt_table`). Row times :func:`pvt_knots`; first row ``s = 0``, last the goal; both ``v = 0``
    (the first row keeps its velocity if the trajectory starts moving: a re-plan, :mod:`trajopt.replan`).
    With ``fit`` (the default) a robot whose cubics through the exact samples break a limit gets the row
    velocities of :func:`fit_row_velocities` when that program has a solution; ``fit=False``: exact samples."""
    t = pvt_knots(trajectory.motion_time * stretch, interval)
    s, v, _a, _j = trajectory.sampler(np.minimum(t / stretch, trajectory.motion_time))
    s, v = np.array(s, dtype=float), np.array(v, dtype=float) / stretch
    if not _starts_moving(trajectory):
        v[0] = 0.0
    v[-1] = 0.0
    s[0] = 0.0
    s[-1] = trajectory.s[-1]
    tab = PVTTable(t=t, s=s, v=v, interval=interval, stretch=stretch)
    lim = trajectory.limits
    vmax, amax, jmax = _piece_peaks(tab)
    change = 0.0
    for r in (0, 1) if fit else ():
        limits = (lim.v[r], lim.a[r], lim.j[r])
        if all(val <= limit * (1 + LIMIT_RTOL / 2) for val, limit in zip((vmax[r], amax[r], jmax[r]), limits)):
            continue
        w = fit_row_velocities(t, s[:, r], v[:, r], *limits)
        if w is not None:
            change = max(change, float(np.max(np.abs(w - v[:, r]))))
            v[:, r] = w
    return PVTTable(t=t, s=s, v=v, interval=interval, stretch=stretch, velocity_change=change)


def check_pvt(trajectory: Trajectory, interval: float = DEFAULT_INTERVAL, stretch: float = 1.0) -> PVTCheck:
    """Check the Hermite reconstruction of the PVT rows at ``interval`` (see the module docstring).

    Parameters
    ----------
    trajectory : Trajectory
    interval : float
        Row interval Δ (s).
    stretch : float
        Time-stretch factor k >= 1 of the sampled motion.

    Raises
    ------
    InvalidInputError
        ``interval`` not a finite number >= 1 ms, ``stretch`` not a finite number >= 1.
    """
    dlt = validate_interval(interval)
    k_st = _validate_stretch(stretch)
    tab = pvt_rows(trajectory, dlt, k_st)
    peak, fails = _piece_limit_check(tab, trajectory.limits)
    # the gate on a dense grid of the reconstruction
    tg, rate = _dense_grid(tab, dlt)
    s, v, _a, _j = hermite_eval(tab.t, tab.s, tab.v, tg)
    a_rows, j_rows = _grid_row_peaks(tab, tg)
    rep, gate_fails = _gate_on_reconstruction(trajectory, tg, (s, v, a_rows, j_rows), rate)
    fails += gate_fails
    return PVTCheck(not fails, tuple(fails), peak, rep, rate)


def _piece_limit_check(tab: PVTTable, lim: Limits) -> tuple[dict[str, tuple[float, float]], list[str]]:
    """Peak ``|v|, |a|, |j|`` of the cubic pieces over the limits per robot, and the failures above them."""
    vmax, amax, jmax = _piece_peaks(tab)
    fails: list[str] = []
    peak: dict[str, tuple[float, float]] = {}
    for name, val, limit in (("v", vmax, lim.v), ("a", amax, lim.a), ("j", jmax, lim.j)):
        ratio = val / limit
        peak[name] = (float(ratio[0]), float(ratio[1]))
        for r in (0, 1):
            if ratio[r] > 1 + LIMIT_RTOL:
                fails.append(f"|{name}| of robot {'AB'[r]}'s cubic pieces reaches {val[r]:.9g}, limit {limit[r]:g}")
    return peak, fails


def _dense_grid(tab: PVTTable, dlt: float) -> tuple[FloatArray, float]:
    """The dense grid the gate checks the reconstruction on: times (s, shape (n,)) at ``m/Δ`` Hz, ``m >= 8`` rows
    per PVT interval and at least :data:`DENSE_RATE`, and that rate (Hz)."""
    m = max(8, math.ceil(dlt * DENSE_RATE - 1e-9))
    rate = m / dlt
    n = int(np.ceil(tab.motion_time * rate - 1e-9)) + 1 if tab.motion_time > 0 else 1
    return np.arange(n) / rate, rate


def _gate_on_reconstruction(
    trajectory: Trajectory,
    tg: FloatArray,
    svaj: tuple[FloatArray, FloatArray, FloatArray, FloatArray],
    rate: float,
) -> tuple[VerificationReport, list[str]]:
    """The gate on the reconstruction's dense rows ``svaj`` (``a, j``: the grid rows' piece peaks) and the failures
    it adds to the piece checks (its per-row limit messages repeat them; a re-plan starts moving by design)."""
    s, v, a_rows, j_rows = svaj
    lim = trajectory.limits
    plan = trajectory.plan
    if not isinstance(plan, Plan):  # a graph plan: the gate in positions on the layout (exact graph distance)
        from trajopt.path.planview import plan_view

        rows = Setpoints(tg, s, v, a_rows, j_rows)
        rep = plan_view(plan).verify(rows, limits=lim, clearance=trajectory.clearance, rate=rate)
        moving = _starts_moving(trajectory)
        return rep, [
            f
            for f in rep.failures
            if (not f.startswith("row ") or "separation" in f)
            and not (moving and f.startswith("first row is not at rest"))
        ]
    routes = plan.routes
    tr = np.stack([routes[0].position(s[:, 0]), routes[1].position(s[:, 1])], axis=1)
    tr[0], tr[-1] = plan.start, plan.goal
    rep = verify_setpoints(
        plan.track,
        routes,
        Setpoints(tg, s, v, a_rows, j_rows, track=tr),
        limits=lim,
        clearance=trajectory.clearance,
        start=plan.start,
        goal=plan.goal,
        word=trajectory.word,
        rate=rate,
    )
    moving = _starts_moving(trajectory)
    return rep, [
        f
        for f in rep.failures
        if (not f.startswith("row ") or "separation" in f) and not (moving and f.startswith("first row is not at rest"))
    ]


def _starts_moving(trajectory: Trajectory) -> bool:
    """Whether the trajectory's first row is in motion (a re-plan from a moving state)."""
    return bool(np.any(trajectory.v[0] != 0.0) or np.any(trajectory.a[0] != 0.0))


def _piece_peaks(tab: PVTTable) -> tuple[FloatArray, FloatArray, FloatArray]:
    """Largest |v|, |a|, |j| per cart (each shape (2,)) over the cubic pieces between the rows, exactly."""
    if len(tab.t) < 2:
        return np.zeros(2), np.zeros(2), np.zeros(2)
    h, c2, c3 = _coefficients(tab.t, tab.s, tab.v)
    v0, v1 = tab.v[:-1], tab.v[1:]
    tau = np.where(c3 != 0, -c2 / np.where(c3 != 0, 3.0 * c3, 1.0), 0.0)
    inside = (tau > 0) & (tau < h)
    v_vertex = np.where(inside, v0 + tau * (2.0 * c2 + 3.0 * tau * c3), 0.0)
    vmax = np.max(np.abs(np.concatenate([v0, v1, v_vertex])), axis=0)
    amax = np.max(np.abs(np.concatenate([2.0 * c2, 2.0 * c2 + 6.0 * c3 * h])), axis=0)
    jmax = np.max(np.abs(6.0 * c3), axis=0)
    return vmax, amax, jmax


def _grid_row_peaks(tab: PVTTable, tg: FloatArray) -> tuple[FloatArray, FloatArray]:
    """Per row of the dense grid ``tg`` (shape (n,)): the largest |a| and |j| of the reconstruction over the grid
    steps next to the row (a is linear on each piece; the only PVT row inside a step is the last one).
    Each shape (n, 2)."""
    n = len(tg)
    a_rows = np.zeros((n, 2))
    j_rows = np.zeros((n, 2))
    if n < 2:
        return a_rows, j_rows
    s_end = np.minimum(tg[1:], tab.t[-1])
    k = np.clip(np.searchsorted(tab.t, tg[:-1], side="right") - 1, 0, max(len(tab.t) - 2, 0))
    if len(tab.t) >= 2:
        _h, c2, c3 = _coefficients(tab.t, tab.s, tab.v)
        tau0 = (tg[:-1] - tab.t[k])[:, None]
        tau1 = np.maximum(s_end - tab.t[k], 0.0)[:, None]
        a0 = np.abs(2.0 * c2[k] + 6.0 * c3[k] * tau0)
        a1 = np.abs(2.0 * c2[k] + 6.0 * c3[k] * tau1)
        step_a = np.maximum(a0, a1)
        step_j = np.abs(6.0 * c3[k])
        moving = (tg[:-1] < tab.t[-1])[:, None]
        step_a = np.where(moving, step_a, 0.0)
        step_j = np.where(moving, step_j, 0.0)
    else:
        step_a = step_j = np.zeros((n - 1, 2))
    a_rows[1:-1] = np.maximum(step_a[:-1], step_a[1:])
    j_rows[1:-1] = np.maximum(step_j[:-1], step_j[1:])
    j_rows[0], j_rows[-1] = step_j[0], step_j[-1]
    return a_rows, j_rows


def _validate_stretch(stretch: object, name: str = "stretch") -> float:
    try:
        k = _to_float(stretch)
    except (TypeError, ValueError):
        raise InvalidInputError(f"PVT {name} is {stretch!r}, expected a finite number >= 1") from None
    if not math.isfinite(k) or k < 1.0:
        raise InvalidInputError(f"PVT {name} is {k!r}, expected a finite number >= 1")
    return k


#: Mantissas of the round intervals tried by :func:`largest_pvt_interval` (1, 2, 2.5, 4, 5, 8 per decade).
ROUND_MANTISSAS = (8.0, 5.0, 4.0, 2.5, 2.0, 1.0)


def _series(upto: float) -> list[float]:
    out: list[float] = []
    for e in range(3, -4, -1):
        for m in ROUND_MANTISSAS:
            x = m * 10.0**e
            if MIN_INTERVAL - 1e-12 <= x <= upto + 1e-12:
                out.append(round(x, 6))
    return out


def largest_pvt_interval(trajectory: Trajectory, upto: float = DEFAULT_INTERVAL, stretch: float = 1.0) -> float | None:
    """The largest round interval (mantissas :data:`ROUND_MANTISSAS`: …, 0.1, 0.08, 0.05, 0.04, 0.025, 0.02,
    0.01, …, 1 ms) not above ``upto`` that passes :func:`check_pvt` (at time-stretch ``stretch``), or None if none
    does."""
    for x in _series(validate_interval(upto)):
        if check_pvt(trajectory, x, stretch).ok:
            return x
    return None


def smallest_pvt_stretch(trajectory: Trajectory, interval: float, max_stretch: float = 2.0) -> float | None:
    """The smallest factor of :data:`STRETCHES` not above ``max_stretch`` with which ``interval`` passes, or None."""
    cap = _validate_stretch(max_stretch, "max_stretch")
    for k in STRETCHES:
        if k <= cap * (1 + 1e-12) and check_pvt(trajectory, interval, k).ok:
            return k
    return None


def pvt_table(
    trajectory: Trajectory, interval: float | str = DEFAULT_INTERVAL, *, max_stretch: float = 1.0
) -> PVTTable:
    """The PVT rows of ``trajectory`` every ``interval`` seconds, if their Hermite reconstruction passes.

    Parameters
    ----------
    trajectory : Trajectory
    interval : float or "auto"
        Row interval Δ (s), >= 1 ms; ``"auto"``: the largest round interval <= :data:`DEFAULT_INTERVAL` that
        passes (:func:`largest_pvt_interval`; if none down to 1 ms does, :data:`DEFAULT_INTERVAL` with the
        stretch allowed by ``max_stretch``, else the error).
    max_stretch : float
        Largest time-stretch factor allowed (>= 1; 1 = the motion as it is). When the motion itself fails, the
        smallest factor of :data:`STRETCHES` up to this one that passes is used (``PVTTable.stretch``): the same
        path, ``k`` times slower, so velocities scale by 1/k, accelerations 1/k², jerks 1/k³.

    Raises
    ------
    InvalidInputError
        ``interval`` is not a number >= 1 ms, or its reconstruction breaks the clearance or a limit; the
        message names the failed check, the largest interval of the 1-2-5 series that works and the smallest
        stretch factor that makes ``interval`` work.

    Examples
    --------
    >>> from mpa import Lollipop
    >>> from trajopt import generate_trajectory
    >>> tab = pvt_table(generate_trajectory(Lollipop(1.0, 1.0), (0.1, 0.6), (0.8, 0.3)), 0.1)
    >>> float(tab.t[1]), bool(tab.v[-1, 0] == 0.0), tab.stretch
    (0.1, True, 1.0)
    """
    if isinstance(interval, str) and interval.strip().lower() == AUTO:
        best = largest_pvt_interval(trajectory, DEFAULT_INTERVAL)
        if best is not None:
            return pvt_rows(trajectory, best)
        cap = _validate_stretch(max_stretch, "max_stretch")
        k = smallest_pvt_stretch(trajectory, DEFAULT_INTERVAL, cap) if cap > 1.0 else None
        if k is not None:
            return pvt_rows(trajectory, DEFAULT_INTERVAL, k)
        chk = check_pvt(trajectory, DEFAULT_INTERVAL)
        k2 = smallest_pvt_stretch(trajectory, DEFAULT_INTERVAL, STRETCHES[-1])
        hint = (
            f"; {DEFAULT_INTERVAL:g} s works with the motion slowed by a factor {k2:g} (max_stretch / --pvt-stretch)"
            if k2 is not None
            else ""
        )
        raise InvalidInputError(
            f"PVT interval auto: no interval from {DEFAULT_INTERVAL:g} s down to {MIN_INTERVAL:g} s keeps the "
            f"clearance and limits in the cubic reconstruction (at {DEFAULT_INTERVAL:g} s: {chk.failures[0]}), "
            f"expected a motion a PVT drive can follow{hint}"
        )
    dlt = validate_interval(interval)
    cap = _validate_stretch(max_stretch, "max_stretch")
    chk = check_pvt(trajectory, dlt)
    if chk.ok:
        return pvt_rows(trajectory, dlt)
    k = smallest_pvt_stretch(trajectory, dlt, cap) if cap > 1.0 else None
    if k is not None:
        return pvt_rows(trajectory, dlt, k)
    best = largest_pvt_interval(trajectory, dlt)
    hint = f"the largest interval that works is {best:g} s" if best is not None else "no interval >= 1 ms works"
    k2 = smallest_pvt_stretch(trajectory, dlt, STRETCHES[-1])
    if k2 is not None:
        hint += f"; {dlt:g} s works with the motion slowed by a factor {k2:g} (max_stretch / --pvt-stretch)"
    raise InvalidInputError(
        f"PVT interval {dlt:g} s: the cubic reconstruction fails ({chk.failures[0]}), expected an interval "
        f"whose reconstruction keeps the clearance and limits; {hint}"
    )


def write_pvt(
    trajectory: Trajectory,
    path: str | os.PathLike[str],
    interval: float | str = DEFAULT_INTERVAL,
    *,
    max_stretch: float = 1.0,
) -> PVTTable:
    """Check and write the PVT table as CSV (atomically). Returns the table.

    Raises
    ------
    InvalidInputError
        See :func:`pvt_table`; nothing is written.
    """
    tab = pvt_table(trajectory, interval, max_stretch=max_stretch)
    atomic_write_text(path, tab.csv_text())
    return tab
