"""``mpa replan --from DIR`` for a run on a layout (``mpa trajectory --graph``, or ``--planner graph`` on a paper
track, written in its layout form).

The run is rebuilt from ``DIR/summary.json``: the layout (``track``, as :meth:`mpa.GraphTrack.to_dict` wrote it),
clearance, limits, rate and the ``recipe`` (``start``, ``goal`` and the ``replans`` as position names
``EDGE:OFFSET`` or vertex names, and the graph planner's ``objective``). The rebuilt motion is checked against
``DIR/setpoints.csv`` row by row (the edge names and every numeric column of
:data:`trajopt.GRAPH_CSV_COLUMNS`, to 1e-9 m + 1e-9 relative); a mismatch is an error (exit 2).
"""

from __future__ import annotations

import csv
from pathlib import Path
from typing import Any

import numpy as np

from mpa.errors import InvalidInputError, MPAError
from mpa.graph_track import GraphTrack
from trajopt.export import GRAPH_CSV_COLUMNS, Trajectory
from trajopt.generator import TrajectoryGenerator
from trajopt.timing import Limits

__all__ = ["is_layout_summary", "layout_goal", "layout_of", "load_layout_trajectory", "query_error", "rebuild"]

#: Tolerance of the check of the rebuilt motion against ``setpoints.csv`` (absolute + relative).
MATCH_TOL = 1e-9
#: The numeric columns compared (every column of :data:`GRAPH_CSV_COLUMNS` but the edge names).
NUMERIC = tuple(c for c in GRAPH_CSV_COLUMNS if not c.endswith("_edge"))


def query_error(option: str, exc: Exception) -> InvalidInputError:
    """The error of a ``summary.json`` whose query (the ``recipe``) cannot be read: names ``option`` and why."""
    return InvalidInputError(
        f"{option}: summary.json lacks the query ({type(exc).__name__}: {exc}), expected one written by mpa trajectory"
    )


def is_layout_summary(summary: dict[str, Any]) -> bool:
    """Whether a ``summary.json`` describes a run on a layout (its ``track`` has ``edges``)."""
    return isinstance(summary.get("track"), dict) and "edges" in summary["track"]


def layout_of(summary: dict[str, Any], option: str = "--from") -> GraphTrack:
    """The layout of a layout run's summary.

    Raises
    ------
    InvalidInputError
        The summary's ``track`` is not a layout.
    """
    try:
        return GraphTrack.from_layout(summary["track"])
    except InvalidInputError as exc:
        raise InvalidInputError(f"{option}: the layout of summary.json is invalid ({exc})") from None


def layout_goal(track: GraphTrack, values: list[str], option: str = "--goal") -> list[str]:
    """The goal of robots A and B as canonical position names (``EDGE:OFFSET`` or vertex names).

    Raises
    ------
    InvalidInputError
        An unknown edge or vertex, or an offset off the edge (the message names ``option`` and the robot).
    """
    return [track.position_name(*track.position(v, f"{option} of robot {r}")) for v, r in zip(values, "AB")]


def _read_rows(d: Path, option: str) -> tuple[list[list[str]], np.ndarray]:
    """Edge names (A, B) and the numeric columns of ``setpoints.csv`` of a layout run."""
    p = d / "setpoints.csv"
    if not p.is_file():
        raise InvalidInputError(
            f"{option} {str(d)!r} holds no setpoints.csv, expected an output directory of mpa trajectory "
            "written with the csv format"
        )
    try:
        with p.open(encoding="utf-8", newline="") as fh:
            reader = csv.reader(fh)
            header = next(reader, [])
            if tuple(header[: len(GRAPH_CSV_COLUMNS)]) != GRAPH_CSV_COLUMNS:
                raise InvalidInputError(
                    f"{option}: {str(p)!r} has header {','.join(header)!r}, expected {','.join(GRAPH_CSV_COLUMNS)}"
                )
            idx = [header.index(c) for c in NUMERIC]
            ea, eb = header.index("a_edge"), header.index("b_edge")
            names: list[list[str]] = []
            values: list[list[float]] = []
            for row in reader:
                names.append([row[ea], row[eb]])
                values.append([float(row[i]) for i in idx])
    except (OSError, UnicodeDecodeError, ValueError, IndexError) as exc:
        raise InvalidInputError(f"{option}: {str(p)!r} cannot be read as setpoints ({exc})") from None
    data = np.array(values, dtype=float).reshape(len(values), len(NUMERIC))
    bad = np.argwhere(~np.isfinite(data))
    if bad.size:
        k, c = (int(x) for x in bad[0])
        raise InvalidInputError(
            f"{option}: {str(p)!r} row {k} (line {k + 2}), column {NUMERIC[c]}: {data[k, c]!r}, expected a finite "
            "number"
        )
    return names, data


