"""``mpa trajectory`` and ``mpa demo``: verified jerk-limited setpoints from the command line.

Both compute everything in memory first and then replace the run files of ``--out`` as a whole
(:func:`write_outputs`): on any error or interruption ``--out`` keeps the previous run's files untouched.
"""

from __future__ import annotations

import argparse
import contextlib
import json
import os
from collections.abc import Iterator, Mapping
from pathlib import Path
from typing import Any

from mpa import defaults
from mpa.errors import InvalidInputError
from mpa.graph_track import GraphTrack
from mpa.tracks import Lollipop, Track
from trajopt.analysis.delay import validate_delay_tolerance
from trajopt.cli.common import (
    TRAJECTORY_DEFAULTS,
    add_footprint_argument,
    add_trajectory_arguments,
    footprint_query,
    query_from_args,
    validate_output_dir,
)
from trajopt.cli.outputs import (
    OutputOptions,
    add_output_arguments,
    output_files,
    summary_text,
    validate_output_options,
)
from trajopt.export import (
    Content,
    Streamed,
    Trajectory,
    atomic_write_bytes,
    atomic_write_text,
    directory_lock,
    write_directory,
)
from trajopt.generator import TrajectoryGenerator
from trajopt.timing import Limits

__all__ = ["DEMO_JOB", "output_lock", "register", "trajectory_files", "write_outputs"]

#: The embedded job of ``mpa demo``: the paper's lollipop, the robots swap order through the loop.
DEMO_JOB: dict[str, Any] = {
    "stick": 1.0,
    "loop": 1.0,
    "start": (0.2, 0.5),
    "goal": (0.5, 0.2),
    "clearance": defaults.CLEARANCE,
    "vmax": defaults.VMAX,
    "amax": defaults.AMAX,
    "jmax": defaults.JMAX,
    "rate": defaults.RATE,
}
DEFAULTS = TRAJECTORY_DEFAULTS


@contextlib.contextmanager
def output_lock(directory: str | os.PathLike[str]) -> Iterator[None]:
    """Hold the lock of :func:`write_outputs` on ``directory`` (:func:`trajopt.io.directory.directory_lock`).

    Readers that want one run's consistent set of files take it too.
    """
    with directory_lock(directory):
        yield


def _write_file(path: Path, content: Content) -> None:
    if isinstance(content, str):
        atomic_write_text(path, content)
    else:
        atomic_write_bytes(path, content)


def write_outputs(out: str | os.PathLike[str], files: Mapping[str, Content]) -> list[Path]:
    """Replace the run files of directory ``out`` by ``files`` (name -> content) as a whole, in one step.

    See :func:`trajopt.io.directory.write_directory`: the files go into a temporary directory beside ``out``, which is
    swapped with ``out`` by one rename; after any interruption ``out`` holds this run's complete set or the
    previous one untouched, and no file of a format this run did not ask for.

    Raises
    ------
    InvalidInputError
        ``out`` is empty or exists and is not a directory, or a file could not be written
        (``--out: cannot write PATH: reason``; ``out`` is then unchanged).
    """
    return write_directory(out, dict(files), write=lambda p, c: _write_file(p, c))


def _summary_text(traj: Trajectory) -> str:
    return summary_text(traj)


def _json(obj: Any) -> str:
    from trajopt.export import _json_default

    return json.dumps(obj, indent=2, default=_json_default) + "\n"


def _cmd_trajectory(args: argparse.Namespace) -> int:
    opts = validate_output_options(args)
    tolerance = None if args.delay_tolerance is None else validate_delay_tolerance(args.delay_tolerance)
    margin = None if args.min_margin is None else validate_margin_option(args.min_margin)
    validate_output_dir(args.out)
    track, start, goal = query_from_args(args)
    track, start, goal, fps = footprint_query(args, track, start, goal)
    limits = Limits(args.vmax, args.amax, args.jmax)
    traj, files = trajectory_files(
        track,
        start,
        goal,
        args.clearance,
        limits,
        args.rate,
        opts,
        tolerance,
        planner=args.planner,
        objective=args.objective,
        min_margin=margin,
        footprint=fps,
    )
    write_outputs(args.out, files)
    print(summary_text(traj))
    if fps is not None:
        sm = traj.summary()
        print(
            f"plane       bodies {fps.spec()}: closest {sm['min_gap_plane']:.4g} m apart in the drawing; "
            f"tracking margin in the plane {sm['tracking_margin_plane']:.4g} m"
        )
    print(f"wrote       {', '.join(str(Path(args.out) / n) for n in files)}")
    return 0


