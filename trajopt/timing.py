"""Stages 2 and 3: a C² geometric path, its time parametrization (toppra) and jerk-limited timing (ruckig).

Path. The smoothed polyline in route coordinates becomes :class:`BlendedPath` ``q(s)`` (``s`` = Euclidean arc
length in the σ-plane on the straight parts): straight pieces joined at every corner by a quintic Bézier
blend with control points ``P1, P1 + r/2·u1, C, C, P2 − r/2·u2, P2`` (``C`` the corner, ``P1 = C − r·u1``,
``P2 = C + r·u2``). It leaves and joins the straight lines with the same tangent and zero curvature (C²), and
lies in the triangle ``P1 C P2`` (convex hull of its control points). A blend is kept only if it is exactly
collision-free (exact minimum along its sampled polyline minus the chord deviation bound); otherwise its radius
is halved, and a corner that cannot be blended is passed at rest.

Time parametrization. toppra (``TOPPRA`` with ``ParametrizeConstAccel``, joint velocity and acceleration limits)
gives the v/a-limited speed profile ``ṡ(s)`` of the path; its duration is reported and its speeds cap the
speeds at the piece boundaries.

Jerk limits. The path parameter ``s`` is one degree of freedom, so a 1-DoF ruckig profile of ``s(t)`` can never
leave the path. Each piece gets its own 1-DoF limits: on a straight piece with unit direction ``u`` exactly
``V/|u_i|, A/|u_i|, J/|u_i|``; on a blend limits from the bounds ``M1, M2, M3`` of ``|q'|, |q''|, |q'''|`` so that
``M1·v ≤ V``, ``M2·v² + M1·a ≤ A``, ``M3·v³ + 3·M2·v·a + M1·j ≤ J`` for every joint (the chain rule
``a = q''ṡ² + q's̈``, ``j = q'''ṡ³ + 3q''ṡs̈ + q's⃛``). Boundary states are ``(s_b, ṡ_b, 0)``; a forward-backward
pass lowers the ``ṡ_b`` until every piece is long enough to change speed within its limits, then one ruckig
call per piece (state to state in one DoF, no waypoints needed) times it.

The continuous hard path (:mod:`trajopt.corridor`) uses the other two: :func:`spline_path` (a cubic B-spline of
the corridor's nodes, every span one piece) and :func:`filtered_scaling` (a v/a-limited profile under eroded
limits, box-filtered so that the jerk is bounded and the timing depends continuously on the path).
:func:`min_time_rest_to_rest` is the 1-DoF jerk-limited minimum time (a lower bound, for tests and benchmarks).
"""

from __future__ import annotations

import time
from dataclasses import dataclass, field
from functools import cached_property
from math import comb
from typing import Any, NamedTuple

import numpy as np
from numpy.typing import ArrayLike, NDArray

from mpa import defaults
from mpa.errors import InvalidInputError, PlanningError
from trajopt.sample_kernels import sample_rows

__all__ = [
    "BlendedPath",
    "Limits",
    "PieceLimits",
    "RestToRest",
    "TimeScaling",
    "blend_polyline",
    "filtered_scaling",
    "jerk_limited_scaling",
    "min_time_rest_to_rest",
    "rest_to_rest_profile",
    "spline_path",
    "toppra_profile",
]

FloatArray = NDArray[np.float64]
#: Bézier samples used to check a blend for collisions.
BLEND_SAMPLES = 64
#: Radius halvings tried before a corner is passed at rest.
BLEND_TRIES = 8


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


# ---------------------------------------------------------------------------------------------------
_BINOM5 = np.array([1, 5, 10, 10, 5, 1], dtype=float)


def _bezier_to_monomial(ctrl: FloatArray, length: float) -> FloatArray:
    """Monomial coefficients (shape (6, 2)) of a quintic Bézier in ``τ = t·length``.

    The coefficient of ``t^k`` is ``C(5,k) Σ_{i≤k} (−1)^(k−i) C(k,i) P_i``.
    """
    coef = np.zeros((6, 2))
    for k in range(6):
        for i in range(k + 1):
            coef[k] += _BINOM5[k] * comb(k, i) * (-1) ** (k - i) * ctrl[i]
    return coef / (length ** np.arange(6))[:, None]


