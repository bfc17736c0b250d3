"""``mpa plan``: the paper's planner on the command line (domain, rule, steps, skeleton word; ``--json``).

``--samples N`` accepts any ``N >= 2`` (smaller is an error); the JSON's ``path`` then holds
``max(N, 200, n_1%)`` points, ``n_1%`` being the number that keeps consecutive points within 1 % of the track's
length for each robot, and its ``samples`` field says how many. ``--clearance`` defaults to
:data:`mpa.defaults.CLEARANCE` like every subcommand.
"""

from __future__ import annotations

import argparse
import json
import os
from pathlib import Path

import numpy as np

from mpa.errors import InvalidInputError
from mpa.planners import make_planner
from mpa.planners.factory import OBJECTIVES, PLANNERS, plan
from mpa.planners.graph import GraphPlan
from mpa.retraction import trace_info
from mpa.tracks import Track
from trajopt.cli.common import (
    add_clearance_argument,
    add_footprint_argument,
    add_query_arguments,
    footprint_query,
    query_from_args,
)

#: Fewest path samples in the JSON (the 1 % rule may ask for more).
MIN_JSON_SAMPLES = 200

__all__ = ["register"]


def _cmd_plan(args: argparse.Namespace) -> int:
    if args.samples < 2:
        raise InvalidInputError(f"--samples is {args.samples}, expected an integer >= 2")
    track, start, goal = query_from_args(args)
    track, start, goal, fps = footprint_query(args, track, start, goal)
    graph_plan = args.planner == "graph" or not isinstance(track, Track)
    if args.plot is not None:
        _check_plot_path(args.plot, graph_plan, args.dpi)
    if graph_plan or not isinstance(track, Track):
        which = args.planner or "auto"
        g = plan(track, start, goal, args.clearance, planner=which, objective=args.objective, footprint=fps)
        if args.plot is not None:
            _write_plot(g, args)  # type: ignore[arg-type]
        rc = _print_graph_plan(g, args)  # type: ignore[arg-type]
        if args.plot is not None and not args.json:
            print(f"plot       {args.plot}")
        return rc
    planner = make_planner(track, args.clearance, args.neighbourhood)
    p = planner.plan(start, goal)
    n = max(args.samples, MIN_JSON_SAMPLES, p.samples_needed(0.01))
    if args.json:
        out = p.to_dict(samples=n)
        out["samples"] = n
        out["min_distance"] = float(np.min(track.distance(*np.asarray(out["path"]).T)))
        print(json.dumps(out))
        return 0
    print(f"track      {track.kind} {json.dumps(track.to_dict())}")
    print(f"start      A = {p.start[0]:.6g}, B = {p.start[1]:.6g}")
    print(f"goal       A = {p.goal[0]:.6g}, B = {p.goal[1]:.6g}")
    print(f"domain     {p.domain}: {p.rule}")
    print(
        f"skeleton   x_i' = ({p.skeleton_start[0]:.6g}, {p.skeleton_start[1]:.6g}),"
        f" x_f' = ({p.skeleton_goal[0]:.6g}, {p.skeleton_goal[1]:.6g})"
    )
    print(f"class      {' '.join(p.word) if p.word else '(trivial)'}")
    for st in p.steps:
        pts = " -> ".join(f"({a:.4g}, {b:.4g})" for a, b in st.waypoints)
        print(f"{st.name:<10} {st.description}")
        if p.regime == "paper" and track.kind != "interval" and st.name != "main":
            info = trace_info(track, p.start if st.name == "preliminary" else p.goal)
            print(f"{'':<10} {'' if st.name == 'preliminary' else 'reversed trace of the goal: '}{info.text}")
        print(f"{'':<10} {pts}")
    print(f"travel     A {p.travel[0]:.4g} m, B {p.travel[1]:.4g} m; min distance {p.min_distance():.4g} m")
    return 0


PLOT_SUFFIXES = (".png", ".pdf", ".svg")


def _check_plot_path(path: str, graph_plan: bool, dpi: float) -> None:
    """Fail before planning if ``--plot`` cannot be honoured (not a graph plan, bad suffix, folder not writable)."""
    from mpa.errors import InvalidInputError

    if not graph_plan:
        raise InvalidInputError("--plot draws graph plans, expected --graph FILE or --planner graph")
    if not (np.isfinite(dpi) and dpi >= 10):
        raise InvalidInputError(f"--dpi is {dpi!r}, expected a finite number >= 10")
    out = Path(path)
    if out.suffix.lower() not in PLOT_SUFFIXES:
        raise InvalidInputError(f"--plot is {path!r}, expected a file name ending in one of {list(PLOT_SUFFIXES)}")
    folder = out.parent if str(out.parent) else Path(".")
    if not folder.is_dir():
        raise InvalidInputError(f"--plot folder {str(folder)!r} does not exist, expected an existing folder")
    if not os.access(folder, os.W_OK) or (out.exists() and not os.access(out, os.W_OK)):
        raise InvalidInputError(f"--plot file {path!r} is not writable, expected a writable location")


