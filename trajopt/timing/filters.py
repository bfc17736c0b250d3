"""Filters on a grid: the range-minimum table (sparse table) over windows, the morphological opening of a
function, the forward-backward pass of a v/a-limited profile, and the box filter of a constant-acceleration
motion (which bounds its jerk).
"""

from __future__ import annotations

from typing import Any, NamedTuple

import numpy as np
from numpy.typing import NDArray

from mpa._arrays import FloatArray
from mpa.errors import PlanningError


def _window_min(values: FloatArray, breaks: FloatArray, lo: FloatArray, hi: FloatArray) -> FloatArray:
    """Minimum of the piecewise-constant ``values`` (one per piece ``[breaks[k], breaks[k+1]]``, shape (P,) or
    (K, P) for K functions at once) over ``[lo, hi]`` (shape (G,)); shape (G,) or (K, G)."""
    P = values.shape[-1]
    first = np.minimum(breaks[1:].searchsorted(lo, "left"), P - 1)
    last = np.minimum(np.maximum(breaks[:-1].searchsorted(hi, "right") - 1, 0), P - 1)
    upto = np.maximum(last, first)
    table = _sparse_table(values, np.minimum, int((upto - first).max()) + 1 if len(first) else None)
    return np.where(last >= first, _range_extreme(table, first, upto, np.minimum), np.inf)


def _sparse_table(f: FloatArray, fn: Any, longest: int | None = None) -> FloatArray:
    """Range extremes of ``f`` (shape (..., n)) over blocks of 2^k: ``t[k, ..., i] = fn(f[..., i : i + 2^k])``
    for ``i <= n − 2^k`` (the rest repeats the level below). Shape (L, ..., n), ``2^(L−1) <= min(n, longest)``
    (``longest``: the longest range that will be asked)."""
    n = f.shape[-1]
    levels = max(int(min(n, n if longest is None else max(int(longest), 1))).bit_length(), 1)
    t = np.empty((levels, *f.shape))
    t[0] = f
    for k in range(1, levels):
        half, valid = 1 << (k - 1), n - (1 << k) + 1
        fn(t[k - 1, ..., :valid], t[k - 1, ..., half : half + valid], out=t[k, ..., :valid])
        t[k, ..., valid:] = t[k - 1, ..., valid:]
    return t


def _range_extreme(table: FloatArray, lo: NDArray[np.intp], hi: NDArray[np.intp], fn: Any) -> FloatArray:
    """``fn`` of the values ``lo[i] .. hi[i]`` (inclusive, ``lo <= hi``) from :func:`_sparse_table`'s table."""
    n = table.shape[-1]
    level = np.frexp(hi - lo + 1)[1] - 1  # floor(log2(length)), exact
    row = level * n  # flat index of (level, i) is row + i
    first, last = row + lo, row + (hi + 1 - np.left_shift(1, level))
    if table.ndim == 2:
        flat = table.ravel()
        return np.asarray(fn(flat.take(first), flat.take(last)))
    flat = np.moveaxis(table, 0, -2).reshape(*table.shape[1:-1], -1)  # (..., levels·n)
    return np.asarray(fn(flat.take(first, axis=-1), flat.take(last, axis=-1)))


def _topp_passes(cap: FloatArray, two_a_ds: FloatArray) -> FloatArray:
    """Forward and backward passes on ``ṡ²``: the largest profile under ``cap`` with ``|Δṡ²| ≤ 2·a·Δs``.

    Two sequential scans on Python floats (each step's rounding is relative to the local ``ṡ²``, so a short grid
    interval keeps its acceleration to rounding; a closed form with running sums would not).
    """
    b = cap.tolist()
    b[0] = 0.0
    d = two_a_ds.tolist()
    n = len(d)
    prev = 0.0
    for i in range(n):  # forward
        nb = prev + d[i]
        prev = b[i + 1]
        if nb < prev:
            b[i + 1] = prev = nb
    for i in range(n - 1, -1, -1):  # backward
        nb = prev + d[i]
        prev = b[i]
        if nb < prev:
            b[i] = prev = nb
    return np.maximum(np.array(b), 0.0)


class _Windows(NamedTuple):
    """The windows ``[x − r, x + r]`` of every grid point ``x``: the grid points ``x ∓ r``, the longest window
    (in grid points) and the flat sparse-table indices of the two blocks that cover each window."""

    left: FloatArray
    right: FloatArray
    longest: int
    first: NDArray[np.intp]
    last: NDArray[np.intp]


def _windows(grid: FloatArray, r: float) -> _Windows:
    """:class:`_Windows` of ``grid`` and radius ``r``."""
    left, right = grid - r, grid + r
    lo = grid.searchsorted(left, "left")
    hi = np.maximum(grid.searchsorted(right, "right") - 1, lo)  # first and last grid index in the window
    level = np.frexp(hi - lo + 1)[1] - 1  # floor(log2(length)), exact (as _range_extreme)
    row = level * len(grid)
    return _Windows(left, right, int((hi - lo).max()) + 1, row + lo, row + (hi + 1 - np.left_shift(1, level)))


def _window_extreme(grid: FloatArray, f: FloatArray, r: float, fn: Any, windows: _Windows | None = None) -> FloatArray:
    """``fn`` (np.minimum or np.maximum) of the piecewise-linear ``f`` over ``[x − r, x + r]`` at every grid point
    (``windows``: :func:`_windows` of ``grid`` and ``r``, if known)."""
    w = _windows(grid, r) if windows is None else windows
    flat = _sparse_table(f, fn, w.longest).ravel()
    out = fn(flat.take(w.first), flat.take(w.last))
    return np.asarray(fn(out, fn(np.interp(w.left, grid, f), np.interp(w.right, grid, f))))


