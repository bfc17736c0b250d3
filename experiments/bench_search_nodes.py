"""The exact search's cost per node: an earlier revision's search against this one, plans bit for bit (issue 25).

    python experiments/bench_search_nodes.py --base REV [--queries 40] [--seed 0] [--only NAME,...] [--repeat K]
        [--out FILE]
    python experiments/bench_search_nodes.py --base REV --check [--queries 60] [--only NAME,...]
    python experiments/bench_search_nodes.py --base REV --per-node [--queries 40] [--repeat 3] [--only NAME,...]

``REV`` is a git revision (a commit before the change measured). Its ``mpa/planners/graph/search.py`` and
``mesh.py`` are loaded beside this tree's as a second planner (the "before" arm: :func:`mpa.planners.graph.plan_graph`
with the earlier search class and mesh; every other module is this tree's). Layouts and seeded queries as in
``bench_plan_tails.py`` (same seeds and clearances, objective "fastest", speeds (1, 1); with ``--check`` the queries
take in turn the objectives and speeds of ``CHECK_OBJECTIVES``). Every query is planned by
both arms one after the other, the order alternating from query to query, the process's CPU time of each measured
(the machine is shared: CPU time leaves out the waits for a core); with ``--repeat K`` K times per arm, alternating,
and the least time kept. Each plan is hashed (SHA-256 of its cells,
segment offsets, waypoints, times, routes, word and the makespan's bits) together with the search's count of nodes:
the two arms must agree on every query, or the script names the first query that differs and exits 1.

Prints a Markdown table per layout, before → after CPU median, p95 and max (ms), and the share of queries whose plans
agree; ``--check`` skips the timing table and only counts agreeing plans (one line per layout, the total at the
end). ``--per-node``: the search alone, without the rest of the plan (:func:`per_node`): microseconds per node.
``--out FILE`` writes every record to ``FILE.json``.
"""

from __future__ import annotations

import argparse
import hashlib
import importlib.util
import json
import math
import subprocess
import sys
import time
from pathlib import Path
from typing import Any

import numpy as np

ROOT = Path(__file__).resolve().parent
sys.path.insert(0, str(ROOT))
sys.path.insert(0, str(ROOT.parent))

import bench_plan_tails  # noqa: E402

from mpa.errors import NoMotionError  # noqa: E402
from mpa.freespace import free_space  # noqa: E402
from mpa.planners.graph import plan_graph  # noqa: E402
from mpa.planners.graph import query as graph_query  # noqa: E402
from mpa.planners.graph.result import GraphPlan  # noqa: E402
from mpa.planners.search_common import SearchQuery  # noqa: E402

#: ``--check``: the objectives and speeds ``(vA, vB)`` (m/s) the queries take in turn.
CHECK_OBJECTIVES = (
    ("fastest", (1.0, 1.0)),
    ("shortest", (1.0, 1.0)),
    ("fastest", (1.0, 0.55)),
    ("fastest", (0.8, 1.3)),
)


def load_revision(rev: str) -> tuple[type, Any]:
    """The search class ``AnyAngleSearch`` and the mesh builder ``_mesh`` of the revision ``rev``, loaded as modules
    of their own (the mesh kept on the free space under another attribute, so that both arms keep their own)."""
    out = []
    for name in ("search", "mesh"):
        src = subprocess.run(
            ["git", "show", f"{rev}:mpa/planners/graph/{name}.py"],
            cwd=ROOT.parent,
            check=True,
            capture_output=True,
            text=True,
        ).stdout
        if name == "mesh":
            src = src.replace("_plan_mesh", "_plan_mesh_before")
        mod_name = f"_before_{name}"
        spec = importlib.util.spec_from_loader(mod_name, loader=None)
        assert spec is not None
        mod = importlib.util.module_from_spec(spec)
        sys.modules[mod_name] = mod  # dataclasses resolve their module while the class is made
        exec(compile(src, f"{rev}:mpa/planners/graph/{name}.py", "exec"), mod.__dict__)
        out.append(mod)
    search_mod, mesh_mod = out
    return search_mod.AnyAngleSearch, mesh_mod._mesh


class _Counting:
    """Wraps a search class: every search made is kept, so that its count of nodes can be read after the plan."""

    def __init__(self, cls: type) -> None:
        self.cls = cls
        self.made: list[Any] = []

    def __call__(self, *args: Any, **kwargs: Any) -> Any:
        s = self.cls(*args, **kwargs)
        self.made.append(s)
        return s


