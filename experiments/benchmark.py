"""Benchmark: ours against the planners a robotics engineer would pick instead, side by side in one run.

Every method turns the same seeded queries into jerk-limited setpoints through the same time parametrization
(``trajopt.timing``) and the same verification gate (``trajopt.verify.gate.verify_setpoints``):

- ``ours``: plan → fast path (one ruckig profile on the straight route-coordinate line) or hard path (corridor QP in
  the plan's homotopy class, B-spline, filtered jerk-limited timing) → the gate (``trajopt.TrajectoryGenerator``);
- ``raw_plan``: the paper's plan as is, step by step, rest to rest;
- ``ompl_rest`` / ``ompl_bspline``: OMPL 2.x RRTConnect with an exact motion validator, shortcut, executed rest
  to rest at its waypoints / B-spline-smoothed, re-verified and timed like ours;
- ``ompl_geo`` (lollipop): the same with motions along shortest paths of the track (the robots may then change
  order through the loop's seam, which a vector space of track coordinates forbids);
- ``grid``: A* on the product of the discretized track graphs (exact edge checks, time-like L∞ cost), shortcut,
  timed like ours: the resolution-complete reference.

Metrics per method and query: success, verification, compute time (inside the worker), makespan, makespan over
the lower bound, minimum separation, homotopy class, and stability: the sup distance to the trajectory of a
perturbed twin query (start and goal moved by δ) over normalised time; the discontinuity rate is the share of
twins farther apart than the threshold.

Usage::

    python experiments/benchmark.py --queries 100,50 --track lollipop,circle --seed 0 --out DIR
    python experiments/benchmark.py --queries 3 --workers 1 --grid 0.05 --ompl-time 0.05 --out DIR
    python experiments/benchmark.py --queries 200 --dask tcp://scheduler:8786 --out DIR
    python experiments/benchmark.py --scaling --queries 20 --out DIR
    python experiments/benchmark.py --compute --queries 200 --out DIR      # ours vs the lean OMPL pipeline
    python experiments/benchmark.py --track graphs --queries 50 --out DIR          # graph layouts, plan level
    python experiments/benchmark.py --track y_junction,my_layout.json --queries 10 --graph-parts layouts --out DIR

Writes ``DIR/results.json`` (one record per method and query), ``DIR/results.md`` (tables),
``DIR/makespan.png``, ``DIR/compute_time.png``, ``DIR/discontinuity.png`` and ``DIR/run.json``; with
``--scaling`` ``DIR/scaling.json``, ``DIR/scaling.md`` and ``DIR/scaling.png`` instead.

Graph layouts (``--track`` names of ``examples/tracks`` — y_junction, passing_loop, two_sidings, theta, figure_eight,
warehouse — or layout files; ``graphs`` = all six) run the plan-level graph benchmark of
:mod:`bench.graph_runner` in this process (ours = ``mpa.plan(..., planner="graph", objective="fastest")``, the
exact-edge grid search and OMPL of :mod:`bench.graph_baselines`), plus with ``--graph-parts`` the Y-junction
threshold oracle, the paper tracks' price of stability and the scaling table; writes ``DIR/graphs.json`` and
``DIR/graphs.md`` (see docs/benchmark_graphs.md).
"""

from __future__ import annotations

import argparse
import json
import os
import platform
import shlex
import sys
import time
from collections.abc import Sequence
from dataclasses import replace
from pathlib import Path
from typing import Any

sys.path.insert(0, str(Path(__file__).resolve().parent))

from bench import graph_runner
from bench.compute import TRACKS as COMPUTE_TRACKS
from bench.compute import compare_compute, compute_markdown
from bench.parallel import run_tasks
from bench.report import plot_results, plot_scaling, results_markdown, scaling_markdown
from bench.runner import METHODS, BenchConfig, make_queries

from mpa import defaults
from trajopt.cli.common import trajectory_options
from trajopt.export import atomic_write_text

__all__ = ["main", "run_benchmark", "run_compute", "run_scaling"]


