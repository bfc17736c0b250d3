"""The hard path's timing: :func:`filtered_scaling`, a v/a-limited profile under eroded per-piece limits,
box-filtered so that the jerk is bounded and the timing depends continuously on the path.
"""

from __future__ import annotations

import time

import numpy as np

from mpa._arrays import FloatArray
from trajopt.timing.curves import (
    BlendedPath,
)
from trajopt.timing.filters import (
    _box_filtered,
    _constant_acceleration_phases,
    _opening,
    _topp_passes,
    _window_min,
)
from trajopt.timing.limits import Limits, PieceLimits, piece_limits
from trajopt.timing.scaling import TimeScaling


def filtered_scaling(
    path: BlendedPath, limits: Limits, per_interval: int = 4, safety: float = 1.0 - 1e-9
) -> TimeScaling:
    """A jerk-limited timing of ``path`` that depends continuously on the path: a v/a-limited profile, box-filtered.

    1. Per-piece 1-DoF limits ``(v_k, a_k, j_k)`` of the path parameter (:func:`piece_limits`).
    2. Filter width ``τ = max_r A_r / J_r`` (the robots' limits), ``a_k ← min(a_k, τ·j_k)`` and reach
       ``Δ = τ·max_k v_k``; the limits are *eroded*: at ``s`` the minimum over the pieces within ``[s − Δ, s + Δ]``.
    3. The time-optimal v/a-limited profile with the eroded limits (forward and backward pass on ``ṡ²``, exact
       on a grid that subdivides, ``per_interval`` times, the intervals between the points ``breaks ± Δ`` and
       ``breaks``; a fixed count, and the eroded limits are constant on every interval); then every speed peak is
       flattened into a plateau at least ``τ`` long (a morphological opening of ``ṡ²``, then the passes again), so
       the acceleration never swings from ``+a`` to ``−a`` within ``τ`` (valleys are flat already: the eroded
       limits are constant over ``2Δ``).
    4. ``s̃(t) = (1/τ)∫_{t−τ}^{t} s``: the filtered ``ṡ, s̈`` are averages of the input's over a window in which the
       input stays within ``Δ`` of ``s̃``, so they keep the limits of the piece under ``s̃``; the jerk
       ``(s̈(t) − s̈(t−τ))/τ`` is at most ``a/τ ≤ j``. Rest to rest, duration ``T + τ``.

    Every step is a continuous function of the path's pieces (fixed structure), unlike a per-piece chain whose
    boundaries are passed at zero acceleration. On a long straight line it is the optimal single profile
    (trapezoidal acceleration); on a short one (no cruise) the plateau costs a little. The verification gate
    re-checks every limit.

    Returns
    -------
    TimeScaling
        Phases of constant jerk (``piece`` empty: the path is evaluated by ``s``).
    """
    t_start = time.perf_counter()
    P = len(path.coef)
    S = path.length
    if S <= 0:
        return TimeScaling(path, np.zeros(0), np.zeros(0), np.zeros(0), np.zeros(0), np.zeros(0), 0.0, np.zeros(P + 1))
    pl = piece_limits(path, limits, safety)
    br = path.breaks
    tau = float((limits.a / limits.j).max())
    reach = tau * float(pl.v.max())
    grid, b, sq, dt = _eroded_flat_top_profile(path, pl, tau, reach, int(per_interval))
    phases = _constant_acceleration_phases(grid, b, sq, dt)
    T = phases.duration
    t0, p_out, v_out, a_out, j_out = _box_filtered(phases, tau, S)
    stats = {
        "pieces": P,
        "blends": int(path.is_blend.sum()),
        "filter_width": tau,
        "input_duration": T,
        "grid": len(grid),
        "jerk_time": time.perf_counter() - t_start,
    }
    return TimeScaling(
        path,
        t0,
        p_out,
        v_out,
        a_out,
        j_out,
        float(T + tau),
        np.interp(br, grid, np.sqrt(b)),
        np.zeros(0, dtype=np.intp),
        stats,
    )


