"""Plan-time tails of the complete graph planner on every layout up to 150 edges (issue 25, point 1).

    python experiments/bench_plan_tails.py [--queries 100] [--seed 0] [--out FILE] [--only NAME,...]
        [--compare | --steps | --limits | --fourth | --fifth | --sixth | --seventh | --eighth | --ninth | --eleventh]
        [--large] [--repeat K] [--python]

Layouts: the example layouts (``examples/tracks``), the benchmark's scaling layouts (``graph_runner.grid_layout``,
10 / 30 / 100 / 150 edges, three seeds each), the seeded warehouse grids and road maps of
``bench.graph_scale`` at 10 / 30 / 100 / 150 edges, and the Open-RMF sample maps converted as layouts (office L1,
hotel L1 / L2 / L3; the airport terminal's level L1, navigation graph 2: 139 lanes, 1 186 m, at D = 0.6 m). Per
layout ``--queries`` seeded queries (``graph_runner.make_graph_queries``: every fourth a swap) at four clearances
(5 %, 20 %, 50 %, 100 % of the median edge length; D = 1 m on the generated layouts),
the free space built and cached before the clock starts, one unrecorded warm-up query. Per layout: median, p95 and
max of ``mpa.plan(..., planner="graph")`` in milliseconds, wall time and the process's CPU time (the machine is
shared: CPU time leaves out the waits for a core), and the slowest query (to profile it). Prints a Markdown
table; ``--out FILE`` also writes ``FILE.json`` with every record. ``--compare``: every query planned twice in a row,
without the passing bound (``mpa.planners.graph.query.PASSING_BOUND_AFTER = None``, before) and with it (after), the
order alternating from query to query; the table gives before → after and the makespans must agree.
``--steps``: the same, before = the search of the earlier scheme (every root reached more cheaply expanded again,
``mpa.planners.graph.search.AGAIN_GRID_STEPS = 0``; the passing bound after 5 000 pops everywhere; a search whose
passing bound gains nothing started again, ``query.RESUME_WITHOUT_GAIN = False``; the passing bound of a face entry
over every segment, ``PassingBound.least_through_all``, and of a point too, ``bounds.POINTS_FROM_FRONTS = False``),
after = the code as it is. ``--limits``: before = the passing bound of whole segments with exact goal costs, built
afresh per query after 2 000 pops (5 000 above 120 edges), every segment at once; after = the code as it is
(pieces, relaxed goal costs, the segments' geometry kept per vertex, the bound after 300 pops whenever it gains more
than 1e-9 of the robots' own at the start instead of 0.1 %, its segments first limited to near the optimum).
``--fourth``: before = Python's cyclic garbage collector paused only while a search runs (not for the whole plan)
and the passing segments of every cell, kept per vertex, on every layout
(``mpa.planners.graph.bounds.REACH_EDGES`` above any layout's size); after = the code as it is (the collector paused
for the whole plan, the segments within the bound's reach above 300 edges).
``--fifth``: before = the bounded searches' limits from the slacks alone (``mpa.planners.graph.query.LIMIT_STEP_ASIDE``
and ``LIMIT_WAIT`` 0); after = the code as it is (the first limit admits a step aside, the second a wait of one
clearance). ``--sixth``: before = mpa's own search in the interpreter
(:class:`mpa.planners.graph.search.AnyAngleSearch`), after = the compiled one (:mod:`trajopt.plan_kernel`: the same
nodes; the makespans must agree). ``--seventh``: before = the corners re-solved with every row of their programme
(``mpa.planners.corners.DROP_IMPLIED_ROWS = False``), after = the rows that others imply left out (the same
minimiser). ``--eighth``: before = every chain's programme solved with all its rows
(``mpa.planners.corners.ACTIVE_SET_SEED = False``), after = first with the rows tight at the chain's own corners and
the durations' rows, the rows its minimiser breaks added (the same minimiser). ``--ninth``: before = each chain's
programme built in the interpreter (:func:`mpa.planners.corners._programme`), after = compiled
(:func:`trajopt.plan_kernel.corners.build_programme`: the same arrays bit for bit). ``--eleventh``: before = every
search's node arrays new (``trajopt.plan_kernel.search.SPARE_BYTES = 0``) and the passing bound's least at the start
computed whole before it is compared with the robots' own bound (no ``floor``); after = the code as it is (a dropped
search's arrays start the next; the least stops once it cannot gain). ``--repeat K``: every query
planned K times per arm in a row, the least time kept.
Every arm searches with the compiled search (:func:`trajopt.plan_kernel.install`, warmed before the clock starts)
unless ``--python`` is given (or the arm is ``--sixth``'s before).
"""