def _versions() -> str:
    from importlib.metadata import PackageNotFoundError, version

    out = [f"python {platform.python_version()}"]
    for pkg in ("ompl", "casadi", "toppra", "ruckig", "numpy"):
        try:
            out.append(f"{pkg} {version(pkg)}")
        except PackageNotFoundError:
            out.append(f"{pkg} missing")
    return ", ".join(out)


def _machine() -> str:
    return f"{platform.machine()}, {os.cpu_count()} cores ({platform.processor() or platform.system()})"


def _write_json(path: Path, obj: Any) -> None:
    atomic_write_text(path, json.dumps(obj, indent=1, allow_nan=False, default=_json_default) + "\n")


def _json_default(obj: Any) -> Any:
    if hasattr(obj, "item"):
        return obj.item()
    raise TypeError(f"not JSON serializable: {type(obj).__name__}")


def _clean(x: Any) -> Any:
    """NaN/inf to None, recursively (strict JSON)."""
    if isinstance(x, float):
        return x if x == x and abs(x) != float("inf") else None
    if isinstance(x, dict):
        return {k: _clean(v) for k, v in x.items()}
    if isinstance(x, list):
        return [_clean(v) for v in x]
    return x


def run_benchmark(
    configs: Sequence[tuple[BenchConfig, int]],
    out: Path,
    *,
    workers: int | None = None,
    dask_address: str | None = None,
    progress: bool = True,
    command: str = "",
) -> list[dict[str, Any]]:
    """Run the side-by-side benchmark for every ``(config, number of queries)`` and write the outputs to ``out``.

    Returns
    -------
    list of dict
        The records written to ``out/results.json``.
    """
    out.mkdir(parents=True, exist_ok=True)
    t0 = time.perf_counter()
    tasks = [(cfg.to_dict(), q) for cfg, n in configs for q in make_queries(cfg, n)]
    records = _clean(run_tasks(tasks, workers=workers, dask_address=dask_address, progress=progress))
    wall = time.perf_counter() - t0
    meta = {
        "command": command,
        "machine": _machine(),
        "versions": _versions(),
        "wall_time_s": round(wall, 1),
        "workers": f"dask {dask_address}" if dask_address else (workers or os.cpu_count()),
        "config": configs[0][0].to_dict() if configs else {},
        "configs": [c.to_dict() | {"queries": n} for c, n in configs],
    }
    _write_json(out / "results.json", records)
    _write_json(out / "run.json", meta)
    atomic_write_text(out / "results.md", results_markdown(records, meta))
    plot_results(records, out)
    return records


def run_scaling(
    base: BenchConfig,
    n: int,
    out: Path,
    *,
    scales: Sequence[float] = (0.5, 1.0, 2.0, 4.0),
    grid_sweep: Sequence[float] = (0.04, 0.02, 0.01, 0.005),
    workers: int | None = None,
    dask_address: str | None = None,
    progress: bool = True,
    command: str = "",
) -> list[dict[str, Any]]:
    """Compute time and makespan against the track size (lollipops ℓ = c = scale, grid spacing scaled with it)
    and against the grid resolution (base track, ``ours`` and ``grid``); no twins. Writes ``scaling.*``."""
    out.mkdir(parents=True, exist_ok=True)
    t0 = time.perf_counter()
    tasks = []
    ell = base.stick or 1.0
    c = base.loop or 1.0
    for s in scales:
        cfg = replace(base, track="lollipop", stick=ell * s, loop=c * s, grid=base.grid * s, twins=False)
        tasks += [(cfg.to_dict(), {**q, "tags": {"sweep": "scale", "scale": s}}) for q in make_queries(cfg, n)]
    for h in grid_sweep:
        cfg = replace(base, track="lollipop", stick=ell, loop=c, grid=h, twins=False, methods=("ours", "grid"))
        tasks += [(cfg.to_dict(), {**q, "tags": {"sweep": "grid", "grid_h": h}}) for q in make_queries(cfg, n)]
    records = _clean(run_tasks(tasks, workers=workers, dask_address=dask_address, progress=progress, desc="scaling"))
    meta = {
        "command": command,
        "machine": _machine(),
        "versions": _versions(),
        "wall_time_s": round(time.perf_counter() - t0, 1),
    }
    _write_json(out / "scaling.json", records)
    atomic_write_text(
        out / "scaling.md",
        scaling_markdown(records, meta)
        + f"\nMachine: {meta['machine']}; {meta['versions']}; wall time {meta['wall_time_s']} s.\n",
    )
    plot_scaling(records, out / "scaling.png")
    return records


