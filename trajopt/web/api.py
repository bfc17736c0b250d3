"""The JSON API of ``mpa serve``, as plain functions of a decoded request body (no web library needed).

Every function takes the request's JSON object and returns a JSON-ready dict; :func:`answer` turns the errors
of :mod:`mpa.errors` into HTTP statuses. The routes (:mod:`trajopt.web.app`) only read the body and call them.

Request body of a query (pinned)::

    {"track": "lollipop", "stick": 1.0, "loop": 1.0, "start": [a, b], "goal": [a, b], "clearance": D}
    {"layout": {...layout JSON...}, "start": [p, p], "goal": [p, p], "clearance": D}

Track coordinates (metres) on the paper's tracks; positions ``"EDGE:OFFSET"`` or vertex names on a layout (robot A
first). Optional: ``planner`` (``"paper"``/``"graph"``), ``objective`` (``"fastest"``/``"shortest"``),
``neighbourhood`` and ``samples`` as ``mpa plan`` takes them; ``footprint`` (the spec string of ``--footprint``,
e.g. ``"0.3"``, ``"2.0x0.8"``, ``"0.3,2x0.8"``: the robots' bodies in the plane); ``vmax``, ``amax``, ``jmax``,
``rate`` and ``formats`` (a list of ``csv``, ``ros2-yaml``, ``pvt``) for a trajectory. A layout is checked with the
validation of layout files (:meth:`mpa.graph_track.GraphTrack.from_layout`); nothing reads the file system.

=========================  ==================================================================================
function                   answer
=========================  ==================================================================================
:func:`plan_answer`        exactly the object ``mpa plan --json`` prints for the same query
:func:`trajectory_answer`  ``{"summary": ..., "csv": ...}``: ``summary.json`` and ``setpoints.csv`` of
                           ``mpa trajectory`` (plus ``"ros2_yaml"``/``"pvt"`` when asked in ``formats``)
:func:`track_answer`       the track drawn to scale: polylines ``[offset, x, y]`` per edge (metres)
:func:`cspace_answer`      paper tracks: the domain of every start on a grid for the goal, and the skeleton
=========================  ==================================================================================
"""

from __future__ import annotations

import argparse
import json
import math
from collections.abc import Callable, Mapping
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np

from mpa import defaults
from mpa.errors import InvalidInputError, MPAError, NoMotionError, PlanningError
from mpa.graph_track import GraphTrack
from mpa.planners.base import DEFAULT_NEIGHBOURHOOD
from mpa.planners.factory import OBJECTIVES
from mpa.tracks import Track, make_track
from trajopt.cli.common import footprint_query
from trajopt.cli.outputs import FORMAT_FILES, OutputOptions, parse_formats
from trajopt.cli.plan import plan_json, plan_query
from trajopt.cli.trajectory import trajectory_files
from trajopt.export import content_text
from trajopt.timing import Limits

__all__ = [
    "EXAMPLES_DIR",
    "MAX_BODY_BYTES",
    "PAPER_TRACKS",
    "Query",
    "answer",
    "cspace_answer",
    "example_layouts",
    "parse_query",
    "plan_answer",
    "track_answer",
    "trajectory_answer",
    "with_footprint",
]

#: Largest request body accepted (bytes); a larger one is refused with HTTP 413.
MAX_BODY_BYTES = 2_000_000
#: The paper's tracks.
PAPER_TRACKS = ("interval", "circle", "lollipop")
#: The example layouts shown on the page (``examples/tracks`` of a source checkout; empty when installed).
EXAMPLES_DIR = Path(__file__).resolve().parents[2] / "examples" / "tracks"
#: Keys of a plan request; a trajectory request also takes :data:`_TRAJECTORY_KEYS`.
_PLAN_KEYS = frozenset(
    {"track", "stick", "loop", "layout", "start", "goal", "clearance", "planner", "objective", "neighbourhood"}
    | {"samples", "footprint"}
)
_TRAJECTORY_KEYS = frozenset({"vmax", "amax", "jmax", "rate", "formats"})
#: Formats a trajectory request may ask for (text files; the MCAP bag is binary: use ``mpa trajectory``).
_TEXT_FORMATS = ("csv", "ros2-yaml", "pvt")
#: Answer key of each extra format.
_FORMAT_KEYS = {"ros2-yaml": "ros2_yaml", "pvt": "pvt"}
#: Grid of :func:`cspace_answer`: default and largest number of cells per axis.
CSPACE_CELLS = 120
MAX_CSPACE_CELLS = 300