def _write_plot(p: GraphPlan, args: argparse.Namespace) -> None:
    """Draw the plan (layout, routes, switches, cells crossed) into ``--plot``, atomically (temp file, rename)."""
    from trajopt.viz.layout import graph_plan_figure
    from trajopt.viz.plotting import save_figure

    fig = graph_plan_figure(p, name=Path(args.graph).stem if args.graph else args.track)
    save_figure(fig, args.plot, args.dpi, facecolor="white")


def _route_text(plan: GraphPlan, robot: int) -> str:
    """A robot's route as ``edge(+) -> edge(-) ...`` (+ along the edge's orientation, - against)."""
    names = plan.track.edge_names
    r = plan.route_a if robot == 0 else plan.route_b
    parts = [
        f"{names[e]}({'+' if d > 0 else '-'}) {hi - lo:.4g} m"
        for e, d, lo, hi in zip(r.edges, r.dirs, r.breaks[:-1], r.breaks[1:])
        if hi - lo > 0
    ]
    return " -> ".join(parts) if parts else "stays"


def _print_graph_plan(p: GraphPlan, args: argparse.Namespace) -> int:
    """Output of ``mpa plan`` for the complete graph planner (text, or one JSON object with ``--json``)."""
    tr = p.track
    n = max(args.samples, MIN_JSON_SAMPLES)
    if args.json:
        out = p.to_dict()
        out["planner"] = "graph"
        _, path_s = p.sample(n)
        (ea, oa), (eb, ob) = p.route_a.positions(path_s[:, 0]), p.route_b.positions(path_s[:, 1])
        names = tr.edge_names
        out["path"] = [[[names[int(a)], float(x)], [names[int(b)], float(y)]] for a, x, b, y in zip(ea, oa, eb, ob)]
        out["path_s"] = path_s.tolist()
        out["samples"] = n
        out["min_distance"] = p.min_distance()
        print(json.dumps(out))
        return 0
    print(f"track      graph: {tr.n_edges} edges, {tr.total_length:.6g} m")
    print(f"start      A = {tr.position_name(*p.start[0])}, B = {tr.position_name(*p.start[1])}")
    print(f"goal       A = {tr.position_name(*p.goal[0])}, B = {tr.position_name(*p.goal[1])}")
    print(f"planner    complete graph planner, objective {p.objective}")
    print(f"class      {' '.join(p.word) if p.word else '(trivial)'}")
    print(f"route A    {_route_text(p, 0)}")
    print(f"route B    {_route_text(p, 1)}")
    print(f"makespan   {p.makespan:.4g} s at speeds {p.speeds[0]:g}, {p.speeds[1]:g} m/s (no acceleration limits)")
    print(f"travel     A {p.route_a.length:.4g} m, B {p.route_b.length:.4g} m; min distance {p.min_distance():.4g} m")
    return 0


def register(sub: argparse._SubParsersAction) -> None:
    """Add ``plan`` to the ``mpa`` command (called by :func:`trajopt.cli.main.build_parser`)."""
    p = sub.add_parser("plan", help="plan a motion (the paper's algorithm, or the complete graph planner) and print it")
    add_query_arguments(p, graph=True)
    p.add_argument(
        "--planner",
        choices=[x for x in PLANNERS if x != "auto"],
        default=None,
        help="paper: the paper's algorithm (paper tracks only; default there); graph: the complete graph planner",
    )
    p.add_argument(
        "--objective", choices=OBJECTIVES, default="fastest", help="graph planner: fastest (default) or shortest"
    )
    add_clearance_argument(p)
    add_footprint_argument(p)
    p.add_argument("--neighbourhood", type=float, default=0.1, help="domain neighbourhood ε as a fraction of loop/2")
    p.add_argument(
        "--samples",
        type=int,
        default=400,
        help="path samples in the JSON: any N >= 2; the JSON holds max(N, 200, the 1%% rule) points and says how "
        "many in 'samples' (default 400)",
    )
    p.add_argument("--json", action="store_true", help="print one JSON object")
    p.add_argument(
        "--plot", metavar="FILE", default=None, help="graph plans: draw layout, routes and switches (.png/.pdf/.svg)"
    )
    p.add_argument("--dpi", type=float, default=110.0, help="resolution of --plot (default 110)")
    p.set_defaults(func=_cmd_plan)
