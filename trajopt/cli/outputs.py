"""The output files of ``mpa trajectory`` and ``mpa replan``: ``--format``, ``--plot`` and their options.

``--format csv,ros2-yaml,mcap,pvt`` (a comma list, several at once; default ``csv``) selects the files written
into ``--out DIR`` besides ``summary.json`` (always):

============  ======================  ===========================================================================
format        file                    content
============  ======================  ===========================================================================
csv           ``setpoints.csv``       the setpoints (:meth:`Trajectory.csv_text`)
ros2-yaml     ``trajectory.yaml``     a ``trajectory_msgs/msg/JointTrajectory`` (:func:`trajopt.io.ros.ros2_yaml_text`)
mcap          ``trajectory.mcap``     the MCAP file of a rosbag2 bag (:func:`trajopt.io.ros.write_mcap`; extra
``[ros]``)
pvt           ``pvt.csv``             PVT rows every ``--pvt-interval`` s (:func:`trajopt.io.pvt.pvt_table`)
============  ======================  ===========================================================================

``--plot`` adds ``trajectory.png`` (:func:`trajopt.viz.layout_run.trajectory_figure`: a paper track's figure, or
a layout run's). Every option is checked before
any work (:func:`validate_output_options`); every file is computed (:func:`output_files`; ``setpoints.csv`` is
:class:`trajopt.io.atomic.Streamed`, formatted piece by piece while it is written) and then written all or nothing
(:func:`trajopt.cli.trajectory.write_outputs`).

``summary.json`` is :meth:`Trajectory.summary` plus ``files`` (what was written), ``pvt`` (interval, stretch,
rows, ``velocity_change``: :attr:`trajopt.io.pvt.PVTTable.velocity_change`) and ``recipe``: the query that rebuilds
the motion deterministically (``start``, ``goal``, ``delay_tolerance`` and the chain of ``replans``
``{at, goal}``), read by ``mpa replan --from DIR``.
"""

from __future__ import annotations

import argparse
import importlib.util
import json
import math
import shutil
import tempfile
from dataclasses import dataclass
from pathlib import Path
from typing import Any

from mpa._deprecation import deprecated_alias
from mpa.errors import InvalidInputError
from trajopt.export import Content, Streamed, Trajectory

__all__ = [
    "FORMAT_FILES",
    "OutputOptions",
    "add_output_arguments",
    "json_text",
    "output_files",
    "parse_formats",
    "summary_text",
    "validate_output_options",
]

#: File written for each ``--format``.
FORMAT_FILES = {"csv": "setpoints.csv", "ros2-yaml": "trajectory.yaml", "mcap": "trajectory.mcap", "pvt": "pvt.csv"}
#: Name of the figure of ``--plot``.
PLOT_FILE = "trajectory.png"


@dataclass(frozen=True)
class OutputOptions:
    """The checked output options (see :func:`validate_output_options`)."""

    formats: tuple[str, ...] = ("csv",)
    pvt_interval: float | str = "auto"
    pvt_stretch: float = 1.0
    joint_names: tuple[str, str] = ("cart_a", "cart_b")
    topic: str = "/joint_trajectory"
    plot: bool = False


def add_output_arguments(p: argparse.ArgumentParser) -> None:
    """``--format``, ``--pvt-interval``, ``--pvt-stretch``, ``--joint-names``, ``--topic``, ``--plot``."""
    g = p.add_argument_group("output files")
    g.add_argument(
        "--format",
        default="csv",
        metavar="LIST",
        help="comma list of csv (setpoints.csv), ros2-yaml (trajectory.yaml), mcap (trajectory.mcap, needs the "
        "[ros] extra), pvt (pvt.csv); default csv; summary.json is always written",
    )
    g.add_argument(
        "--pvt-interval",
        default="auto",
        metavar="S",
        help="PVT row interval in s, or auto (default): the largest round interval <= 0.1 s whose cubic "
        "reconstruction keeps the clearance and the limits (written in summary.json); an interval that would "
        "break them is refused (the error names the largest interval that works)",
    )
    g.add_argument(
        "--pvt-stretch",
        type=float,
        default=1.0,
        metavar="K",
        help="allow the PVT rows to slow the motion down by up to this factor if the interval fails (default 1)",
    )
    g.add_argument(
        "--joint-names", default="cart_a,cart_b", metavar="A,B", help="ROS joint names (default cart_a,cart_b)"
    )
    g.add_argument(
        "--topic", default="/joint_trajectory", help="MCAP topic of the JointTrajectory (default /joint_trajectory)"
    )
    g.add_argument(
        "--plot",
        action="store_true",
        help="also write trajectory.png (paper tracks: track, configuration space, s/v/a/j; layouts: the layout with "
        "both routes and the carts at a few times, speed, acceleration and distance over time)",
    )