@dataclass(frozen=True)
class BlendedPath:
    """A C² path ``q(s)`` in route coordinates made of straight pieces and quintic corner blends.

    Attributes
    ----------
    breaks : ndarray, shape (P+1,)
        Path parameter at the piece ends (metres of σ-plane arc length on straight pieces).
    coef : ndarray, shape (P, 6, 2)
        Monomial coefficients of every piece in ``τ = s − breaks[k]``.
    is_blend : ndarray of bool, shape (P,)
    stop : ndarray of bool, shape (P+1,)
        Boundaries that must be passed at rest (unblended corners, start and end).
    corners : ndarray, shape (M, 2)
        The polyline the path was built from.
    radii : ndarray, shape (M,)
        Blend radius at every corner (0 at the ends and at corners passed at rest).
    """

    breaks: FloatArray
    coef: FloatArray
    is_blend: NDArray[np.bool_]
    stop: NDArray[np.bool_]
    corners: FloatArray
    radii: FloatArray
    bounds: FloatArray = field(repr=False)  # (P, 3, 2): M1, M2, M3 per piece and joint

    @property
    def dof(self) -> int:
        """Degrees of freedom (2: the robots)."""
        return 2

    @property
    def path_interval(self) -> FloatArray:
        """``[0, S]``."""
        return np.array([self.breaks[0], self.breaks[-1]])

    @property
    def length(self) -> float:
        """``S``, the end of the path parameter."""
        return float(self.breaks[-1])

    def __call__(self, s: ArrayLike, order: int = 0, piece: ArrayLike | None = None) -> FloatArray:
        """``q``, ``q'``, ``q''`` or ``q'''`` at ``s`` (toppra's interface). Shape ``s.shape + (2,)``.

        ``piece`` (same shape as ``s``) chooses the piece explicitly (one-sided derivatives at a boundary).
        """
        s_arr = np.asarray(s, dtype=float)
        flat = np.clip(s_arr.ravel(), self.breaks[0], self.breaks[-1])
        if piece is None:
            k = np.clip(np.searchsorted(self.breaks, flat, side="right") - 1, 0, len(self.coef) - 1)
        else:
            k = np.asarray(piece, dtype=np.intp).ravel()
        tau = flat - self.breaks[k]
        c = self.coef[k]  # (n, 6, 2)
        out = np.zeros((len(flat), 2))
        for i in range(order, 6):
            fac = float(np.prod(np.arange(i - order + 1, i + 1))) if order > 0 else 1.0
            out += fac * c[:, i, :] * (tau ** (i - order))[:, None]
        return out.reshape((*s_arr.shape, 2))

    def derivatives(self, s: ArrayLike, piece: ArrayLike | None = None) -> tuple[FloatArray, ...]:
        """``q``, ``q'``, ``q''`` and ``q'''`` at ``s`` (shape (N,)) in one pass, each shape (N, 2).

        The same values as :meth:`__call__` for orders 0 to 3 (``piece`` likewise), by Horner's scheme.
        """
        flat = np.clip(np.asarray(s, dtype=float).ravel(), self.breaks[0], self.breaks[-1])
        if piece is None:
            k = np.clip(np.searchsorted(self.breaks, flat, side="right") - 1, 0, len(self.coef) - 1)
        else:
            k = np.asarray(piece, dtype=np.intp).ravel()
        tau = (flat - self.breaks[k])[:, None]
        deg = self.degree
        c = self.coef[k, : deg + 1]  # (n, deg + 1, 2)
        out = []
        for order in range(4):
            if order > deg:
                out.append(np.zeros((len(flat), 2)))
                continue
            fac = _FALLING[order]
            acc = c[:, deg, :] * fac[deg]
            for i in range(deg - 1, order - 1, -1):
                acc = acc * tau + c[:, i, :] * fac[i]
            out.append(acc)
        return tuple(out)

    @cached_property
    def degree(self) -> int:
        """The highest power with a non-zero coefficient on any piece (0 to 5; 1 for a polyline)."""
        for d in range(self.coef.shape[1] - 1, 0, -1):  # (a few tiny .any() calls: cheaper than one reduction)
            if self.coef[:, d].any():
                return d
        return 0

    def eval(self, s: ArrayLike) -> FloatArray:
        """``q(s)``."""
        return self(s, 0)

    def evald(self, s: ArrayLike) -> FloatArray:
        """``q'(s)``."""
        return self(s, 1)

    def evaldd(self, s: ArrayLike) -> FloatArray:
        """``q''(s)``."""
        return self(s, 2)