GRAPH_PARTS = ("layouts", "oracle", "price", "scaling")


def run_graphs(
    layouts: Sequence[str],
    n: int,
    out: Path,
    *,
    seed: int = 0,
    parts: Sequence[str] = GRAPH_PARTS,
    ompl_budget: float = 1.0,
    delta: float = 1e-6,
    threshold: float = 0.01,
    progress: bool = True,
    command: str = "",
) -> dict[str, Any]:
    """The plan-level graph benchmark (:mod:`bench.graph_runner`); writes ``out/graphs.json`` and ``out/graphs.md``."""
    gr = graph_runner
    out.mkdir(parents=True, exist_ok=True)
    t0 = time.perf_counter()
    say = (lambda m: print(f"\r{m:<60}", end="", file=sys.stderr, flush=True)) if progress else None
    res: dict[str, Any] = {}
    md = ["# Graph layouts: plan-level benchmark", ""]
    if "layouts" in parts:
        res["layouts"] = gr.run_layouts(
            layouts, n, seed=seed, ompl_budget=ompl_budget, delta=delta, threshold=threshold, progress=say
        )
        md += ["## Layouts: ours, grid, OMPL", "", gr.layouts_markdown(res["layouts"])]
        md += ["", "## Layouts: our verified trajectories", "", gr.trajectories_markdown(res["layouts"])]
    if "oracle" in parts:
        res["oracle"] = gr.run_y_oracle(max(1, n // 5), seed=seed)
        md += ["## Y-junction threshold (swap iff D <= shortest branch b)", "", gr.y_oracle_markdown(res["oracle"])]
        res["completeness"] = gr.run_completeness(max(2, n // 2), seed=seed)
        md += ["## Completeness on random small graphs", "", gr.completeness_markdown(res["completeness"])]
    if "price" in parts:
        res["price"] = gr.run_price(n, seed=seed)
        md += [
            "## Paper tracks: graph planner (fastest) against the paper planner",
            "",
            gr.price_markdown(res["price"]),
        ]
    if "scaling" in parts:
        res["scaling"] = gr.run_scaling(seed=seed, queries=max(3, n // 5), progress=say)
        md += ["## Scaling (grid-like building layouts, D = 1 m)", "", gr.scaling_markdown(res["scaling"])]
    if progress:
        print(file=sys.stderr)
    meta = {
        "command": command,
        "machine": _machine(),
        "versions": _versions(),
        "wall_time_s": round(time.perf_counter() - t0, 1),
    }
    md += [f"Command: `{command}`; machine: {meta['machine']}; {meta['versions']}; wall {meta['wall_time_s']} s.", ""]
    _write_json(out / "graphs.json", _clean({"meta": meta, **res}))
    atomic_write_text(out / "graphs.md", "\n".join(md))
    return res


def run_compute(config: BenchConfig, n: int, out: Path, *, command: str = "") -> list[dict[str, Any]]:
    """Ours against the lean OMPL pipeline (:mod:`bench.compute`) on the five compute tracks, in this process.

    Writes ``out/compute.json`` and ``out/compute.md``; returns the per-track results.
    """
    out.mkdir(parents=True, exist_ok=True)
    t0 = time.perf_counter()
    results = []
    for label, kind, stick, loop in COMPUTE_TRACKS:
        res = compare_compute(replace(config, track=kind, stick=stick, loop=loop), n)
        res["label"] = label
        results.append(res)
        print(compute_markdown([res]).splitlines()[-1], flush=True)
    meta = {"command": command, "versions": _versions(), "machine": _machine(), "seconds": time.perf_counter() - t0}
    _write_json(out / "compute.json", _clean({"meta": meta, "results": results}))
    md = f"Command: `{command}` ({meta['seconds']:.0f} s; {meta['versions']}; {meta['machine']})\n\n"
    atomic_write_text(out / "compute.md", md + compute_markdown(results))
    return results


def _graph_track_names(tracks: Sequence[str]) -> list[str]:
    """Expand ``graphs``; names of example layouts and existing layout files are graph tracks."""
    LAYOUTS = graph_runner.LAYOUTS
    out: list[str] = []
    for t in tracks:
        if t == "graphs":
            out += list(LAYOUTS)
        elif t in LAYOUTS or (t.endswith(".json") and Path(t).is_file()):
            out.append(t)
        else:
            raise ValueError(f"track is {t!r}, expected lollipop, circle, graphs, a layout name or a layout file")
    return out


def _floats(text: str, name: str) -> list[float]:
    try:
        vals = [float(x) for x in text.split(",") if x.strip()]
    except ValueError:
        raise argparse.ArgumentTypeError(f"{name} is {text!r}, expected comma-separated numbers") from None
    if not vals or any(not (v > 0) for v in vals):
        raise argparse.ArgumentTypeError(f"{name} is {text!r}, expected positive numbers")
    return vals


def main(argv: Sequence[str] | None = None) -> int:
    """Command line entry point (see the module docstring)."""
    ap = argparse.ArgumentParser(description=(__doc__ or "").splitlines()[0])
    ap.add_argument("--queries", default="50", help="queries per track, or one count per --track (comma list)")
    ap.add_argument("--seed", type=int, default=0)
    ap.add_argument("--out", required=True, type=Path, help="output directory")
    ap.add_argument(
        "--track",
        default="lollipop",
        help="lollipop, circle, or a comma list of both; or graph layouts: graphs (all examples), names of "
        "examples/tracks layouts (y_junction, passing_loop, two_sidings, theta, figure_eight, warehouse) "
        "or .json files",
    )
    ap.add_argument(
        "--graph-parts",
        default=",".join(GRAPH_PARTS),
        help="graph layouts only: comma list from layouts,oracle,price,scaling",
    )
    ap.add_argument("--stick", type=float, default=None, help="lollipop stick length (m, default 1)")
    ap.add_argument("--loop", type=float, default=None, help="loop length (m, default 1)")
    ap.add_argument("--clearance", type=float, default=defaults.CLEARANCE, help="required separation D (m)")
    ap.add_argument("--vmax", type=float, default=defaults.VMAX)
    ap.add_argument("--amax", type=float, default=defaults.AMAX)
    ap.add_argument("--jmax", type=float, default=defaults.JMAX)
    ap.add_argument("--rate", type=float, default=defaults.RATE, help="setpoint rate (Hz)")
    ap.add_argument("--ompl-time", type=float, default=1.0, help="RRTConnect time budget per query (s)")
    ap.add_argument("--grid", type=float, default=0.01, help="grid node spacing (m)")
    ap.add_argument("--methods", default=",".join(METHODS), help=f"comma list from {','.join(METHODS)}")
    ap.add_argument("--delta", type=float, default=None, help="twin perturbation (m; default 1e-4, graphs 1e-6)")
    ap.add_argument(
        "--threshold", type=float, default=None, help="discontinuity threshold (m; default 0.05, graphs 0.01)"
    )
    ap.add_argument("--workers", type=int, default=None, help="worker processes (default: all cores)")
    ap.add_argument("--dask", default=None, metavar="ADDRESS", help="run on an existing Dask cluster")
    ap.add_argument("--scaling", action="store_true", help="track-size and grid-resolution sweep instead")
    ap.add_argument(
        "--compute",
        action="store_true",
        help="compute time of ours against the lean OMPL pipeline, one process, interleaved, on the five "
        "compute tracks (--queries per track)",
    )
    ap.add_argument("--scales", default="0.5,1,2,4", help="track scales of --scaling")
    ap.add_argument("--grid-sweep", default="0.04,0.02,0.01,0.005", help="grid spacings of --scaling (m)")
    ap.add_argument("--no-progress", action="store_true")
    args = ap.parse_args(argv)
    graph_layouts: list[str] = []
    try:
        tracks = [t.strip() for t in args.track.split(",") if t.strip()]
        if tracks and all(t not in ("lollipop", "circle") for t in tracks):
            graph_layouts = _graph_track_names(tracks)
            tracks = ["lollipop"]  # not used: the graph benchmark runs below
        delta_default, threshold_default = (1e-6, 0.01) if graph_layouts else (1e-4, 0.05)
        args.delta = delta_default if args.delta is None else args.delta
        args.threshold = threshold_default if args.threshold is None else args.threshold
        if not tracks or any(t not in ("lollipop", "circle") for t in tracks):
            raise ValueError(f"track is {args.track!r}, expected lollipop, circle or both")
        counts = [int(x) for x in args.queries.split(",")]
        if len(counts) == 1:
            counts *= len(tracks)
        if len(counts) != len(tracks) or any(n < 1 for n in counts):
            raise ValueError(f"queries is {args.queries!r}, expected one positive count or one per track")
        methods = tuple(m.strip() for m in args.methods.split(",") if m.strip())
        bad = [m for m in methods if m not in METHODS]
        if bad or not methods:
            raise ValueError(f"methods {bad or args.methods!r} unknown, expected a comma list from {METHODS}")
        if "ours" not in methods:
            methods = ("ours", *methods)  # ratios, domains and classes are relative to ours
        for name in ("clearance", "vmax", "amax", "jmax", "rate", "ompl_time", "grid", "delta", "threshold"):
            v = getattr(args, name)
            if not (v > 0) or v != v or v == float("inf"):
                raise ValueError(f"{name} is {v!r}, expected a positive finite number")
        if args.workers is not None and args.workers < 1:
            raise ValueError(f"workers is {args.workers}, expected at least 1")
        scales = _floats(args.scales, "scales")
        sweep = _floats(args.grid_sweep, "grid-sweep")
    except (ValueError, argparse.ArgumentTypeError) as exc:
        print(f"error: {exc}", file=sys.stderr)
        return 2
    if graph_layouts:
        return _main_graphs(args, argv, graph_layouts)
    command = "python experiments/benchmark.py " + " ".join(shlex.quote(a) for a in (argv or sys.argv[1:]))
    configs = []
    for t, n in zip(tracks, counts):
        cfg = BenchConfig(
            track=t,
            stick=args.stick if t == "lollipop" else None,
            loop=args.loop,
            **trajectory_options(args),
            ompl_time=args.ompl_time,
            grid=args.grid,
            methods=methods,
            seed=args.seed,
            delta=args.delta,
            threshold=args.threshold,
        )
        configs.append((cfg, n))
    common = {"workers": args.workers, "dask_address": args.dask, "progress": not args.no_progress, "command": command}
    if args.compute:
        run_compute(configs[0][0], counts[0], args.out, command=command)
        print(f"wrote {args.out / 'compute.md'}")
        return 0
    if args.scaling:
        run_scaling(configs[0][0], counts[0], args.out, scales=scales, grid_sweep=sweep, **common)
        print(f"wrote {args.out / 'scaling.md'}")
        return 0
    run_benchmark(configs, args.out, **common)
    print(f"wrote {args.out / 'results.json'} and {args.out / 'results.md'}")
    return 0


def _main_graphs(args: argparse.Namespace, argv: Sequence[str] | None, layouts: list[str]) -> int:
    try:
        n = int(args.queries)
        if n < 1:
            raise ValueError
    except ValueError:
        print(f"error: queries is {args.queries!r}, expected one positive count for graph layouts", file=sys.stderr)
        return 2
    parts = [p.strip() for p in args.graph_parts.split(",") if p.strip()]
    if not parts or any(p not in GRAPH_PARTS for p in parts):
        print(f"error: graph-parts is {args.graph_parts!r}, expected a comma list from {GRAPH_PARTS}", file=sys.stderr)
        return 2
    delta, threshold = args.delta, args.threshold  # validated in main
    command = "python experiments/benchmark.py " + " ".join(shlex.quote(a) for a in (argv or sys.argv[1:]))
    run_graphs(
        layouts,
        n,
        args.out,
        seed=args.seed,
        parts=parts,
        ompl_budget=args.ompl_time,
        delta=delta,
        threshold=threshold,
        progress=not args.no_progress,
        command=command,
    )
    print(f"wrote {args.out / 'graphs.json'} and {args.out / 'graphs.md'}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
