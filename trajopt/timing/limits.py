"""Limits: the robots' speed, acceleration and jerk limits (:class:`Limits`) and the 1-DoF limits of the path
parameter on every piece of a path (:func:`piece_limits`).

On a straight piece with unit direction ``u`` the limits of ``s`` are exactly ``V/|u_i|, A/|u_i|, J/|u_i|``; on a
blend they follow from the bounds ``M1, M2, M3`` of ``|q'|, |q''|, |q'''|`` so that ``M1·v ≤ V``,
``M2·v² + M1·a ≤ A``, ``M3·v³ + 3·M2·v·a + M1·j ≤ J`` for every joint (the chain rule ``a = q''ṡ² + q's̈``,
``j = q'''ṡ³ + 3q''ṡs̈ + q's⃛``).
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np

from mpa import defaults
from mpa._arrays import FloatArray
from mpa.errors import InvalidInputError, PlanningError
from trajopt.timing.curves import (
    BlendedPath,
)


def _pair(name: str, value: Any, unit: str, default: float) -> tuple[float, float]:
    try:
        arr = np.broadcast_to(np.asarray(value, dtype=float), (2,))
    except (TypeError, ValueError, OverflowError):
        raise InvalidInputError(
            f"{name} is {value!r}, expected a positive finite number ({unit}) or one per robot"
        ) from None
    for i, v in enumerate(arr):
        if not np.isfinite(v) or v <= 0:
            who = "" if np.ndim(value) == 0 else f" of robot {'AB'[i]}"
            raise InvalidInputError(f"{name}{who} is {float(v)!r}, expected a positive finite number ({unit})")
        lo, hi = (default * f for f in defaults.LIMIT_RANGE)
        if not lo <= v <= hi:
            who = "" if np.ndim(value) == 0 else f" of robot {'AB'[i]}"
            raise InvalidInputError(
                f"{name}{who} is {float(v)!r}, expected a number in [{lo:g}, {hi:g}] {unit} (the supported range: "
                f"{defaults.LIMIT_RANGE[0]:g} to {defaults.LIMIT_RANGE[1]:g} times the default {default:g})"
            )
    return float(arr[0]), float(arr[1])


@dataclass(frozen=True)
class Limits:
    """Per-robot symmetric limits ``|v| ≤ vmax``, ``|a| ≤ amax``, ``|j| ≤ jmax`` of the route coordinate.

    Each may be one number (both robots) or a pair (A, B). Stored as pairs.

    Parameters
    ----------
    vmax : float or (float, float)
        m/s.
    amax : float or (float, float)
        m/s².
    jmax : float or (float, float)
        m/s³.

    Raises
    ------
    InvalidInputError
        A limit that is not a positive finite number, or outside the supported range
        :data:`mpa.defaults.LIMIT_RANGE` (1e-3 to 1e4 times its default).

    Examples
    --------
    >>> Limits(0.5, 1.0, 5.0).v
    array([0.5, 0.5])
    """

    vmax: Any = defaults.VMAX
    amax: Any = defaults.AMAX
    jmax: Any = defaults.JMAX

    def __post_init__(self) -> None:
        object.__setattr__(self, "vmax", _pair("vmax", self.vmax, "m/s", defaults.VMAX))
        object.__setattr__(self, "amax", _pair("amax", self.amax, "m/s^2", defaults.AMAX))
        object.__setattr__(self, "jmax", _pair("jmax", self.jmax, "m/s^3", defaults.JMAX))

    @property
    def v(self) -> FloatArray:
        """Speed limits, shape (2,)."""
        return np.array(self.vmax)

    @property
    def a(self) -> FloatArray:
        """Acceleration limits, shape (2,)."""
        return np.array(self.amax)

    @property
    def j(self) -> FloatArray:
        """Jerk limits, shape (2,)."""
        return np.array(self.jmax)

    def to_dict(self) -> dict[str, list[float]]:
        """JSON-ready: ``{"vmax": [A, B], "amax": …, "jmax": …}``."""
        return {"vmax": list(self.vmax), "amax": list(self.amax), "jmax": list(self.jmax)}


@dataclass(frozen=True)
class PieceLimits:
    """1-DoF limits ``(v, a, j)`` of the path parameter on every piece. Arrays of shape (P,)."""

    v: FloatArray
    a: FloatArray
    j: FloatArray


def piece_limits(path: BlendedPath, limits: Limits, safety: float = 1.0) -> PieceLimits:
    """Limits of ``s`` on every piece that keep every joint within ``limits`` (see module docstring)."""
    V, A, J = limits.v * safety, limits.a * safety, limits.j * safety
    m1, m2, m3 = path.bounds[:, 0], path.bounds[:, 1], path.bounds[:, 2]  # (P, 2) each
    inf = np.inf

    def jmin(x: FloatArray) -> FloatArray:
        """Minimum over the joints (axis 1 of length 2, without numpy's slow short-axis reduction)."""
        return np.minimum(x[:, 0], x[:, 1])

    with np.errstate(divide="ignore", invalid="ignore", over="ignore"):
        pos1, pos2 = m1 > 0, m2 > 0
        v_lin = np.where(pos1, V / m1, inf)
        v = jmin(
            np.minimum(
                np.minimum(v_lin, np.where(pos2, np.sqrt(0.5 * A / m2), inf)),
                np.where(m3 > 0, np.cbrt(0.5 * J / m3), inf),
            )
        )
        vc = v[:, None]
        vc3 = vc**3
        a = jmin(np.where(pos1, (A - m2 * vc * vc) / m1, inf))
        a = np.minimum(a, jmin(np.where(pos2, 0.5 * (J - m3 * vc3) / (3 * m2 * vc), inf)))
        j = jmin(np.where(pos1, (J - m3 * vc3 - 3 * m2 * vc * a[:, None]) / m1, inf))
        straight = ~np.asarray(path.is_blend, dtype=bool)
        if straight.any():
            vs = np.where(straight, jmin(v_lin), v)
            as_ = np.where(straight, jmin(np.where(pos1, A / m1, inf)), a)
            js = np.where(straight, jmin(np.where(pos1, J / m1, inf)), j)
        else:  # all curved (the hard path's spline)
            vs, as_, js = v, a, j
    if not (np.isfinite(vs).all() and (vs > 0).all() and (as_ > 0).all() and (js > 0).all()):
        bad = PieceLimits(vs, as_, js)
        raise PlanningError(f"no valid 1-DoF limits on some piece: {bad}")
    return PieceLimits(vs, as_, js)