def parse_formats(text: str) -> tuple[str, ...]:
    """The formats of ``--format`` (comma list, duplicates removed, order kept).

    Raises
    ------
    InvalidInputError
        An empty list or an unknown format.
    """
    items = [x.strip() for x in str(text).split(",")]
    if not any(items):
        raise InvalidInputError(f"--format is {text!r}, expected a comma list of {', '.join(FORMAT_FILES)}")
    out: list[str] = []
    for x in items:
        if x not in FORMAT_FILES:
            raise InvalidInputError(
                f"--format has {x!r}, expected a comma list of {', '.join(FORMAT_FILES)} (e.g. csv,ros2-yaml)"
            )
        if x not in out:
            out.append(x)
    return tuple(out)


def _rosbags_available() -> bool:
    """Whether the optional dependency ``rosbags`` (extra ``[ros]``) can be imported (without importing it)."""
    try:
        return all(importlib.util.find_spec(m) is not None for m in ("rosbags", "rosbags.rosbag2", "rosbags.typesys"))
    except (ImportError, ValueError):
        return False


def validate_output_options(args: argparse.Namespace) -> OutputOptions:
    """Check the output options before any work.

    Raises
    ------
    InvalidInputError
        Unknown format, bad joint names, topic, PVT interval or stretch; ``mcap`` without ``rosbags``.
    """
    from trajopt.io.pvt import validate_interval
    from trajopt.io.ros import validate_joint_names, validate_topic

    formats = parse_formats(args.format)
    names = validate_joint_names(args.joint_names)
    topic = validate_topic(args.topic, "--topic")
    try:
        auto = isinstance(args.pvt_interval, str) and args.pvt_interval.strip().lower() == "auto"
        interval: float | str = "auto" if auto else validate_interval(args.pvt_interval)
    except InvalidInputError as exc:
        raise InvalidInputError(str(exc).replace("PVT interval", "--pvt-interval", 1)) from None
    k = float(args.pvt_stretch)
    if not math.isfinite(k) or k < 1.0:
        raise InvalidInputError(f"--pvt-stretch is {args.pvt_stretch!r}, expected a factor >= 1")
    if "mcap" in formats and not _rosbags_available():
        raise InvalidInputError(
            "--format mcap needs the optional dependency rosbags, which is not installed: "
            "pip install 'lollipop-mpa[ros]' (or drop mcap from --format)"
        )
    return OutputOptions(formats, interval, k, names, topic, bool(getattr(args, "plot", False)))


#: Deprecated name of :func:`validate_output_options` (warns).
check_output_options = deprecated_alias(validate_output_options, "check_output_options")


def _mcap_bytes(traj: Trajectory, opts: OutputOptions) -> bytes:
    """The MCAP file of a rosbag2 bag of ``traj`` (written in a temporary directory, read back, removed)."""
    from trajopt.io.ros import write_mcap

    tmp = Path(tempfile.mkdtemp(prefix="mpa-mcap-"))
    try:
        path = write_mcap(traj, tmp / "trajectory", joint_names=opts.joint_names, topic=opts.topic)
        return path.read_bytes()
    finally:
        shutil.rmtree(tmp, ignore_errors=True)


def json_text(obj: Any) -> str:
    """JSON with the project's encoder (numpy arrays and scalars, enums)."""
    from trajopt.export import _json_default

    return json.dumps(obj, indent=2, default=_json_default) + "\n"