from __future__ import annotations

import argparse
import gc
import json
import math
import sys
import time
import types
from collections.abc import Iterator
from pathlib import Path
from typing import Any

import numpy as np

ROOT = Path(__file__).resolve().parent
sys.path.insert(0, str(ROOT))
sys.path.insert(0, str(ROOT.parent))

from bench.graph_runner import CLEARANCE_FRACTIONS, _plan, grid_layout, make_graph_queries  # noqa: E402
from bench.graph_scale import road_map_layout, warehouse_layout  # noqa: E402

from mpa.freespace import free_space  # noqa: E402
from mpa.graph_track import GraphTrack  # noqa: E402
from mpa.planners import corners as plan_corners  # noqa: E402
from mpa.planners.graph import bounds as graph_bounds  # noqa: E402
from mpa.planners.graph import passing as graph_passing  # noqa: E402
from mpa.planners.graph import query as graph_query  # noqa: E402
from mpa.planners.graph import search as graph_search  # noqa: E402
from mpa.planners.graph.bounds import PassingBound  # noqa: E402
from trajopt import plan_kernel  # noqa: E402
from trajopt.plan_kernel import search as kernel_search  # noqa: E402
from trajopt.plan_kernel.corners import build_programme  # noqa: E402

DATA = ROOT.parent / "tests" / "data" / "openrmf"
EXAMPLES = ROOT.parent / "examples" / "tracks"
SIZES = (10, 30, 100, 150)


def layouts(large: bool = False) -> list[tuple[str, GraphTrack, list[float] | None]]:
    """``(name, track, clearances)``; clearances None: the fractions of the median edge length. ``large``: also the
    seeded warehouse grid and road map of 1 000 edges (D = 1 m; the free space takes 1-2 s and about 400 MB)."""
    out: list[tuple[str, GraphTrack, list[float] | None]] = []
    for p in sorted(EXAMPLES.glob("*.json")):
        out.append((p.stem, GraphTrack.from_json(p), None))
    for level in ("L1",):
        out.append((f"office {level}", GraphTrack.from_file(DATA / "office.building.yaml", level=level), None))
    for level in ("L1", "L2", "L3"):
        out.append((f"hotel {level}", GraphTrack.from_file(DATA / "hotel.building.yaml", level=level), None))
    airport = GraphTrack.from_file(DATA / "airport_terminal.building.yaml", level="L1", nav_graph=2)
    out.append(("airport L1 graph 2", airport, [0.6]))
    for n_e in SIZES:
        for k in range(3):
            out.append((f"scaling {n_e}/{k}", grid_layout(n_e, n_e * 10 + k), [1.0]))
        out.append((f"warehouse {n_e}", warehouse_layout(n_e, n_e), [1.0]))
        out.append((f"road map {n_e}", road_map_layout(n_e, n_e), [1.0]))
    if large:
        out.append(("warehouse 1000", warehouse_layout(1000, 1000), [1.0]))
        out.append(("road map 1000", road_map_layout(1000, 1000), [1.0]))
    return out


def layout_queries(
    queries: int, seed: int, only: set[str] | None = None, large: bool = False
) -> Iterator[tuple[str, GraphTrack, list[float], list[dict[str, Any]]]]:
    """Per layout (those named in ``only``, or all; ``large``: with the 1 000-edge ones): ``(name, track,
    clearances, queries + 1 seeded queries)``, the first query the unrecorded warm-up."""
    for li, (name, track, ds) in enumerate(layouts(large)):
        if only and name not in only:
            continue
        if ds is None:
            med = float(np.median(track.lengths))
            ds = [round(f * med, 6) for f in CLEARANCE_FRACTIONS]
        yield name, track, ds, make_graph_queries(track, queries + 1, seed * 1000 + li, ds)


