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
from typing import Any

import numpy as np

from mpa.errors import InvalidInputError
from mpa.graph_track import GraphTrack
from mpa.planners import make_planner
from mpa.planners.factory import OBJECTIVES, PLANNERS, plan
from mpa.planners.graph import GraphPlan
from mpa.plans import MotionPlan, Plan
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

__all__ = ["plan_json", "plan_query", "register"]


def _cmd_plan(args: argparse.Namespace) -> int:
    if args.samples < 2:
        raise InvalidInputError(f"--samples is {args.samples}, expected an integer >= 2")
    track, start, goal = query_from_args(args)
    track, start, goal, fps = footprint_query(args, track, start, goal)
    graph_plan = args.planner == "graph" or not isinstance(track, Track)
    if args.plot is not None:
        _validate_plot_path(args.plot, graph_plan, args.dpi)
    p = plan_query(track, start, goal, args.clearance, args.planner, args.objective, args.neighbourhood, footprint=fps)
    if not isinstance(p, Plan):  # the paper's plan prints its own pinned form (track coordinates, domain, rule)
        if args.plot is not None:
            _write_plot(p, args)
        rc = _print_graph_plan(p, args)
        if args.plot is not None and not args.json:
            print(f"plot       {args.plot}")
        return rc
    if args.plot is not None:
        _write_paper_plot(p, args)
    if args.json:
        print(json.dumps(plan_json(p, args.samples)))
        return 0
    _print_paper_plan(p)
    if args.plot is not None:
        print(f"plot       {args.plot}")
    return 0


def plan_query(
    track: Track | GraphTrack,
    start: Any,
    goal: Any,
    clearance: float,
    planner: str | None = None,
    objective: str = "fastest",
    neighbourhood: float = 0.1,
    footprint: Any = None,
) -> Plan | GraphPlan:
    """The plan ``mpa plan`` prints for a query: the paper's planner on a paper track, else the graph planner.

    Parameters
    ----------
    track : Track or GraphTrack
        A paper track (``--track``) or a layout (``--graph``).
    start, goal : pair
        Track coordinates (metres) on a paper track; positions ``(edge, offset)`` on a layout; robot A first.
    clearance : float
        Required clearance D (metres).
    planner : {None, "paper", "graph"}
        ``--planner``: None picks the paper's planner on paper tracks and the graph planner on layouts.
    objective : {"fastest", "shortest"}
        ``--objective`` of the graph planner.
    neighbourhood : float
        ``--neighbourhood``: the domains' ε as a fraction of half the loop (paper planner).
    footprint : None, mpa.Footprints, spec
        ``--footprint``: the bodies in the plane (the graph planner on the track's drawing, :mod:`mpa.planar`).
    """
    if planner == "graph" or not isinstance(track, Track) or footprint is not None:
        which = planner or "auto"
        return plan(track, start, goal, clearance, planner=which, objective=objective, footprint=footprint)
    return make_planner(track, clearance, neighbourhood).plan(start, goal)


def plan_json(p: Plan | GraphPlan, samples: int = 400) -> dict[str, Any]:
    """The object ``mpa plan --json`` prints (``samples``: ``--samples``, any integer >= 2).

    A paper plan: :meth:`mpa.plans.Plan.to_dict` with ``max(samples, 200, the 1 % rule)`` path points, ``samples``
    and ``min_distance`` (metres). A graph plan: :meth:`GraphPlan.to_dict` with ``planner``, ``path`` (shape
    (n, 2, 2): ``[edge name, offset]`` per robot), ``path_s`` (shape (n, 2), metres along each route),
    ``samples`` and ``min_distance``.
    """
    if samples < 2:
        raise InvalidInputError(f"--samples is {samples}, expected an integer >= 2")
    if not isinstance(p, Plan):  # the paper's JSON is pinned: the path in track coordinates, domain, rule
        return _graph_plan_json(p, max(samples, MIN_JSON_SAMPLES))
    n = max(samples, MIN_JSON_SAMPLES, p.samples_needed(0.01))
    out = p.to_dict(samples=n)
    out["samples"] = n
    out["min_distance"] = float(np.min(p.track.distance(*np.asarray(out["path"]).T)))
    return out


def _print_paper_plan(p: Plan) -> None:
    """The text output of ``mpa plan`` for the paper's planner."""
    track = p.track
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


