"""An independent checker of bodies in the plane, for the tests (shares no code with mpa.footprint, mpa.planar or
trajopt.verify.planar): poses from the layout's own coordinates, discs exactly, rectangles as polygons with their own
separating-axis distance, a robot on a corner in every orientation there.

Along a motion (``depth_many(..., along=True)``) a robot on a vertex or a polyline corner takes the orientations of
the pieces it arrives on and leaves by, as the documented model says ("the body takes the orientation of the piece it
is on", docs/graphs.md "Footprints in the plane"): a robot that passes straight through a switch (main to east) keeps
the heading of main and east there and is never turned to the siding's diagonal, which meets the same vertex; one that
drives up to a polyline corner and back keeps the heading of the piece it drove on. Only a robot whose arrival or
departure is not in the samples (a motion that starts or ends there) takes every orientation there."""

from __future__ import annotations

import math
from typing import Any

import numpy as np


class Drawn:
    """A layout's drawing read from its dict: per edge the polyline and the offsets of its points."""

    def __init__(self, layout: dict[str, Any], lengths: list[float]) -> None:
        vx = layout["vertices"]
        self.polys: list[np.ndarray] = []
        self.offs: list[np.ndarray] = []
        for k, e in enumerate(layout["edges"]):
            pts = np.array([vx[e["from"]], *e.get("points", []), vx[e["to"]]], dtype=float)
            seg = np.hypot(*np.diff(pts, axis=0).T)
            cum = np.concatenate([[0.0], np.cumsum(seg)])
            self.polys.append(pts)
            self.offs.append(cum / cum[-1] * lengths[k])
        self.ends = [(e["from"], e["to"]) for e in layout["edges"]]

    def point(self, e: int, o: float) -> np.ndarray:
        pts, off = self.polys[e], self.offs[e]
        return np.array([np.interp(o, off, pts[:, 0]), np.interp(o, off, pts[:, 1])])

    def vertex_of(self, e: int, o: float, tol: float) -> str | None:
        """The vertex a robot at offset o of edge e stands on (within tol metres), None inside the edge."""
        if o <= tol:
            return str(self.ends[e][0])
        if o >= self.offs[e][-1] - tol:
            return str(self.ends[e][1])
        return None

    def end_headings(self, e: int, name: str) -> list[float]:
        """The directions of edge e's pieces that meet vertex ``name`` (empty when e does not meet it)."""
        p = self.polys[e]
        out = []
        if self.ends[e][0] == name:
            out.append(math.atan2(*(p[1] - p[0])[::-1]))
        if self.ends[e][1] == name:
            out.append(math.atan2(*(p[-1] - p[-2])[::-1]))
        return out

    def headings(self, e: int, o: float, tol: float = 1e-7) -> list[float]:
        """The directions of the polyline pieces at offset o: one inside a piece; all at a corner or vertex."""
        pts, off = self.polys[e], self.offs[e]
        out: list[float] = []
        if o <= tol or o >= off[-1] - tol:  # a vertex: every piece of every edge there
            name = self.ends[e][0] if o <= tol else self.ends[e][1]
            for f, (a, b) in enumerate(self.ends):
                p = self.polys[f]
                if a == name:
                    out.append(math.atan2(*(p[1] - p[0])[::-1]))
                if b == name:
                    out.append(math.atan2(*(p[-1] - p[-2])[::-1]))
            return out
        for i in range(len(off) - 1):
            if off[i] - tol <= o <= off[i + 1] + tol and off[i + 1] > off[i]:
                out.append(math.atan2(*(pts[i + 1] - pts[i])[::-1]))
        return out


def rect(c: np.ndarray, h: float, length: float, width: float) -> np.ndarray:
    u = np.array([math.cos(h), math.sin(h)])
    n = np.array([-u[1], u[0]])
    return np.array(
        [c + sx * 0.5 * length * u + sy * 0.5 * width * n for sx, sy in ((-1, -1), (1, -1), (1, 1), (-1, 1))]
    )


def _pt_seg(p: np.ndarray, a: np.ndarray, b: np.ndarray) -> float:
    ab = b - a
    lam = min(1.0, max(0.0, float((p - a) @ ab) / float(ab @ ab)))
    return float(np.hypot(*(a + lam * ab - p)))