def _stats(times: list[float], cpu: list[float]) -> dict[str, float]:
    ts, cs = np.array(times), np.array(cpu)
    return {
        "median_ms": 1e3 * float(np.median(ts)),
        "p95_ms": 1e3 * float(np.percentile(ts, 95)),
        "max_ms": 1e3 * float(ts.max()),
        "cpu_median_ms": 1e3 * float(np.median(cs)),
        "cpu_p95_ms": 1e3 * float(np.percentile(cs, 95)),
        "cpu_max_ms": 1e3 * float(cs.max()),
    }


def _arm(compare: str | None, before: bool) -> None:
    """Set the planner to one arm of a comparison: ``compare`` "bound" (without / with the passing bound) or "steps"
    (the earlier search / this one); None or ``before`` False: the code as it is."""
    old = compare == "steps" and before
    whole = compare == "limits" and before
    graph_query.PASSING_BOUND_AFTER = (
        None
        if compare == "bound" and before
        else (EARLIER_AFTER if old else (WHOLE_AFTER[0] if whole else _AS_IS["after"]))
    )
    graph_query.PASSING_BOUND_AFTER_LARGE = WHOLE_AFTER[1] if whole else _AS_IS["after_large"]
    graph_passing.PIECE_LENGTH = None if whole else _AS_IS["piece"]
    graph_bounds.W_EXACT = True if whole else _AS_IS["w_exact"]
    graph_passing.GEOMETRY_CACHE = 0 if whole else _AS_IS["cache"]
    graph_query.LIMIT_SLACKS = () if whole else _AS_IS["slacks"]
    graph_query.BOUND_GAIN = WHOLE_GAIN if whole else _AS_IS["gain"]
    graph_search.AGAIN_GRID_STEPS = 0.0 if old else _AS_IS["again"]
    graph_query.RESUME_WITHOUT_GAIN = False if old else _AS_IS["resume"]
    graph_bounds.POINTS_FROM_FRONTS = False if old else _AS_IS["points"]
    PassingBound.least_through = PassingBound.least_through_all if old else _AS_IS["least"]  # type: ignore[method-assign]
    fourth = compare == "fourth" and before
    graph_query.gc = _NO_PAUSE if fourth else gc  # type: ignore[assignment]
    graph_bounds.REACH_EDGES = 2**62 if fourth else _AS_IS["reach"]
    fifth = compare == "fifth" and before
    graph_query.LIMIT_STEP_ASIDE = 0.0 if fifth else _AS_IS["step_aside"]
    graph_query.LIMIT_WAIT = 0.0 if fifth else _AS_IS["wait"]
    plan_corners.DROP_IMPLIED_ROWS = False if compare == "seventh" and before else _AS_IS["implied"]
    plan_corners.ACTIVE_SET_SEED = False if compare == "eighth" and before else _AS_IS["seed"]
    python = SEARCH["python"] or (compare == "sixth" and before)
    graph_query.use_search(None if python else plan_kernel.CompiledSearch)
    interpreted = python or (compare == "ninth" and before)
    plan_corners.use_programme(None if interpreted else build_programme)
    eleventh = compare == "eleventh" and before
    if eleventh and kernel_search.SPARE_BYTES:  # the after arm's spare arrays set aside, not dropped
        _SET_ASIDE[:] = kernel_search._spare
        kernel_search._spare.clear()
    elif not eleventh and not kernel_search.SPARE_BYTES:
        kernel_search._spare[:] = _SET_ASIDE
        _SET_ASIDE.clear()
    kernel_search.SPARE_BYTES = 0 if eleventh else _AS_IS["spare"]
    graph_query.passing_bound = _whole_passing_bound if eleventh else graph_bounds.passing_bound  # type: ignore[assignment]


#: ``--eleventh``: the after arm's spare node arrays while the before arm runs.
_SET_ASIDE: list[Any] = []


def _whole_passing_bound(mesh: Any, start: Any, goal: Any, va: float, vb: float, floor: float = -math.inf) -> Any:
    """``--eleventh``'s before: the passing bound with its whole least at the start, then compared with ``floor``."""
    b = graph_bounds.passing_bound(mesh, start, goal, va, vb)
    return b if b is not None and b.at_start > floor else None


