"""The JSON summary of a trajectory (everything but the arrays) and its file."""

from __future__ import annotations

import enum
import json
import os
from typing import TYPE_CHECKING, Any

import numpy as np

from trajopt.path.planview import plan_view

if TYPE_CHECKING:
    from trajopt.result import Trajectory
from trajopt.io.directory import validate_output_path, write_output_file


def _json_default(obj: Any) -> Any:
    if isinstance(obj, np.generic):
        return obj.item()
    if isinstance(obj, np.ndarray):
        return obj.tolist()
    if isinstance(obj, enum.Enum):
        return obj.value
    raise TypeError(f"not JSON serializable: {type(obj).__name__}")


def summary(traj: Trajectory, *, margins: bool = False) -> dict[str, Any]:
    """JSON-ready summary of ``traj`` (everything but the arrays).

    ``routes`` gives each robot's route (``"a"``, ``"b"``): the edges in the order travelled, each with ``dir``
    (+1 along the edge, -1 against), the ``entry`` offset and the route coordinates ``from_s``/``to_s`` where
    the robot is on it (what a controller needs to set the switches). On a layout ``start`` and ``goal`` are
    position names (``EDGE:OFFSET`` or a vertex) and ``track`` is the layout. ``margins=True`` adds
    ``"margins"``: the tracking margin and delay tolerance (:func:`trajopt.analysis.margins.margins`, 0.4-2 s the first
    time; ``summary.json`` of the command line has them).
    """
    view = plan_view(traj.plan)
    plan = traj.plan
    if view.is_graph:
        g = plan.layout
        track: Any = g.to_dict()
        start: Any = [g.position_name(*p) for p in plan.layout_start]
        goal: Any = [g.position_name(*p) for p in plan.layout_goal]
        units = {"time": "s", "offset": "m", "s": "m", "v": "m/s", "a": "m/s^2", "j": "m/s^3"}
    else:  # the paper's files speak in its track coordinates (docs/conventions.md, "Command line and files")
        paper = view.paper
        track, start, goal = paper.track.to_dict(), paper.start.tolist(), paper.goal.tolist()
        units = {"time": "s", "track": "m", "offset": "m", "s": "m", "v": "m/s", "a": "m/s^2", "j": "m/s^3"}
    if "b_y" in traj.columns:
        units["x"] = units["y"] = "m"
    extra: dict[str, Any] = {}
    if traj.footprint is not None:
        units["heading"] = "rad"
        plane = dict(traj.plane or {})
        gap = float(plane.get("min_gap_plane", float("nan")))
        from mpa.footprint import drawing_of

        scale = float(np.max(np.hypot(*drawing_of(plan.layout).piece_dir.T)))
        extra = {
            "footprint": traj.footprint.to_dict(),
            "min_gap_plane": gap,
            # each cart may lag or lead its setpoint by this much along its track (both at once) while the
            # bodies stay apart in the plane (translation; turning at corners not included)
            "tracking_margin_plane": max(0.0, gap) / (2.0 * scale),
            "plane": plane,
        }
    out = extra | {
        "makespan": traj.makespan,
        "motion_time": traj.motion_time,
        "min_separation": traj.min_separation,
        "domain": traj.domain,
        "fallback": traj.fallback,
        "fallback_reason": traj.fallback_reason,
        "source": traj.source.value,
        "word": list(traj.word),
        "track": track,
        "start": start,
        "goal": goal,
        "clearance": traj.clearance,
        "limits": traj.limits.to_dict(),
        "limits_used": traj.limits_used.to_dict(),
        "rate": traj.rate,
        "rows": len(traj.t),
        "columns": list(traj.columns),
        "units": units,
        "routes": traj.routes(),
        "peak": {
            "v": np.max(np.abs(traj.v), axis=0).tolist(),
            "a": np.max(np.abs(traj.a), axis=0).tolist(),
            "j": np.max(np.abs(traj.j), axis=0).tolist(),
        },
        "solver": traj.solver_stats,
        "timings": traj.timings,
        "verification": traj.verification,
        "words": traj.description(),
    }
    if margins:
        out["margins"] = traj.margins().to_dict()
        out["words"] = out.pop("words")  # the file's order: margins, then words
    return out


def write_json(traj: Trajectory, path: str | os.PathLike[str], *, margins: bool = True) -> None:
    """Write :func:`summary` of ``traj`` as JSON (atomically).

    Raises
    ------
    InvalidInputError
        ``path`` is not a file path, or the file cannot be written (the message names the path and the reason).
    """
    target = validate_output_path(path)
    write_output_file(target, json.dumps(summary(traj, margins=margins), indent=2, default=_json_default) + "\n")
