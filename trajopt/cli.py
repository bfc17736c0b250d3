"""The ``mpa`` command line (console script entry point).

Subcommands: ``plan`` (the paper's planner), ``trajectory`` and ``demo`` (jerk-limited setpoints), ``animate``
(animations), ``topology`` (topology of two robots on any graph). Every error the user can cause ends with exit
status 2 and one line on stderr starting with ``error:``; no traceback, no output file left behind.
"""

from __future__ import annotations

import argparse
import importlib
import json
import sys
from collections.abc import Sequence

import numpy as np

from mpa.errors import MPAError
from mpa.planners import make_planner
from mpa.retraction import trace_info
from mpa.tracks import make_track

__all__ = ["TRAJECTORY_DEFAULTS", "add_query_arguments", "add_trajectory_arguments", "main", "track_from_args"]

#: Modules that add subcommands through a ``register(subparsers)`` function (missing ones are skipped).
SUBCOMMAND_MODULES = ("trajopt.cli_trajectory", "trajopt.cli_animate", "trajopt.cli_topology")


class _Parser(argparse.ArgumentParser):
    def error(self, message: str) -> None:  # type: ignore[override]
        self.exit(2, f"error: {message}\n")


def add_query_arguments(p: argparse.ArgumentParser) -> None:
    """Options shared by every subcommand that takes a query on a track."""
    p.add_argument("--track", required=True, choices=["interval", "circle", "lollipop"], help="track shape")
    p.add_argument("--stick", type=float, default=None, help="stick length ℓ in metres (interval, lollipop; default 1)")
    p.add_argument(
        "--loop", type=float, default=None, help="loop circumference c in metres (circle, lollipop; default 1)"
    )
    p.add_argument("--start", type=float, nargs=2, required=True, metavar=("A", "B"), help="start track coordinates")
    p.add_argument("--goal", type=float, nargs=2, required=True, metavar=("A", "B"), help="goal track coordinates")


#: Defaults of the trajectory options (pinned by the trajectory issue).
TRAJECTORY_DEFAULTS = {"clearance": 0.05, "vmax": 0.5, "amax": 1.0, "jmax": 5.0, "rate": 100.0}


def add_trajectory_arguments(p: argparse.ArgumentParser) -> None:
    """The query plus clearance and per-robot limits (``mpa trajectory`` and ``mpa animate``)."""
    add_query_arguments(p)
    d = TRAJECTORY_DEFAULTS
    p.add_argument("--clearance", type=float, default=d["clearance"], help="clearance D, m (default 0.05)")
    p.add_argument("--vmax", type=float, default=d["vmax"], help="speed limit per robot, m/s (default 0.5)")
    p.add_argument("--amax", type=float, default=d["amax"], help="acceleration limit, m/s^2 (default 1.0)")
    p.add_argument("--jmax", type=float, default=d["jmax"], help="jerk limit, m/s^3 (default 5.0)")
    p.add_argument("--rate", type=float, default=d["rate"], help="setpoint rate in Hz (default 100)")


def track_from_args(args: argparse.Namespace):  # type: ignore[no-untyped-def]
    """The track named by ``--track/--stick/--loop``."""
    return make_track(args.track, args.stick, args.loop)


def _cmd_plan(args: argparse.Namespace) -> int:
    track = track_from_args(args)
    planner = make_planner(track, args.clearance, args.neighbourhood)
    p = planner.plan(args.start, args.goal)
    if args.samples < 2:
        from mpa.errors import InvalidInputError

        raise InvalidInputError(f"samples is {args.samples}, expected an integer >= 2")
    n = max(args.samples, 200, p.samples_needed(0.01))
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


def build_parser() -> argparse.ArgumentParser:
    """The argument parser of the ``mpa`` command."""
    parser = _Parser(
        prog="mpa", description="Topological motion planning for two robots on a track (Boughrira & Colman)."
    )
    sub = parser.add_subparsers(dest="command", required=True, parser_class=_Parser)
    p = sub.add_parser("plan", help="plan with the paper's algorithm and print the plan")
    add_query_arguments(p)
    p.add_argument("--clearance", type=float, default=0.0, help="required clearance D in metres (default 0)")
    p.add_argument("--neighbourhood", type=float, default=0.1, help="domain neighbourhood ε as a fraction of loop/2")
    p.add_argument("--samples", type=int, default=400, help="path samples in the JSON (at least 200 and the 1%% rule)")
    p.add_argument("--json", action="store_true", help="print one JSON object")
    p.set_defaults(func=_cmd_plan)
    for name in SUBCOMMAND_MODULES:
        try:
            mod = importlib.import_module(name)
        except ModuleNotFoundError as exc:
            if exc.name != name:
                raise
            continue
        mod.register(sub)
    return parser


def main(argv: Sequence[str] | None = None) -> int:
    """Run the ``mpa`` command; returns the exit status."""
    parser = build_parser()
    args = parser.parse_args(argv)
    try:
        return int(args.func(args))
    except MPAError as exc:
        print(f"error: {exc}", file=sys.stderr)
        return 2
    except BrokenPipeError:  # output piped into e.g. `head`: stop quietly
        sys.stderr.close()
        return 0
    except OSError as exc:
        print(f"error: {exc}", file=sys.stderr)
        return 2


if __name__ == "__main__":  # pragma: no cover
    sys.exit(main())