#: ``_FALLING[order][i] = i·(i−1)···(i−order+1)``: the factor of ``c_i τ^(i−order)`` in the ``order``-th derivative.
_FALLING = tuple(
    tuple(float(np.prod(np.arange(i - o + 1, i + 1))) if i >= o else 0.0 for i in range(6)) for o in range(4)
)
_FALLING_ARRAY = np.array(_FALLING)  # (4, 6), for the compiled sampler


def _piece_bounds(coef: FloatArray, length: float) -> FloatArray:
    """Rigorous bounds (shape (3, 2)) of the first three derivatives' magnitudes per joint on a polynomial piece."""
    return _piece_bounds_many(coef[None], np.array([length]))[0]


def _cubic_bounds(coef: FloatArray, length: float) -> FloatArray:
    """Exact bounds (shape (P, 3, 2)) of the first three derivatives' magnitudes of cubic pieces on ``[0, length]``.

    The third derivative is constant, the second linear (extremes at the ends), the first quadratic (ends or its
    vertex); a maximum of continuous functions of the coefficients, so continuous too.
    """
    c1, c2, c3 = coef[:, 1], coef[:, 2], coef[:, 3]
    L = float(length)
    two_c2, three_c3, six_c3 = 2 * c2, 3 * c3, 6 * c3
    cubic = c3 != 0
    tv = np.where(cubic, -c2 / np.where(cubic, three_c3, 1.0), -1.0)  # the vertex of the first derivative
    inside = (tv > 0) & (tv < L)
    out = np.empty((len(coef), 3, 2))
    m1 = np.maximum(np.abs(c1), np.abs(c1 + two_c2 * L + three_c3 * L * L))
    np.maximum(m1, np.where(inside, np.abs(c1 + two_c2 * tv + three_c3 * tv * tv), 0.0), out=out[:, 0])
    np.maximum(np.abs(two_c2), np.abs(two_c2 + six_c3 * L), out=out[:, 1])
    np.abs(six_c3, out=out[:, 2])
    out *= 1 + 1e-9
    return out


def _piece_bounds_many(coef: FloatArray, length: FloatArray, n: int = 257) -> FloatArray:
    """:func:`_piece_bounds` of many pieces at once: ``coef`` shape (P, 6, 2), ``length`` (P,); shape (P, 3, 2).

    Dense evaluation at ``n`` points plus the next derivative's bound times half the step (the fourth derivative
    of a quintic is linear: its maximum is at an end, exactly).
    """
    P = len(coef)
    out = np.zeros((P, 3, 2))
    ok = length > 0
    if not np.any(ok):
        return out
    c = coef[ok]
    L = length[ok]
    x = np.linspace(0.0, 1.0, n)[None, :] * L[:, None]  # (p, n)
    h = L / (n - 1)
    ders = []
    for order in (1, 2, 3, 4):
        val = np.zeros((len(c), n, 2))
        for i in range(order, 6):
            fac = float(np.prod(np.arange(i - order + 1, i + 1)))
            val += fac * c[:, None, i, :] * (x ** (i - order))[:, :, None]
        ders.append(np.max(np.abs(val), axis=1))  # (p, 2)
    hh = (h / 2)[:, None]
    m4 = ders[3]
    m3 = ders[2] + m4 * hh
    m2 = ders[1] + m3 * hh
    m1 = ders[0] + m2 * hh
    out[ok] = np.stack([m1, m2, m3], axis=1) * (1 + 1e-9)
    return out


