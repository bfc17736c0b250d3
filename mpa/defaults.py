"""The project's defaults, in one place: clearance, limits, setpoint rate and the clearance tolerance.

Used by the API (:func:`trajopt.generate_trajectory`, :class:`trajopt.TrajectoryGenerator`,
:class:`trajopt.Limits`), the command line (every subcommand that takes ``--clearance``, ``--vmax``, …) and the
scripts in ``experiments/``. :func:`mpa.plan` and :func:`mpa.make_planner` keep their documented default
clearance 0 (the paper's point robots); the command line uses :data:`CLEARANCE` everywhere.
"""

from __future__ import annotations

__all__ = ["AMAX", "CLEARANCE", "CLEARANCE_TOL", "JMAX", "LIMIT_RANGE", "RATE", "VMAX"]

#: Default clearance D (m, graph distance between the robots).
CLEARANCE = 0.05
#: Default speed limit of each robot (m/s, route coordinate).
VMAX = 0.5
#: Default acceleration limit of each robot (m/s²).
AMAX = 1.0
#: Default jerk limit of each robot (m/s³).
JMAX = 5.0
#: Supported range of each limit, as factors of its default: ``vmax`` in [5e-4, 5e3] m/s, ``amax`` in [1e-3, 1e4] m/s²,
#: ``jmax`` in [5e-3, 5e4] m/s³. Inside it the pipeline answers (a verified motion or a clear error) within seconds,
#: and the makespan does not grow when a limit is loosened (tested); outside it a limit is an input error.
LIMIT_RANGE = (1e-3, 1e4)
#: Default setpoint rate (Hz).
RATE = 100.0
#: Absolute tolerance (m) of the clearance test of a start or goal: robots at least ``D − CLEARANCE_TOL`` apart
#: count as the clearance apart (so ``(0.2, 0.25)`` keeps ``D = 0.05`` although ``0.25 − 0.2 < 0.05`` in floating
#: point). Far below any physical scale and below the gate's :data:`trajopt.verify.gate.SEPARATION_TOL` (1e-9 m).
CLEARANCE_TOL = 1e-12
