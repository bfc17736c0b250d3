"""bench: the side-by-side benchmark of ``experiments/benchmark.py``.

Modules: :mod:`bench.geometry` (exact separation along joint straight moves; joint paths cut into single-route
segments), :mod:`bench.motion` (timing and verification of those segments with ``trajopt``'s own stages),
:mod:`bench.baselines` (OMPL RRTConnect and grid A*), :mod:`bench.runner` (one query, every method, inside a
worker), :mod:`bench.parallel` (process pool or Dask cluster), :mod:`bench.report` (tables and plots).
The package lives beside the script: ``experiments/`` must be on ``sys.path`` (it is when the script runs).
"""

__all__: list[str] = []