#: Every arm with mpa's own search: ``--python``, or where the compiled one is not installed
#: (:func:`trajopt.plan_kernel.install`; :func:`main` installs it, a caller of :func:`run` may).
SEARCH = {"python": True}


#: ``--fourth``'s "before": the plan does not pause the collector (the search still does, in ``AnyAngleSearch.run``).
_NO_PAUSE = types.SimpleNamespace(isenabled=lambda: False, disable=lambda: None, enable=lambda: None)

#: The pops after which the earlier search started again with the passing bound.
EARLIER_AFTER = 5000

#: The pops after which the search with whole passing segments started again with the bound (up to 120 edges,
#: above).
WHOLE_AFTER = (2000, 5000)

#: The passing bound of whole segments was used only when it gained 0.1 % at the start.
WHOLE_GAIN = 1e-3

_AS_IS: dict[str, Any] = {
    "after": graph_query.PASSING_BOUND_AFTER,
    "after_large": graph_query.PASSING_BOUND_AFTER_LARGE,
    "piece": graph_passing.PIECE_LENGTH,
    "w_exact": graph_bounds.W_EXACT,
    "cache": graph_passing.GEOMETRY_CACHE,
    "slacks": graph_query.LIMIT_SLACKS,
    "gain": graph_query.BOUND_GAIN,
    "again": graph_search.AGAIN_GRID_STEPS,
    "resume": graph_query.RESUME_WITHOUT_GAIN,
    "reach": graph_bounds.REACH_EDGES,
    "points": graph_bounds.POINTS_FROM_FRONTS,
    "least": PassingBound.least_through,
    "step_aside": graph_query.LIMIT_STEP_ASIDE,
    "wait": graph_query.LIMIT_WAIT,
    "implied": plan_corners.DROP_IMPLIED_ROWS,
    "seed": plan_corners.ACTIVE_SET_SEED,
    "spare": kernel_search.SPARE_BYTES,
}