def _blend_ctrl(c: FloatArray, u1: FloatArray, u2: FloatArray, r: float) -> FloatArray:
    p1, p2 = c - r * u1, c + r * u2
    return np.array([p1, p1 + 0.5 * r * u1, c, c, p2 - 0.5 * r * u2, p2])


def _even_blend_ctrl(c: FloatArray, u1: FloatArray, u2: FloatArray, r: float) -> FloatArray:
    """Control points ``C − r·u1, C − 0.6r·u1, C − 0.2r·u1, C + 0.2r·u2, C + 0.6r·u2, C + r·u2``.

    With the parameter length ``2r`` the blend leaves and joins the lines at unit speed with zero curvature (C²),
    lies in the triangle ``(C − r·u1, C, C + r·u2)``, and a straight corner (``u1 = u2``) is the line itself at
    unit speed: the blend degenerates continuously.
    """
    return np.array([c - r * u1, c - 0.6 * r * u1, c - 0.2 * r * u1, c + 0.2 * r * u2, c + 0.6 * r * u2, c + r * u2])


def _bezier_points(ctrl: FloatArray, n: int) -> FloatArray:
    t = np.linspace(0.0, 1.0, n)[:, None]
    out = np.zeros((n, 2))
    for i in range(6):
        out += _BINOM5[i] * t**i * (1 - t) ** (5 - i) * ctrl[i]
    return out


def blend_polyline(
    corners: ArrayLike,
    min_distance: Any = None,
    separation: float = 0.0,
    radius_cap: float = np.inf,
    radii: ArrayLike | None = None,
) -> BlendedPath:
    """Build the C² path through a polyline with collision-checked corner blends.

    Parameters
    ----------
    corners : array_like, shape (M, 2)
        Polyline in route coordinates (first = start, last = goal); consecutive points distinct.
    min_distance : callable, optional
        ``min_distance(points)`` -> exact minimum separation along the polyline through ``points``
        (:meth:`mpa.geometry.RouteGeometry.polyline_min_distance`). Without it no corner is blended.
    separation : float
        Separation every blend must keep (metres).
    radius_cap : float
        Largest blend radius (metres).
    radii : array_like, shape (M,), optional
        Given blend radii (the caller vouches that they are collision-free): no check, no halving, and every
        interior corner with a positive radius gets a blend piece, a straight one included, so the piece
        structure depends only on which radii are positive (the continuous hard path,
        :mod:`trajopt.corridor`). Corners with radius 0 are passed at rest.

    Returns
    -------
    BlendedPath
    """
    p = np.atleast_2d(np.asarray(corners, dtype=float))
    m = len(p)
    seg = np.diff(p, axis=0)
    ln = np.linalg.norm(seg, axis=1)
    if m >= 2 and np.any(ln <= 0):
        raise PlanningError("polyline has repeated corners")
    u = seg / ln[:, None] if m >= 2 else np.zeros((0, 2))
    if radii is not None:
        rad = np.array(radii, dtype=float)
        blends = _blends_of_given_radii(p, u, rad)
    else:
        rad = np.zeros(m)
        blends = {} if min_distance is None else _checked_blends(p, u, ln, rad, min_distance, separation, radius_cap)
    return _assemble_blended_path(p, u, ln, rad, blends, radii is not None)


_Blends = dict[int, tuple[FloatArray, FloatArray]]  # corner index -> (monomial coefficients, derivative bounds)


def _blends_of_given_radii(p: FloatArray, u: FloatArray, rad: FloatArray) -> _Blends:
    """Even blends of the interior corners ``p[i]`` with radius ``rad[i] > 0`` (unchecked; ``rad``'s end entries
    are set to 0 in place)."""
    blends: _Blends = {}
    rad[0] = rad[-1] = 0.0
    for i in range(1, len(p) - 1):
        if rad[i] > 0:
            coef = _bezier_to_monomial(_even_blend_ctrl(p[i], u[i - 1], u[i], rad[i]), 2.0 * rad[i])
            blends[i] = (coef, _piece_bounds(coef, 2.0 * rad[i]))
    return blends


