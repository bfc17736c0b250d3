"""Sampling a timed path at the setpoint rate, compiled (numba), in one call per grid.

:meth:`trajopt.timing.TimeScaling.sample` (the jerk phases ``s(t)``, then the path's derivatives by Horner's scheme
and the chain rule) on a few hundred rows: as numpy it was some thirty array calls, and their fixed cost was most of
the time. The same formulas, row by row. The rows' track coordinates are
:func:`trajopt.verify.kernels.track_positions`.
"""

from __future__ import annotations

import math

import numpy as np

from mpa._arrays import FloatArray, IntArray
from trajopt._numba import njit, numpy_twins
from trajopt.verify.kernels import _bisect_right, _piece

__all__ = ["sample_rows"]


@njit(cache=True)
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

    Parameters
    ----------
    tt : shape (N,)
        Times (s).
    t0, p, v, a, j : shape (Q,), Q ≥ 1
        The timing's phases: start times (s), ``s, ṡ, s̈`` at them (m, m/s, m/s²) and their jerks (m/s³); after
        ``duration`` (s) at rest at ``length`` (m).
    piece : shape (Q,) or (0,)
        The path piece of each phase (empty: looked up from ``s``).
    breaks, coef : shapes (P+1,), (P, 6, 2)
        The path (:class:`trajopt.timing.BlendedPath`), of ``degree``.
    falling : shape (4, 6)
        ``falling[order, i]``: the factor of ``c_i τ^(i−order)`` in the ``order``-th derivative.
    """
    n_pieces = len(coef)
    has_piece = len(piece) == len(t0)
    q = np.zeros(4)  # the path's derivatives of orders 0 to 3 for one robot at s
    for r in range(len(tt)):
        t = tt[r]
        k = max(_bisect_right(t0, t) - 1, 0)  # the phase
        tau = max(t - t0[k], 0.0)
        jk = j[k]
        acc = a[k] + jk * tau
        vel = v[k] + a[k] * tau + 0.5 * jk * tau**2
        s = p[k] + v[k] * tau + 0.5 * a[k] * tau**2 + jk * math.pow(tau, 3.0) / 6.0
        if t >= duration:
            s, vel, acc, jk = length, 0.0, 0.0, 0.0
        else:
            s = min(max(s, 0.0), length)
        # the path piece and its derivatives at s
        sc = min(max(s, breaks[0]), breaks[-1])
        if has_piece:
            pc = n_pieces - 1 if t >= duration else piece[k]
        else:
            pc = _piece(breaks, sc)
        x = sc - breaks[pc]
        for col in range(2):
            for order in range(4):
                if order > degree:
                    q[order] = 0.0
                    continue
                h = coef[pc, degree, col] * falling[order, degree]
                for i in range(degree - 1, order - 1, -1):
                    h = h * x + coef[pc, i, col] * falling[order, i]
                q[order] = h
            S[r, col] = q[0]
            V[r, col] = q[1] * vel
            if degree <= 1:  # straight pieces: the second and third path derivatives are 0
                A[r, col] = q[1] * acc + 0.0
                J[r, col] = q[1] * jk + 0.0
            else:
                A[r, col] = q[2] * vel**2 + q[1] * acc
                J[r, col] = q[3] * math.pow(vel, 3.0) + 3 * q[2] * vel * acc + q[1] * jk


if numpy_twins():  # a process that runs without numba (trajopt._numba): the numpy twin
    import trajopt.verify.sampling_numpy as sampling_numpy

    sample_rows = sampling_numpy.sample_rows
