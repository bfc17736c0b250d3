"""``mpa domains``: which domain of continuity every start (for a fixed goal) or goal (for a fixed start) falls in.

``mpa domains --track lollipop --stick L --loop C --goal A B [--plot FILE]`` samples the configuration space on a
``--samples`` × ``--samples`` grid (default 200), answers every query at once (:func:`mpa.plan_many`) and prints
the share of each domain; ``--start A B`` instead maps the goals. ``--plot FILE`` (.png/.pdf/.svg) draws the map
(:func:`trajopt.viz.domains.domain_map_figure`), written atomically.
"""

from __future__ import annotations

import argparse
import json
from typing import Any

from mpa.errors import InvalidInputError
from trajopt.cli.common import add_clearance_argument, parse_coordinates, track_from_args

__all__ = ["register"]


def _cmd_domains(args: argparse.Namespace) -> int:
    from trajopt.cli.plan import _validate_plot_path

    if args.samples < 10:
        raise InvalidInputError(f"--samples is {args.samples}, expected an integer >= 10")
    if (args.goal is None) == (args.start is None):
        raise InvalidInputError("give exactly one of --goal A B (the map of starts) and --start A B (the map of goals)")
    if args.plot is not None:
        _validate_plot_path(args.plot, True, args.dpi)
    track = track_from_args(args)
    fixed = parse_coordinates(args.goal if args.goal is not None else args.start, "--goal" if args.goal else "--start")
    from trajopt.viz.domains import domain_grid

    kw: dict[str, Any] = {"goal": fixed} if args.goal is not None else {"start": fixed}
    grid = domain_grid(track, clearance=args.clearance, neighbourhood=args.neighbourhood, samples=args.samples, **kw)
    if args.plot is not None:
        from trajopt.viz.domains import domain_map_figure
        from trajopt.viz.plotting import save_figure

        save_figure(domain_map_figure(grid), args.plot, args.dpi, facecolor="white")
    frac = grid.fractions()
    if args.json:
        out = {
            "track": track.to_dict(),
            "varies": grid.varies,
            "fixed": grid.fixed.tolist(),
            "clearance": grid.clearance,
            "samples": args.samples,
            "fractions": {str(k): v for k, v in frac.items()},
        }
        print(json.dumps(out))
        return 0
    other = "goal" if grid.varies == "start" else "start"
    print(f"track      {track.kind} {json.dumps(track.to_dict())}")
    print(f"{other:<10} A = {grid.fixed[0]:g}, B = {grid.fixed[1]:g}; every {grid.varies} on a {args.samples}² grid")
    for k in (1, 2, 3):
        print(f"domain {k}   {100 * frac[k]:.1f} % of the {grid.varies}s at least {grid.clearance:g} m apart")
    if frac[-1] > 0:
        print(f"no motion  {100 * frac[-1]:.1f} %")
    if args.plot is not None:
        print(f"plot       {args.plot}")
    return 0


def register(sub: Any) -> None:
    """Add ``domains`` to the ``mpa`` command (called by :func:`trajopt.cli.main.build_parser`)."""
    p = sub.add_parser(
        "domains", help="which domain every start (for a fixed goal) or goal (for a fixed start) falls in"
    )
    p.add_argument(
        "--track", required=True, choices=["interval", "circle", "lollipop"], help="one of the paper's tracks"
    )
    p.add_argument("--stick", type=float, default=None, help="stick length ℓ in metres (interval, lollipop; default 1)")
    p.add_argument(
        "--loop", type=float, default=None, help="loop circumference c in metres (circle, lollipop; default 1)"
    )
    p.add_argument("--goal", nargs=2, default=None, metavar=("A", "B"), help="the fixed goal: map every start")
    p.add_argument("--start", nargs=2, default=None, metavar=("A", "B"), help="the fixed start: map every goal")
    add_clearance_argument(p)
    p.add_argument("--neighbourhood", type=float, default=0.1, help="domain neighbourhood ε as a fraction of loop/2")
    p.add_argument("--samples", type=int, default=200, help="grid cells per axis (default 200: 40 000 queries)")
    p.add_argument("--plot", metavar="FILE", default=None, help="draw the map (.png/.pdf/.svg)")
    p.add_argument("--dpi", type=float, default=110.0, help="resolution of --plot (default 110)")
    p.add_argument("--json", action="store_true", help="print one JSON object (the shares of the domains)")
    p.set_defaults(func=_cmd_domains)