def _checked_blends(
    p: FloatArray,
    u: FloatArray,
    ln: FloatArray,
    rad: FloatArray,
    min_distance: Any,
    separation: float,
    radius_cap: float,
) -> _Blends:
    """Blends of the interior corners that keep ``separation`` (``min_distance`` minus the blend's deviation),
    the radius halved up to :data:`BLEND_TRIES` times; the radii found are written into ``rad``."""
    blends: _Blends = {}
    for i in range(1, len(p) - 1):
        if abs(float(u[i - 1] @ u[i])) > 1 - 1e-12 and float(u[i - 1] @ u[i]) > 0:
            continue  # collinear: no corner
        r = min(0.5 * ln[i - 1], 0.5 * ln[i], radius_cap)
        for _ in range(BLEND_TRIES):
            ctrl = _blend_ctrl(p[i], u[i - 1], u[i], r)
            lb = 2.5 * r
            coef = _bezier_to_monomial(ctrl, lb)
            bnd = _piece_bounds(coef, lb)
            pts = _bezier_points(ctrl, BLEND_SAMPLES)
            h = lb / (BLEND_SAMPLES - 1)  # the parameter is not arc length; h is its step
            dev = float(np.sum(bnd[1])) * h * h / 8.0
            if min_distance(pts) - dev >= separation:
                rad[i] = r
                blends[i] = (coef, bnd)
                break
            r *= 0.5
    return blends


def _assemble_blended_path(
    p: FloatArray, u: FloatArray, ln: FloatArray, rad: FloatArray, blends: _Blends, given: bool
) -> BlendedPath:
    """The pieces in order: each segment's straight part (if any is left) and the blend of its end corner; a
    corner without a blend is passed at rest."""
    m = len(p)
    brk = [0.0]
    coefs: list[FloatArray] = []
    isb: list[bool] = []
    stop = [True]
    bnds: list[FloatArray] = []
    for i in range(m - 1):
        a = p[i] + rad[i] * u[i]
        b_len = ln[i] - rad[i] - rad[i + 1]
        if b_len > 1e-12:
            c = np.zeros((6, 2))
            c[0], c[1] = a, u[i]
            coefs.append(c)
            isb.append(False)
            bnds.append(np.stack([np.abs(u[i]), np.zeros(2), np.zeros(2)]))
            brk.append(brk[-1] + b_len)
            stop.append(False)
        if i + 1 < m - 1:
            if rad[i + 1] > 0:
                c, bd = blends[i + 1]
                coefs.append(c)
                isb.append(True)
                bnds.append(bd)
                brk.append(brk[-1] + (2.0 if given else 2.5) * rad[i + 1])
                stop.append(False)
            else:
                stop[-1] = True
    stop[-1] = True
    if not coefs:  # a single point
        c = np.zeros((6, 2))
        c[0] = p[0]
        coefs.append(c)
        isb.append(False)
        bnds.append(np.zeros((3, 2)))
        brk.append(0.0)
        stop.append(True)
    return BlendedPath(
        breaks=np.array(brk),
        coef=np.array(coefs),
        is_blend=np.array(isb),
        stop=np.array(stop),
        corners=p,
        radii=rad,
        bounds=np.array(bnds),
    )