@dataclass(frozen=True)
class Query:
    """A checked query: the track, start and goal as the command line would have them, and its options.

    Attributes
    ----------
    track : Track or GraphTrack
    start, goal : pair
        Track coordinates (metres) on a paper track; ``(edge index, offset)`` on a layout; robot A first.
    clearance : float
        Metres.
    planner : str or None
        ``"paper"``, ``"graph"`` or None (the paper's planner on paper tracks, the graph planner on layouts).
    objective : str
        ``"fastest"`` or ``"shortest"`` (graph planner).
    neighbourhood : float
        The domains' ε as a fraction of half the loop.
    samples : int
        ``mpa plan --samples``.
    footprint : Footprints or None
        ``--footprint``: the robots' bodies in the plane; with it a paper track is replaced by its drawn graph form
        and ``start``, ``goal`` by positions on it, as the command line does (:func:`with_footprint`).
    """

    track: Track | GraphTrack
    start: Any
    goal: Any
    clearance: float
    planner: str | None = None
    objective: str = "fastest"
    neighbourhood: float = DEFAULT_NEIGHBOURHOOD
    samples: int = 400
    footprint: Any = None


def _number(body: Mapping[str, Any], key: str, default: float | None, what: str) -> float | None:
    """``body[key]`` as a finite float (``default`` when absent or null)."""
    v = body.get(key)
    if v is None:
        return default
    if isinstance(v, bool) or not isinstance(v, (int, float)) or not math.isfinite(float(v)):
        raise InvalidInputError(f"{key} is {v!r}, expected {what}")
    return float(v)


def _coordinate(v: Any, name: str) -> float:
    """A track coordinate given as a number or a numeric string (like ``mpa plan --start``)."""
    if isinstance(v, str):
        try:
            return float(v)
        except ValueError:
            pass
    elif not isinstance(v, bool) and isinstance(v, (int, float)):
        return float(v)
    raise InvalidInputError(f"{name} has {v!r}, expected a track coordinate (a number, metres)")


def _pair(body: Mapping[str, Any], key: str) -> list[Any]:
    v = body.get(key)
    if not isinstance(v, list) or len(v) != 2:
        raise InvalidInputError(f"{key} is {v!r}, expected a list of two positions [A, B] (robot A first)")
    return v


def parse_track(body: Mapping[str, Any]) -> Track | GraphTrack:
    """The track of a request: ``track`` (with ``stick``, ``loop``) or ``layout``, exactly one of them.

    Raises
    ------
    InvalidInputError
        Neither or both given, an unknown track, bad lengths, a layout that a layout file could not hold.
    """
    if not isinstance(body, Mapping):
        raise InvalidInputError(f"request body is a JSON {type(body).__name__}, expected a JSON object")
    has_track, has_layout = body.get("track") is not None, body.get("layout") is not None
    if has_track and has_layout:
        raise InvalidInputError("both track and layout given, expected one of them")
    if has_layout:
        layout = body["layout"]
        if not isinstance(layout, dict):
            raise InvalidInputError(f"layout is a JSON {type(layout).__name__}, expected a layout object")
        return GraphTrack.from_layout(layout)
    if not has_track:
        raise InvalidInputError(f"no track given, expected track (one of {', '.join(PAPER_TRACKS)}) or layout")
    kind = body["track"]
    if kind not in PAPER_TRACKS:
        raise InvalidInputError(f"track is {kind!r}, expected one of {', '.join(PAPER_TRACKS)} (or a layout)")
    stick = _number(body, "stick", None, "a stick length in metres")
    loop = _number(body, "loop", None, "a loop circumference in metres")
    return make_track(kind, stick, loop)