def run(
    queries: int,
    seed: int,
    only: set[str] | None = None,
    compare: bool | str = False,
    large: bool = False,
    repeat: int = 1,
) -> list[dict[str, Any]]:
    """Every layout's seeded queries planned (twice, before and after, when ``compare`` is "bound" or True, or
    "steps"); one record per layout. ``repeat``: each query planned that many times per arm in a row, its least wall
    and CPU time recorded (a shared virtual machine's single runs of identical code differ by up to 1.5x)."""
    records = []
    mode = "bound" if compare is True else (compare or None)
    arms = (True, False) if mode else (False,)
    for name, track, ds, qs in layout_queries(queries, seed, only, large):
        for d in ds:
            free_space(track, d)
        _arm(mode, False)
        _plan(track, qs[0], (1.0, 1.0))
        times: list[list[float]] = [[] for _ in arms]
        cpu: list[list[float]] = [[] for _ in arms]
        spans: list[list[float | None]] = [[] for _ in arms]
        for qi, q in enumerate(qs[1:]):
            order = range(len(arms)) if qi % 2 == 0 else reversed(range(len(arms)))
            for k in order:
                _arm(mode, arms[k])
                best_cpu = best_wall = math.inf
                for _ in range(repeat):
                    t0, c0 = time.perf_counter(), time.process_time()
                    p = _plan(track, q, (1.0, 1.0))
                    best_cpu = min(best_cpu, time.process_time() - c0)
                    best_wall = min(best_wall, time.perf_counter() - t0)
                cpu[k].append(best_cpu)
                times[k].append(best_wall)
                spans[k].append(None if p is None else p.makespan)
        _arm(None, False)
        worst = int(np.argmax(times[-1]))
        rec: dict[str, Any] = {
            "layout": name,
            "edges": track.n_edges,
            "queries": len(times[-1]),
            **_stats(times[-1], cpu[-1]),
            "worst": {
                "start": qs[1 + worst]["start"],
                "goal": qs[1 + worst]["goal"],
                "clearance": qs[1 + worst]["clearance"],
            },
            "makespans": spans[-1],
        }
        if mode:
            rec["before"] = _stats(times[0], cpu[0])
            rec["makespan_differences"] = sum(
                1
                for x, y in zip(spans[0], spans[1], strict=True)
                if (x is None) != (y is None) or (x is not None and y is not None and abs(x - y) > 1e-9 * max(1.0, x))
            )
            b4 = rec["before"]
            print(
                f"| {name} | {rec['edges']} | {rec['queries']} | "
                f"{b4['cpu_median_ms']:.2f} → {rec['cpu_median_ms']:.2f} | "
                f"{b4['cpu_p95_ms']:.1f} → {rec['cpu_p95_ms']:.1f} | "
                f"{b4['cpu_max_ms']:.1f} → {rec['cpu_max_ms']:.1f} | "
                f"{b4['median_ms']:.2f} → {rec['median_ms']:.2f} | {b4['p95_ms']:.1f} → {rec['p95_ms']:.1f} | "
                f"{b4['max_ms']:.1f} → {rec['max_ms']:.1f} | {rec['makespan_differences']} |",
                flush=True,
            )
        else:
            print(
                f"| {name} | {rec['edges']} | {rec['queries']} | {rec['median_ms']:.2f} | {rec['p95_ms']:.1f} | "
                f"{rec['max_ms']:.1f} | {rec['cpu_median_ms']:.2f} | {rec['cpu_p95_ms']:.1f} | "
                f"{rec['cpu_max_ms']:.1f} |",
                flush=True,
            )
        records.append(rec)
    return records


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--queries", type=int, default=100)
    ap.add_argument("--seed", type=int, default=0)
    ap.add_argument("--only", default=None, help="comma-separated layout names")
    ap.add_argument("--out", default=None)
    ap.add_argument("--compare", action="store_true", help="without and with the passing bound, side by side")
    ap.add_argument("--steps", action="store_true", help="the earlier search and this one, side by side")
    ap.add_argument(
        "--limits", action="store_true", help="the bound of whole segments and the one of pieces and limits"
    )
    ap.add_argument(
        "--fourth",
        action="store_true",
        help="the collector paused in the search only and every passing segment, against the code as it is",
    )
    ap.add_argument("--fifth", action="store_true", help="the limits from the slacks alone, against the code as it is")
    ap.add_argument("--sixth", action="store_true", help="mpa's own search against the compiled one")
    ap.add_argument("--seventh", action="store_true", help="the corners' programme with every row against the lean one")
    ap.add_argument(
        "--eighth", action="store_true", help="every chain solved with all its rows against from its tight rows"
    )
    ap.add_argument(
        "--ninth", action="store_true", help="the corners' programme built in the interpreter against compiled"
    )
    ap.add_argument(
        "--eleventh",
        action="store_true",
        help="new node arrays per search and the passing bound's whole least at the start, against the code as it is",
    )
    ap.add_argument("--python", action="store_true", help="every arm with mpa's own search (not the compiled one)")
    ap.add_argument("--repeat", type=int, default=1, help="plans per query and arm, the least time kept")
    ap.add_argument("--large", action="store_true", help="also the 1 000-edge warehouse grid and road map")
    args = ap.parse_args()
    SEARCH["python"] = args.python or not plan_kernel.install()
    if not SEARCH["python"]:
        plan_kernel.warm()  # compiled, or loaded from the cache, before the clock
    arms = ("steps", "limits", "fourth", "fifth", "sixth", "seventh", "eighth", "ninth", "eleventh")
    mode = next((a for a in arms if getattr(args, a)), args.compare)
    if mode:
        print(
            "| layout | edges | queries | CPU median (ms) before → after | CPU p95 (ms) | CPU max (ms) | "
            "wall median (ms) | wall p95 (ms) | wall max (ms) | makespans differing |"
        )
        print("|---|---|---|---|---|---|---|---|---|---|")
    else:
        print(
            "| layout | edges | queries | wall median (ms) | wall p95 (ms) | wall max (ms) | CPU median (ms) | "
            "CPU p95 (ms) | CPU max (ms) |"
        )
        print("|---|---|---|---|---|---|---|---|---|")
    only = set(args.only.split(",")) if args.only else None
    records = run(args.queries, args.seed, only, mode, args.large, args.repeat)
    if args.out:
        Path(args.out).with_suffix(".json").write_text(json.dumps(records, indent=1))


if __name__ == "__main__":
    main()
