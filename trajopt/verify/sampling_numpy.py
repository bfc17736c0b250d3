"""Sampling a timed path at the setpoint rate in numpy, for one-shot processes: numba is never imported.

:func:`sample_rows` takes the arguments of the compiled :func:`trajopt.verify.sampling.sample_rows` and fills the
same rows, bit for bit (tested on the pipeline's own arguments, other times and hypothesis's): the same
floating-point operations in the same order, on many rows at once. The phase of each time is
``np.searchsorted(t0, t, side="right") − 1``; the path's derivatives are Horner's scheme over the coefficients of
each row's piece (fancy indexing), the orders 0 to 3 and both columns at once; the clamps are Python's
``min``/``max`` of two floats (``b if b < a else a``, which keeps ``a`` when ``b`` is NaN and the first of two equal
zeros). Two powers are written as the kernel's compiled code computes them: ``x**2`` is ``x * x`` (numba multiplies
for a constant integer power), and ``math.pow(x, 3.0)`` is :func:`numpy.float_power`, which calls the C library's
``pow`` as numba does (:func:`numpy.power` may take a vectorised ``pow`` that differs in the last bit: it does on
CPUs with AVX-512). The rows go in blocks of :data:`_BLOCK`.

A command-line process samples one trajectory: a few milliseconds of numpy cost less than importing numba and
loading its compiled kernels (about half a second); the per-process switch of :mod:`trajopt._numba` picks this twin
there. This module imports numpy and :mod:`mpa`'s array types only.
"""

from __future__ import annotations

import numpy as np

from mpa._arrays import FloatArray, IntArray
from trajopt.verify.elementwise import BLOCK as _BLOCK
from trajopt.verify.elementwise import pmax as _pmax
from trajopt.verify.elementwise import pmin as _pmin

__all__ = ["sample_rows"]


def sample_rows(
    tt: FloatArray,
    t0: FloatArray,
    p: FloatArray,
    v: FloatArray,
    a: FloatArray,
    j: FloatArray,
    duration: float,
    length: float,
    piece: IntArray,
    breaks: FloatArray,
    coef: FloatArray,
    degree: int,
    falling: FloatArray,
    S: FloatArray,
    V: FloatArray,
    A: FloatArray,
    J: FloatArray,
) -> None:
    """Route coordinates and their first three time derivatives at times ``tt`` into ``S, V, A, J`` (shape (N, 2)).

    The same numbers as :func:`trajopt.verify.sampling.sample_rows`: the phase's polynomial ``s(t)`` and its
    derivatives (at rest at ``length`` from ``duration`` on, else ``s`` clamped to ``[0, length]``), the path's
    derivatives at ``s`` by Horner's scheme, and the chain rule.

    Parameters
    ----------
    tt : ndarray, shape (N,)
        Times (s).
    t0, p, v, a, j : ndarray, shape (Q,), Q ≥ 1
        The timing's phases: start times (s), ``s, ṡ, s̈`` at them (m, m/s, m/s²) and their jerks (m/s³); after
        ``duration`` (s) at rest at ``length`` (m).
    duration, length : float
        The motion's duration (s) and the path's length (m).
    piece : ndarray, shape (Q,) or (0,)
        The path piece of each phase (empty: looked up from ``s``).
    breaks, coef : ndarray, shapes (P+1,), (P, 6, 2)
        The path (:class:`trajopt.timing.BlendedPath`): its pieces' start parameters (m) and the coefficients
        ``c_i`` of ``τ^i`` per column, of ``degree`` ≤ 5.
    degree : int
        Degree of the pieces' polynomials.
    falling : ndarray, shape (4, 6)
        ``falling[order, i]``: the factor of ``c_i τ^(i−order)`` in the ``order``-th derivative.
    S, V, A, J : ndarray, shape (N, 2)
        Filled with the route coordinates (m), velocities (m/s), accelerations (m/s²) and jerks (m/s³).
    """
    timing = (t0, p, v, a, j, float(duration), float(length), piece)
    path = (breaks, coef, int(degree), falling)
    with np.errstate(all="ignore"):
        for lo in range(0, len(tt), _BLOCK):
            rows = slice(lo, lo + _BLOCK)
            _sample_block(tt[rows], timing, path, (S[rows], V[rows], A[rows], J[rows]))


def _sample_block(
    tt: FloatArray,
    timing: tuple[FloatArray, FloatArray, FloatArray, FloatArray, FloatArray, float, float, IntArray],
    path: tuple[FloatArray, FloatArray, int, FloatArray],
    out: tuple[FloatArray, FloatArray, FloatArray, FloatArray],
) -> None:
    """:func:`sample_rows` on one block of times ``tt`` (shape (K,)): ``timing`` is ``t0, p, v, a, j, duration,
    length, piece``, ``path`` is ``breaks, coef, degree, falling``, ``out`` the block's ``S, V, A, J`` (shape
    (K, 2)), as :func:`sample_rows` takes them."""
    t0, p, v, a, j, duration, length, piece = timing
    breaks, coef, degree, falling = path
    S, V, A, J = out
    k = np.maximum(np.searchsorted(t0, tt, side="right") - 1, 0)  # the phase
    tau = _pmax(tt - t0[k], 0.0)
    jk, ak, vk = j[k], a[k], v[k]
    tau2 = tau * tau
    acc = ak + jk * tau
    vel = vk + ak * tau + 0.5 * jk * tau2
    s = _pmin(_pmax(p[k] + vk * tau + 0.5 * ak * tau2 + jk * np.float_power(tau, 3.0) / 6.0, 0.0), length)
    after = tt >= duration
    pc = piece[k] if len(piece) == len(t0) else None
    if after.any():  # at rest at the end
        s = np.where(after, length, s)
        vel, acc, jk = (np.where(after, 0.0, x) for x in (vel, acc, jk))
        if pc is not None:
            pc = np.where(after, len(coef) - 1, pc)
    # the path piece and its derivatives at s
    sc = _pmin(_pmax(s, breaks[0]), breaks[-1])
    if pc is None:
        pc = np.minimum(np.maximum(np.searchsorted(breaks, sc, side="right") - 1, 0), len(breaks) - 2)
    x = sc - breaks[pc]
    # each row's piece's coefficients up to the degree, rows last: shape (degree + 1, 2, K)
    c = np.take(np.ascontiguousarray(coef[:, : degree + 1].transpose(1, 2, 0)), pc, axis=2)
    # Horner's scheme for the orders 0 to 3 and both columns at once: at step i the orders up to i take it
    top = min(degree, 3) + 1
    f = falling[:, :, None, None]  # (4, 6, 1, 1)
    q = np.empty((4, 2, len(tt)))  # the path's derivatives of orders 0 to 3 at s
    q[top:] = 0.0  # orders above the degree
    np.multiply(c[degree], f[:top, degree], out=q[:top])
    for i in range(degree - 1, -1, -1):
        m = min(i, 3) + 1
        np.multiply(q[:m], x, out=q[:m])
        q[:m] += c[i] * f[:m, i]
    S.T[:] = q[0]
    V.T[:] = q[1] * vel
    if degree <= 1:  # straight pieces: the second and third path derivatives are 0
        A.T[:] = q[1] * acc + 0.0
        J.T[:] = q[1] * jk + 0.0
    else:
        A.T[:] = q[2] * (vel * vel) + q[1] * acc
        J.T[:] = q[3] * np.float_power(vel, 3.0) + 3.0 * q[2] * vel * acc + q[1] * jk