def parse_query(body: Any, trajectory: bool = False) -> Query:
    """Check a request body and build its :class:`Query` (the checks of ``mpa plan``/``mpa trajectory``).

    Parameters
    ----------
    body : object
        The decoded JSON body.
    trajectory : bool
        Also accept the trajectory keys (``vmax``, ``amax``, ``jmax``, ``rate``, ``formats``).

    Raises
    ------
    InvalidInputError
        Not an object, an unknown key, a bad track, position, clearance or option.
    """
    if not isinstance(body, dict):
        raise InvalidInputError(f"request body is a JSON {type(body).__name__}, expected a JSON object")
    allowed = _PLAN_KEYS | (_TRAJECTORY_KEYS if trajectory else frozenset())
    unknown = sorted(set(body) - allowed)
    if unknown:
        raise InvalidInputError(f"request has unknown key {unknown[0]!r}, expected keys among {sorted(allowed)}")
    track = parse_track(body)
    raw_start, raw_goal = _pair(body, "start"), _pair(body, "goal")
    start: Any
    goal: Any
    if isinstance(track, GraphTrack):
        start = tuple(track.position(v, f"start of robot {r}") for v, r in zip(raw_start, "AB"))
        goal = tuple(track.position(v, f"goal of robot {r}") for v, r in zip(raw_goal, "AB"))
    else:
        start = tuple(_coordinate(v, "start") for v in raw_start)
        goal = tuple(_coordinate(v, "goal") for v in raw_goal)
    clearance = _number(body, "clearance", defaults.CLEARANCE, "a clearance in metres (a number >= 0)")
    planner = body.get("planner")
    if planner not in (None, "paper", "graph"):
        raise InvalidInputError(f"planner is {planner!r}, expected 'paper' or 'graph'")
    objective = body.get("objective") or "fastest"
    if objective not in OBJECTIVES:
        raise InvalidInputError(f"objective is {objective!r}, expected one of {', '.join(OBJECTIVES)}")
    eps = _number(body, "neighbourhood", DEFAULT_NEIGHBOURHOOD, "a fraction of half the loop (a number)")
    samples = body.get("samples", 400)
    if isinstance(samples, bool) or not isinstance(samples, int) or samples < 2:
        raise InvalidInputError(f"samples is {samples!r}, expected an integer >= 2")
    assert clearance is not None and eps is not None
    track, start, goal, fps = with_footprint(body.get("footprint"), track, start, goal)
    return Query(track, start, goal, clearance, planner, objective, eps, samples, fps)


def with_footprint(spec: Any, track: Track | GraphTrack, start: Any, goal: Any) -> tuple[Any, Any, Any, Any]:
    """``(track, start, goal, footprints)`` of a request's ``footprint`` (``mpa plan --footprint SPEC``).

    Parameters
    ----------
    spec : str or None
        The command line's spec: ``R`` (disc radius, metres), ``LxW`` (rectangle, metres) or ``SPEC_A,SPEC_B``;
        None (or absent): no bodies, the arguments come back unchanged.
    track, start, goal
        The checked query (track coordinates on a paper track, ``(edge, offset)`` on a layout).

    Raises
    ------
    InvalidInputError
        A spec that is not a string or is malformed (the command line's message), a layout without coordinates.
    """
    if spec is None:
        return track, start, goal, None
    if not isinstance(spec, str):
        raise InvalidInputError(f"footprint is {spec!r}, expected a spec string such as '0.5' or '2.0x0.8'")
    return footprint_query(argparse.Namespace(footprint=spec), track, start, goal)


def plan_answer(body: Any) -> dict[str, Any]:
    """``POST /api/plan``: exactly the object ``mpa plan --json`` prints for the same query.

    Raises
    ------
    InvalidInputError, NoMotionError
        As ``mpa plan`` (exit 2, exit 3).
    """
    q = parse_query(body)
    p = plan_query(
        q.track, q.start, q.goal, q.clearance, q.planner, q.objective, q.neighbourhood, footprint=q.footprint
    )
    return plan_json(p, q.samples)


def trajectory_answer(body: Any) -> dict[str, Any]:
    """``POST /api/trajectory``: the files of ``mpa trajectory`` for the same query, in one object.

    Returns
    -------
    dict
        ``summary``: the object in ``summary.json``; ``csv``: the text of ``setpoints.csv``; with ``formats``
        asking for them, ``ros2_yaml`` (``trajectory.yaml``) and ``pvt`` (``pvt.csv``).

    Raises
    ------
    InvalidInputError, NoMotionError
        As ``mpa trajectory`` (exit 2, exit 3).
    """
    q = parse_query(body, trajectory=True)
    d = defaults
    vmax = _number(body, "vmax", d.VMAX, "a speed limit in m/s (a number > 0)")
    amax = _number(body, "amax", d.AMAX, "an acceleration limit in m/s^2 (a number > 0)")
    jmax = _number(body, "jmax", d.JMAX, "a jerk limit in m/s^3 (a number > 0)")
    rate = _number(body, "rate", d.RATE, "a setpoint rate in Hz (a number > 0)")
    assert vmax is not None and amax is not None and jmax is not None and rate is not None
    raw = body.get("formats", ["csv"])
    if isinstance(raw, list) and all(isinstance(x, str) for x in raw):
        raw = ",".join(raw)
    if not isinstance(raw, str):
        raise InvalidInputError(f"formats is {raw!r}, expected a list of {', '.join(_TEXT_FORMATS)}")
    formats = parse_formats(raw)
    for f in formats:
        if f not in _TEXT_FORMATS:
            raise InvalidInputError(
                f"formats has {f!r}, expected some of {', '.join(_TEXT_FORMATS)} (mcap: mpa trajectory)"
            )
    if "csv" not in formats:
        formats = ("csv", *formats)
    _, files = trajectory_files(
        q.track,
        q.start,
        q.goal,
        q.clearance,
        Limits(vmax, amax, jmax),
        rate,
        OutputOptions(formats=formats),
        planner=q.planner,
        objective=q.objective,
        footprint=q.footprint,
    )
    out: dict[str, Any] = {
        "summary": json.loads(content_text(files["summary.json"])),
        "csv": content_text(files[FORMAT_FILES["csv"]]),
    }
    for f, key in _FORMAT_KEYS.items():
        if f in formats:
            out[key] = content_text(files[FORMAT_FILES[f]])
    return out


