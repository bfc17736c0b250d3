"""Options shared by the subcommands that take a query on a track (the query, clearance, limits, rate)."""

from __future__ import annotations

import argparse
from typing import Any

from mpa.errors import InvalidInputError
from mpa.graph_track import GraphTrack
from mpa.tracks import Track, make_track

__all__ = [
    "TRAJECTORY_DEFAULTS",
    "add_query_arguments",
    "add_trajectory_arguments",
    "query_from_args",
    "track_from_args",
]


def add_query_arguments(p: argparse.ArgumentParser, graph: bool = False) -> None:
    """Options shared by every subcommand that takes a query on a track (with ``graph``: also ``--graph FILE``)."""
    p.add_argument(
        "--track", required=not graph, choices=["interval", "circle", "lollipop"], help="one of the paper's tracks"
    )
    if graph:
        p.add_argument("--graph", metavar="FILE", default=None, help="a track layout (JSON) instead of --track")
    p.add_argument("--stick", type=float, default=None, help="stick length ℓ in metres (interval, lollipop; default 1)")
    p.add_argument(
        "--loop", type=float, default=None, help="loop circumference c in metres (circle, lollipop; default 1)"
    )
    what = (
        "track coordinates (--track) or positions EDGE:OFFSET / vertex names (--graph)"
        if graph
        else "track coordinates"
    )
    p.add_argument("--start", nargs=2, required=True, metavar=("A", "B"), help=f"start: {what}")
    p.add_argument("--goal", nargs=2, required=True, metavar=("A", "B"), help=f"goal: {what}")


def _coordinates(values: list[str], option: str) -> tuple[float, float]:
    out = []
    for v in values:
        try:
            out.append(float(v))
        except ValueError:
            raise InvalidInputError(f"{option} has {v!r}, expected a track coordinate (a number, metres)") from None
    return out[0], out[1]


def query_from_args(args: argparse.Namespace) -> tuple[Track | GraphTrack, Any, Any]:
    """The track and the query ``(start, goal)`` of ``--track``/``--graph``, ``--start`` and ``--goal``.

    Paper tracks take track coordinates (floats); a ``--graph`` layout takes positions ``EDGE:OFFSET`` or vertex
    names (robot A first).
    """
    graph = getattr(args, "graph", None)
    if graph is not None and args.track is not None:
        raise InvalidInputError(f"both --track {args.track} and --graph {graph} given, expected one of them")
    if graph is None and args.track is None:
        raise InvalidInputError("no track given, expected --track {interval,circle,lollipop} or --graph FILE")
    if graph is not None:
        track = GraphTrack.from_json(graph)
        start = tuple(track.position(v, f"--start of robot {r}") for v, r in zip(args.start, "AB"))
        goal = tuple(track.position(v, f"--goal of robot {r}") for v, r in zip(args.goal, "AB"))
        return track, start, goal
    return track_from_args(args), _coordinates(args.start, "--start"), _coordinates(args.goal, "--goal")


#: Defaults of the trajectory options (pinned by the trajectory issue).
TRAJECTORY_DEFAULTS = {"clearance": 0.05, "vmax": 0.5, "amax": 1.0, "jmax": 5.0, "rate": 100.0}


def add_trajectory_arguments(p: argparse.ArgumentParser) -> None:
    """The query plus clearance and per-robot limits (``mpa trajectory`` and ``mpa animate``)."""
    add_query_arguments(p)
    d = TRAJECTORY_DEFAULTS
    p.add_argument("--clearance", type=float, default=d["clearance"], help="clearance D, m (default 0.05)")
    p.add_argument("--vmax", type=float, default=d["vmax"], help="speed limit per robot, m/s (default 0.5)")
    p.add_argument("--amax", type=float, default=d["amax"], help="acceleration limit, m/s^2 (default 1.0)")
    p.add_argument("--jmax", type=float, default=d["jmax"], help="jerk limit, m/s^3 (default 5.0)")
    p.add_argument("--rate", type=float, default=d["rate"], help="setpoint rate in Hz (default 100)")


def track_from_args(args: argparse.Namespace):  # type: ignore[no-untyped-def]
    """The track named by ``--track/--stick/--loop``."""
    return make_track(args.track, args.stick, args.loop)
