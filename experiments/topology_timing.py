"""Time :func:`mpa.topology.configuration_space_topology` on seeded random graphs of growing size.

Each graph is a random spanning tree on ``n`` vertices plus random extra edges (about ``1.5 n`` edges in all, no
loops). Prints one table row per size: the cells of ``D₂``, what is left after the collapses, the Betti numbers,
the TC bounds and the wall-clock time (best of ``--repeat`` runs).

Usage::

    python experiments/topology_timing.py [--sizes 10 20 40] [--seed 1] [--repeat 1]
"""

from __future__ import annotations

import argparse
import time
from collections.abc import Sequence

import numpy as np

from mpa.graph import MetricGraph
from mpa.topology import ConfigurationSpaceTopology, configuration_space_topology


def random_graph(n: int, n_edges: int, seed: int) -> MetricGraph:
    """A connected random graph: a random spanning tree on ``n`` vertices plus random extra edges (no loops)."""
    rng = np.random.default_rng(seed)
    edges = [[i, int(rng.integers(0, i))] for i in range(1, n)]
    while len(edges) < n_edges:
        a, b = (int(x) for x in rng.integers(0, n, size=2))
        if a != b:
            edges.append([a, b])
    return MetricGraph.from_edge_list(edges)


def time_one(n: int, seed: int, repeat: int = 1) -> tuple[MetricGraph, ConfigurationSpaceTopology, float]:
    """Build the graph of size ``n`` and time the computation (best of ``repeat``)."""
    graph = random_graph(n, (3 * n) // 2, seed)
    best = float("inf")
    top = None
    for _ in range(max(1, repeat)):
        t0 = time.perf_counter()
        top = configuration_space_topology(graph)
        best = min(best, time.perf_counter() - t0)
    assert top is not None
    return graph, top, best


def main(argv: Sequence[str] | None = None) -> list[dict[str, object]]:
    """Run the timing table; returns the rows (also printed)."""
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--sizes", type=int, nargs="+", default=[10, 20, 40], help="numbers of graph vertices")
    parser.add_argument("--seed", type=int, default=1, help="random seed")
    parser.add_argument("--repeat", type=int, default=1, help="runs per size (the best time is kept)")
    args = parser.parse_args(argv)
    header = (
        f"{'V':>4} {'E':>4} | {'D2 cells (V, E, S)':>22} | {'collapsed (V, E, S)':>22} | {'betti':>15} | TC     | time"
    )
    print(header)
    print("-" * len(header))
    rows = []
    for n in args.sizes:
        graph, top, dt = time_one(n, args.seed, args.repeat)
        cc = top.cell_counts
        left = [sum(getattr(c.collapsed_cells, k) for c in top.components) for k in ("vertices", "edges", "squares")]
        tc = str(top.tc) if top.tc is not None else f"{top.tc_bounds[0]}..{top.tc_bounds[1]}"
        print(
            f"{graph.n_vertices:>4} {graph.n_edges:>4} | {(cc.vertices, cc.edges, cc.squares)!s:>22} | "
            f"{tuple(left)!s:>22} | {top.betti!s:>15} | {tc:<6} | {dt:.2f} s"
        )
        rows.append({"vertices": graph.n_vertices, "edges": graph.n_edges, "betti": top.betti, "tc": top.tc, "s": dt})
    return rows


if __name__ == "__main__":
    main()