def track_answer(body: Any, points_per_metre: float = 400.0) -> dict[str, Any]:
    """``POST /api/track``: the track of a request (``track``/``stick``/``loop`` or ``layout``) drawn to scale.

    Returns
    -------
    dict
        ``kind`` (``"interval"``, ``"circle"``, ``"lollipop"`` or ``"graph"``), ``track`` (the paper track's
        parameters or the layout), ``total_length`` (m), ``edges``: per edge ``name``, ``length`` (m), ``p0`` (the
        track coordinate of offset 0, paper tracks only) and ``points``: shape (n, 3) rows ``[offset, x, y]``
        (metres; the paper's drawing of the paper tracks, the layout's coordinates or an automatic drawing), and
        ``vertices``: ``{name: [x, y]}``.
    """
    track = parse_track(body)
    if isinstance(track, Track):
        graph = track.as_graph_track()
        names = graph.edge_names
        starts = {"stick": 0.0, "loop": float(getattr(track, "stick", 0.0)) if track.kind == "lollipop" else 0.0}
        edges = []
        for i, name in enumerate(names):
            length = float(graph.lengths[i])
            off = np.linspace(0.0, length, max(int(length * points_per_metre), 8) + 1)
            p = starts[name] + off
            if name == "loop":  # the last point is P again
                p[-1] = starts[name]
            xy = track.embed(p)
            rows = np.column_stack([off, xy]).round(6).tolist()
            edges.append({"name": name, "length": length, "p0": starts[name], "points": rows})
        vertices: dict[str, list[float]] = {}
        for v in graph.graph.vertices:
            e, o = graph.vertex_position(str(v))
            vertices[str(v)] = [round(float(x), 6) for x in track.embed(starts[names[e]] + o)]
        return {
            "kind": track.kind,
            "track": track.to_dict(),
            "total_length": track.total_length,
            "edges": edges,
            "vertices": vertices,
        }
    from trajopt.viz.layout import layout_geometry

    geo = layout_geometry(track)
    edges = []
    for i, name in enumerate(track.edge_names):
        length = float(track.lengths[i])
        off = np.linspace(0.0, length, max(int(length * points_per_metre), 8) + 1)
        xy = geo.embed(np.full(off.shape, i), off, track.lengths)
        edges.append({"name": name, "length": length, "points": np.column_stack([off, xy]).round(6).tolist()})
    vertices = {
        str(v): [round(float(x), 6) for x in geo.vertices[k]]
        for k, v in enumerate(track.graph.vertices)
        if np.all(np.isfinite(geo.vertices[k]))
    }
    return {
        "kind": "graph",
        "track": track.to_dict(),
        "total_length": track.total_length,
        "edges": edges,
        "vertices": vertices,
    }