def output_files(traj: Trajectory, opts: OutputOptions, recipe: dict[str, Any]) -> dict[str, Content]:
    """Every file of the run, in memory: name -> content (``summary.json`` last).

    Raises
    ------
    InvalidInputError
        The PVT interval does not keep the clearance and limits (``--pvt-interval ...``: the message names the
        largest interval that works), or another writer refuses its input.
    """
    files: dict[str, Content] = {}
    extra: dict[str, Any] = {}
    for fmt in opts.formats:
        name = FORMAT_FILES[fmt]
        if fmt == "csv":
            files[name] = Streamed(traj.csv_chunks)  # formatted piece by piece as it is written
        elif fmt == "ros2-yaml":
            from trajopt.io.ros import ros2_yaml_text

            files[name] = ros2_yaml_text(traj, joint_names=opts.joint_names)
        elif fmt == "mcap":
            files[name] = _mcap_bytes(traj, opts)
        elif fmt == "pvt":
            from trajopt.io.pvt import pvt_table

            try:
                tab = pvt_table(traj, opts.pvt_interval, max_stretch=opts.pvt_stretch)
            except InvalidInputError as exc:
                raise InvalidInputError(str(exc).replace("PVT interval", "--pvt-interval", 1)) from None
            files[name] = tab.csv_text()
            auto = opts.pvt_interval == "auto"
            extra["pvt"] = {
                "interval": tab.interval,
                "auto": auto,
                "stretch": tab.stretch,
                "rows": len(tab.t),
                "velocity_change": tab.velocity_change,
            }
    if opts.plot:
        from trajopt.viz.layout_run import trajectory_figure
        from trajopt.viz.plotting import figure_png

        files[PLOT_FILE] = figure_png(trajectory_figure(traj))
    summary = traj.summary(margins=True)
    summary.update(extra)
    summary["formats"] = list(opts.formats)
    summary["files"] = [*files, "summary.json"]
    if "ros2-yaml" in opts.formats or "mcap" in opts.formats:
        summary["ros"] = {"joint_names": list(opts.joint_names), "topic": opts.topic}
    summary["recipe"] = recipe
    files["summary.json"] = json_text(summary)
    return files


def summary_text(traj: Trajectory) -> str:
    """The printout of a trajectory: class, timing, separation, margins and each cart's motion in words."""
    s = traj.summary()
    src = "fallback (plan re-timed): " + traj.fallback_reason if traj.fallback else "optimized"
    m = traj.margins()
    tau = "unbounded" if math.isinf(m.delay_tolerance) else f"{m.delay_tolerance:.4g} s"
    words = traj.description()
    if traj.is_graph:  # a layout: each robot's route (edges with the direction travelled) instead of the domain
        first = [
            f"route {r.upper()}     " + " → ".join(f"{p['edge']}{'+' if p['dir'] > 0 else '-'}" for p in s["routes"][r])
            for r in "ab"
        ]
    else:
        first = [f"domain      {traj.domain}, class {' '.join(traj.word) or '(trivial)'}"]
    lines = [
        *first,
        f"A           {words.get('A', '')}",
        f"B           {words.get('B', '')}",
        f"makespan    {traj.makespan:.3f} s ({len(traj.t)} rows at {traj.rate:g} Hz)",
        f"separation  min {traj.min_separation:.4f} m (clearance {traj.clearance:g} m)",
        f"margins     tracking {m.tracking_margin:.4g} m, delay {tau}",
        f"peaks       |v| {max(s['peak']['v']):.3f}, |a| {max(s['peak']['a']):.3f}, |j| {max(s['peak']['j']):.3f}",
        f"source      {src}",
        f"time        {1e3 * traj.timings.get('total', 0.0):.1f} ms",
    ]
    dt = traj.solver_stats.get("delay_tolerance")
    if dt:
        lines.insert(
            6,
            f"tolerance   asked {dt['requested']:g} s: effective clearance {dt['effective_clearance']:.4g} m, "
            f"slowdown {dt['slowdown']:g}",
        )
    mm = traj.solver_stats.get("min_margin")
    if mm:
        lines.insert(
            len(lines) - 4,
            f"margin      asked {mm['requested']:g} m: effective clearance {mm['effective_clearance']:.4g} m",
        )
    return "\n".join(lines)
