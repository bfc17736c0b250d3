"""The graph planner's exact any-angle search (:class:`mpa.planners.graph.search.AnyAngleSearch`), compiled by numba.

:mod:`mpa` is numpy and scipy only, and its search runs in the interpreter: 12-22 µs per node, and the slow queries
of a large map take 20 000-40 000 nodes (docs/performance.md). This module is the same search as loops over arrays,
compiled by numba, and :func:`install` hands it to :func:`mpa.planners.graph.query.plan_graph`
(:func:`mpa.planners.graph.query.use_search`). It is the search node for node: the same nodes in the same order, the
same floating-point operations in the same order (Python's :func:`math.hypot` included, :func:`_py_hypot`), so the
plans are the same bit for bit; the tests check it on thousands of queries.

The kernel reads the layout and its free space from arrays (the edges' ends and lengths, each vertex's edge ends, the
faces' intervals, a bit per free piece of each cell: :func:`~trajopt.plan_kernel.search._layout_arrays`, made once per
mesh) and names polygons, faces and points as :class:`~mpa.planners.graph.mesh._Mesh` does, by integers and hash
tables; nothing of the mesh is built in the interpreter. The passing bound's fronts of hinges are made in the kernel
(:func:`~trajopt.plan_kernel.bound._front`) from the bound's segments, by the operations of
:class:`~mpa.planners.graph.bounds.PassingBound`.

:func:`install` also hands :mod:`mpa.planners.corners` the compiled builder of each chain's least-distance programme
(:func:`trajopt.plan_kernel.corners.build_programme`, :func:`mpa.planners.corners.use_programme`): the same arrays
bit for bit, so the corners re-solved after the search are the same too.

numba's on-disk cache of these kernels is kept consistent across the package's modules
(:mod:`trajopt.plan_kernel.cache`): on import, before any kernel is loaded, the cache is emptied when one of the
modules the kernels are compiled from has changed since it was written.
"""

from pathlib import Path

from trajopt.plan_kernel.cache import fresh_cache, kernel_sources

fresh_cache(Path(__file__).resolve().parent / "__pycache__", kernel_sources())

from trajopt.plan_kernel.search import ENV, CompiledSearch, install, installed, warm  # noqa: E402

__all__ = ["ENV", "CompiledSearch", "install", "installed", "warm"]