def trajectory_files(
    track: Track | GraphTrack,
    start: Any,
    goal: Any,
    clearance: float,
    limits: Limits,
    rate: float,
    opts: OutputOptions,
    tolerance: float | None = None,
    planner: str | None = None,
    objective: str = "fastest",
    min_margin: float | None = None,
    footprint: Any = None,
) -> tuple[Trajectory, dict[str, Content]]:
    """The verified motion of ``mpa trajectory`` and its files, in memory (nothing is written).

    Parameters
    ----------
    track, start, goal, clearance
        The query, as :func:`trajopt.cli.plan.plan_query` takes it (metres; positions ``(edge, offset)`` on a
        layout).
    limits : Limits
        ``--vmax`` (m/s), ``--amax`` (m/s²), ``--jmax`` (m/s³) per robot.
    rate : float
        ``--rate`` of the setpoints (Hz).
    opts : OutputOptions
        The checked output options (:func:`trajopt.cli.outputs.validate_output_options`).
    tolerance : float, optional
        ``--delay-tolerance`` (s), already checked.
    planner : {None, "paper", "graph"}
        ``--planner``: ``graph`` on a paper track plans its layout form (:func:`planner_query`).
    objective : {"fastest", "shortest"}
        ``--objective`` of the graph planner.
    min_margin : float, optional
        ``--min-margin`` (metres), already checked.
    footprint : None, mpa.Footprints, spec
        ``--footprint``: the bodies in the plane (a layout with coordinates).

    Returns
    -------
    traj : Trajectory
        The motion, through the verification gate.
    files : dict
        File name -> content, as :func:`trajopt.cli.outputs.output_files` gives them (``summary.json`` last,
        with the ``recipe`` that rebuilds the motion).
    """
    track, start, goal = planner_query(track, start, goal, planner)
    gen = TrajectoryGenerator(
        track, clearance=clearance, limits=limits, rate=rate, objective=objective, footprint=footprint
    )
    traj = gen.generate(start, goal, delay_tolerance=tolerance, min_margin=min_margin)
    recipe: dict[str, Any]
    if isinstance(track, Track):
        recipe = {"start": list(start), "goal": list(goal), "delay_tolerance": tolerance, "replans": []}
        if min_margin is not None:
            recipe["min_margin"] = min_margin
    else:  # positions by name (EDGE:OFFSET or a vertex)
        names = [[track.position_name(*track.position(p)) for p in q] for q in (start, goal)]
        recipe = {
            "start": names[0],
            "goal": names[1],
            "delay_tolerance": tolerance,
            "objective": objective,
            "replans": [],
        }
        if min_margin is not None:
            recipe["min_margin"] = min_margin
    return traj, output_files(traj, opts, recipe)


def _cmd_demo(args: argparse.Namespace) -> int:
    from trajopt.viz.plotting import figure_png, plot_trajectory

    validate_output_dir(args.out)
    job = DEMO_JOB
    track = Lollipop(job["stick"], job["loop"])
    gen = TrajectoryGenerator(
        track, clearance=job["clearance"], limits=Limits(job["vmax"], job["amax"], job["jmax"]), rate=job["rate"]
    )
    traj = gen.generate(job["start"], job["goal"])
    png = figure_png(plot_trajectory(traj))
    plan: Any = traj.plan  # a paper Plan (the demo's lollipop)
    files: dict[str, Content] = {
        "setpoints.csv": Streamed(traj.csv_chunks),
        "summary.json": _json(traj.summary(margins=True)),
        "plan.json": _json(plan.to_dict(samples=max(400, plan.samples_needed(0.01)))),
        "trajectory.png": png,
    }
    write_outputs(args.out, files)
    print(f"mpa demo: lollipop stick {job['stick']:g} m, loop {job['loop']:g} m; A and B swap order through the loop")
    print(f"start       A = {plan.start[0]:g}, B = {plan.start[1]:g}")
    print(f"goal        A = {plan.goal[0]:g}, B = {plan.goal[1]:g}")
    print(_summary_text(traj))
    print(f"wrote       {', '.join(str(Path(args.out) / n) for n in files)}")
    return 0


