"""Stages 2 and 3: a C² geometric path, its time parametrization (toppra) and jerk-limited timing (ruckig).

One job a module: :mod:`~trajopt.timing.limits` (the robots' limits, the path parameter's limits per piece),
:mod:`~trajopt.timing.curves` (Bézier blends and B-splines: :class:`BlendedPath`),
:mod:`~trajopt.timing.scaling` (the timing result :class:`TimeScaling`), :mod:`~trajopt.timing.toppra_path`
(toppra's v/a-limited speed profile), :mod:`~trajopt.timing.ruckig_profiles` (jerk-limited timing with ruckig,
rest-to-rest profiles), :mod:`~trajopt.timing.filters` (range-minimum table, opening, box filter) and
:mod:`~trajopt.timing.filtered` (the hard path's box-filtered timing). This package re-exports the names the
rest of the project imports from ``trajopt.timing``.

The private helpers imported ``as`` themselves are re-exported for the tests that check them.
"""

from __future__ import annotations

from trajopt.timing.curves import BLEND_SAMPLES, BLEND_TRIES, BlendedPath, blend_polyline, spline_path
from trajopt.timing.filtered import _eroded_flat_top_profile as _eroded_flat_top_profile
from trajopt.timing.filtered import filtered_scaling
from trajopt.timing.filters import _constant_acceleration_phases as _constant_acceleration_phases
from trajopt.timing.filters import _window_extreme as _window_extreme
from trajopt.timing.filters import _window_min as _window_min
from trajopt.timing.limits import Limits, PieceLimits, piece_limits
from trajopt.timing.ruckig_profiles import (
    RestToRest,
    jerk_limited_scaling,
    min_time_rest_to_rest,
    reachable_speed,
    rest_to_rest_profile,
)
from trajopt.timing.scaling import TimeScaling
from trajopt.timing.toppra_path import toppra_profile

__all__ = [
    "BLEND_SAMPLES",
    "BLEND_TRIES",
    "BlendedPath",
    "Limits",
    "PieceLimits",
    "RestToRest",
    "TimeScaling",
    "blend_polyline",
    "filtered_scaling",
    "jerk_limited_scaling",
    "min_time_rest_to_rest",
    "piece_limits",
    "reachable_speed",
    "rest_to_rest_profile",
    "spline_path",
    "toppra_profile",
]
