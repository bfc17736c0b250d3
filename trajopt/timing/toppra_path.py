"""Time-optimal parametrization: the v/a-limited speed profile ``ṡ(s)`` of a path with toppra (``TOPPRA`` with
``ParametrizeConstAccel``, joint velocity and acceleration limits). Its duration is reported and its speeds cap
the speeds at the piece boundaries.
"""

from __future__ import annotations

import numpy as np

from mpa._arrays import FloatArray
from mpa.errors import PlanningError
from trajopt.timing.curves import (
    BlendedPath,
)
from trajopt.timing.limits import Limits


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
