"""The deformation retraction H: X × [0, 1] → X onto the skeleton (paper §5.2 and §6.1; docs/conventions.md,
"The lollipop skeleton").

``H(x, 0) = x``, ``H(x, 1) ∈ S``, ``H(s, t) = s`` for every skeleton point ``s``. Along each trace every
robot moves at constant speed along one edge of the track, so ``H(x, t)`` is the linear interpolation, in
edge coordinates, between ``x`` and ``H(x, 1)``; the distance between the robots changes linearly in ``t``
from ``d(x)`` to ``h`` (hence monotonically). Each trace is a fibre of ``H₁``: ``H₁(H(x, t)) = H₁(x)``.

Circle (paper §5.2): robot A moves away from B until it is antipodal; B waits.

Lollipop, in model coordinates (``ℓ ≥ h``), by region (x = depth of a stick robot below P, w = loop
distance of a loop robot from P, d the graph distance):

=====================  ==========================================================================
state                  trace ("speed ratio" = ratio of the two robots' speeds)
=====================  ==========================================================================
``d ≥ h`` (stick)       the robot nearer the free end moves towards the other; the other waits
both on the stick,     both move apart; the rear one towards the free end, the front one towards P,
``d < h``              sharing the missing distance ``h − d`` in proportion to their free room
one on the stick, one  both move away from P, speeds in ratio ``x : w`` (radial scaling about P)
on the loop, ``d < h``
both on the loop       both move along the arc between them that contains P, keeping their distances
                       to P in a fixed ratio, until antipodal (they move apart, staying on the loop)
=====================  ==========================================================================
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike

from mpa._arrays import FloatArray
from mpa.errors import InvalidInputError, PlanningError
from mpa.routes import RobotMove
from mpa.skeleton import LollipopSkeleton, skeleton_of
from mpa.tracks import Circle, Interval, Lollipop, Track

__all__ = [
    "TraceInfo",
    "circle_trace",
    "lollipop_trace",
    "lollipop_trace_scalar",
    "retract",
    "trace_info",
    "trace_moves",
]


def circle_trace(track: Circle, states: ArrayLike) -> FloatArray:
    """Signed displacements ``(Δa, Δb)`` of the trace of ``H`` on the circle (A only). Shape (N, 2)."""
    st = np.atleast_2d(np.asarray(states, dtype=float))
    c, h = track.loop, track.half
    delta = np.mod(st[:, 0] - st[:, 1], c)  # A's ccw offset from B, in (0, c)
    return np.stack([h - delta, np.zeros(len(st))], axis=-1)


def lollipop_trace(model: Lollipop, states: ArrayLike) -> FloatArray:
    """Signed edge-coordinate displacements ``(Δa, Δb)`` of the traces of ``H`` on a lollipop with ``ℓ ≥ h``.

    A stick robot's displacement is ``Δp`` (positive towards P); a loop robot's is ``Δθ`` (ccw positive).

    Parameters
    ----------
    model : Lollipop
        A lollipop with ``stick ≥ loop / 2``.
    states : array_like, shape (N, 2)
        Collision-free states (track coordinates of A and B).

    Returns
    -------
    ndarray, shape (N, 2)
    """
    st = np.atleast_2d(np.asarray(states, dtype=float))
    ell, c = model.stick, model.loop
    h = 0.5 * c
    a, b = st[:, 0], st[:, 1]
    a_st, b_st = a <= ell, b <= ell
    # every case on every state (branch-free; the divisions are guarded), then each state takes its own case
    # both on the stick
    front_is_b = b > a
    rear = np.where(front_is_b, a, b)
    front = np.where(front_is_b, b, a)
    dd = front - rear  # = |a - b|
    far = dd >= h
    room_rear, room_front = rear, ell - front
    total = np.maximum(room_rear + room_front, 1e-300)
    miss = h - dd
    d_rear = np.where(far, dd - h, -miss * room_rear / total)
    d_front = np.where(far, 0.0, miss * room_front / total)
    ss0 = np.where(front_is_b, d_rear, d_front)
    ss1 = np.where(front_is_b, d_front, d_rear)
    # one on the stick: ps the stick robot, pl the loop robot
    ps = np.where(a_st, a, b)
    pl = np.where(a_st, b, a)
    x = ell - ps
    th = pl - ell
    side = np.where(th <= h, 1.0, -1.0)
    w = np.minimum(th, c - th)
    d1 = x + w
    far1 = d1 >= h
    lam1 = np.where(far1, 1.0, h / np.maximum(d1, 1e-300))
    x_new = np.where(far1, h - w, lam1 * x)
    w_new = np.where(far1, w, lam1 * w)
    stick_disp = -(x_new - x)
    loop_disp = side * (w_new - w)
    # both on the loop
    ta, tb = a - ell, b - ell
    p_on_ccw = tb < ta
    wa = np.where(p_on_ccw, c - ta, ta)
    wb = np.where(p_on_ccw, tb, c - tb)
    lam = h / np.maximum(wa + wb, 1e-300)
    da = (lam - 1.0) * wa
    db = (lam - 1.0) * wb
    ll0 = np.where(p_on_ccw, -da, da)
    ll1 = np.where(p_on_ccw, db, -db)
    both = a_st & b_st
    none = ~a_st & ~b_st
    out0 = np.where(both, ss0, np.where(none, ll0, np.where(a_st, stick_disp, loop_disp)))
    out1 = np.where(both, ss1, np.where(none, ll1, np.where(a_st, loop_disp, stick_disp)))
    return np.stack([out0, out1], axis=1)


def lollipop_trace_scalar(ell: float, c: float, a: float, b: float) -> tuple[float, float]:
    """Scalar twin of :func:`lollipop_trace` for one state (pure Python, for single queries)."""
    h = 0.5 * c
    a_st, b_st = a <= ell, b <= ell
    if a_st and b_st:
        front_is_b = b > a
        rear, front = (a, b) if front_is_b else (b, a)
        d = front - rear
        if d >= h:
            d_rear, d_front = d - h, 0.0
        else:
            total = max(rear + ell - front, 1e-300)
            d_rear, d_front = -(h - d) * rear / total, (h - d) * (ell - front) / total
        return (d_rear, d_front) if front_is_b else (d_front, d_rear)
    if a_st != b_st:
        ps, pl = (a, b) if a_st else (b, a)
        x = ell - ps
        th = pl - ell
        side = 1.0 if th <= h else -1.0
        w = min(th, c - th)
        d = x + w
        if d >= h:
            x_new, w_new = h - w, w
        else:
            lam = h / d
            x_new, w_new = lam * x, lam * w
        ds, dl = -(x_new - x), side * (w_new - w)
        return (ds, dl) if a_st else (dl, ds)
    ta, tb = a - ell, b - ell
    p_on_ccw = tb < ta
    wa, wb = (c - ta, tb) if p_on_ccw else (ta, c - tb)
    lam = h / (wa + wb)
    da, db = (lam - 1.0) * wa, (lam - 1.0) * wb
    return (-da, db) if p_on_ccw else (da, -db)


def _apply(track: Track, st: FloatArray, disp: FloatArray, t: ArrayLike) -> FloatArray:
    t_arr = np.asarray(t, dtype=float)
    t_arr = t_arr[:, None] if t_arr.ndim == 1 else t_arr
    new = st + t_arr * disp
    if isinstance(track, Circle):
        return np.mod(new, track.loop)
    if isinstance(track, Lollipop):
        ell, c = track.stick, track.loop
        on_loop = st > ell
        wrapped = ell + np.mod(new - ell, c)
        return np.where(on_loop, wrapped, new)
    return new


def retract(track: Track, states: ArrayLike, t: ArrayLike = 1.0) -> FloatArray:
    """The deformation ``H(x, t)`` (vectorized over states; ``t`` scalar or one per state).

    Parameters
    ----------
    track : Track
        A circle or a lollipop (for an interval ``H`` is the straight-line contraction of each component to its
        skeleton point).
    states : array_like, shape (N, 2)
        Collision-free states (track coordinates).
    t : float or array_like of shape (N,)
        Deformation time in [0, 1].

    Returns
    -------
    ndarray, shape (N, 2)
        ``H(x, t)`` in track coordinates.
    """
    st = np.atleast_2d(np.asarray(states, dtype=float))
    if isinstance(track, Interval):
        ell = track.stick
        target = np.where((st[:, 0] < st[:, 1])[:, None], [[0.0, ell]], [[ell, 0.0]])
        return _apply(track, st, target - st, t)
    if isinstance(track, Circle):
        return _apply(track, st, circle_trace(track, st), t)
    if not isinstance(track, Lollipop):
        raise InvalidInputError(f"track is {track!r}, expected a Lollipop")
    sk = skeleton_of(track)
    if not isinstance(sk, LollipopSkeleton):
        raise PlanningError(f"internal: sk is a {type(sk).__name__}, expected a LollipopSkeleton")
    ms = sk.to_model(st)
    disp = lollipop_trace(sk.model, ms)
    return sk.from_model(_apply(sk.model, ms, disp, t))


@dataclass(frozen=True)
class TraceInfo:
    """Physical meaning of the trace ``t ↦ H(x, t)`` of one state.

    Attributes
    ----------
    moves : tuple of RobotMove
        A's and B's motion (one edge each, constant speed over t ∈ [0, 1]).
    moving : str
        ``"none"``, ``"A"``, ``"B"`` or ``"both"``.
    speed_ratio : float
        |speed of A| / |speed of B| (``inf`` if only A moves, 0 if only B moves, nan if none).
    distance : tuple of float
        Distance between the robots at t = 0 and t = 1 (it changes monotonically in between).
    text : str
        The instruction in words.
    """

    moves: tuple[RobotMove, RobotMove]
    moving: str
    speed_ratio: float
    distance: tuple[float, float]
    text: str


def trace_info(track: Track, state: ArrayLike) -> TraceInfo:
    """Which robot moves along the trace of ``state``, in which direction, at what speed ratio.

    Examples
    --------
    >>> from mpa.tracks import Lollipop
    >>> trace_info(Lollipop(1.0, 1.0), (0.1, 0.9)).text
    'A moves 0.3 m towards P while B waits (distance 0.8 -> 0.5 m)'
    """
    ma, mb = trace_moves(track, state)
    end = retract(track, np.asarray(state, dtype=float)[None, :], 1.0)[0]
    d0 = float(track.distance(*np.asarray(state, dtype=float)))
    d1 = float(track.distance(*end))
    la, lb = abs(ma.delta), abs(mb.delta)
    moving = "both" if la > 1e-15 and lb > 1e-15 else ("A" if la > 1e-15 else ("B" if lb > 1e-15 else "none"))
    ratio = la / lb if lb > 1e-15 else (float("inf") if la > 1e-15 else float("nan"))

    def words(name: str, mv: RobotMove) -> str:
        if mv.edge == "stick" and isinstance(track, Lollipop):
            where = "towards P" if mv.delta > 0 else "towards the free end"
        elif mv.edge == "stick":
            where = "forwards" if mv.delta > 0 else "backwards"
        else:
            where = "counterclockwise" if mv.delta > 0 else "clockwise"
        return f"{name} moves {abs(mv.delta):.3g} m {where}"

    span = f"(distance {d0:.3g} -> {d1:.3g} m)"
    if moving == "none":
        text = f"both robots wait: already on the skeleton {span}"
    elif moving == "A":
        text = f"{words('A', ma)} while B waits {span}"
    elif moving == "B":
        text = f"{words('B', mb)} while A waits {span}"
    else:
        text = f"{words('A', ma)} and {words('B', mb)}, speeds in ratio {ratio:.3g} : 1 {span}"
    return TraceInfo((ma, mb), moving, ratio, (d0, d1), text)


def trace_moves(track: Track, state: ArrayLike) -> tuple[RobotMove, RobotMove]:
    """The trace ``t ↦ H(x, t)`` of one state as one move per robot (real track coordinates)."""
    a, b = (float(v) for v in np.asarray(state, dtype=float))
    if isinstance(track, Circle):
        da = track.half - (a - b) % track.loop
        return RobotMove("loop", a, da), RobotMove("loop", b, 0.0)
    if not isinstance(track, Lollipop):
        raise InvalidInputError(f"track is {track!r}, expected a Lollipop")
    sk = skeleton_of(track)
    if not isinstance(sk, LollipopSkeleton):
        raise PlanningError(f"internal: sk is a {type(sk).__name__}, expected a LollipopSkeleton")
    ell = sk.model.stick
    ma = a if a <= ell else ell + (a - ell) * sk.kappa
    mb = b if b <= ell else ell + (b - ell) * sk.kappa
    da, db = lollipop_trace_scalar(ell, sk.model.loop, ma, mb)
    moves = []
    for p, dp in ((ma, float(da)), (mb, float(db))):
        mv = RobotMove("stick", p, dp) if p <= ell else RobotMove("loop", p - ell, dp)
        moves.append(sk.move_from_model(mv))
    return moves[0], moves[1]