def planner_query(
    track: Track | GraphTrack, start: Any, goal: Any, planner: str | None
) -> tuple[Track | GraphTrack, Any, Any]:
    """The track and query the generator gets for ``--planner``.

    ``graph`` on a paper track: its graph form (:meth:`mpa.tracks.Track.as_graph_track`, edges ``stick`` and
    ``loop``) with the track coordinates as positions ``(edge, offset)``, so the complete graph planner answers
    and the files are written as for a layout. ``paper`` (or none) on a paper track: unchanged; ``paper`` on a
    layout is an error.

    Raises
    ------
    InvalidInputError
        ``--planner paper`` with ``--graph``; a start or goal off the track.
    """
    if not isinstance(track, Track):
        if planner == "paper":
            raise InvalidInputError(
                "--planner is 'paper' with --graph, expected --planner graph (the paper's algorithm plans the "
                "paper's tracks only: --track interval|circle|lollipop)"
            )
        return track, start, goal
    if planner != "graph":
        return track, start, goal
    from mpa.planners.factory import _paper_positions

    return track.as_graph_track(), _paper_positions(track, start, "--start"), _paper_positions(track, goal, "--goal")


def add_planner_arguments(p: argparse.ArgumentParser) -> None:
    """``--planner paper|graph`` and ``--objective fastest|shortest`` (as ``mpa plan``)."""
    p.add_argument(
        "--planner",
        choices=["paper", "graph"],
        default=None,
        help="paper: the paper's algorithm (paper tracks only; default there); graph: the complete graph planner "
        "(always on --graph layouts; on a paper track the files are written as for its layout form, edges stick "
        "and loop)",
    )
    p.add_argument(
        "--objective",
        choices=["fastest", "shortest"],
        default="fastest",
        help="graph planner: fastest (default: minimum time at --vmax) or shortest (minimum length)",
    )


def validate_margin_option(value: float) -> float:
    """``--min-margin``: a finite number of metres >= 0 (InvalidInputError naming the option otherwise)."""
    from trajopt.analysis.min_margin import validate_min_margin

    try:
        return validate_min_margin(value)
    except InvalidInputError as exc:
        raise InvalidInputError(str(exc).replace("min_margin", "--min-margin", 1)) from None


def add_min_margin_argument(p: argparse.ArgumentParser) -> None:
    """``--min-margin M`` (see :mod:`trajopt.analysis.min_margin`)."""
    p.add_argument(
        "--min-margin",
        type=float,
        default=None,
        metavar="M",
        help="ask for a motion whose tracking margin is at least M metres (either cart may be M off its setpoint "
        "along its route); exit 3 naming the largest margin that can be had if none is",
    )


def add_delay_tolerance_argument(p: argparse.ArgumentParser) -> None:
    """``--delay-tolerance T`` (see :mod:`trajopt.analysis.delay`)."""
    p.add_argument(
        "--delay-tolerance",
        type=float,
        default=None,
        metavar="T",
        help="ask for a motion that tolerates at least T s of delay of either cart (larger effective clearance, "
        "then slower); exit 3 with the best value found if none does",
    )


def register(subparsers: Any) -> None:
    """Add ``trajectory`` and ``demo`` to the ``mpa`` command (called by :func:`trajopt.cli.main.build_parser`)."""
    p = subparsers.add_parser("trajectory", help="verified jerk-limited setpoints for a query (CSV, ROS 2, PVT, JSON)")
    add_trajectory_arguments(p)
    add_footprint_argument(p)
    p.add_argument(
        "--out", required=True, help="output directory (setpoints.csv and the other --format files, summary.json)"
    )
    add_output_arguments(p)
    add_delay_tolerance_argument(p)
    add_min_margin_argument(p)
    add_planner_arguments(p)
    p.set_defaults(func=_cmd_trajectory)
    d = subparsers.add_parser("demo", help="the embedded default job: a lollipop swap, files and a PNG")
    d.add_argument("--out", default="mpa-demo", help="output directory (default ./mpa-demo)")
    d.set_defaults(func=_cmd_demo)
