"""The graph planner's exact any-angle search (:class:`mpa.planners.graph.search.AnyAngleSearch`), compiled by numba.

:mod:`mpa` is numpy and scipy only, and its search runs in the interpreter: 12-22 µs per node, and the slow queries
of a large map take 20 000-40 000 nodes (docs/performance.md). This module is the same search as loops over arrays,
compiled by numba, and :func:`install` hands it to :func:`mpa.planners.graph.query.plan_graph`
(:func:`mpa.planners.graph.use_search`). It is the search node for node: the same nodes in the same order, the
same floating-point operations in the same order (Python's :func:`math.hypot` included, :func:`_py_hypot`), so the
plans are the same bit for bit; the tests check it on thousands of queries.

The free space's polygons, faces and points are named by integers and written into arrays as the search first
reaches them (:class:`_MeshArrays`, kept with the mesh across queries); the kernel (:func:`_run`) stops and asks
(:data:`NEED_PAGES`, :data:`NEED_MEMBERS`) when it needs a part not written yet, before it takes the node that needs
it from the queue, and resumes where it stopped. The passing bound's fronts of hinges are made in the kernel
(:func:`_front`) from the bound's segments, by the operations of :class:`~mpa.planners.graph.bounds.PassingBound`.
"""

from trajopt.plan_kernel.search import ENV, CompiledSearch, install, installed, warm

__all__ = ["ENV", "CompiledSearch", "install", "installed", "warm"]
