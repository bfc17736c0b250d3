"""A motion in plain words, per cart: ``"B: up the stick to P, 0.06 m into the loop clockwise, waits 0.4 s, …"``.

Reads only the rows (times and route coordinates) and the routes, so it describes any setpoint grid the
project writes. For each cart:

1. **Legs and waits.** The row steps are classed as forward, backward (the sign of ``Δσ``) or still
   (``|Δσ| ≤`` :data:`STILL`). A leg is a maximal run of steps in one direction, still steps included; a still
   run of at least :data:`WAIT_MIN` seconds between or before legs is reported as a wait (shorter stops, e.g. a
   corner passed at rest, are not; the rest after the last leg is the end of the motion and not reported).
2. **Edges.** A leg is cut where its route passes the pole P (:meth:`mpa.routes.Route.junctions`); each piece
   lies on one edge: the stick of a lollipop (or the interval), where *up* means towards P (increasing track
   coordinate), or the loop (or the circle), where the direction is *counterclockwise* (increasing θ, the
   track's orientation) or *clockwise*.
3. **Phrases.** Stick: ``up the stick to P`` / ``up the stick to 0.80 m`` (track coordinate), and ``back up`` /
   ``back down`` when the cart already travelled the stick the other way. Loop: ``0.06 m into the loop
   clockwise`` (from P), ``0.30 m counterclockwise round the loop to P`` (to P), ``once round the loop
   clockwise`` (P to P), ``0.20 m clockwise along the loop to 1.55 m`` (neither end at P); circle: ``0.25 m
   clockwise to 0.10 m``. A leg that reverses the previous one (the cart retraces its way) is one phrase,
   where it ends: ``back down to 0.20 m`` (even if it first comes back out of the loop through P). Positions
   are track coordinates. Distances are in metres with 2 decimals (3 significant digits below 1 cm), waits in
   seconds with 1. A cart that never moves ``stays at 0.20 m``.

On a layout (:class:`mpa.GraphTrack`) the words follow the route's pieces (:func:`describe_graph_rows`): legs and
waits as above, each leg cut at the route's pieces, one phrase per piece ``along e1 to J`` (with the edge's
orientation) or ``back along e1 to e1:0.4`` (against it), positions as vertex names or ``EDGE:OFFSET`` (offsets in
metres to the millimetre).
"""

from __future__ import annotations

import itertools
from collections.abc import Sequence
from typing import TYPE_CHECKING

import numpy as np
from numpy.typing import ArrayLike

from mpa._arrays import FloatArray
from mpa.geometry import DirectedRoute
from mpa.graph_track import GraphTrack
from mpa.plans import Plan
from mpa.routes import Route
from mpa.tracks import Circle, Lollipop, Track

if TYPE_CHECKING:
    from trajopt.result import Trajectory

__all__ = ["STILL", "WAIT_MIN", "describe", "describe_graph_rows", "describe_rows", "describe_text"]

#: A row step moving less than this is still (m).
STILL = 1e-9
#: Shortest stop reported as a wait (s).
WAIT_MIN = 0.05
_TOL = 1e-6  # metres: "at P", "a full turn"


def _m(x: float) -> str:
    x = abs(float(x))
    return f"{x:.2f} m" if x >= 0.01 or x == 0 else f"{x:.3g} m"


def _where(track: Track, p: float) -> str:
    """A track position in words."""
    if isinstance(track, Lollipop):
        if abs(p - track.stick) <= _TOL:
            return "P"
        if p < track.stick:
            return f"{_m(p)} on the stick"
        return f"{_m(p - track.stick)} round the loop"
    return _m(p)


def _legs(t: FloatArray, s: FloatArray) -> list[tuple[str, float, float]]:
    """``("move", σ0, σ1)`` and ``("wait", seconds, 0)`` events of one cart (see the module docstring)."""
    ds = np.diff(s)
    sign = np.where(ds > STILL, 1, np.where(ds < -STILL, -1, 0))
    dt = np.diff(t)
    out: list[tuple[str, float, float]] = []
    cur_dir, start, k_last_move = 0, 0.0, -1
    still_time = 0.0
    for k in range(len(ds)):
        if sign[k] == 0:
            still_time += dt[k]
            continue
        if sign[k] != cur_dir or still_time >= WAIT_MIN:
            if cur_dir != 0:
                out.append(("move", start, float(s[k_last_move + 1])))
            if still_time >= WAIT_MIN:
                out.append(("wait", still_time, 0.0))
            cur_dir, start = int(sign[k]), float(s[k])
        still_time = 0.0
        k_last_move = k
    if cur_dir != 0:
        out.append(("move", start, float(s[k_last_move + 1])))
    return out