def _write_paper_plot(p: Plan, args: argparse.Namespace) -> None:
    """Draw a paper plan (track, configuration space with the path, the domain map of its goal) into ``--plot``."""
    from trajopt.viz.domains import plan_figure
    from trajopt.viz.plotting import save_figure

    save_figure(plan_figure(p, neighbourhood=args.neighbourhood), args.plot, args.dpi, facecolor="white")


PLOT_SUFFIXES = (".png", ".pdf", ".svg")


def _validate_plot_path(path: str, graph_plan: bool, dpi: float) -> None:
    """Fail before planning if ``--plot`` cannot be honoured (bad suffix or resolution, folder not writable).

    ``graph_plan``: whether a graph plan is drawn (a paper plan is drawn as well; kept for the callers)."""
    from mpa.errors import InvalidInputError

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

    fig = graph_plan_figure(
        p, name=Path(args.graph).stem if args.graph else args.track, footprint=getattr(args, "footprint", None)
    )
    save_figure(fig, args.plot, args.dpi, facecolor="white")


def _route_text(plan: MotionPlan, robot: int) -> str:
    """A robot's route as ``edge(+) -> edge(-) ...`` (+ along the edge's orientation, - against)."""
    names = plan.layout.edge_names
    r = plan.layout_routes[robot]
    parts = [
        f"{names[e]}({'+' if d > 0 else '-'}) {hi - lo:.4g} m"
        for e, d, lo, hi in zip(r.edges, r.dirs, r.breaks[:-1], r.breaks[1:])
        if hi - lo > 0
    ]
    return " -> ".join(parts) if parts else "stays"


def _graph_plan_json(p: GraphPlan, n: int) -> dict[str, Any]:
    """The JSON object of a graph plan with ``n`` path samples (see :func:`plan_json`)."""
    out = p.to_dict()
    out["planner"] = "graph"
    u, path_s = p.sample_s(n)
    (ea, oa), (eb, ob) = p.positions(u)
    names = p.layout.edge_names
    out["path"] = [[[names[int(a)], float(x)], [names[int(b)], float(y)]] for a, x, b, y in zip(ea, oa, eb, ob)]
    out["path_s"] = path_s.tolist()
    out["samples"] = n
    out["min_distance"] = p.min_distance()
    return out


def _print_graph_plan(p: GraphPlan, args: argparse.Namespace) -> int:
    """Output of ``mpa plan`` for the complete graph planner (text, or one JSON object with ``--json``)."""
    tr = p.track
    n = max(args.samples, MIN_JSON_SAMPLES)
    if args.json:
        print(json.dumps(_graph_plan_json(p, n)))
        return 0
    print(f"track      graph: {tr.n_edges} edges, {tr.total_length:.6g} m")
    print(f"start      A = {tr.position_name(*p.start[0])}, B = {tr.position_name(*p.start[1])}")
    print(f"goal       A = {tr.position_name(*p.goal[0])}, B = {tr.position_name(*p.goal[1])}")
    print(f"planner    complete graph planner, objective {p.objective}")
    print(f"class      {' '.join(p.word) if p.word else '(trivial)'}")
    print(f"route A    {_route_text(p, 0)}")
    print(f"route B    {_route_text(p, 1)}")
    print(f"makespan   {p.makespan:.4g} s at speeds {p.speeds[0]:g}, {p.speeds[1]:g} m/s (no acceleration limits)")
    ra, rb = p.layout_routes
    print(f"travel     A {ra.length:.4g} m, B {rb.length:.4g} m; min distance {p.min_distance():.4g} m")
    if p.lower_bound is not None:  # a layout with one-way lanes or speed limits
        unit = "s" if p.objective == "fastest" else "m"
        value = p.makespan if p.objective == "fastest" else p.length
        print(
            f"rules      {sum(tr.oneway)} one-way, {sum(v is not None for v in tr.speed_limits)} speed-limited edges; "
            f"no motion under them beats {p.lower_bound:.4g} {unit} (this plan at most "
            f"{max(0.0, value - p.lower_bound):.4g} {unit} above the optimum)"
        )
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
        "--plot",
        metavar="FILE",
        default=None,
        help="draw the plan (.png/.pdf/.svg): graph plans as layout, routes and switches; paper plans as track, "
        "configuration space with the path, and the domain of every start for this goal",
    )
    p.add_argument("--dpi", type=float, default=110.0, help="resolution of --plot (default 110)")
    p.set_defaults(func=_cmd_plan)