def plan_hash(plan: GraphPlan | None, nodes: list[int]) -> str:
    """SHA-256 of everything a plan says (None: no motion) and the searches' counts of nodes."""
    h = hashlib.sha256(repr(nodes).encode())
    if plan is None:
        h.update(b"no motion")
        return h.hexdigest()
    names = list(plan.track.edge_names)
    h.update(repr(plan.segment_cells).encode())
    for arr in (plan.segment_offsets, plan.waypoints, plan._times):
        h.update(np.ascontiguousarray(arr, dtype=float).tobytes())
    h.update(repr((plan.route_a.to_list(names), plan.route_b.to_list(names), plan.word)).encode())
    h.update(float(plan.makespan).hex().encode())
    return h.hexdigest()


class Arms:
    """The two planners: ``before`` (the revision's search and mesh) and ``after`` (this tree's)."""

    def __init__(self, rev: str) -> None:
        before_cls, before_mesh = load_revision(rev)
        self.classes = {
            "before": (_Counting(before_cls), before_mesh),
            "after": (_Counting(graph_query.AnyAngleSearch), graph_query._mesh),
        }
        self._as_is = (graph_query.AnyAngleSearch, graph_query._mesh)
        self.searched = False  # whether the last plan searched (the others were answered without a search)

    def plan(
        self, arm: str, track: Any, q: dict[str, Any], objective: str = "fastest", speeds: tuple[float, float] = (1, 1)
    ) -> tuple[float, str]:
        """CPU seconds of one plan by ``arm`` and the hash of its plan and nodes."""
        counting, mesh = self.classes[arm]
        vars(graph_query).update(AnyAngleSearch=counting, _mesh=mesh)
        counting.made.clear()
        try:
            c0 = time.process_time()
            try:
                p = plan_graph(track, q["start"], q["goal"], q["clearance"], objective, speeds)
            except NoMotionError:
                p = None
            cpu = time.process_time() - c0
        finally:
            vars(graph_query).update(AnyAngleSearch=self._as_is[0], _mesh=self._as_is[1])
        self.searched = bool(counting.made)
        return cpu, plan_hash(p, [len(s.nodes) for s in counting.made])


def _ms(xs: list[float]) -> tuple[float, float, float]:
    a = 1e3 * np.array(xs)
    return float(np.median(a)), float(np.percentile(a, 95)), float(a.max())


def run(rev: str, queries: int, seed: int, only: set[str] | None, check: bool, repeat: int = 1) -> list[dict[str, Any]]:
    arms = Arms(rev)
    records = []
    for name, track, ds, qs in bench_plan_tails.layout_queries(queries, seed, only):
        for d in ds:
            free_space(track, d)
        for arm in ("before", "after"):
            arms.plan(arm, track, qs[0])  # warm-up, unrecorded (each arm's mesh made)
        cpu: dict[str, list[float]] = {"before": [], "after": []}
        same = searched = 0
        for qi, q in enumerate(qs[1:]):
            hashes = {}
            how = CHECK_OBJECTIVES[qi % len(CHECK_OBJECTIVES)] if check else ("fastest", (1.0, 1.0))
            least = {"before": math.inf, "after": math.inf}
            for k in range(repeat):
                for arm in ("before", "after") if (qi + k) % 2 == 0 else ("after", "before"):
                    t, hashes[arm] = arms.plan(arm, track, q, *how)
                    least[arm] = min(least[arm], t)
            for arm in least:
                cpu[arm].append(least[arm])
            searched += arms.searched
            if hashes["before"] != hashes["after"]:
                print(f"plans differ: {name} query {q['id']} {q}", flush=True)
                raise SystemExit(1)
            same += 1
        rec: dict[str, Any] = {
            "layout": name,
            "edges": track.n_edges,
            "queries": len(qs) - 1,
            "identical": same,
            "searched": searched,
        }
        for arm in ("before", "after"):
            rec[arm] = dict(zip(("cpu_median_ms", "cpu_p95_ms", "cpu_max_ms"), _ms(cpu[arm]), strict=True))
        records.append(rec)
        if check:
            print(f"{name}: {same} of {len(qs) - 1} plans identical ({searched} searched)", flush=True)
        else:
            b, a = rec["before"], rec["after"]
            print(
                f"| {name} | {track.n_edges} | {len(qs) - 1} | {b['cpu_median_ms']:.2f} → {a['cpu_median_ms']:.2f} | "
                f"{b['cpu_p95_ms']:.1f} → {a['cpu_p95_ms']:.1f} | {b['cpu_max_ms']:.1f} → {a['cpu_max_ms']:.1f} | "
                f"{b['cpu_max_ms'] / a['cpu_max_ms']:.2f} | {same} of {len(qs) - 1} |",
                flush=True,
            )
    if check:
        n_same, n_all = sum(r["identical"] for r in records), sum(r["queries"] for r in records)
        print(f"total: {n_same} of {n_all} plans identical ({sum(r['searched'] for r in records)} searched)")
    return records


