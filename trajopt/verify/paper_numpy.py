"""The paper tracks' kernels in numpy, for one-shot processes: numba is never imported.

The six kernels of :mod:`trajopt.verify.kernels` that the pipeline calls on the paper's tracks (the interval, the
circle, the lollipop) have twins here with the same signatures and contracts, outputs filled in place where the
kernel fills them: :func:`track_positions` (route coordinates to track coordinates, :func:`mpa.routes.affine_position`
of every row), :func:`needs_densify` and :func:`dense_polyline` (:func:`mpa.geometry.densify_polyline`'s refinement),
:func:`lollipop_skeleton_points` and :func:`circle_skeleton_points` (the retraction ``H₁`` of every state onto the
skeleton, :func:`mpa.retraction.lollipop_trace_scalar` and :func:`mpa.skeleton.lollipop_point_index`), and
:func:`word_samples` (the samples that make the skeleton word). Their results equal the compiled kernels' bit for
bit (tested on the pipeline's own arguments, perturbed and edge cases and hypothesis's): the same floating-point
operations in the same order, on many rows at once.

- mpa's scalar functions are vectorised case by case: each branch is computed on every row and chosen with
  :func:`numpy.where` (the branch a row does not take may compute NaN or ``inf``, never kept); Python's ``min`` and
  ``max`` of two floats are :func:`_pmin` and :func:`_pmax` (``b if b < a else a``: ``a`` when ``b`` is NaN, the
  first of two equal zeros); ``x % c`` is :func:`numpy.mod`, Python's floor modulo as numba compiles it (``fmod``,
  then ``+ c`` where the signs differ, ``copysign(0, c)`` for a zero result).
- A division or modulo by zero raises :class:`ZeroDivisionError` in the compiled kernels (numba keeps Python's
  error model), in the middle of their loop over the rows: the twins raise it too, after filling the rows before
  the first that divides by zero, as the kernel does (the gate catches it: a state at a collision).
- ``math.ceil(x)`` is an ``int64`` in the compiled code; where ``x`` is NaN, infinite or beyond ``2⁶³`` the
  conversion gives ``−2⁶³`` (x86-64's ``cvttsd2si``), so such a leg is not cut (:func:`_ceil_counts`). (A CPU
  that saturates the conversion instead, aarch64, would cut an infinite leg in the kernel; the gate takes the word
  of finite rows only: a non-finite row fails the separation check first.)
- The rows go in blocks of :data:`_BLOCK`.

A command-line process on a paper track makes one trajectory: a few milliseconds of numpy cost less than importing
numba and loading its compiled kernels (about half a second). The per-process switch of :mod:`trajopt._numba`
picks these twins there. This module imports numpy and :mod:`mpa` only (not the kernels' module, which imports
numba).
"""

from __future__ import annotations

import numpy as np
from numpy.typing import NDArray

from mpa._arrays import FloatArray, IntArray
from mpa.skeleton import VERTEX_TOL
from trajopt.verify.elementwise import BLOCK as _BLOCK
from trajopt.verify.elementwise import pmax as _pmax
from trajopt.verify.elementwise import pmin as _pmin

__all__ = [
    "circle_skeleton_points",
    "dense_polyline",
    "lollipop_skeleton_points",
    "needs_densify",
    "track_positions",
    "word_samples",
]


#: ``2⁶³``: the ``int64`` conversion of a ceiling at or beyond it (or NaN, or infinite) is ``−2⁶³``.
_INT_LIMIT = 2.0**63


def _blocks(n: int) -> list[slice]:
    """The rows ``0 … n−1`` in slices of :data:`_BLOCK`."""
    return [slice(lo, min(lo + _BLOCK, n)) for lo in range(0, n, _BLOCK)]


def _first(mask: NDArray[np.bool_]) -> int:
    """The first index where ``mask`` (shape (K,)) holds, or −1."""
    hit = np.flatnonzero(mask)
    return int(hit[0]) if len(hit) else -1


def _ceil_counts(x: FloatArray) -> IntArray:
    """``max(1, math.ceil(x))`` as the compiled kernels compute it (shape of ``x``): the ceiling converted to
    ``int64``, which is ``−2⁶³`` where ``x`` is NaN, infinite or the ceiling is ``2⁶³`` or more."""
    c = np.ceil(x)
    return np.where((c > 1.0) & (c < _INT_LIMIT), c, 1.0).astype(np.int64)