def _inside(p: np.ndarray, poly: np.ndarray) -> bool:
    s = [np.cross(poly[(i + 1) % 4] - poly[i], p - poly[i]) for i in range(4)]
    return all(x >= 0 for x in s) or all(x <= 0 for x in s)


def _segments_cross(a: np.ndarray, b: np.ndarray, c: np.ndarray, d: np.ndarray) -> bool:
    def o(p: np.ndarray, q: np.ndarray, r: np.ndarray) -> float:
        return float(np.cross(q - p, r - p))

    return o(a, b, c) * o(a, b, d) < 0 and o(c, d, a) * o(c, d, b) < 0


def poly_distance(p: np.ndarray, q: np.ndarray) -> float:
    """Distance between two convex quadrilaterals, 0 (or negative-free 0) when they overlap."""
    if any(_inside(v, q) for v in p) or any(_inside(v, p) for v in q):
        return 0.0
    for i in range(4):
        for j in range(4):
            if _segments_cross(p[i], p[(i + 1) % 4], q[j], q[(j + 1) % 4]):
                return 0.0
    best = math.inf
    for a, b in ((p, q), (q, p)):
        for v in a:
            for j in range(4):
                best = min(best, _pt_seg(v, b[j], b[(j + 1) % 4]))
    return best


def gap(
    drawn: Drawn, fa: tuple[float, ...], pos_a: tuple[int, float], fb: tuple[float, ...], pos_b: tuple[int, float]
) -> float:
    """Distance between the bodies (0 when they touch or overlap), every orientation at a corner.

    A footprint is ``(r,)`` (disc) or ``(length, width)`` (rectangle).
    """
    ca, cb = drawn.point(*pos_a), drawn.point(*pos_b)
    if len(fa) == 1 and len(fb) == 1:
        return max(0.0, float(np.hypot(*(ca - cb))) - fa[0] - fb[0])
    best = math.inf
    for ha in drawn.headings(*pos_a):
        for hb in drawn.headings(*pos_b):
            if len(fa) == 1:
                q = rect(cb, hb, *fb)
                d = 0.0 if _inside(ca, q) else min(_pt_seg(ca, q[j], q[(j + 1) % 4]) for j in range(4))
                best = min(best, max(0.0, d - fa[0]))
            elif len(fb) == 1:
                q = rect(ca, ha, *fa)
                d = 0.0 if _inside(cb, q) else min(_pt_seg(cb, q[j], q[(j + 1) % 4]) for j in range(4))
                best = min(best, max(0.0, d - fb[0]))
            else:
                best = min(best, poly_distance(rect(ca, ha, *fa), rect(cb, hb, *fb)))
    return best


def overlap_depth(
    drawn: Drawn,
    fa: tuple[float, ...],
    pos_a: tuple[int, float],
    fb: tuple[float, ...],
    pos_b: tuple[int, float],
    heads_a: list[float] | None = None,
    heads_b: list[float] | None = None,
) -> float:
    """How deep the bodies overlap (0 if they do not): the smallest push apart over the separating axes (metres),
    every orientation at a corner unless ``heads_a`` / ``heads_b`` (radians) give the orientations. Positive means
    overlap."""
    ca, cb = drawn.point(*pos_a), drawn.point(*pos_b)
    worst = 0.0
    for ha in drawn.headings(*pos_a) if heads_a is None else heads_a:
        for hb in drawn.headings(*pos_b) if heads_b is None else heads_b:
            pa = _shape(fa, ca, ha)
            pb = _shape(fb, cb, hb)
            worst = max(worst, _depth(pa, pb, ca, cb, fa, fb))
    return worst


def _shape(fp: tuple[float, ...], c: np.ndarray, h: float) -> np.ndarray:
    return rect(c, h, *fp) if len(fp) == 2 else c[None, :]


