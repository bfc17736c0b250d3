"""``mpa trajectory`` and ``mpa demo``: verified jerk-limited setpoints from the command line.

Both compute everything in memory first and then write the files into ``--out`` each through a temporary file
and :func:`os.replace`; on any error the files written so far (and the directory, if this run created it) are
removed, so no half-filled output directory is left behind.
"""

from __future__ import annotations

import argparse
import contextlib
import json
import os
import shutil
from collections.abc import Iterator, Mapping
from pathlib import Path
from typing import Any

from mpa import defaults
from mpa.errors import InvalidInputError
from mpa.tracks import Lollipop, Track
from trajopt.cli.common import (
    TRAJECTORY_DEFAULTS,
    add_footprint_argument,
    add_trajectory_arguments,
    check_output_dir,
    footprint_query,
    output_error,
    query_from_args,
)
from trajopt.cli.outputs import add_output_arguments, check_output_options, output_files, summary_text
from trajopt.delay import check_delay_tolerance
from trajopt.export import Trajectory, atomic_write_bytes, atomic_write_text
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
    """Hold an exclusive lock on ``directory`` (``flock`` on the directory itself; no lock file).

    :func:`write_outputs` writes all its files under it, so two processes writing into one directory never
    interleave their files: the directory holds one run's complete set. Readers that want a consistent set
    take it too. Without ``fcntl`` (Windows) it does nothing.
    """
    try:
        import fcntl
    except ImportError:  # pragma: no cover - not POSIX
        yield
        return
    fd = os.open(directory, os.O_RDONLY)
    try:
        fcntl.flock(fd, fcntl.LOCK_EX)
        yield
    finally:
        os.close(fd)  # releases the lock


def write_outputs(out: str | os.PathLike[str], files: Mapping[str, str | bytes]) -> list[Path]:
    """Write ``files`` (name -> content) into directory ``out``, all or nothing, under :func:`output_lock`.

    Raises
    ------
    InvalidInputError
        ``out`` is empty or exists and is not a directory, or a file could not be written
        (``--out: cannot write PATH: reason``; everything written so far is removed).
    """
    if not str(out).strip():
        raise InvalidInputError(f"--out is {str(out)!r}, expected a directory path")
    d = Path(out)
    if d.exists() and not d.is_dir():
        raise InvalidInputError(f"--out is {str(d)!r}, which exists and is not a directory")
    created = not d.exists()
    written: list[Path] = []
    target = d
    try:
        d.mkdir(parents=True, exist_ok=True)
        with output_lock(d):
            for name, content in files.items():
                target = d / name
                if isinstance(content, bytes):
                    atomic_write_bytes(target, content)
                else:
                    atomic_write_text(target, content)
                written.append(target)
    except OSError as exc:
        for p in written:
            p.unlink(missing_ok=True)
        if created:
            shutil.rmtree(d, ignore_errors=True)
        raise output_error("--out", target, exc) from None
    except BaseException:
        for p in written:
            p.unlink(missing_ok=True)
        if created:
            shutil.rmtree(d, ignore_errors=True)
        raise
    return written


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
    track, start, goal, fps = footprint_query(args, track, start, goal)
    if not isinstance(track, Track):  # a layout (--graph)
        if opts.plot:
            raise InvalidInputError(
                "--plot draws trajectories on the paper's tracks, expected no --plot with --graph "
                "(draw a layout with mpa animate --graph or mpa plan --graph --plot)"
            )
        if tolerance is not None:
            raise InvalidInputError("--delay-tolerance is implemented for the paper's tracks, expected no --graph")
    gen = TrajectoryGenerator(
        track,
        clearance=args.clearance,
        limits=Limits(args.vmax, args.amax, args.jmax),
        rate=args.rate,
        footprint=fps,
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
    if fps is not None:
        sm = traj.summary()
        print(
            f"plane       bodies {fps.spec()}: closest {sm['min_gap_plane']:.4g} m apart in the drawing; "
            f"tracking margin in the plane {sm['tracking_margin_plane']:.4g} m"
        )
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
    add_footprint_argument(p)
    p.add_argument(
        "--out", required=True, help="output directory (setpoints.csv and the other --format files, summary.json)"
    )
    add_output_arguments(p)
    add_delay_tolerance_argument(p)
    p.set_defaults(func=_cmd_trajectory)
    d = subparsers.add_parser("demo", help="the embedded default job: a lollipop swap, files and a PNG")
    d.add_argument("--out", default="mpa-demo", help="output directory (default ./mpa-demo)")
    d.set_defaults(func=_cmd_demo)