def _leg_sizes(S: FloatArray) -> FloatArray:
    """``max(|ΔA|, |ΔB|)`` of every leg of the polyline ``S`` (shape (N, 2)), Python's ``max``: shape (N−1,)."""
    return _pmax(np.abs(S[1:, 0] - S[:-1, 0]), np.abs(S[1:, 1] - S[:-1, 1]))


# ------------------------------------------------------------------------------------------ track coordinates
def _affine_positions(
    breaks: FloatArray,
    A: FloatArray,
    B: FloatArray,
    is_line: NDArray[np.bool_],
    interval: bool,
    stick: float,
    loop: float,
    sigma: FloatArray,
) -> tuple[FloatArray, NDArray[np.bool_]]:
    """:func:`mpa.routes.affine_position` of every route coordinate ``sigma`` (m, shape (K,)): the track coordinates
    (m, shape (K,)) and where the kernel divides by zero (``loop == 0`` on a loop piece), shape (K,)."""
    if len(A) == 1:
        idx = np.zeros(len(sigma), dtype=np.intp)
    else:  # the kernel's binary search: searchsorted(breaks, sigma, "left"), and 0 for NaN (never above a break)
        idx = np.searchsorted(breaks, sigma, side="left")
        idx[np.isnan(sigma)] = 0
    val = A[idx] + B[idx] * sigma
    clamp = np.ones(len(sigma), dtype=bool) if interval else ~is_line[idx]
    th = np.mod(val, loop)
    th = np.where(th >= loop - 1e-12, 0.0, th)
    out = np.where(clamp, _pmin(_pmax(val, 0.0), stick), stick + th)
    return out, ~clamp & (loop == 0.0)


