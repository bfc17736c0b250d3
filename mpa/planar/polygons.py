"""Convex polygons in the offsets ``(s, t)`` of a cell: areas, half-planes, hulls, membership, intersections, the
free pieces' record and the shared points of two glued pieces."""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

import numpy as np

from mpa._arrays import FloatArray
from mpa.freespace import _clip

Coords = tuple[float, float]
TOUCH = 1e-9  # times max(1, total length): bodies this close count as apart


def _area(p: list[Coords]) -> float:
    n = len(p)
    if n < 3:
        return 0.0
    return 0.5 * sum(p[i][0] * p[(i + 1) % n][1] - p[(i + 1) % n][0] * p[i][1] for i in range(n))


def _halfplanes(poly: list[Coords], slack: float) -> list[tuple[float, float, float]]:
    """Half-planes ``a*s + b*t >= c`` of a counter-clockwise convex polygon, loosened by ``slack`` metres."""
    out = []
    n = len(poly)
    for i in range(n):
        (x0, y0), (x1, y1) = poly[i], poly[(i + 1) % n]
        a, b = -(y1 - y0), x1 - x0
        nrm = math.hypot(a, b)
        if nrm <= 0.0:
            continue
        out.append((a / nrm, b / nrm, (a * x0 + b * y0) / nrm - slack))
    return out


def _hull(pts: FloatArray) -> FloatArray:
    """Convex hull, counter-clockwise (monotone chain)."""
    p = sorted(map(tuple, np.round(pts, 15)))
    if len(p) <= 2:
        return np.array(p)

    def cross(o: Any, a: Any, b: Any) -> float:
        return float((a[0] - o[0]) * (b[1] - o[1]) - (a[1] - o[1]) * (b[0] - o[0]))

    lower: list[Any] = []
    for q in p:
        while len(lower) >= 2 and cross(lower[-2], lower[-1], q) <= 0:
            lower.pop()
        lower.append(q)
    upper: list[Any] = []
    for q in reversed(p):
        while len(upper) >= 2 and cross(upper[-2], upper[-1], q) <= 0:
            upper.pop()
        upper.append(q)
    return np.array(lower[:-1] + upper[:-1])


def _inside(poly: FloatArray, s: float, t: float, tol: float) -> bool:
    n = len(poly)
    if n == 1:
        return abs(poly[0, 0] - s) <= tol and abs(poly[0, 1] - t) <= tol
    if n == 2 or abs(_area([tuple(x) for x in poly])) <= tol * tol:
        # degenerate: distance to the segment hull
        best = math.inf
        for i in range(n):
            a, b = poly[i], poly[(i + 1) % n]
            ab = b - a
            den = float(ab @ ab)
            lam = 0.0 if den <= 0 else min(1.0, max(0.0, float((np.array([s, t]) - a) @ ab) / den))
            best = min(best, math.hypot(a[0] + lam * ab[0] - s, a[1] + lam * ab[1] - t))
        return best <= tol
    for a, b, c in _halfplanes([tuple(x) for x in poly], tol):
        if a * s + b * t < c:
            return False
    return True


def _meet(p: FloatArray, q: FloatArray, tol: float) -> list[Coords] | None:
    """Points of the intersection of two closed convex polygons (within ``tol``), None if they do not meet."""
    small, big = (p, q) if abs(_area([tuple(x) for x in p])) <= abs(_area([tuple(x) for x in q])) else (q, p)
    if len(big) >= 3 and abs(_area([tuple(x) for x in big])) > tol * tol:
        out: list[Coords] = [tuple(x) for x in small]
        for a, b, c in _halfplanes([tuple(x) for x in big], tol):
            out = _clip(out, a, b, c)
            if not out:
                return None
        return out
    # both degenerate: a vertex of one close to the other
    for v in small:
        if _inside(big, float(v[0]), float(v[1]), tol):
            return [(float(v[0]), float(v[1]))]
    for v in big:
        if _inside(small, float(v[0]), float(v[1]), tol):
            return [(float(v[0]), float(v[1]))]
    return None


@dataclass(frozen=True)
class _Piece:
    cell: tuple[int, int, int]  # (edge A, edge B, along-track piece k)
    sub: tuple[int, int]  # (drawing piece of A, drawing piece of B)
    poly: FloatArray  # (n, 2) offsets (s, t), counter-clockwise


def _portal_values(a0: float, a1: float) -> list[float]:
    if a1 - a0 <= 1e-12:
        return [0.5 * (a0 + a1)]
    return [a0, 0.5 * (a0 + a1), a1]


def _portal_points(m: list[Coords]) -> list[Coords]:
    """The shared points of a glued pair: its one point, or the two points of ``m`` farthest apart (the first such
    pair in row-major order: the ends of a shared segment) with their middle between them."""
    n = len(m)
    if n == 1:
        return [(float(m[0][0]), float(m[0][1]))]
    arr = np.asarray(m, dtype=float)
    dist = np.hypot(arr[:, None, 0] - arr[None, :, 0], arr[:, None, 1] - arr[None, :, 1])
    bi, bj = divmod(int(np.argmax(dist)), n)  # the first largest in row-major order
    a = (float(m[bi][0]), float(m[bi][1]))
    b = (float(m[bj][0]), float(m[bj][1]))
    # the exact middle of the two ends (not the mean of m, whose near-duplicate points move it off the middle):
    # the one-way search reads an end, middle, end triple as the whole segment (_parts)
    return [a, (0.5 * (a[0] + b[0]), 0.5 * (a[1] + b[1])), b]