def _depth(
    p: np.ndarray, q: np.ndarray, ca: np.ndarray, cb: np.ndarray, fa: tuple[float, ...], fb: tuple[float, ...]
) -> float:
    if len(fa) == 1 and len(fb) == 1:
        return max(0.0, fa[0] + fb[0] - float(np.hypot(*(ca - cb))))
    if len(fa) == 1 or len(fb) == 1:
        r, c, poly = (fa[0], ca, q) if len(fa) == 1 else (fb[0], cb, p)
        d = 0.0 if _inside(c, poly) else min(_pt_seg(c, poly[j], poly[(j + 1) % 4]) for j in range(4))
        return max(0.0, r - d)
    depth = math.inf
    for poly in (p, q):  # two rectangles: their four edge normals separate them if anything does
        d = np.roll(poly, -1, axis=0) - poly
        for ax in np.stack([-d[:, 1], d[:, 0]], axis=1) / np.hypot(*d.T)[:, None]:
            a, b = p @ ax, q @ ax
            depth = min(depth, min(a.max() - b.min(), b.max() - a.min()))
    return max(0.0, depth)


def depth_many(
    drawn: Drawn,
    fa: tuple[float, ...],
    fb: tuple[float, ...],
    ea: np.ndarray,
    oa: np.ndarray,
    eb: np.ndarray,
    ob: np.ndarray,
    tol: float = 1e-7,
    along: bool = False,
) -> np.ndarray:
    """:func:`overlap_depth` of many configurations at once (shape (N,)): vectorised for bodies inside a drawn
    piece, the one-at-a-time code for a body on a corner or vertex (every orientation there).

    With ``along`` the N samples are consecutive instants of one motion: a robot on a vertex or a polyline corner
    (within ``tol`` metres) takes the orientations of the pieces it arrives on and leaves by (the nearest samples
    off that vertex or corner before and after), not those of every piece there; every orientation there where the
    motion starts or ends on it.
    """
    ea, eb = np.asarray(ea, dtype=int), np.asarray(eb, dtype=int)
    oa, ob = np.asarray(oa, dtype=float), np.asarray(ob, dtype=float)
    ca, ha, corner_a = _poses(drawn, ea, oa, tol)
    cb, hb, corner_b = _poses(drawn, eb, ob, tol)
    d = cb - ca
    if len(fa) == 1 and len(fb) == 1:
        out = np.maximum(0.0, fa[0] + fb[0] - np.hypot(d[:, 0], d[:, 1]))
    elif len(fa) == 1 or len(fb) == 1:
        r, (hl, hw), h = (fa[0], fb, hb) if len(fa) == 1 else (fb[0], fa, ha)
        u = np.stack([np.cos(h), np.sin(h)], axis=1)
        x = np.abs(np.sum(d * u, axis=1)) - 0.5 * hl
        y = np.abs(d[:, 0] * -u[:, 1] + d[:, 1] * u[:, 0]) - 0.5 * hw
        dist = np.hypot(np.maximum(x, 0.0), np.maximum(y, 0.0))
        out = np.maximum(0.0, r - dist)
    else:
        depth = np.full(len(d), np.inf)
        ua = np.stack([np.cos(ha), np.sin(ha)], axis=1)
        ub = np.stack([np.cos(hb), np.sin(hb)], axis=1)
        na, nb = np.stack([-ua[:, 1], ua[:, 0]], axis=1), np.stack([-ub[:, 1], ub[:, 0]], axis=1)
        for k in (ua, na, ub, nb):  # the four edge normals separate two rectangles if anything does
            ra = 0.5 * fa[0] * np.abs(np.sum(ua * k, axis=1)) + 0.5 * fa[1] * np.abs(np.sum(na * k, axis=1))
            rb = 0.5 * fb[0] * np.abs(np.sum(ub * k, axis=1)) + 0.5 * fb[1] * np.abs(np.sum(nb * k, axis=1))
            depth = np.minimum(depth, ra + rb - np.abs(np.sum(d * k, axis=1)))
        out = np.maximum(0.0, depth)
    pass_a = _passage_headings(drawn, ea, oa, tol) if along else {}
    pass_b = _passage_headings(drawn, eb, ob, tol) if along else {}
    for i in np.nonzero(corner_a | corner_b)[0]:
        out[i] = overlap_depth(
            drawn,
            fa,
            (int(ea[i]), float(oa[i])),
            fb,
            (int(eb[i]), float(ob[i])),
            pass_a.get(int(i), drawn.headings(int(ea[i]), float(oa[i]), tol)),
            pass_b.get(int(i), drawn.headings(int(eb[i]), float(ob[i]), tol)),
        )
    return out


