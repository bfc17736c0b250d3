"""``mpa replan --from DIR --at T --goal A B --out DIR``: re-plan a written trajectory from its moving state.

The trajectory is rebuilt from ``DIR/summary.json`` (track, clearance, limits, rate and the ``recipe``: the
query, the requested delay tolerance and the chain of earlier re-plans; a summary without a recipe, e.g. of
``mpa demo``, is rebuilt from its ``start`` and ``goal``). The pipeline is deterministic, so the rebuilt motion is
checked against ``DIR/setpoints.csv`` row by row (every column, edge names, offsets and directions included,
to 1e-9 m + 1e-9 relative: the file holds 12 significant digits); a cell that is not a finite number or a
mismatch is an error naming the file, the row and the column. Then :meth:`TrajectoryGenerator.replan` and the files of
``mpa trajectory`` (same ``--format``/``--plot`` options), with the recipe extended by ``{at, goal}`` so that the
result can be re-planned again.

A layout run (``mpa trajectory --graph``, or ``--planner graph``) is rebuilt by
:func:`trajopt.cli.replan_layout.load_layout_trajectory`; its ``--goal`` is two positions ``EDGE:OFFSET`` or
vertex names (the run's kind is read from ``summary.json`` before the goal is parsed).

Errors (exit 2, one ``error:`` line, nothing written): ``--from`` without ``summary.json`` or ``setpoints.csv``
(or with files that do not describe the same motion), ``--at`` outside ``[0, makespan]``, a goal off the track or
closer than the clearance; a goal without motion: exit 3.
"""

from __future__ import annotations

import argparse
import csv
import math
from pathlib import Path
from typing import Any

import numpy as np

from mpa.errors import InvalidInputError, MPAError
from mpa.graph import parse_json
from mpa.tracks import make_track
from trajopt.cli.common import parse_coordinates, validate_output_dir
from trajopt.cli.outputs import add_output_arguments, output_files, summary_text, validate_output_options
from trajopt.cli.replan_layout import (
    is_layout_summary,
    layout_goal,
    layout_of,
    load_layout_trajectory,
    query_error,
    rebuild,
)
from trajopt.export import CSV_COLUMNS, Trajectory
from trajopt.generator import TrajectoryGenerator
from trajopt.timing import Limits

__all__ = ["load_trajectory", "register"]

#: The numeric columns of the paper tracks' CSV.
NUMERIC = CSV_COLUMNS[:11]
#: The numeric columns compared with the rebuilt motion: :data:`NUMERIC`, then each robot's offset and direction.
COMPARED = (*NUMERIC, "a_offset", "a_dir", "b_offset", "b_dir")
#: Tolerance of the check of the rebuilt motion against ``setpoints.csv`` (absolute + relative).
MATCH_TOL = 1e-9


def _read_summary(d: Path, option: str) -> dict[str, Any]:
    p = d / "summary.json"
    if not p.is_file():
        raise InvalidInputError(
            f"{option} {str(d)!r} holds no trajectory (no summary.json), expected an output directory of "
            "mpa trajectory (summary.json and setpoints.csv)"
        )
    try:
        text = p.read_text(encoding="utf-8")
    except (OSError, UnicodeDecodeError) as exc:
        raise InvalidInputError(f"{option}: {str(p)!r} cannot be read as JSON ({exc})") from None
    data = parse_json(text, f"{option}: {str(p)!r}")
    if not isinstance(data, dict):
        raise InvalidInputError(f"{option}: {str(p)!r} is not a summary of mpa trajectory (not a JSON object)")
    return data


