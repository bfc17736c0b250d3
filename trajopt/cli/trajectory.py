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
from mpa.tracks import Lollipop
from trajopt.cli.common import (
    TRAJECTORY_DEFAULTS,
    add_trajectory_arguments,
    check_output_dir,
    output_error,
    query_from_args,
)
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
    s = traj.summary()
    src = "fallback (plan re-timed): " + traj.fallback_reason if traj.fallback else "optimized"
    if traj.is_graph:
        first = [
            f"route {r.upper()}     " + " → ".join(f"{p['edge']}{'+' if p['dir'] > 0 else '-'}" for p in s["routes"][r])
            for r in "ab"
        ]
    else:
        first = [f"domain      {traj.domain}, class {' '.join(traj.word) or '(trivial)'}"]
    lines = [
        *first,
        f"makespan    {traj.makespan:.3f} s ({len(traj.t)} rows at {traj.rate:g} Hz)",
        f"separation  min {traj.min_separation:.4f} m (clearance {traj.clearance:g} m)",
        f"peaks       |v| {max(s['peak']['v']):.3f}, |a| {max(s['peak']['a']):.3f}, |j| {max(s['peak']['j']):.3f}",
        f"source      {src}",
        f"time        {1e3 * traj.timings.get('total', 0.0):.1f} ms",
    ]
    return "\n".join(lines)


def _json(obj: Any) -> str:
    from trajopt.export import _json_default

    return json.dumps(obj, indent=2, default=_json_default) + "\n"


def _cmd_trajectory(args: argparse.Namespace) -> int:
    check_output_dir(args.out)
    track, start, goal = query_from_args(args)
    gen = TrajectoryGenerator(
        track, clearance=args.clearance, limits=Limits(args.vmax, args.amax, args.jmax), rate=args.rate
    )
    traj = gen.generate(start, goal)
    files = {"setpoints.csv": traj.csv_text(), "summary.json": _json(traj.summary())}
    write_outputs(args.out, files)
    print(_summary_text(traj))
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


def register(subparsers: Any) -> None:
    """Add ``trajectory`` and ``demo`` to the ``mpa`` command (called by :func:`trajopt.cli.main.build_parser`)."""
    p = subparsers.add_parser("trajectory", help="verified jerk-limited setpoints for a query (CSV + JSON)")
    add_trajectory_arguments(p)
    p.add_argument("--out", required=True, help="output directory (setpoints.csv, summary.json)")
    p.set_defaults(func=_cmd_trajectory)
    d = subparsers.add_parser("demo", help="the embedded default job: a lollipop swap, files and a PNG")
    d.add_argument("--out", default="mpa-demo", help="output directory (default ./mpa-demo)")
    d.set_defaults(func=_cmd_demo)