def _opening(grid: FloatArray, f: FloatArray, r: float) -> FloatArray:
    """Morphological opening of ``f`` with the window ``[−r, r]``: narrow peaks become plateaus ``2r`` wide."""
    w = _windows(grid, r)
    return _window_extreme(grid, _window_extreme(grid, f, r, np.minimum, w), r, np.maximum, w)


class _Phases(NamedTuple):
    """A rest-to-rest motion ``s(t)`` of constant acceleration per phase: phase ``k`` starts at ``t[k]`` with
    position ``s[k]``, speed ``v[k]``, acceleration ``a[k]``; ``f[k] = ∫_0^{t[k]} s``. ``t`` and ``f`` have one
    entry more than the phases (the end: ``t[-1]`` is the duration)."""

    t: FloatArray
    s: FloatArray
    v: FloatArray
    a: FloatArray
    f: FloatArray

    @property
    def duration(self) -> float:
        return float(self.t[-1])


def _constant_acceleration_phases(
    grid: FloatArray, b: FloatArray, sq: FloatArray | None = None, dt: FloatArray | None = None
) -> _Phases:
    """The motion through the grid points ``grid`` with ``ṡ² = b`` there (constant acceleration between them);
    ``sq = √b`` and the intervals' durations ``dt`` if known (as :func:`_eroded_flat_top_profile` computes them)."""
    ds = grid[1:] - grid[:-1]
    with np.errstate(divide="ignore", invalid="ignore"):
        if sq is None or dt is None:
            sq = np.sqrt(b)
            dt = np.where(ds > 0, 2.0 * ds / (sq[:-1] + sq[1:]), 0.0)
        acc = np.where(ds > 0, (b[1:] - b[:-1]) / (2.0 * ds), 0.0)
    if not np.isfinite(dt).all():
        k = int(np.argmin(np.isfinite(dt)))
        raise PlanningError(f"the timing is stuck: zero speed over [{grid[k]:.6g}, {grid[k + 1]:.6g}] m of the path")
    keep = dt > 0
    ti = np.concatenate(((0.0,), dt[keep].cumsum()))
    s_i, v_i, a_i = grid[:-1][keep], sq[:-1][keep], acc[keep]
    # integral F(t) = ∫_0^t s: exact at the phase starts
    dtk = ti[1:] - ti[:-1]
    f_i = np.concatenate(((0.0,), (s_i * dtk + v_i * dtk**2 / 2 + a_i * dtk**3 / 6).cumsum()))
    return _Phases(ti, s_i, v_i, a_i, f_i)


def _phase_state(ph: _Phases, S: float, t: FloatArray) -> tuple[FloatArray, FloatArray, FloatArray]:
    """``(F, s, v)`` of the motion at times ``t``; before 0 at rest at 0, after the end at rest at ``S`` (the
    acceleration: :func:`_phase_acceleration`)."""
    ti, s_i, v_i, a_i, f_i = ph
    T = ph.duration
    k = np.minimum(np.maximum(ti.searchsorted(t, "right") - 1, 0), len(s_i) - 1)  # (np.clip is slow)
    x = np.maximum(t - ti.take(k), 0.0)
    x2 = x**2
    sk, vk, ak = s_i.take(k), v_i.take(k), a_i.take(k)
    s = sk + vk * x + ak * x2 / 2
    v = vk + ak * x
    f = f_i.take(k) + sk * x + vk * x2 / 2 + ak * x**3 / 6
    before, after = t < 0.0, t >= T
    f = np.where(before, 0.0, np.where(after, f_i[-1] + S * (t - T), f))
    s = np.where(before, 0.0, np.where(after, S, s))
    v = np.where(before | after, 0.0, v)
    return f, s, v


def _box_filtered(
    ph: _Phases, tau: float, S: float
) -> tuple[FloatArray, FloatArray, FloatArray, FloatArray, FloatArray]:
    """Step 4 of :func:`filtered_scaling`: ``s̃(t) = (1/τ)∫_{t−τ}^{t} s`` as phases of constant jerk: their start
    times and ``s̃, ṡ̃, s̈̃`` there, and their jerks (each shape (K,))."""
    ti, T = ph.t, ph.duration
    t0 = np.concatenate([ti, ti + tau])
    t0.sort()
    keep = np.empty(len(t0), dtype=bool)  # (np.unique, without its overhead)
    keep[0] = True
    np.not_equal(t0[1:], t0[:-1], out=keep[1:])
    keep &= t0 < T + tau
    t0 = t0[keep]
    mid = 0.5 * (t0 + np.concatenate((t0[1:], (T + tau,))))  # the jerk of a phase, away from rounding at its ends
    k = len(t0)
    f, s, v = _phase_state(ph, S, np.concatenate([t0, t0 - tau]))  # one evaluation each
    a = _phase_acceleration(ph, np.concatenate([mid, mid - tau]))
    p_out = np.minimum(np.maximum((f[:k] - f[k:]) / tau, 0.0), S)
    v_out = (s[:k] - s[k:]) / tau
    a_out = (v[:k] - v[k:]) / tau
    j_out = (a[:k] - a[k:]) / tau
    return t0, p_out, v_out, a_out, j_out


def _phase_acceleration(ph: _Phases, t: FloatArray) -> FloatArray:
    """The acceleration of the motion of :func:`_phase_state` at times ``t`` (right-continuous; 0 at rest)."""
    ti = ph.t
    k = np.minimum(np.maximum(ti.searchsorted(t, "right") - 1, 0), len(ph.s) - 1)
    return np.where((t < 0.0) | (t >= ph.duration), 0.0, ph.a.take(k))