def per_node(rev: str, queries: int, seed: int, only: set[str] | None, repeat: int = 3) -> list[dict[str, Any]]:
    """The search alone (``AnyAngleSearch(mesh, query).run()``, objective "fastest", speeds (1, 1), no passing bound)
    of every query whose start and goal share a component, by both arms, ``repeat`` times each alternating (the first
    run of a query pays for the parts of the free space and the mesh it reads first: take ``repeat`` >= 2), the least
    CPU time kept; the nodes made and the segments found must be the same (``repr``, bit for bit). Per layout the
    total over the queries and the slowest query: nodes, milliseconds and microseconds per node, before → after."""
    before_cls, before_mesh = load_revision(rev)
    records = []
    for name, track, _, qs in bench_plan_tails.layout_queries(queries, seed, only):
        rows = []
        for qi, q in enumerate(qs[1:]):
            fs = free_space(track, q["clearance"])
            s = (track.position(q["start"][0]), track.position(q["start"][1]))
            g = (track.position(q["goal"][0]), track.position(q["goal"][1]))
            comp = fs.component_of(*s)
            if comp is None or comp != fs.component_of(*g):
                continue
            query = SearchQuery(track, fs, s, g, "fastest", (1.0, 1.0))
            pair = {
                "before": (before_cls, before_mesh(fs)),
                "after": (graph_query.AnyAngleSearch, graph_query._mesh(fs)),
            }
            least = {"before": math.inf, "after": math.inf}
            nodes: dict[str, int] = {}
            found: dict[str, str] = {}
            for k in range(repeat):
                for arm in ("before", "after") if (qi + k) % 2 == 0 else ("after", "before"):
                    cls, mesh = pair[arm]
                    c0 = time.process_time()
                    search = cls(mesh, query)
                    segs = search.run()
                    least[arm] = min(least[arm], time.process_time() - c0)
                    nodes[arm], found[arm] = len(search.nodes), repr(segs)
                    del search, segs
            if nodes["before"] != nodes["after"] or found["before"] != found["after"]:
                print(f"searches differ: {name} query {q['id']} {q}", flush=True)
                raise SystemExit(1)
            rows.append((least["before"], least["after"], nodes["after"]))
        worst = max(rows, key=lambda x: x[0])
        total = [sum(x[i] for x in rows) for i in range(3)]
        rec = {"layout": name, "searches": len(rows), "total": total, "slowest": list(worst)}
        records.append(rec)
        print(
            f"| {name} | {len(rows)} | {total[2]} | {1e3 * total[0]:.0f} → {1e3 * total[1]:.0f} | "
            f"{1e6 * total[0] / total[2]:.1f} → {1e6 * total[1] / total[2]:.1f} | {total[0] / total[1]:.2f} | "
            f"{worst[2]} | {1e3 * worst[0]:.0f} → {1e3 * worst[1]:.0f} | {worst[0] / worst[1]:.2f} |",
            flush=True,
        )
    return records


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--base", required=True, help="the git revision of the search compared with (the 'before' arm)")
    ap.add_argument("--queries", type=int, default=40)
    ap.add_argument("--seed", type=int, default=0)
    ap.add_argument("--only", default=None, help="comma-separated layout names")
    ap.add_argument("--check", action="store_true", help="only check that the plans agree")
    ap.add_argument("--repeat", type=int, default=1, help="plans per query and arm; the least CPU time is kept")
    ap.add_argument("--per-node", action="store_true", help="the search alone: microseconds per node")
    ap.add_argument("--out", default=None)
    args = ap.parse_args()
    only = set(args.only.split(",")) if args.only else None
    if args.per_node:
        print(
            "| layout | searches | nodes | CPU total (ms) before → after | µs per node | speed-up | "
            "slowest: nodes | its CPU (ms) | its speed-up |"
        )
        print("|---|---|---|---|---|---|---|---|---|")
        records = per_node(args.base, args.queries, args.seed, only, args.repeat)
        if args.out:
            Path(args.out).with_suffix(".json").write_text(json.dumps(records, indent=1))
        return
    if not args.check:
        print(
            "| layout | edges | queries | CPU median (ms) before → after | CPU p95 (ms) | CPU max (ms) | "
            "max speed-up | plans identical |"
        )
        print("|---|---|---|---|---|---|---|---|")
    records = run(args.base, args.queries, args.seed, only, args.check, args.repeat)
    if args.out:
        Path(args.out).with_suffix(".json").write_text(json.dumps(records, indent=1))


if __name__ == "__main__":
    main()