def _pieces(track: Track, route: Route, s0: float, s1: float) -> list[tuple[str, int, float, float, float]]:
    """Cut a leg at P: ``(edge, direction, length, p_from, p_to)`` with edge "stick" or "loop"."""
    lo, hi = min(s0, s1), max(s0, s1)
    junc = [float(x) for x in route.junctions() if lo + _TOL < x < hi - _TOL]
    cuts = [s0, *(junc if s1 > s0 else junc[::-1]), s1]
    out = []
    for a, b in itertools.pairwise(cuts):
        mid = 0.5 * (a + b)
        pa, pb, pm = (float(route.position(x)) for x in (a, b, mid))
        if isinstance(track, Circle) or (isinstance(track, Lollipop) and pm > track.stick):
            c = track.loop
            eps = min(1e-4, abs(b - a) / 4)
            step = float(route.position(mid + eps * np.sign(b - a))) - pm
            step = (step + c / 2) % c - c / 2
            direction = 1 if step > 0 else -1
            out.append(("loop", direction, abs(b - a), pa, pb))
        else:
            out.append(("stick", 1 if pb > pa else -1, abs(b - a), pa, pb))
    return out


def describe_rows(track: Track, routes: Sequence[Route], t: ArrayLike, s: ArrayLike) -> dict[str, str]:
    """Plain words per cart for rows ``t`` (N,) s and route coordinates ``s`` (N, 2) m on ``routes``.

    Returns
    -------
    dict
        ``{"A": "...", "B": "..."}`` (without the ``"A: "`` prefix).
    """
    tt = np.asarray(t, dtype=float)
    ss = np.asarray(s, dtype=float)
    out: dict[str, str] = {}
    for r, name in ((0, "A"), (1, "B")):
        route = routes[r]
        phrases: list[str] = []
        stick_dirs: set[int] = set()
        prev = 0.0
        for kind, x0, x1 in _legs(tt, ss[:, r]):
            if kind == "wait":
                phrases.append(f"waits {x0:.1f} s")
                continue
            pieces = _pieces(track, route, x0, x1)
            if prev * (x1 - x0) < 0:  # retraces the previous leg: one phrase, where it ends up
                edge, direction, _length, _pa, pb = pieces[-1]
                phrases.append(_back(track, edge, direction, pb))
                if edge == "stick":
                    stick_dirs.add(direction)
            else:
                for edge, direction, length, pa, pb in pieces:
                    phrases.append(_phrase(track, edge, direction, length, pa, pb, stick_dirs))
            prev = x1 - x0
        if not phrases or all(p.startswith("waits") for p in phrases):
            phrases = [f"stays at {_where(track, float(route.position(ss[0, r])))}"]
        out[name] = ", ".join(phrases)
    return out


def _back(track: Track, edge: str, direction: int, pb: float) -> str:
    dest = "P" if isinstance(track, Lollipop) and abs(pb - track.stick) <= _TOL else _m(pb)
    if edge == "loop":
        return f"back {'counterclockwise' if direction > 0 else 'clockwise'} to {dest}"
    return f"back {'up' if direction > 0 else 'down'} to {dest}"