def spline_path(control: ArrayLike, span: float | None = None) -> BlendedPath:
    """The uniform cubic B-spline of the control polygon ``control`` (shape (n+1, 2), n ≥ 2), ends reflected.

    Ghost points ``2·c_0 − c_1`` and ``2·c_n − c_{n−1}`` make it start at ``c_0`` and end at ``c_n`` with zero
    curvature and the speed of the adjacent leg. Span ``i`` (``i = 0 … n−1``) uses ``c_{i−1} … c_{i+2}`` and lies
    in their convex hull (at the ends the ghost's weight is absorbed: the weights stay non-negative), so it lies in
    the hull of at most four consecutive control points; evenly spaced collinear points give the line at constant
    speed. The parameter length of a span is ``span`` (default: the polygon's length divided by ``n``). Every span
    is one piece (``is_blend`` true: its limits come from the bounds of its first three derivatives); only the ends
    are passed at rest.
    """
    c = np.atleast_2d(np.asarray(control, dtype=float))
    n = len(c) - 1
    if n < 2:
        raise PlanningError(f"a cubic spline needs at least 3 control points, got {n + 1}")
    if span is None:
        leg = c[1:] - c[:-1]
        span = float(np.sqrt(leg[:, 0] * leg[:, 0] + leg[:, 1] * leg[:, 1]).sum()) / n  # (np.linalg.norm's sum)
    if not span > 0:
        raise PlanningError("the control polygon has length 0")
    g = np.vstack([2 * c[0] - c[1], c, 2 * c[-1] - c[-2]])
    p0, p1, p2, p3 = g[:-3], g[1:-2], g[2:-1], g[3:]
    coef = np.zeros((n, 6, 2))
    coef[:, 0] = (p0 + 4 * p1 + p2) / 6
    coef[:, 1] = (p2 - p0) / 2 / span
    coef[:, 2] = (p0 - 2 * p1 + p2) / 2 / span**2
    coef[:, 3] = (-p0 + 3 * p1 - 3 * p2 + p3) / 6 / span**3
    coef[0, 0], coef[-1, 0] = c[0], coef[-1, 0]
    bounds = _cubic_bounds(coef, span)
    stop = np.zeros(n + 1, dtype=bool)
    stop[0] = stop[-1] = True
    return BlendedPath(
        breaks=np.arange(n + 1, dtype=float) * float(span),
        coef=coef,
        is_blend=np.ones(n, dtype=bool),
        stop=stop,
        corners=c,
        radii=np.zeros(n + 1),
        bounds=bounds,
    )


# ---------------------------------------------------------------------------------------------------
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


def _dmin(v0: float, v1: float, a: float, j: float) -> float:
    """Shortest distance to change speed from ``v0`` to ``v1`` (both ≥ 0) at zero acceleration at both ends."""
    dv = abs(v1 - v0)
    t = 2.0 * np.sqrt(dv / j) if dv <= a * a / j else dv / a + a / j
    return 0.5 * (v0 + v1) * t


def _reach(v0: float, ds: float, cap: float, a: float, j: float) -> float:
    """Highest speed ``≤ cap`` reachable from ``v0`` within ``ds`` (a = 0 at both ends)."""
    if _dmin(v0, cap, a, j) <= ds:
        return cap
    lo, hi = min(v0, cap), cap
    for _ in range(60):
        mid = 0.5 * (lo + hi)
        if _dmin(v0, mid, a, j) <= ds:
            lo = mid
        else:
            hi = mid
    return lo


def toppra_profile(
    path: BlendedPath, limits: Limits, n_grid: int = 100, per_piece: int | None = None
) -> tuple[FloatArray, FloatArray, float]:
    """The v/a-limited time-optimal speed profile of ``path`` with toppra.

    ``per_piece`` (instead of ``n_grid``) puts that many equal intervals on every piece: the grid then moves
    continuously with the path and its size depends only on the number of pieces.

    Returns
    -------
    grid : ndarray, shape (G,)
        Grid of the path parameter (contains every piece boundary).
    sd : ndarray, shape (G,)
        Path speed ``ṡ`` on the grid.
    duration : float
        Duration of the const-acceleration parametrization (s): a lower bound of the jerk-limited one.

    Raises
    ------
    PlanningError
        toppra reports a failure (its ``return_code``).
    """
    # (toppra's logging is left as the application configured it: a library configures no logging)
    import toppra.algorithm as algo
    import toppra.constraint as constraint

    if per_piece is not None:
        frac = np.arange(int(per_piece)) / int(per_piece)
        br = path.breaks
        grid = np.concatenate([(br[:-1, None] + frac[None, :] * np.diff(br)[:, None]).ravel(), br[-1:]])
    else:
        grid = np.unique(np.concatenate([np.linspace(0.0, path.length, n_grid), path.breaks]))
    vlim = np.stack([-limits.v, limits.v], axis=1)
    alim = np.stack([-limits.a, limits.a], axis=1)
    cons = [constraint.JointVelocityConstraint(vlim), constraint.JointAccelerationConstraint(alim)]
    inst = algo.TOPPRA(cons, path, gridpoints=grid, parametrizer="ParametrizeConstAccel")
    inst.compute_parameterization(0.0, 0.0)
    data = inst.problem_data
    if data.return_code != algo.ParameterizationReturnCode.Ok or data.sd_vec is None:
        raise PlanningError(f"toppra failed: {data.return_code}")
    sd = np.sqrt(np.maximum(np.asarray(data.sd_vec, dtype=float), 0.0))
    ds = np.diff(grid)
    avg = sd[:-1] + sd[1:]
    with np.errstate(divide="ignore"):
        dur = float(np.sum(np.where(avg > 0, 2 * ds / avg, np.inf)))
    return grid, sd, dur


