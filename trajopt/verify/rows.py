"""The rows of a setpoint grid as one object: :class:`Setpoints` (times, route coordinates and their derivatives per
robot, and the positions where the caller has them).

The gate (:func:`trajopt.verify.gate.verify_setpoints`, :func:`trajopt.verify.gate.verify_graph_setpoints`), the plan's
view
(:meth:`trajopt.path.planview.PlanView.verify`) and the independent checker (:func:`trajopt.testing.check_setpoints`,
:func:`trajopt.testing.check_graph_setpoints`) take the rows in this form (or, positionally, as their arrays);
:meth:`trajopt.result.Trajectory.rows` gives a trajectory's. The compiled kernels under them
(:func:`trajopt.verify.kernels.check_rows`, :func:`trajopt.verify.sampling.sample_rows`) keep plain arrays. Nothing is
validated here: the gate reports inconsistent shapes and non-finite values as failures.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike, NDArray

from mpa.errors import InvalidInputError

__all__ = ["Setpoints", "rows_of"]


@dataclass(frozen=True, eq=False)
class Setpoints:
    """A setpoint grid of two robots (A first), one row per time.

    Arrays are taken as given (``numpy.asarray``, dtypes kept, no copies of arrays); shapes are the caller's
    promise and the gate's check.

    Attributes
    ----------
    t : ndarray, shape (N,)
        Times (s).
    s, v, a, j : ndarray, shape (N, 2)
        Route coordinates (m) and their first three time derivatives (m/s, m/s², m/s³).
    edges : ndarray of int, shape (N, 2), or None
        Edge index of each robot on the layout.
    offsets : ndarray, shape (N, 2), or None
        Offset of each robot from its edge's tail (m).
    track : ndarray, shape (N, 2), or None
        Track coordinates on one of the paper's tracks (m).
    dirs : ndarray of int, shape (N, 2), or None
        Direction of travel on the edge: +1 along it, -1 against, 0 at rest.
    """

    t: NDArray[np.generic]
    s: NDArray[np.generic]
    v: NDArray[np.generic]
    a: NDArray[np.generic]
    j: NDArray[np.generic]
    edges: NDArray[np.generic] | None = None
    offsets: NDArray[np.generic] | None = None
    track: NDArray[np.generic] | None = None
    dirs: NDArray[np.generic] | None = None

    def __post_init__(self) -> None:
        for name in ("t", "s", "v", "a", "j", "edges", "offsets", "track", "dirs"):
            x = getattr(self, name)
            if x is not None and not isinstance(x, np.ndarray):
                object.__setattr__(self, name, np.asarray(x))

    def __len__(self) -> int:
        """N, the number of rows."""
        return len(self.t)

    @property
    def svaj(self) -> tuple[NDArray[np.generic], ...]:
        """``(s, v, a, j)``."""
        return self.s, self.v, self.a, self.j


def rows_of(rows: Setpoints | ArrayLike, arrays: Sequence[ArrayLike | None], order: Sequence[str]) -> Setpoints:
    """The rows a function was given: a :class:`Setpoints`, or its positional arrays in ``order``.

    Parameters
    ----------
    rows : Setpoints or array_like
        The rows, or the first array of the positional form (the times).
    arrays : sequence of array_like
        The rest of the positional form (empty when ``rows`` is a Setpoints).
    order : sequence of str
        The fields of the positional form, e.g. ``("t", "edges", "offsets", "s", "v", "a", "j")``.

    Raises
    ------
    InvalidInputError
        Setpoints given together with arrays, or the positional form incomplete.
    """
    if isinstance(rows, Setpoints):
        if arrays:
            raise InvalidInputError(f"rows are Setpoints and {len(arrays)} more arrays, expected Setpoints alone")
        return rows
    if len(arrays) != len(order) - 1:
        raise InvalidInputError(
            f"rows are {len(arrays) + 1} arrays, expected Setpoints or the {len(order)} arrays {', '.join(order)}"
        )
    given = dict(zip(order, (rows, *arrays)))

    def arr(name: str) -> NDArray[np.generic] | None:
        x = given.get(name)
        return None if x is None else np.asarray(x)

    t, s, v, a, j = (np.asarray(given[k]) for k in ("t", "s", "v", "a", "j"))
    return Setpoints(t, s, v, a, j, edges=arr("edges"), offsets=arr("offsets"), track=arr("track"), dirs=arr("dirs"))
