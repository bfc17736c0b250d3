"""The timing result: :class:`TimeScaling`, a jerk-limited ``s(t)`` of a :class:`~trajopt.timing.curves.BlendedPath`
as piecewise-constant jerk phases, sampled into setpoint rows.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from functools import cached_property
from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from mpa._arrays import FloatArray
from trajopt.timing.curves import (
    _FALLING_ARRAY,
    BlendedPath,
)
from trajopt.verify.sampling import sample_rows


@dataclass(frozen=True)
class TimeScaling:
    """A jerk-limited timing ``s(t)`` of a :class:`BlendedPath`: piecewise-constant jerk phases.

    Attributes
    ----------
    path : BlendedPath
    t0 : ndarray, shape (Q,)
        Start time of every phase (s).
    p, v, a, j : ndarray, shape (Q,)
        ``s``, ``ṡ``, ``s̈`` at the phase start and the constant ``s⃛`` of the phase.
    duration : float
        End of the motion (s).
    boundary_speed : ndarray, shape (P+1,)
        ``ṡ`` at the piece boundaries.
    stats : dict
    """

    path: BlendedPath
    t0: FloatArray
    p: FloatArray
    v: FloatArray
    a: FloatArray
    j: FloatArray
    duration: float
    boundary_speed: FloatArray
    piece: NDArray[np.intp] = field(default_factory=lambda: np.zeros(0, dtype=np.intp))
    stats: dict[str, Any] = field(default_factory=dict)

    def _phase(self, tt: FloatArray) -> NDArray[np.intp]:
        # searchsorted returns at most len(t0), so only the lower end needs clamping
        return np.maximum(np.searchsorted(self.t0, tt, side="right") - 1, 0)

    def param(self, t: ArrayLike) -> tuple[FloatArray, FloatArray, FloatArray, FloatArray]:
        """``s, ṡ, s̈, s⃛`` at times ``t`` (after the end: held at rest at the end)."""
        tt = np.asarray(t, dtype=float)
        if len(self.t0) == 0:
            z = np.zeros_like(tt)
            return z + self.path.length, z, z.copy(), z.copy()
        return self._param(tt, self._phase(tt))

    def _param(self, tt: FloatArray, k: NDArray[np.intp]) -> tuple[FloatArray, FloatArray, FloatArray, FloatArray]:
        """:meth:`param` at times ``tt`` in phases ``k`` (``t0`` not empty)."""
        tau = np.maximum(tt - self.t0[k], 0.0)
        j = self.j[k]
        a = self.a[k] + j * tau
        v = self.v[k] + self.a[k] * tau + 0.5 * j * tau**2
        s = self.p[k] + self.v[k] * tau + 0.5 * self.a[k] * tau**2 + j * tau**3 / 6.0
        after = tt >= self.duration
        s = np.where(after, self.path.length, np.clip(s, 0.0, self.path.length))
        v = np.where(after, 0.0, v)
        a = np.where(after, 0.0, a)
        j = np.where(after, 0.0, j)
        return s, v, a, j

    def sample(self, t: ArrayLike) -> tuple[FloatArray, FloatArray, FloatArray, FloatArray]:
        """Route coordinates and their first three time derivatives at ``t``. Each shape ``t.shape + (2,)``.

        Row by row in one compiled call (:func:`trajopt.verify.sampling.sample_rows`): the phase's polynomial
        (:meth:`param`), the path's derivatives at ``s`` (:meth:`BlendedPath.derivatives`, Horner's scheme) and
        the chain rule.
        """
        tt = np.asarray(t, dtype=float)
        shape = (*tt.shape, 2)
        if len(self.t0) == 0:  # no motion: at rest at the end
            s, sd, sdd, sddd = self.param(tt)
            q0, q1, _, _ = (x.reshape(shape) for x in self.path.derivatives(s))
            return q0, q1 * sd[..., None], q1 * sdd[..., None] + 0.0, q1 * sddd[..., None] + 0.0
        flat = np.ascontiguousarray(tt.ravel())
        n = len(flat)
        S, V, A, J = np.empty((n, 2)), np.empty((n, 2)), np.empty((n, 2)), np.empty((n, 2))
        path = self.path
        t0, p, v, a, j, piece = self._phase_arrays
        sample_rows(
            flat,
            t0,
            p,
            v,
            a,
            j,
            float(self.duration),
            float(path.length),
            piece,
            np.ascontiguousarray(path.breaks, dtype=float),
            np.ascontiguousarray(path.coef, dtype=float),
            path.degree,
            _FALLING_ARRAY,
            S,
            V,
            A,
            J,
        )
        return S.reshape(shape), V.reshape(shape), A.reshape(shape), J.reshape(shape)

    @cached_property
    def _phase_arrays(self) -> tuple[FloatArray, FloatArray, FloatArray, FloatArray, FloatArray, NDArray[np.intp]]:
        """``t0, p, v, a, j, piece`` as the compiled sampler takes them (C-contiguous; built once)."""
        f = np.ascontiguousarray
        return (
            f(self.t0, dtype=float),
            f(self.p, dtype=float),
            f(self.v, dtype=float),
            f(self.a, dtype=float),
            f(self.j, dtype=float),
            f(self.piece, dtype=np.intp),
        )
