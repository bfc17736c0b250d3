"""Path geometry: the smoothed polyline as a C² path :class:`BlendedPath` ``q(s)``, and the cubic B-spline of the
hard path's nodes.

The smoothed polyline in route coordinates becomes :class:`BlendedPath` ``q(s)`` (``s`` = Euclidean arc length in
the σ-plane on the straight parts): straight pieces joined at every corner by a quintic Bézier blend with control
points ``P1, P1 + r/2·u1, C, C, P2 − r/2·u2, P2`` (``C`` the corner, ``P1 = C − r·u1``, ``P2 = C + r·u2``). It
leaves and joins the straight lines with the same tangent and zero curvature (C²), and lies in the triangle
``P1 C P2`` (convex hull of its control points). A blend is kept only if it is exactly collision-free (exact
minimum along its sampled polyline minus the chord deviation bound); otherwise its radius is halved, and a corner
that cannot be blended is passed at rest (:func:`blend_polyline`).

The continuous hard path (:mod:`trajopt.path.corridor`) uses :func:`spline_path`: a cubic B-spline of the corridor's
nodes, every span one piece.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from functools import cached_property
from math import comb
from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from mpa._arrays import FloatArray
from mpa.errors import PlanningError

#: Bézier samples used to check a blend for collisions.
BLEND_SAMPLES = 64
#: Radius halvings tried before a corner is passed at rest.
BLEND_TRIES = 8


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
        :mod:`trajopt.path.corridor`). Corners with radius 0 are passed at rest.

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