# ---------------------------------------------------------------------------------------------------
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

        Row by row in one compiled call (:func:`trajopt.sample_kernels.sample_rows`): the phase's polynomial
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


def jerk_limited_scaling(
    path: BlendedPath,
    limits: Limits,
    speed_caps: FloatArray | None = None,
    safety: float = 1.0 - 1e-9,
) -> TimeScaling:
    """Time the path with one 1-DoF ruckig profile per piece (see module docstring).

    Parameters
    ----------
    path : BlendedPath
    limits : Limits
    speed_caps : ndarray, shape (P+1,), optional
        Upper bounds of ``ṡ`` at the piece boundaries (e.g. toppra's profile).
    safety : float
        Factor applied to the joint limits.

    Returns
    -------
    TimeScaling

    Raises
    ------
    PlanningError
        If ruckig reports an error.
    """
    t_start = time.perf_counter()
    P = len(path.coef)
    lens = np.diff(path.breaks)
    if path.length <= 0:
        return TimeScaling(path, np.zeros(0), np.zeros(0), np.zeros(0), np.zeros(0), np.zeros(0), 0.0, np.zeros(P + 1))
    pl = piece_limits(path, limits, safety)
    vb = _boundary_speeds(path, pl, lens, speed_caps)
    t0s, ps, vs, as_, js, pcs, t_acc = _ruckig_phases(path, pl, lens, vb)
    stats = {"pieces": P, "blends": int(np.sum(path.is_blend)), "jerk_time": time.perf_counter() - t_start}
    return TimeScaling(
        path,
        np.array(t0s),
        np.array(ps),
        np.array(vs),
        np.array(as_),
        np.array(js),
        float(t_acc),
        vb,
        np.array(pcs, dtype=np.intp),
        stats,
    )


def _boundary_speeds(path: BlendedPath, pl: PieceLimits, lens: FloatArray, speed_caps: ArrayLike | None) -> FloatArray:
    """Speeds at the piece boundaries (shape (P + 1,)): the pieces' speed limits and the caps, 0 at stops, then
    lowered by a forward and a backward pass to what a jerk-limited piece can reach."""
    P = len(lens)
    vb = np.full(P + 1, np.inf)
    vb[1:] = np.minimum(vb[1:], pl.v)
    vb[:-1] = np.minimum(vb[:-1], pl.v)
    vb[path.stop] = 0.0
    if speed_caps is not None:
        vb = np.minimum(vb, np.asarray(speed_caps, dtype=float))
    vb = np.maximum(vb, 0.0)
    for k in range(P):  # forward
        vb[k + 1] = min(vb[k + 1], _reach(vb[k], lens[k] * (1 - 1e-9), vb[k + 1], pl.a[k], pl.j[k]))
    for k in range(P - 1, -1, -1):  # backward
        vb[k] = min(vb[k], _reach(vb[k + 1], lens[k] * (1 - 1e-9), vb[k], pl.a[k], pl.j[k]))
    return vb