def _read_setpoints(d: Path, option: str) -> tuple[np.ndarray, list[tuple[str, str]]]:
    """The setpoints of ``d/setpoints.csv``: the numeric columns (:data:`COMPARED`) and each row's edge names.

    Raises
    ------
    InvalidInputError
        No file, another header, a row with another number of fields, or a numeric cell that is not a finite
        number (the message names the file, the row and the column).
    """
    p = d / "setpoints.csv"
    if not p.is_file():
        raise InvalidInputError(
            f"{option} {str(d)!r} holds no setpoints.csv, expected an output directory of mpa trajectory "
            "written with the csv format"
        )
    where = f"{option}: {str(p)!r}"
    index = [CSV_COLUMNS.index(c) for c in COMPARED]
    edge_cols = (CSV_COLUMNS.index("a_edge"), CSV_COLUMNS.index("b_edge"))
    values: list[list[float]] = []
    edges: list[tuple[str, str]] = []
    try:
        with p.open(encoding="utf-8", newline="") as fh:
            reader = csv.reader(fh)
            header = next(reader, None)
            if header != list(CSV_COLUMNS):
                shown = "" if header is None else ",".join(header)
                raise InvalidInputError(f"{where} has header {shown!r}, expected {','.join(CSV_COLUMNS)}")
            for k, cells in enumerate(reader):
                if len(cells) != len(CSV_COLUMNS):
                    raise InvalidInputError(
                        f"{where} row {k} (line {k + 2}) has {len(cells)} fields, expected {len(CSV_COLUMNS)}"
                    )
                row = []
                for c in index:
                    try:
                        x = float(cells[c])
                    except ValueError:
                        x = math.nan
                    if not math.isfinite(x):
                        raise InvalidInputError(
                            f"{where} row {k} (line {k + 2}), column {CSV_COLUMNS[c]}: {cells[c]!r}, expected a "
                            "finite number"
                        )
                    row.append(x)
                values.append(row)
                edges.append((cells[edge_cols[0]], cells[edge_cols[1]]))
    except (OSError, UnicodeDecodeError, csv.Error) as exc:
        raise InvalidInputError(f"{where} cannot be read as setpoints ({exc})") from None
    if not values:
        raise InvalidInputError(f"{where} has a header but no rows, expected the setpoints of a motion")
    return np.array(values, dtype=float), edges


def _csv_array(traj: Trajectory) -> np.ndarray:
    cols = [traj.t, traj.track[:, 0], traj.s[:, 0], traj.v[:, 0], traj.a[:, 0], traj.j[:, 0]]
    cols += [traj.track[:, 1], traj.s[:, 1], traj.v[:, 1], traj.a[:, 1], traj.j[:, 1]]
    cols += [traj.offsets[:, 0], traj.directions[:, 0].astype(float), traj.offsets[:, 1]]
    cols += [traj.directions[:, 1].astype(float)]
    return np.column_stack(cols)


def load_trajectory(directory: str | Path, option: str = "--from") -> tuple[TrajectoryGenerator, Trajectory, dict]:
    """The generator, the trajectory and the recipe of an output directory of ``mpa trajectory``/``replan``.

    Raises
    ------
    InvalidInputError
        No such directory, no ``summary.json`` or ``setpoints.csv``, unreadable files, or a motion that cannot
        be rebuilt or does not match ``setpoints.csv``.
    """
    d = Path(directory)
    if not d.is_dir():
        raise InvalidInputError(f"{option} is {str(d)!r}, expected a directory written by mpa trajectory")
    summary = _read_summary(d, option)
    if is_layout_summary(summary):  # a layout run (mpa trajectory --graph, or --planner graph)
        return load_layout_trajectory(d, summary, option)
    rows, row_edges = _read_setpoints(d, option)
    try:
        tr = dict(summary["track"])
        kind = tr.pop("track")
        if kind not in ("interval", "circle", "lollipop"):
            raise InvalidInputError(f"{option}: track {kind!r}, expected interval, circle or lollipop")
        track = make_track(kind, tr.get("stick"), tr.get("loop"))
        lim = summary["limits"]
        limits = Limits(lim["vmax"], lim["amax"], lim["jmax"])
        gen = TrajectoryGenerator(track, clearance=float(summary["clearance"]), limits=limits, rate=summary["rate"])
        recipe = summary.get("recipe") or {
            "start": summary["start"],
            "goal": summary["goal"],
            "delay_tolerance": None,
            "replans": [],
        }
        recipe = {
            "start": [float(x) for x in recipe["start"]],
            "goal": [float(x) for x in recipe["goal"]],
            "delay_tolerance": None if recipe.get("delay_tolerance") is None else float(recipe["delay_tolerance"]),
            "replans": [{"at": float(r["at"]), "goal": [float(x) for x in r["goal"]]} for r in recipe["replans"]],
        }
    except InvalidInputError:
        raise
    except (KeyError, TypeError, ValueError, AttributeError) as exc:
        raise query_error(option, exc) from None
    try:
        margin = (summary.get("recipe") or {}).get("min_margin")
        if margin is not None:
            recipe["min_margin"] = float(margin)
        traj = rebuild(gen, recipe)
    except MPAError as exc:
        raise InvalidInputError(f"{option}: the motion of summary.json cannot be rebuilt ({exc})") from None
    ours = _csv_array(traj)
    if ours.shape != rows.shape:
        raise InvalidInputError(
            f"{option}: setpoints.csv has {rows.shape[0]} rows, the motion rebuilt from summary.json "
            f"{ours.shape[0]}: the files do not belong together (edited, or written by another version)"
        )
    err = np.abs(ours - rows) - MATCH_TOL * (1.0 + np.abs(rows))
    if float(np.max(err)) > 0.0:
        k, c = np.unravel_index(int(np.argmax(err)), err.shape)
        raise InvalidInputError(
            f"{option}: setpoints.csv differs from the motion rebuilt from summary.json (row {k}, column "
            f"{COMPARED[c]}: {rows[k, c]!r} vs {ours[k, c]!r}): the files do not belong together"
        )
    names = traj.edge_names
    for row, (pair, e) in enumerate(zip(row_edges, traj.edges.tolist(), strict=True)):
        for r, x in enumerate("ab"):
            if pair[r] != names[e[r]]:
                raise InvalidInputError(
                    f"{option}: setpoints.csv differs from the motion rebuilt from summary.json (row {row}, column "
                    f"{x}_edge: {pair[r]!r} vs {names[e[r]]!r}): the files do not belong together"
                )
    return gen, traj, recipe