def _rows_of(traj: Trajectory) -> tuple[list[list[str]], np.ndarray]:
    names = np.asarray(traj.edge_names, dtype=object)
    e, o, d = traj.edges, traj.offsets, traj.directions
    col = {"time": traj.t}
    for r, x in enumerate("ab"):
        col.update({f"{x}_offset": o[:, r], f"{x}_s": traj.s[:, r], f"{x}_v": traj.v[:, r]})
        col.update({f"{x}_a": traj.a[:, r], f"{x}_j": traj.j[:, r], f"{x}_dir": d[:, r].astype(float)})
    return names[e].tolist(), np.column_stack([col[c] for c in NUMERIC])


def load_layout_trajectory(
    d: Path, summary: dict[str, Any], option: str = "--from"
) -> tuple[TrajectoryGenerator, Trajectory, dict[str, Any]]:
    """The generator, the trajectory and the recipe of a layout run's output directory ``d``.

    Raises
    ------
    InvalidInputError
        No ``setpoints.csv``, unreadable files, or a motion that cannot be rebuilt or does not match
        ``setpoints.csv``.
    """
    track = layout_of(summary, option)
    rows_names, rows = _read_rows(d, option)
    try:
        lim = summary["limits"]
        limits = Limits(lim["vmax"], lim["amax"], lim["jmax"])
        src = summary.get("recipe") or {"start": summary["start"], "goal": summary["goal"], "replans": []}
        objective = str(src.get("objective") or "fastest")
        gen = TrajectoryGenerator(
            track, clearance=float(summary["clearance"]), limits=limits, rate=summary["rate"], objective=objective
        )
        recipe: dict[str, Any] = {
            "start": [str(x) for x in src["start"]],
            "goal": [str(x) for x in src["goal"]],
            "delay_tolerance": None if src.get("delay_tolerance") is None else float(src["delay_tolerance"]),
            "objective": objective,
            "replans": [{"at": float(r["at"]), "goal": [str(x) for x in r["goal"]]} for r in src["replans"]],
        }
        if src.get("min_margin") is not None:
            recipe["min_margin"] = float(src["min_margin"])
    except InvalidInputError:
        raise
    except (KeyError, TypeError, ValueError, AttributeError) as exc:
        raise query_error(option, exc) from None
    try:
        traj = rebuild(gen, recipe)
    except MPAError as exc:
        raise InvalidInputError(f"{option}: the motion of summary.json cannot be rebuilt ({exc})") from None
    names, ours = _rows_of(traj)
    if ours.shape != rows.shape:
        raise InvalidInputError(
            f"{option}: setpoints.csv has {rows.shape[0]} rows, the motion rebuilt from summary.json "
            f"{ours.shape[0]}: the files do not belong together (edited, or written by another version)"
        )
    err = np.abs(ours - rows) - MATCH_TOL * (1.0 + np.abs(rows))
    if float(np.max(err, initial=0.0)) > 0.0 or names != rows_names:
        if names != rows_names:
            k = next(i for i, (x, y) in enumerate(zip(names, rows_names)) if x != y)
            where = f"row {k}, edges {rows_names[k]} vs {names[k]}"
        else:
            kc = np.unravel_index(int(np.argmax(err)), err.shape)
            where = f"row {int(kc[0])}, column {NUMERIC[int(kc[1])]}: {rows[kc]!r} vs {ours[kc]!r}"
        raise InvalidInputError(
            f"{option}: setpoints.csv differs from the motion rebuilt from summary.json ({where}): the files do "
            "not belong together"
        )
    return gen, traj, recipe


def rebuild(gen: TrajectoryGenerator, recipe: dict[str, Any]) -> Trajectory:
    """The motion of a recipe: the query (with its delay tolerance or margin), then the chain of re-plans."""
    kwargs: dict[str, Any] = {"delay_tolerance": recipe.get("delay_tolerance")}
    if recipe.get("min_margin") is not None:
        kwargs["min_margin"] = recipe["min_margin"]
    traj = gen.generate(recipe["start"], recipe["goal"], **kwargs)
    for r in recipe["replans"]:
        traj = gen.replan(traj, r["at"], r["goal"])
    return traj