def _ruckig_phases(
    path: BlendedPath, pl: PieceLimits, lens: FloatArray, vb: FloatArray
) -> tuple[list[float], list[float], list[float], list[float], list[float], list[int], float]:
    """One 1-DoF ruckig profile per piece between the boundary speeds ``vb``: the phases of constant jerk (start
    times, ``s, ṡ, s̈``, jerks, piece index) and the total duration.

    Raises
    ------
    PlanningError
        ruckig fails or needs a brake profile on a piece.
    """
    from ruckig import InputParameter, Result, Ruckig, Trajectory

    otg = Ruckig(1)
    inp = InputParameter(1)
    traj = Trajectory(1)
    t0s: list[float] = []
    ps: list[float] = []
    vs: list[float] = []
    as_: list[float] = []
    js: list[float] = []
    pcs: list[int] = []
    t_acc = 0.0
    for k in range(len(lens)):
        if lens[k] <= 0:
            continue
        inp.current_position = [float(path.breaks[k])]
        inp.current_velocity = [float(vb[k])]
        inp.current_acceleration = [0.0]
        inp.target_position = [float(path.breaks[k + 1])]
        inp.target_velocity = [float(vb[k + 1])]
        inp.target_acceleration = [0.0]
        inp.max_velocity = [float(pl.v[k])]
        inp.max_acceleration = [float(pl.a[k])]
        inp.max_jerk = [float(pl.j[k])]
        res = otg.calculate(inp, traj)
        if res not in (Result.Working, Result.Finished):
            raise PlanningError(f"ruckig failed on piece {k}: {res}")
        prof = traj.profiles[0][0]
        if prof.brake.duration > 0 or prof.accel.duration > 0:
            raise PlanningError(f"ruckig used a brake profile on piece {k}")
        tp = np.asarray(prof.t, dtype=float)
        for i in range(7):
            if tp[i] <= 0:
                continue
            t0s.append(t_acc)
            ps.append(prof.p[i])
            vs.append(prof.v[i])
            as_.append(prof.a[i])
            js.append(prof.j[i])
            pcs.append(k)
            t_acc += tp[i]
    return t0s, ps, vs, as_, js, pcs, t_acc


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


class RestToRest(NamedTuple):
    """A 1-DoF jerk-limited profile from rest at 0 to rest at ``length``: ruckig's seven phases.

    ``dt`` (shape (7,)) the phase durations (some may be 0), ``t0`` their start times, ``p, v, a`` the state at
    each phase start and ``j`` the phase's constant jerk (each shape (7,)); ``duration`` the sum of ``dt``.
    """

    dt: FloatArray
    t0: FloatArray
    p: FloatArray
    v: FloatArray
    a: FloatArray
    j: FloatArray
    duration: float


def rest_to_rest_profile(length: float, v: float, a: float, j: float) -> RestToRest:
    """The time-optimal jerk-limited 1-DoF profile over ``length`` (m) from rest to rest (ruckig; ``length > 0``).

    Raises
    ------
    PlanningError
        ruckig reports a failure.
    """
    from ruckig import InputParameter, Result, Ruckig, Trajectory

    otg, inp, traj = Ruckig(1), InputParameter(1), Trajectory(1)
    inp.current_position, inp.target_position = [0.0], [float(length)]
    inp.current_velocity = inp.target_velocity = [0.0]
    inp.current_acceleration = inp.target_acceleration = [0.0]
    inp.max_velocity, inp.max_acceleration, inp.max_jerk = [float(v)], [float(a)], [float(j)]
    res = otg.calculate(inp, traj)
    if res not in (Result.Working, Result.Finished):
        raise PlanningError(f"ruckig failed on a rest-to-rest move of {length!r} m: {res}")
    prof = traj.profiles[0][0]
    dt = np.asarray(prof.t, dtype=float)
    t0 = np.concatenate([[0.0], np.cumsum(dt)])[:-1]
    p, vv, aa = (np.asarray(x[:7], dtype=float) for x in (prof.p, prof.v, prof.a))
    return RestToRest(dt, t0, p, vv, aa, np.asarray(prof.j, dtype=float), float(dt.sum()))


def min_time_rest_to_rest(distance: float, v: float, a: float, j: float) -> float:
    """Jerk-limited minimum time (s) to travel ``distance`` from rest to rest in one DoF (ruckig)."""
    if distance <= 0:
        return 0.0
    return rest_to_rest_profile(distance, v, a, j).duration
