"""Configuration space of two robots with a clearance.

Conventions: docs/conventions.md, "Robots, clearance, configuration space".

The free configuration space is ``{(a, b) ∈ Γ×Γ : d(a, b) ≥ D}``; the paper's ``C²(Γ) = Γ² − Δ`` is ``D → 0``
(a state with ``d = 0`` is always a collision). Connectivity facts used to answer "no motion exists":

- interval: the robots can never change order (two components: A before B, B before A);
- circle and lollipop: the robots can change order only by using the loop, which needs ``D < c/2``
  (at ``D ≥ c/2`` the order of a lollipop state -- which robot is nearer the free end -- is kept).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike, NDArray

from mpa._deprecation import deprecated_alias
from mpa.defaults import CLEARANCE_TOL
from mpa.errors import InvalidInputError, NoMotionError
from mpa.tracks import Circle, Interval, Lollipop, Track

__all__ = ["ConfigurationSpace"]


@dataclass(frozen=True)
class ConfigurationSpace:
    """Two robots A and B on ``track`` kept at least ``clearance`` apart (metres, graph distance).

    Parameters
    ----------
    track : Track
    clearance : float
        Required clearance D >= 0 (body length plus margin).
    """

    track: Track
    clearance: float = 0.0

    def __post_init__(self) -> None:
        try:
            d = float(self.clearance)
        except (TypeError, ValueError, OverflowError):
            raise InvalidInputError(
                f"clearance is {self.clearance!r}, expected a finite number >= 0 (metres)"
            ) from None
        if not np.isfinite(d) or d < 0:
            raise InvalidInputError(f"clearance is {d!r}, expected a finite number >= 0 (metres)")
        object.__setattr__(self, "clearance", d)

    def distance(self, states: ArrayLike) -> NDArray[np.float64]:
        """Graph distance between the robots for states of shape (N, 2)."""
        st = np.atleast_2d(np.asarray(states, dtype=float))
        return self.track.distance(st[:, 0], st[:, 1])

    def feasible(self, states: ArrayLike) -> NDArray[np.bool_]:
        """Whether states (N, 2) are collision-free: ``d ≥ D`` and ``d > 0``."""
        d = self.distance(states)
        return (d >= self.clearance) & (d > 0.0)

    def validate_state(self, state: ArrayLike, name: str = "state") -> NDArray[np.float64]:
        """Validate one state ``(a, b)`` and return it normalized.

        Raises
        ------
        InvalidInputError
            Wrong shape, a coordinate not finite or off the track, robots coincident or closer than D.
        """
        arr: NDArray[np.float64] | None = None
        if not isinstance(state, (str, bytes)):
            try:
                arr = np.asarray(state, dtype=float)
            except (TypeError, ValueError, OverflowError):
                arr = None
        if arr is None or arr.shape != (2,):
            raise InvalidInputError(f"{name} is {state!r}, expected two track coordinates (A B)")
        a = self.track.validate(arr[0], f"{name} of robot A")
        b = self.track.validate(arr[1], f"{name} of robot B")
        out = np.array([float(a), float(b)])
        d = self.track.distance_scalar(float(a), float(b))
        if d <= 0.0:
            raise InvalidInputError(f"{name} puts both robots at {out[0]:g}: robots coincide (distance 0)")
        if d < self.clearance - CLEARANCE_TOL:
            raise InvalidInputError(
                f"{name} ({float(out[0])!r}, {float(out[1])!r}) has the robots {d:g} apart, expected at least the "
                f"clearance {self.clearance:g} (distance {d!r} m, clearance {self.clearance!r} m, "
                f"tolerance {CLEARANCE_TOL:g} m)"
            )
        return out

    def order(self, state: ArrayLike) -> int:
        """+1 if A is behind B (nearer the start of the stick), -1 if ahead, 0 if not defined.

        On an interval the order is A < B. On a lollipop the robot on the stick nearer the free end is behind;
        with both robots on the loop the order is not defined (0). On a circle it is never defined.
        """
        a, b = (float(v) for v in np.asarray(state, dtype=float))
        if isinstance(self.track, Interval):
            return 1 if a < b else -1
        if isinstance(self.track, Lollipop):
            ell = self.track.stick
            if a > ell and b > ell:
                return 0
            return 1 if min(a, ell) < min(b, ell) or (a <= ell < b) else -1
        return 0

    def validate_query(self, start: ArrayLike, goal: ArrayLike) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
        """Validate a query and decide whether a collision-free motion exists.

        Returns
        -------
        start, goal : ndarray, shape (2,)
            Normalized states.

        Raises
        ------
        InvalidInputError
            Bad start or goal (see :meth:`validate_state`).
        NoMotionError
            The robots would have to change order where they cannot.
        """
        s = self.validate_state(start, "start")
        g = self.validate_state(goal, "goal")
        tr = self.track
        os_, og = self.order(s), self.order(g)
        if isinstance(tr, Interval) and os_ != og:
            who = "A before B" if os_ > 0 else "B before A"
            raise NoMotionError(
                f"no collision-free motion exists: on an interval the robots can never change order "
                f"(start has {who}, goal the reverse)"
            )
        if isinstance(tr, Lollipop) and self.clearance >= tr.half and os_ * og < 0:
            raise NoMotionError(
                f"no collision-free motion exists: the robots must change order, which needs the loop and a "
                f"clearance below half the loop (clearance {self.clearance:g} >= loop/2 = {tr.half:g})"
            )
        if isinstance(tr, Circle) and self.clearance > tr.half:  # pragma: no cover - states already invalid
            raise NoMotionError(f"clearance {self.clearance:g} exceeds half the loop {tr.half:g}")
        return s, g

    #: Deprecated name of :meth:`validate_state` (warns).
    check_state = deprecated_alias(validate_state, "ConfigurationSpace.check_state")
    #: Deprecated name of :meth:`validate_query` (warns).
    check_query = deprecated_alias(validate_query, "ConfigurationSpace.check_query")
