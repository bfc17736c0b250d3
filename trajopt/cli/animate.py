"""``mpa animate``: an animation of a query, the raw plan beside the jerk-limited trajectory.

Same query options as ``mpa trajectory``; writes ``DIR/animation.gif`` (or ``.mp4``) through a temporary file and a
rename, so an error leaves no file behind (and no directory, if this run created it). Errors are
:class:`mpa.errors.InvalidInputError` and friends, which the ``mpa`` command prints as one ``error:`` line (exit 2).
"""

from __future__ import annotations

import argparse
from pathlib import Path
from typing import TYPE_CHECKING, Any, cast

from mpa.errors import InvalidInputError
from mpa.tracks import Track
from trajopt.cli.common import (
    TRAJECTORY_DEFAULTS,
    add_footprint_argument,
    add_trajectory_arguments,
    footprint_query,
    output_error,
    query_from_args,
    trajectory_options,
    validate_output_dir,
)

if TYPE_CHECKING:
    from mpa.graph_track import GraphTrack
    from mpa.planners.graph import GraphPlan

__all__ = ["DEFAULTS", "register"]

#: Defaults shared with ``mpa trajectory``.
DEFAULTS = TRAJECTORY_DEFAULTS


def _cmd_animate(args: argparse.Namespace) -> int:
    validate_output_dir(args.out)
    track, start, goal = query_from_args(args)
    if getattr(args, "footprint", None) is not None and args.graph is None:
        raise InvalidInputError("--footprint needs a layout drawn in metres, expected --graph FILE with it")
    track, start, goal, fps = footprint_query(args, track, start, goal)
    args.footprints = fps
    if args.max_frames is not None and args.max_frames < 2:
        raise InvalidInputError(f"--max-frames is {args.max_frames}, expected an integer >= 2")
    from trajopt.viz.animation import FORMATS, animate_query

    d = Path(args.out)
    created = not d.exists()
    target = d / f"animation{FORMATS[args.format]}"
    try:
        if args.graph is not None:
            path = _animate_graph(cast("GraphTrack", track), start, goal, target, args)  # --graph: a layout
        elif not isinstance(track, Track):
            raise InvalidInputError("mpa animate takes --track interval|circle|lollipop or --graph FILE")
        else:
            path = animate_query(
                track,
                start,
                goal,
                target,
                **trajectory_options(args),
                trajectory=not args.raw_only,
                fps=args.fps,
                dpi=args.dpi,
                max_frames=args.max_frames,
                fmt=args.format,
            )
    except BaseException as exc:
        if created and d.is_dir() and not any(d.iterdir()):
            d.rmdir()
        if isinstance(exc, OSError) and not isinstance(exc, BrokenPipeError):
            raise output_error("--out", target, exc) from None
        raise
    print(path)
    return 0


def _animate_graph(track: GraphTrack, start: Any, goal: Any, target: Path, args: argparse.Namespace) -> Path:
    """The layout animation of a ``--graph`` query: the verified trajectory (or with ``--raw-only`` the plan)."""
    from trajopt.generator import TrajectoryGenerator
    from trajopt.timing import Limits
    from trajopt.viz.layout import plan_title
    from trajopt.viz.layout_animation import animate_graph_plan, animate_layout

    gen = TrajectoryGenerator(
        track,
        clearance=args.clearance,
        limits=Limits(args.vmax, args.amax, args.jmax),
        rate=args.rate,
        footprint=getattr(args, "footprints", None),
    )
    name = Path(args.graph).stem
    kw = {"fps": args.fps, "dpi": args.dpi, "max_frames": args.max_frames, "fmt": args.format}
    if args.raw_only:
        raw = cast("GraphPlan", gen.plan(start, goal))  # a layout's plan
        return animate_graph_plan(raw, target, name=name, footprint=getattr(args, "footprints", None), **kw)
    traj = gen.generate(start, goal)
    plan = traj.plan
    title = plan_title(plan, name).split("\n")[0] + (
        f"\nD = {traj.clearance:g} m, verified jerk-limited trajectory, {traj.makespan:.3g} s"
    )
    fps = getattr(args, "footprints", None)
    if fps is not None:
        title += f", bodies {fps.spec()} m to scale"
    return animate_layout(
        plan.layout,
        *plan.layout_routes,
        traj.t,
        traj.s,
        target,
        clearance=traj.clearance,
        title=title,
        footprint=fps,
        **kw,
    )


def register(subparsers: Any) -> None:
    """Add ``animate`` to the ``mpa`` command (called by :func:`trajopt.cli.main.build_parser`)."""
    p = subparsers.add_parser("animate", help="animate a query: raw plan and jerk-limited trajectory side by side")
    add_trajectory_arguments(p)
    add_footprint_argument(p)
    p.add_argument("--out", required=True, help="output directory (animation.gif or animation.mp4)")
    p.add_argument("--fps", type=float, default=20.0, help="frames per second (default 20)")
    p.add_argument(
        "--format",
        choices=["gif", "mp4"],
        default="gif",
        help="gif (Pillow) or mp4 (needs ffmpeg: pip install imageio-ffmpeg)",
    )
    p.add_argument("--dpi", type=float, default=80.0, help="resolution (default 80)")
    p.add_argument("--max-frames", type=int, default=None, help="cap the number of frames (plays faster)")
    p.add_argument("--raw-only", action="store_true", help="animate the raw plan only (no trajectory optimisation)")
    p.set_defaults(func=_cmd_animate)
