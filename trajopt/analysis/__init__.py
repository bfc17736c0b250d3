"""Measurements on verified trajectories, computed only when asked.

:mod:`~trajopt.analysis.margins` (tracking margins), :mod:`~trajopt.analysis.min_margin` (the least margin over a
motion), :mod:`~trajopt.analysis.delay` (delay tolerance), :mod:`~trajopt.analysis.stability` (continuity in the
query: twins, switch points, sweeps) and :mod:`~trajopt.analysis.words` (the motion described in words).
"""