def _phrase(track: Track, edge: str, direction: int, length: float, pa: float, pb: float, seen: set[int]) -> str:
    rot = "counterclockwise" if direction > 0 else "clockwise"
    if isinstance(track, Circle):
        return f"{_m(length)} {rot} to {_m(pb)}"
    if edge == "loop":
        assert isinstance(track, Lollipop)
        at_p0, at_p1 = abs(pa - track.stick) <= _TOL, abs(pb - track.stick) <= _TOL
        if at_p0 and at_p1:
            turns = length / track.loop
            return f"once round the loop {rot}" if abs(turns - 1) < 1e-6 else f"{_m(length)} round the loop {rot}"
        if at_p0:
            return f"{_m(length)} into the loop {rot}"
        if at_p1:
            return f"{_m(length)} {rot} round the loop to P"
        return f"{_m(length)} {rot} along the loop to {_m(pb)}"
    word = "up" if direction > 0 else "down"
    back = -direction in seen
    seen.add(direction)
    top = isinstance(track, Lollipop) and abs(pb - track.stick) <= _TOL
    dest = "P" if top else _m(pb)
    if back:
        return f"back {word} to {dest}"
    where = "the stick" if isinstance(track, Lollipop) else "the track"
    return f"{word} {where} to {dest}"


def describe(trajectory: Trajectory) -> dict[str, str]:
    """Plain words per cart for a :class:`~trajopt.result.Trajectory` (its rows and its plan's routes).

    Examples
    --------
    >>> from mpa import Lollipop
    >>> from trajopt import generate_trajectory
    >>> describe(generate_trajectory(Lollipop(1.0, 1.0), (0.1, 0.6), (0.3, 0.8)))
    {'A': 'up the stick to 0.30 m', 'B': 'up the stick to 0.80 m'}
    """
    plan = trajectory.plan
    if isinstance(plan, Plan):  # the paper's plans in the paper's words: the stick, the loop, track coordinates
        return describe_rows(plan.track, plan.routes, trajectory.t, trajectory.s)
    return describe_graph_rows(plan.layout, plan.layout_routes, trajectory.t, trajectory.s)


def _graph_where(track: GraphTrack, route: DirectedRoute, r: float) -> str:
    """The position at route coordinate ``r`` by name: a vertex within half a millimetre of an edge end, else
    ``EDGE:OFFSET`` with the offset in metres rounded to the millimetre (``spur:0.8``, not ``spur:0.80010000095``)."""
    e, o = route.position_scalar(float(r))
    length = float(track.lengths[e])
    if abs(o - length) < 5e-4:
        o = length
    elif abs(o) < 5e-4:
        o = 0.0
    if track.vertex_at(e, o) is not None:
        return str(track.position_name(e, o))
    return f"{track.edge_names[e]}:{np.format_float_positional(round(o, 3), precision=3, trim='-')}"


def describe_graph_rows(
    track: GraphTrack, routes: Sequence[DirectedRoute], t: ArrayLike, s: ArrayLike
) -> dict[str, str]:
    """Plain words per cart on a layout for rows ``t`` (N,) and route coordinates ``s`` (N, 2) on ``routes``.

    Parameters
    ----------
    track : GraphTrack
    routes : (DirectedRoute, DirectedRoute)

    Returns
    -------
    dict
        ``{"A": "...", "B": "..."}``.
    """
    tt = np.asarray(t, dtype=float)
    ss = np.asarray(s, dtype=float)
    out: dict[str, str] = {}
    names = track.edge_names
    for r, name in ((0, "A"), (1, "B")):
        route = routes[r]
        phrases: list[str] = []
        for kind, x0, x1 in _legs(tt, ss[:, r]):
            if kind == "wait":
                phrases.append(f"waits {x0:.1f} s")
                continue
            lo, hi = min(x0, x1), max(x0, x1)
            cuts = [b for b in route.breaks if lo < b < hi]
            pts = [x0, *(cuts if x1 > x0 else cuts[::-1]), x1]
            for a, b in itertools.pairwise(pts):
                if abs(b - a) <= STILL:
                    continue
                i = int(route.piece_index(0.5 * (a + b)))
                direction = int(route.dirs[i]) * (1 if b > a else -1)
                where = _graph_where(track, route, b)
                phrases.append(f"{'along' if direction > 0 else 'back along'} {names[int(route.edges[i])]} to {where}")
        if not phrases or all(p.startswith("waits") for p in phrases):
            phrases = [f"stays at {_graph_where(track, route, ss[0, r])}"]
        out[name] = ", ".join(phrases)
    return out


def describe_text(trajectory: Trajectory) -> str:
    """``"A: …\\nB: …"``."""
    d = describe(trajectory)
    return f"A: {d['A']}\nB: {d['B']}"