def _passage_headings(drawn: Drawn, e: np.ndarray, o: np.ndarray, tol: float) -> dict[int, list[float]]:
    """Per sample on a vertex or a polyline corner, the orientations of the pieces a robot arrives on and leaves
    by: for each run of consecutive samples on one vertex (corner), the pieces of the nearest samples off it before
    and after the run (at a vertex: the edges' end pieces there; at a corner: the pieces of its edge on either side,
    one piece when the robot touches the corner and turns back). A run at either end of the motion, or next to a
    sample on an edge that does not meet the vertex, is left out (every orientation there)."""
    # per sample the nearest point of its edge's polyline and whether it stands on it (one pass per edge)
    near = np.zeros(len(e), dtype=np.int64)
    on = np.zeros(len(e), dtype=bool)
    last = np.zeros(len(e), dtype=np.int64)
    for k in np.unique(e):
        m = e == k
        off = drawn.offs[int(k)]
        j = np.clip(np.searchsorted(off, o[m]), 1, len(off) - 1)
        j = np.where(np.abs(off[j - 1] - o[m]) <= np.abs(off[j] - o[m]), j - 1, j)
        near[m], on[m], last[m] = j, np.abs(off[j] - o[m]) <= tol, len(off) - 1
    keys: list[Any] = [None] * len(e)
    for i in np.flatnonzero(on).tolist():
        k, j = int(e[i]), int(near[i])
        if j == 0 or j == last[i]:
            keys[i] = ("v", str(drawn.ends[k][0 if j == 0 else 1]))
        else:
            keys[i] = ("c", k, j)
    out: dict[int, list[float]] = {}
    i, n = 0, len(keys)
    while i < n:
        key = keys[i]
        if key is None:
            i += 1
            continue
        j = i
        while j + 1 < n and keys[j + 1] == key:
            j += 1
        if i > 0 and j + 1 < n:
            if key[0] == "v":
                arrive = drawn.end_headings(int(e[i - 1]), key[1])
                leave = drawn.end_headings(int(e[j + 1]), key[1])
            else:
                arrive = _piece_heading(drawn, key[1], int(e[i - 1]), float(o[i - 1]))
                leave = _piece_heading(drawn, key[1], int(e[j + 1]), float(o[j + 1]))
            if arrive and leave:
                for k in range(i, j + 1):
                    out[k] = arrive + leave
        i = j + 1
    return out


def _piece_heading(drawn: Drawn, edge: int, e: int, o: float) -> list[float]:
    """The direction of the piece of ``edge`` holding offset ``o`` (empty when the sample is on another edge)."""
    if e != edge:
        return []
    pts, off = drawn.polys[e], drawn.offs[e]
    i = int(np.clip(np.searchsorted(off, o, side="right") - 1, 0, len(off) - 2))
    return [math.atan2(*(pts[i + 1] - pts[i])[::-1])]


def _poses(drawn: Drawn, e: np.ndarray, o: np.ndarray, tol: float) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Centres (N, 2), headings (N,) and whether on a corner or vertex (N,), edge by edge."""
    c = np.zeros((len(e), 2))
    h = np.zeros(len(e))
    corner = np.zeros(len(e), dtype=bool)
    for k in np.unique(e):
        m = e == k
        pts, off = drawn.polys[k], drawn.offs[k]
        x = o[m]
        c[m, 0] = np.interp(x, off, pts[:, 0])
        c[m, 1] = np.interp(x, off, pts[:, 1])
        i = np.clip(np.searchsorted(off, x, side="right") - 1, 0, len(off) - 2)
        seg = pts[i + 1] - pts[i]
        h[m] = np.arctan2(seg[:, 1], seg[:, 0])
        corner[m] = np.min(np.abs(x[:, None] - off[None, :]), axis=1) <= tol
    return c, h, corner