def track_positions(
    S: FloatArray,
    breaks_a: FloatArray,
    A_a: FloatArray,
    B_a: FloatArray,
    line_a: NDArray[np.bool_],
    breaks_b: FloatArray,
    A_b: FloatArray,
    B_b: FloatArray,
    line_b: NDArray[np.bool_],
    interval: bool,
    stick: float,
    loop: float,
    out: FloatArray,
) -> None:
    """Track coordinates of route coordinates into ``out``: :meth:`mpa.routes.Route.position` of each robot's route.

    The same numbers as :func:`trajopt.verify.kernels.track_positions` (:func:`mpa.routes.affine_position` of
    every row, vectorised).

    Parameters
    ----------
    S : ndarray, shape (N, 2)
        Route coordinates of A and B (m).
    breaks_a, A_a, B_a, line_a : ndarray, shapes (M−1,), (M,), (M,), (M,)
        A's route as :meth:`mpa.routes.Route.affine_form`: the pieces' sorted breaks (m), the track coordinate
        ``A + B σ`` of each piece (m, 1), and whether the piece lies on the loop.
    breaks_b, A_b, B_b, line_b : ndarray
        B's route, the same way.
    interval : bool
        The track is an interval (every position clamped to ``[0, stick]``).
    stick, loop : float
        The stick's length (0 on a circle) and the loop's circumference (m).
    out : ndarray, shape (N, 2)
        Filled with the track coordinates of A and B (m).

    Raises
    ------
    ZeroDivisionError
        ``loop == 0`` where a row is on a loop piece (the rows before it filled, as by the kernel).
    """
    routes = ((breaks_a, A_a, B_a, line_a), (breaks_b, A_b, B_b, line_b))
    with np.errstate(all="ignore"):
        for rows in _blocks(len(S)):
            pos = np.empty((rows.stop - rows.start, 2))
            bad = np.empty((rows.stop - rows.start, 2), dtype=bool)
            for r, (breaks, A, B, line) in enumerate(routes):
                pos[:, r], bad[:, r] = _affine_positions(breaks, A, B, line, interval, stick, loop, S[rows, r])
            k = _first(bad.reshape(-1))  # row by row, A before B, as the kernel fills them
            if k >= 0:
                out[rows.start : rows.start + k // 2] = pos[: k // 2]
                if k % 2:
                    out[rows.start + k // 2, 0] = pos[k // 2, 0]
                raise ZeroDivisionError("modulo by zero")
            out[rows] = pos


# ------------------------------------------------------------------------------------------ dense polylines
def needs_densify(S: FloatArray, step: float) -> bool:
    """Whether some leg of the polyline ``S`` is longer than ``step`` in the max-norm.

    The same answer as :func:`trajopt.verify.kernels.needs_densify` (:func:`mpa.geometry.densify_polyline` would
    cut the leg: ``⌈|leg|_∞ / step⌉ > 1``).

    Parameters
    ----------
    S : ndarray, shape (N, 2)
        Route coordinates of A and B (m).
    step : float
        The longest leg kept (m).

    Raises
    ------
    ZeroDivisionError
        ``step == 0`` and ``S`` has a leg.
    """
    if len(S) >= 2 and step == 0.0:
        raise ZeroDivisionError("division by zero")
    with np.errstate(all="ignore"):
        for rows in _blocks(len(S) - 1):
            legs = S[rows.start : rows.stop + 1]
            if bool((_ceil_counts(_leg_sizes(legs) / step) > 1).any()):
                return True
    return False


def dense_polyline(S: FloatArray, step: float) -> FloatArray:
    """The polyline of route coordinates ``S`` refined to ``step``: the points of
    :func:`mpa.geometry.densify_polyline`, as :func:`trajopt.verify.kernels.dense_polyline` computes them.

    Every leg ``k`` is cut into ``n_k = max(1, ⌈|leg|_∞ / step⌉)`` equal parts, its points
    ``S[k] + (q / n_k) (S[k+1] − S[k])`` for ``q = 0 … n_k − 1``, then the last point ``S[N−1]``.

    Parameters
    ----------
    S : ndarray, shape (N, 2), N ≥ 1
        Route coordinates of A and B (m).
    step : float
        The longest leg kept (m).

    Returns
    -------
    ndarray, shape (M, 2)
        The refined polyline (m), ``M = 1 + Σ n_k``.

    Raises
    ------
    ZeroDivisionError
        ``step == 0`` and ``S`` has a leg.
    IndexError
        ``S`` has no row (the kernel reads outside ``S`` there).
    """
    n = len(S)
    if n >= 2 and step == 0.0:
        raise ZeroDivisionError("division by zero")
    with np.errstate(all="ignore"):
        counts = _ceil_counts(_leg_sizes(S) / step)
        la, lb = S[1:, 0] - S[:-1, 0], S[1:, 1] - S[:-1, 1]
    total = 1 + int(counts.sum())
    out = np.empty((total, 2))
    leg = np.repeat(np.arange(n - 1), counts)  # the leg of each point but the last
    first = np.cumsum(counts) - counts  # each leg's first point
    with np.errstate(all="ignore"):
        for rows in _blocks(total - 1):
            k = leg[rows]
            nk = counts[k]
            frac = (np.arange(rows.start, rows.stop) - first[k]) / nk
            out[rows, 0] = S[k, 0] + frac * la[k]
            out[rows, 1] = S[k, 1] + frac * lb[k]
    out[total - 1] = S[n - 1]
    return out


# ------------------------------------------------------------------------------------------ skeleton words
def _lollipop_trace(
    ell: float, c: float, a: FloatArray, b: FloatArray
) -> tuple[FloatArray, FloatArray, NDArray[np.bool_]]:
    """:func:`mpa.retraction.lollipop_trace_scalar` of every model state ``(a, b)`` (model m, shape (K,)): the
    displacements of A and B (shape (K,) each) and where the scalar function divides by zero (shape (K,))."""
    h = 0.5 * c
    a_st, b_st = a <= ell, b <= ell
    # both on the stick: the rear robot to the free end's side, the front one to P's, until h apart
    front_is_b = b > a
    rear, front = np.where(front_is_b, a, b), np.where(front_is_b, b, a)
    d = front - rear
    far = d >= h
    total = _pmax(rear + ell - front, 1e-300)
    d_rear = np.where(far, d - h, -(h - d) * rear / total)
    d_front = np.where(far, 0.0, (h - d) * (ell - front) / total)
    ss = (np.where(front_is_b, d_rear, d_front), np.where(front_is_b, d_front, d_rear))
    # one on the stick, one on the loop: scaled apart to h along the shortest way through P
    ps, pl = np.where(a_st, a, b), np.where(a_st, b, a)
    x = ell - ps
    th = pl - ell
    side = np.where(th <= h, 1.0, -1.0)
    w = _pmin(th, c - th)
    dm = x + w
    far_m = dm >= h
    lam = h / dm
    x_new = np.where(far_m, h - w, lam * x)
    w_new = np.where(far_m, w, lam * w)
    ds, dl = -(x_new - x), side * (w_new - w)
    mixed = (np.where(a_st, ds, dl), np.where(a_st, dl, ds))
    # both on the loop: scaled apart to h along the arc through P
    ta, tb = a - ell, b - ell
    p_on_ccw = tb < ta
    wa, wb = np.where(p_on_ccw, c - ta, ta), np.where(p_on_ccw, tb, c - tb)
    span = wa + wb
    lam_l = h / span
    da, db = (lam_l - 1.0) * wa, (lam_l - 1.0) * wb
    loop = (np.where(p_on_ccw, -da, da), np.where(p_on_ccw, db, -db))
    both, one = a_st & b_st, a_st != b_st
    out_a = np.where(both, ss[0], np.where(one, mixed[0], loop[0]))
    out_b = np.where(both, ss[1], np.where(one, mixed[1], loop[1]))
    zero = (one & ~far_m & (dm == 0.0)) | (~both & ~one & (span == 0.0))
    return out_a, out_b, zero


def _point_indices(
    h: float, ell: float, a: FloatArray, b: FloatArray
) -> tuple[IntArray, FloatArray, NDArray[np.bool_]]:
    """:func:`mpa.skeleton.lollipop_point_index` of every model state ``(a, b)`` (model m, shape (K,)) on the
    skeleton: edge indices, ``t`` (shape (K,) each), and where it divides by zero (``h == 0`` off the stick)."""
    c = 2 * h
    a_stick, b_stick = a <= ell + VERTEX_TOL, b <= ell + VERTEX_TOL
    on_stick = a_stick & b_stick
    b_ahead = b > a
    t_stick = np.where(b_ahead, _pmin(_pmax(a, 0.0), ell - h), _pmin(_pmax(b, 0.0), ell - h))
    e_stick = np.where(b_ahead, 0, 7)
    a_only = a_stick & ~b_stick
    j = np.where(a_only, 1, np.where(b_stick, 3, 2))
    phi = np.mod(np.where(a_only, b, a) - ell, c)
    phi = np.where(phi >= c - VERTEX_TOL, 0.0, phi)
    upper = phi >= h
    edge = np.where(on_stick, e_stick, np.where(upper, 2 * j, 2 * j - 1)).astype(np.int64)
    t = np.where(on_stick, t_stick, np.where(upper, phi - h, phi))
    return edge, t, ~on_stick & (c == 0.0)


def _lollipop_points(
    P: FloatArray, ell: float, c_model: float, kappa: float, degenerate: bool
) -> tuple[IntArray, FloatArray, NDArray[np.bool_]]:
    """The kernel's steps on the states ``P`` (shape (K, 2)): edges and ``t`` (shape (K,) each), and where a step
    divides by zero (shape (K,))."""
    h = 0.5 * c_model
    a, b = P[:, 0], P[:, 1]
    ma = np.where(a <= ell, a, ell + (a - ell) * kappa)  # ψ to the model
    mb = np.where(b <= ell, b, ell + (b - ell) * kappa)
    da, db, zero = _lollipop_trace(ell, c_model, ma, mb)
    na, nb = ma + 1.0 * da, mb + 1.0 * db  # H at t = 1, wrapped on the loop
    zero |= ((ma > ell) | (mb > ell)) & (c_model == 0.0)
    na = np.where(ma > ell, ell + np.mod(na - ell, c_model), na)
    nb = np.where(mb > ell, ell + np.mod(nb - ell, c_model), nb)
    zero |= (~(na <= ell) | ~(nb <= ell)) & (kappa == 0.0)
    ra = np.where(na <= ell, na, ell + (na - ell) / kappa)  # retract returns track coordinates ...
    rb = np.where(nb <= ell, nb, ell + (nb - ell) / kappa)
    ra = np.where(ra <= ell, ra, ell + (ra - ell) * kappa)  # ... which skeleton_points takes to the model
    rb = np.where(rb <= ell, rb, ell + (rb - ell) * kappa)
    edge, t, zero_p = _point_indices(h, ell, ra, rb)
    zero |= zero_p
    if degenerate:  # I1 and I2 are single points: the vertices S1a(0) and S3a(0)
        end = (edge == 0) | (edge == 7)
        edge = np.where(end, np.where(edge == 0, 1, 5), edge)
        t = np.where(end, 0.0, t)
    return edge, t, zero


def lollipop_skeleton_points(
    P: FloatArray, ell: float, c_model: float, kappa: float, degenerate: bool, edge: IntArray, t: FloatArray
) -> None:
    """``H₁`` of each state on a lollipop: its skeleton edge into ``edge`` and the position along it into ``t``.

    The same numbers as :func:`trajopt.verify.kernels.lollipop_skeleton_points`: ψ to the model, the trace of
    :func:`mpa.retraction.lollipop_trace_scalar` at ``t = 1``, ψ⁻¹ as :func:`mpa.retraction.retract` returns, ψ
    again, :func:`mpa.skeleton.lollipop_point_index`, every step vectorised over the states.

    Parameters
    ----------
    P : ndarray, shape (N, 2)
        Track coordinates of A and B (m; collision-free).
    ell, c_model, kappa : float
        The stick (m), the model's loop (model m) and the loop scale ψ (:class:`mpa.skeleton.LollipopSkeleton`).
    degenerate : bool
        ``ℓ = h``: I1 and I2 are single points, taken as the vertices ``S1a(0)`` and ``S3a(0)``.
    edge : ndarray of int64, shape (N,)
        Filled with the skeleton edge index of each state (:class:`mpa.skeleton.LollipopSkeleton`'s graph).
    t : ndarray, shape (N,)
        Filled with the position along that edge (model m).

    Raises
    ------
    ZeroDivisionError
        A state at a collision (the robots coincide: the trace divides by zero), or ``c_model`` or ``kappa`` zero
        where a step divides by it; the rows before it are filled, as by the kernel.
    """
    with np.errstate(all="ignore"):
        for rows in _blocks(len(P)):
            e, tk, zero = _lollipop_points(P[rows], ell, c_model, kappa, degenerate)
            k = _first(zero)
            if k >= 0:
                edge[rows.start : rows.start + k], t[rows.start : rows.start + k] = e[:k], tk[:k]
                raise ZeroDivisionError("division by zero")
            edge[rows], t[rows] = e, tk


def circle_skeleton_points(P: FloatArray, c: float, edge: IntArray, t: FloatArray) -> None:
    """``H₁`` of each state on a circle: its skeleton edge (0 = Aa, 1 = Ab) into ``edge``, the position along it
    into ``t``.

    The same numbers as :func:`trajopt.verify.kernels.circle_skeleton_points`: A moves until antipodal and B waits
    (:func:`mpa.retraction.circle_trace`), so the skeleton point is B's position φ
    (:meth:`mpa.skeleton.CircleSkeleton.points_of_states`).

    Parameters
    ----------
    P : ndarray, shape (N, 2)
        Track coordinates of A and B (m).
    c : float
        The circumference (m).
    edge : ndarray of int64, shape (N,)
        Filled with the skeleton edge of each state.
    t : ndarray, shape (N,)
        Filled with the position along it (m).

    Raises
    ------
    ZeroDivisionError
        ``c == 0`` and there is a state (nothing filled).
    """
    if len(P) and c == 0.0:
        raise ZeroDivisionError("modulo by zero")
    h = 0.5 * c
    with np.errstate(all="ignore"):
        for rows in _blocks(len(P)):
            phi = np.mod(np.mod(P[rows, 1] + 1.0 * 0.0, c), c)  # as retract (B's displacement 0), then the points
            upper = phi >= h
            edge[rows] = np.where(upper, 1, 0)
            t[rows] = np.where(upper, phi - h, phi)


def word_samples(edge: IntArray, adjacent: NDArray[np.bool_]) -> tuple[IntArray, bool]:
    """The samples that matter for the skeleton word, and whether the sampling is too coarse somewhere.

    The same answer as :func:`trajopt.verify.kernels.word_samples`: the first and the last sample and both sides
    of every edge change (:func:`mpa.homotopy.word_from_points`).

    Parameters
    ----------
    edge : ndarray of int64, shape (N,)
        The skeleton edge of each sample (valid indices into ``adjacent``).
    adjacent : ndarray of bool, shape (E, E)
        Whether two skeleton edges share a vertex.

    Returns
    -------
    keep : ndarray of int64, shape (K,)
        The indices of the samples kept, increasing.
    jump : bool
        Whether two consecutive samples lie on skeleton edges without a common vertex.
    """
    n = len(edge)
    change = edge[1:] != edge[:-1]  # shape (N−1,): between samples k and k + 1
    keep = np.zeros(n, dtype=bool)
    if n:
        keep[0] = keep[n - 1] = True
        keep[:-1] |= change
        keep[1:] |= change
    k = np.flatnonzero(change)
    jump = bool(len(k)) and not bool(adjacent[edge[k], edge[k + 1]].all())
    return np.flatnonzero(keep).astype(np.int64), jump