def _eroded_flat_top_profile(
    path: BlendedPath, pl: PieceLimits, tau: float, reach: float, per_interval: int, ends_once: bool = True
) -> tuple[FloatArray, FloatArray, FloatArray, FloatArray]:
    """Steps 2 and 3 of :func:`filtered_scaling`: the grid of path lengths (shape (G,)) and ``ṡ²`` on it (shape
    (G,), >= 0) of the time-optimal v/a-limited profile under the eroded limits, with flattened speed peaks; also
    ``ṡ`` (shape (G,)) and the duration of every grid interval (shape (G−1,)). ``ends_once``: the points clipped
    to the ends are merged (the same profile on fewer grid points; False for the full grid, for tests)."""
    S = path.length
    br = path.breaks
    a_lim = np.minimum(pl.a, tau * pl.j)
    pts = np.minimum(np.maximum(np.concatenate([br, br - reach, br + reach]), 0.0), S)  # (np.clip is slow)
    pts.sort()
    m = per_interval
    # The points clipped to 0 and S repeat the path's ends, where ṡ = 0 (stops): their zero-length intervals
    # change nothing but cost grid points; one copy of each end is kept (the durations' sum still adds their zeros,
    # so that it is rounded as on the full grid).
    pad0 = padS = 0
    if ends_once and path.stop[0] and path.stop[-1]:
        z0, zS = int(pts.searchsorted(0.0, "right")), len(pts) - int(pts.searchsorted(S, "left"))
        if z0 > 1 or zS > 1:
            pts = pts[max(z0, 1) - 1 : len(pts) - max(zS, 1) + 1]
            pad0, padS = (max(z0, 1) - 1) * m, (max(zS, 1) - 1) * m
    frac = np.arange(m) / m
    grid = np.concatenate([(pts[:-1, None] + frac[None, :] * (pts[1:] - pts[:-1])[:, None]).ravel(), pts[-1:]])
    ds = grid[1:] - grid[:-1]
    mid = 0.5 * (grid[:-1] + grid[1:])
    v_int, a_int = _window_min(np.stack([pl.v, a_lim]), br, mid - reach, mid + reach)
    cap = np.empty(len(grid))
    cap[0], cap[-1] = 0.0, 0.0
    cap[1:-1] = np.minimum(v_int[:-1], v_int[1:]) ** 2
    stops = br[path.stop]
    if len(stops) <= 4:  # (the spline's two ends; np.isin is slow)
        for stop in stops.tolist():
            cap[grid == stop] = 0.0
    else:
        cap[np.isin(grid, stops)] = 0.0
    two_a_ds = 2.0 * a_int * ds
    b0 = _topp_passes(cap, two_a_ds)
    ds_max = max(float(ds.max()), 0.0) if len(ds) else 0.0

    def flat_tops(c: float) -> tuple[FloatArray, float, FloatArray, FloatArray]:
        """Speeds capped at ``c`` with every speed peak a plateau at least τ long (an opening of ``ṡ²`` over ±r,
        ``r = c·τ/2`` plus the grid step), so the input's acceleration never swings from +a to −a within τ;
        ``ṡ²`` on the grid and the duration (inf where the profile is stuck at zero speed)."""
        capped = np.minimum(b0, c * c)
        bb = _topp_passes(np.minimum(capped, _opening(grid, capped, 0.5 * tau * c + ds_max)), two_a_ds)  # (>= 0)
        sq = np.sqrt(bb)
        with np.errstate(divide="ignore", invalid="ignore"):
            dt = np.where(ds > 0, 2.0 * ds / (sq[:-1] + sq[1:]), 0.0)
        total = dt.sum() if pad0 + padS == 0 else np.concatenate((np.zeros(pad0), dt, np.zeros(padS))).sum()
        return bb, float(total), sq, dt

    vpeak = reach / tau if tau > 0 else float(np.max(pl.v))
    b, total, sq, dt = flat_tops(vpeak)
    if not np.isfinite(total):
        # a path too short for plateaus at full speed (τ·vmax beyond its length): the plateau speed that
        # minimises the duration (golden section on a fixed bracket and count: continuous in the path)
        lo, hi = 0.0, vpeak
        g = (np.sqrt(5.0) - 1.0) / 2.0
        x1, x2 = hi - g * (hi - lo), lo + g * (hi - lo)
        f1, f2 = flat_tops(x1)[1], flat_tops(x2)[1]
        for _ in range(60):
            if f1 <= f2:
                hi, x2, f2 = x2, x1, f1
                x1 = hi - g * (hi - lo)
                f1 = flat_tops(x1)[1]
            else:
                lo, x1, f1 = x1, x2, f2
                x2 = lo + g * (hi - lo)
                f2 = flat_tops(x2)[1]
        b, total, sq, dt = flat_tops(0.5 * (lo + hi))
    return grid, b, sq, dt
