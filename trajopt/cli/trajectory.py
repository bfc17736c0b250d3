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
from mpa.tracks import Lollipop, Track
from trajopt.cli.common import (
    TRAJECTORY_DEFAULTS,
    add_trajectory_arguments,
    check_output_dir,
    query_from_args,
)
from trajopt.cli.outputs import add_output_arguments, check_output_options, output_files, summary_text
from trajopt.delay import check_delay_tolerance
from trajopt.export import Trajectory, atomic_write_bytes, atomic_write_text, directory_lock, write_directory
from trajopt.generator import TrajectoryGenerator
from trajopt.timing import Limits

__all__ = ["DEMO_JOB", "output_lock", "register", "write_outputs"]

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
    """Hold the lock of :func:`write_outputs` on ``directory`` (:func:`trajopt.export.directory_lock`).

    Readers that want one run's consistent set of files take it too.
    """
    with directory_lock(directory):
        yield


def _write_file(path: Path, content: str | bytes) -> None:
    if isinstance(content, bytes):
        atomic_write_bytes(path, content)
    else:
        atomic_write_text(path, content)


def write_outputs(out: str | os.PathLike[str], files: Mapping[str, str | bytes]) -> list[Path]:
    """Replace the run files of directory ``out`` by ``files`` (name -> content) as a whole, in one step.

    See :func:`trajopt.export.write_directory`: the files go into a temporary directory beside ``out``, which is
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
    opts = check_output_options(args)
    tolerance = None if args.delay_tolerance is None else check_delay_tolerance(args.delay_tolerance)
    check_output_dir(args.out)
    track, start, goal = query_from_args(args)
    if not isinstance(track, Track):  # a layout (--graph)
        if opts.plot:
            raise InvalidInputError(
                "--plot draws trajectories on the paper's tracks, expected no --plot with --graph "
                "(draw a layout with mpa animate --graph or mpa plan --graph --plot)"
            )
        if tolerance is not None:
            raise InvalidInputError("--delay-tolerance is implemented for the paper's tracks, expected no --graph")
    gen = TrajectoryGenerator(
        track, clearance=args.clearance, limits=Limits(args.vmax, args.amax, args.jmax), rate=args.rate
    )
    traj = gen.generate(start, goal, delay_tolerance=tolerance)
    if isinstance(track, Track):
        recipe = {"start": list(start), "goal": list(goal), "delay_tolerance": tolerance, "replans": []}
    else:  # positions by name (EDGE:OFFSET or a vertex)
        names = [[track.position_name(*p) for p in q] for q in (start, goal)]
        recipe = {"start": names[0], "goal": names[1], "delay_tolerance": None, "replans": []}
    files = output_files(traj, opts, recipe)
    write_outputs(args.out, files)
    print(summary_text(traj))
    print(f"wrote       {', '.join(str(Path(args.out) / n) for n in files)}")
    return 0


def _cmd_demo(args: argparse.Namespace) -> int:
    from trajopt.viz.plotting import figure_png, plot_trajectory

    check_output_dir(args.out)
    job = DEMO_JOB
    track = Lollipop(job["stick"], job["loop"])
    gen = TrajectoryGenerator(
        track, clearance=job["clearance"], limits=Limits(job["vmax"], job["amax"], job["jmax"]), rate=job["rate"]
    )
    traj = gen.generate(job["start"], job["goal"])
    png = figure_png(plot_trajectory(traj))
    plan: Any = traj.plan  # a paper Plan (the demo's lollipop)
    files: dict[str, str | bytes] = {
        "setpoints.csv": traj.csv_text(),
        "summary.json": _json(traj.summary()),
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


def add_delay_tolerance_argument(p: argparse.ArgumentParser) -> None:
    """``--delay-tolerance T`` (see :mod:`trajopt.delay`)."""
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
    p.add_argument(
        "--out", required=True, help="output directory (setpoints.csv and the other --format files, summary.json)"
    )
    add_output_arguments(p)
    add_delay_tolerance_argument(p)
    p.set_defaults(func=_cmd_trajectory)
    d = subparsers.add_parser("demo", help="the embedded default job: a lollipop swap, files and a PNG")
    d.add_argument("--out", default="mpa-demo", help="output directory (default ./mpa-demo)")
    d.set_defaults(func=_cmd_demo)