def _cmd_replan(args: argparse.Namespace) -> int:
    opts = validate_output_options(args)
    goal: Any = _goal_for_run(args.from_dir, args.goal)
    at = float(args.at)
    if not math.isfinite(at):
        raise InvalidInputError(f"--at is {args.at!r}, expected a time in seconds")
    validate_output_dir(args.out)
    gen, traj, recipe = load_trajectory(args.from_dir)
    if not 0.0 <= at <= traj.makespan:
        raise InvalidInputError(f"--at is {at!r} s, expected a time in [0, {traj.makespan:g}] s (the motion of --from)")
    new = gen.replan(traj, at, goal)
    recipe = dict(recipe, replans=[*recipe["replans"], {"at": at, "goal": list(goal)}])
    files = output_files(new, opts, recipe)
    from trajopt.cli.trajectory import write_outputs

    write_outputs(args.out, files)
    rp = new.solver_stats["replan"]
    print(f"replan      at {at:g} s of {args.from_dir}: brake {rp['brake_duration']:.3f} s, then to the new goal")
    print(summary_text(new))
    print(f"wrote       {', '.join(str(Path(args.out) / n) for n in files)}")
    return 0


def _goal_for_run(from_dir: str, values: list[str]) -> Any:
    """``--goal`` parsed for the kind of run in ``from_dir``: positions by name on a layout run (``EDGE:OFFSET``
    or vertex names), track coordinates on a paper track's run."""
    d = Path(from_dir)
    summary = _read_summary(d, "--from") if d.is_dir() else {}
    if is_layout_summary(summary):
        return layout_goal(layout_of(summary), values)
    return parse_coordinates(values, "--goal")


def register(subparsers: Any) -> None:
    """Add ``replan`` to the ``mpa`` command (called by :func:`trajopt.cli.main.build_parser`)."""
    p = subparsers.add_parser(
        "replan", help="re-plan a written trajectory from the carts' moving state at a time to a new goal"
    )
    p.add_argument("--from", dest="from_dir", required=True, metavar="DIR", help="output directory of mpa trajectory")
    p.add_argument("--at", type=float, required=True, metavar="T", help="time of that motion (s) to re-plan from")
    p.add_argument(
        "--goal",
        nargs=2,
        required=True,
        metavar=("A", "B"),
        help="new goal: track coordinates (a paper track's run) or positions EDGE:OFFSET / vertex names (a layout's)",
    )
    p.add_argument("--out", required=True, help="output directory (the files of mpa trajectory)")
    add_output_arguments(p)
    p.set_defaults(func=_cmd_replan)
