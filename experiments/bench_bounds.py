"""The passing bound (``mpa.planners.graph.bounds``) against the search's own bound, on the queries that need a search.

    python experiments/bench_bounds.py [--queries 40] [--seed 0] [--budget 200000] [--only NAME,...] [--out FILE]

Layouts and seeded queries as in ``bench_plan_tails.py`` (same seeds, same clearances). Per layout, the queries the
planner answers with the search (the robots' independent motion does not keep the clearance), each searched twice
in one process, one after the other: the search's own bound, then with the passing bound (its construction timed
apart). Per query: the search's bound at the start (``max(dA/vA, dB/vB)``), the passing bound at the start, the
optimum (the search's cost), the queue's pops and the wall times; both searches must give the same cost. Prints a
Markdown table per layout (medians, p95 and max of the times; the share of the gap between the search's bound and
the optimum that the passing bound closes at the start); ``--out FILE`` writes every record to ``FILE.json``.
"""

from __future__ import annotations

import argparse
import heapq
import json
import math
import sys
import time
from pathlib import Path
from typing import Any

import numpy as np

ROOT = Path(__file__).resolve().parent
sys.path.insert(0, str(ROOT))
sys.path.insert(0, str(ROOT.parent))

import bench_plan_tails  # noqa: E402

from mpa.freespace import free_space  # noqa: E402
from mpa.planners.graph import search as search_module  # noqa: E402
from mpa.planners.graph.bounds import PassingBound, fastest_cost  # noqa: E402
from mpa.planners.graph.mesh import _mesh  # noqa: E402
from mpa.planners.graph.shortcut import _independent_motion  # noqa: E402
from mpa.planners.search_common import SearchQuery  # noqa: E402


class _Pops:
    """Counts the search queue's pops (wraps ``heapq.heappop`` as the search module sees it)."""

    def __init__(self) -> None:
        self.n = 0
        self._pop = heapq.heappop

    def __call__(self, heap: list[Any]) -> Any:
        self.n += 1
        return self._pop(heap)


def run(queries: int, seed: int, budget: int, only: set[str] | None) -> list[dict[str, Any]]:
    records: list[dict[str, Any]] = []
    pops = _Pops()
    search_module.heapq.heappop = pops  # type: ignore[attr-defined]
    for name, track, _, qs in bench_plan_tails.layout_queries(queries, seed, only):
        rows = []
        geo = track.geometry
        for q in qs[1:]:
            fs = free_space(track, q["clearance"])
            s, g = q["start"], q["goal"]
            comp = fs.component_of(*s)
            if comp is None or comp != fs.component_of(*g):
                continue
            mesh = _mesh(fs)
            if _independent_motion(mesh, s, g) is not None:
                continue
            pops.n = 0
            t0 = time.perf_counter()
            query = SearchQuery(track, fs, s, g, "fastest", (1.0, 1.0))
            plain = search_module.AnyAngleSearch(mesh, query).run(budget)
            t1 = time.perf_counter()
            n_plain = pops.n
            pb = PassingBound(mesh, s, g, 1.0, 1.0)
            t2 = time.perf_counter()
            pops.n = 0
            with_bound = search_module.AnyAngleSearch(mesh, query, bound=pb if pb.vertex is not None else None).run(
                budget
            )
            t3 = time.perf_counter()
            base = max(geo.distance_scalar(*s[0], *g[0]), geo.distance_scalar(*s[1], *g[1]))
            opt = fastest_cost(with_bound, 1.0, 1.0) if with_bound is not None else math.nan
            if plain is not None and with_bound is not None:
                c0 = fastest_cost(plain, 1.0, 1.0)
                if abs(c0 - opt) > 1e-9 * max(1.0, opt):
                    raise AssertionError(f"{name} query {q['id']}: cost {c0!r} without, {opt!r} with the bound")
            rows.append(
                {
                    "layout": name,
                    "query": q["id"],
                    "swap": q["swap"],
                    "clearance": q["clearance"],
                    "base_bound": base,
                    "passing_bound": pb.at_start,
                    "optimum": opt,
                    "segments": pb.n_segments,
                    "pops_plain": n_plain if plain is not None else None,
                    "pops_bound": pops.n if with_bound is not None else None,
                    "plain_ms": 1e3 * (t1 - t0),
                    "build_ms": 1e3 * (t2 - t1),
                    "bound_ms": 1e3 * (t3 - t1),
                }
            )
        records.extend(rows)
        if not rows:
            print(f"| {name} | {track.n_edges} | 0 | | | | | | |", flush=True)
            continue
        plain_t = np.array([r["plain_ms"] for r in rows])
        bound_t = np.array([r["bound_ms"] for r in rows])
        closed = [
            (r["passing_bound"] - r["base_bound"]) / (r["optimum"] - r["base_bound"])
            for r in rows
            if r["optimum"] - r["base_bound"] > 1e-9 * max(1.0, r["optimum"])
        ]
        pp = sum(r["pops_plain"] or 0 for r in rows)
        pw = sum(r["pops_bound"] or 0 for r in rows)
        print(
            f"| {name} | {track.n_edges} | {len(rows)} | "
            f"{np.median(plain_t):.1f} → {np.median(bound_t):.1f} | "
            f"{np.percentile(plain_t, 95):.1f} → {np.percentile(bound_t, 95):.1f} | "
            f"{plain_t.max():.1f} → {bound_t.max():.1f} | {pp} → {pw} | "
            f"{np.median(closed) if closed else math.nan:.2f} |",
            flush=True,
        )
    return records


def main() -> None:
    ap = argparse.ArgumentParser(description=(__doc__ or "").splitlines()[0])
    ap.add_argument("--queries", type=int, default=40)
    ap.add_argument("--seed", type=int, default=0)
    ap.add_argument("--budget", type=int, default=200_000, help="queue pops before a search gives up")
    ap.add_argument("--only", default=None, help="comma-separated layout names")
    ap.add_argument("--out", default=None)
    args = ap.parse_args()
    print(
        "| layout | edges | searched queries | search median (ms) own → passing | p95 (ms) | max (ms) | "
        "pops (sum) | gap closed at the start (median) |"
    )
    print("|---|---|---|---|---|---|---|---|")
    only = set(args.only.split(",")) if args.only else None
    records = run(args.queries, args.seed, args.budget, only)
    if args.out:
        Path(args.out).with_suffix(".json").write_text(json.dumps(records, indent=1))


if __name__ == "__main__":
    main()
