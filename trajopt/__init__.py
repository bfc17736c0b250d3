"""trajopt: optimisation-based, jerk-limited trajectories on the plans of :mod:`mpa`, exported as setpoints.

The pipeline has one module per stage: :mod:`trajopt.smoothing` (CasADi/IPOPT in the plan's homotopy class),
:mod:`trajopt.timing` (C² path, toppra time parametrization, 1-DoF ruckig jerk limiting),
:mod:`trajopt.verify` (the independent gate), :mod:`trajopt.export` (the :class:`Trajectory` result, CSV/JSON)
and :mod:`trajopt.generator` (the pipeline with its fallback). The drawings (:mod:`trajopt.viz`) and the command
line (:mod:`trajopt.cli`, one module per subcommand) sit on top; the pipeline imports neither, and nothing else in
:mod:`trajopt` imports matplotlib.

Conventions: arrays are ``(N, 2)`` with robot A in column 0 and B in column 1, time is ``t``, SI units (m, s),
limits are per robot on the route coordinate ``s`` (signed distance along the robot's own route).
"""

from trajopt.export import CSV_COLUMNS, Source, Trajectory
from trajopt.generator import TrajectoryGenerator, generate_trajectory
from trajopt.timing import Limits
from trajopt.verify import VerificationError, VerificationReport, verify_setpoints

__all__ = [
    "CSV_COLUMNS",
    "Limits",
    "Source",
    "Trajectory",
    "TrajectoryGenerator",
    "VerificationError",
    "VerificationReport",
    "generate_trajectory",
    "verify_setpoints",
]