def cspace_answer(body: Any) -> dict[str, Any]:
    """``POST /api/cspace``: the configuration space of a paper track with the domain of every start for the goal.

    The body is a plan request (its ``start`` is ignored but checked) with an optional ``cells`` (cells per axis,
    default :data:`CSPACE_CELLS`, at most :data:`MAX_CSPACE_CELLS`).

    Returns
    -------
    dict
        ``extent``: ``[0, L]`` (track coordinates of both axes, metres); ``cells``: n; ``domain``: shape (n, n),
        row i = robot B's cell, column j = robot A's cell (cell centres ``(k + 1/2) L / n``): 0 where the robots
        are closer than the clearance, else the domain of the query from that start to the goal (-1: no motion);
        ``skeleton``: polylines of states ``[a, b]`` (one per skeleton edge, with its name); ``goal``;
        ``no_motion``: the reason when some start has no motion to the goal, else None.

    Raises
    ------
    InvalidInputError
        A layout (the picture is for the paper's tracks), a bad goal, clearance or ``cells``.
    """
    from mpa.batch import plan_many
    from mpa.skeleton import SkeletonPoint, skeleton_of

    if not isinstance(body, dict):
        raise InvalidInputError(f"request body is a JSON {type(body).__name__}, expected a JSON object")
    cells = body.get("cells", CSPACE_CELLS)
    if isinstance(cells, bool) or not isinstance(cells, int) or not 8 <= cells <= MAX_CSPACE_CELLS:
        raise InvalidInputError(f"cells is {cells!r}, expected an integer in [8, {MAX_CSPACE_CELLS}]")
    q = parse_query({k: v for k, v in body.items() if k != "cells"})
    track = q.track
    if not isinstance(track, Track):
        raise InvalidInputError("layout given, expected one of the paper's tracks (the picture is of their C-space)")
    from mpa.planners import make_planner

    planner = make_planner(track, q.clearance, q.neighbourhood)
    goal = np.asarray(planner.cspace.validate_state(q.goal, "goal"), dtype=float).reshape(2)
    total = track.total_length
    c = (np.arange(cells) + 0.5) * total / cells
    a, b = np.meshgrid(c, c)  # row = B, column = A
    free = track.distance(a, b) >= q.clearance
    dom = np.zeros((cells, cells), dtype=np.int64)
    starts = np.column_stack([a[free], b[free]])
    reason = None
    if track.kind == "interval":
        same = (starts[:, 0] < starts[:, 1]) == (goal[0] < goal[1])
        dom[free] = np.where(same, 1, -1)
        if not same.all():
            reason = "the robots cannot change order on an interval"
    else:
        try:
            batch = plan_many(track, starts, np.tile(goal, (len(starts), 1)), q.clearance, q.neighbourhood)
            dom[free] = batch.domain
        except NoMotionError as exc:
            dom[free] = -1
            reason = str(exc)
    skeleton = []
    if track.kind != "interval":
        sk: Any = skeleton_of(track)  # circle or lollipop skeleton: both have state()
        for e in sk.graph.edges:
            ts = np.linspace(0.0, e.length, 81)
            pts = np.array([sk.state(SkeletonPoint(e.name, float(t))) for t in ts]).round(6)
            skeleton.append({"edge": e.name, "points": pts.tolist()})
    return {
        "extent": [0.0, total],
        "cells": cells,
        "domain": dom.tolist(),
        "skeleton": skeleton,
        "goal": goal.tolist(),
        "clearance": q.clearance,
        "no_motion": reason,
    }


def example_layouts(directory: Path = EXAMPLES_DIR) -> dict[str, Any]:
    """The example layouts by name (file stem), decoded; empty when the folder is absent."""
    out: dict[str, Any] = {}
    if directory.is_dir():
        for path in sorted(directory.glob("*.json")):
            try:
                out[path.stem] = json.loads(path.read_text(encoding="utf-8"))
            except (OSError, ValueError):
                continue
    return out


def answer(fn: Callable[[Any], dict[str, Any]], body: Any) -> tuple[int, dict[str, Any]]:
    """Run an API function and map its outcome to an HTTP status and a JSON object.

    ======  =========================================================================================
    status  meaning
    ======  =========================================================================================
    200     the answer
    400     ``{"error": message}``: :class:`InvalidInputError` (the command line's ``error:``, exit 2)
    422     ``{"no_motion": reason}``: :class:`NoMotionError` (``no motion:``, exit 3)
    500     ``{"error": "internal error: ..."}``: :class:`PlanningError` or a bug (one line, no traceback)
    ======  =========================================================================================
    """
    try:
        return 200, fn(body)
    except NoMotionError as exc:
        return 422, {"no_motion": _one_line(exc)}
    except PlanningError as exc:
        return 500, {"error": "internal error: " + _one_line(exc)}
    except MPAError as exc:
        return 400, {"error": _one_line(exc)}
    except Exception as exc:  # a bug: one line, never a traceback
        return 500, {"error": f"internal error: {type(exc).__name__}: {_one_line(exc)}"}


def _one_line(exc: BaseException) -> str:
    return " ".join(str(exc).split()) or type(exc).__name__
