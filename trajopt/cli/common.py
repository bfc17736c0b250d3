"""Options shared by the subcommands that take a query on a track (the query, clearance, limits, rate)."""

from __future__ import annotations

import argparse
import errno
import os
import tempfile
from pathlib import Path
from typing import Any

from mpa import defaults
from mpa._deprecation import deprecated_alias
from mpa.errors import InvalidInputError
from mpa.graph_track import GraphTrack
from mpa.tracks import Track, make_track

__all__ = [
    "TRAJECTORY_DEFAULTS",
    "add_fleet_arguments",
    "add_footprint_argument",
    "add_map_arguments",
    "add_query_arguments",
    "add_trajectory_arguments",
    "apply_fleet",
    "footprint_query",
    "graph_from_args",
    "output_error",
    "parse_coordinates",
    "query_from_args",
    "track_from_args",
    "validate_output_dir",
]


def add_query_arguments(p: argparse.ArgumentParser, graph: bool = False) -> None:
    """Options shared by every subcommand that takes a query on a track (with ``graph``: also ``--graph FILE``)."""
    p.add_argument(
        "--track", required=not graph, choices=["interval", "circle", "lollipop"], help="one of the paper's tracks"
    )
    if graph:
        p.add_argument(
            "--graph",
            metavar="FILE",
            default=None,
            help="a track layout instead of --track: our JSON, an Open-RMF building map or navigation graph",
        )
        add_map_arguments(p)
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


def add_map_arguments(p: argparse.ArgumentParser) -> None:
    """``--level NAME`` and ``--nav-graph IDX``: which part of an Open-RMF map ``--graph`` reads."""
    p.add_argument(
        "--level", default=None, metavar="NAME", help="Open-RMF maps: the level (default: the reference level)"
    )
    p.add_argument(
        "--nav-graph",
        type=int,
        default=None,
        metavar="IDX",
        help="Open-RMF building maps: the navigation graph, the lanes' graph_idx (default 0)",
    )


def graph_from_args(args: argparse.Namespace) -> GraphTrack:
    """The layout of ``--graph FILE`` (with ``--level`` and ``--nav-graph`` for Open-RMF maps)."""
    return GraphTrack.from_file(
        args.graph, level=getattr(args, "level", None), nav_graph=getattr(args, "nav_graph", None)
    )


def parse_coordinates(values: list[str], option: str) -> tuple[float, float]:
    """Two track coordinates (metres) given to ``option`` (InvalidInputError naming the option otherwise)."""
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
    apply_fleet(args)
    graph = getattr(args, "graph", None)
    if graph is None and (getattr(args, "level", None) is not None or getattr(args, "nav_graph", None) is not None):
        raise InvalidInputError("--level and --nav-graph choose part of an Open-RMF map, expected them with --graph")
    if graph is not None and args.track is not None:
        raise InvalidInputError(f"both --track {args.track} and --graph {graph} given, expected one of them")
    if graph is None and args.track is None:
        raise InvalidInputError("no track given, expected --track {interval,circle,lollipop} or --graph FILE")
    if graph is not None:
        track = graph_from_args(args)
        start = tuple(track.position(v, f"--start of robot {r}") for v, r in zip(args.start, "AB"))
        goal = tuple(track.position(v, f"--goal of robot {r}") for v, r in zip(args.goal, "AB"))
        return track, start, goal
    return track_from_args(args), parse_coordinates(args.start, "--start"), parse_coordinates(args.goal, "--goal")


#: Defaults of the query options of every subcommand (from :mod:`mpa.defaults`).
TRAJECTORY_DEFAULTS = {
    "clearance": defaults.CLEARANCE,
    "vmax": defaults.VMAX,
    "amax": defaults.AMAX,
    "jmax": defaults.JMAX,
    "rate": defaults.RATE,
}


def add_trajectory_arguments(p: argparse.ArgumentParser) -> None:
    """Query (``--track`` or ``--graph FILE``), clearance, per-robot limits (``mpa trajectory``, ``mpa animate``)."""
    add_query_arguments(p, graph=True)
    d = TRAJECTORY_DEFAULTS
    add_clearance_argument(p)
    p.add_argument(
        "--vmax",
        type=float,
        default=d["vmax"],
        action=_StoreGiven,
        help=f"speed limit per robot, m/s (default {d['vmax']:g}, or the --fleet file's)",
    )
    p.add_argument(
        "--amax",
        type=float,
        default=d["amax"],
        action=_StoreGiven,
        help=f"acceleration limit, m/s^2 (default {d['amax']:g}, or the --fleet file's)",
    )
    p.add_argument("--jmax", type=float, default=d["jmax"], help=f"jerk limit, m/s^3 (default {d['jmax']:g})")
    p.add_argument("--rate", type=float, default=d["rate"], help=f"setpoint rate in Hz (default {d['rate']:g})")
    add_fleet_arguments(p)


def trajectory_options(args: argparse.Namespace) -> dict[str, float]:
    """The motion options of :func:`add_trajectory_arguments` as keywords: ``clearance`` (m), ``vmax``, ``amax``,
    ``jmax`` (m/s, m/s², m/s³) and ``rate`` (Hz)."""
    return {k: args.__dict__[k] for k in ("clearance", "vmax", "amax", "jmax", "rate")}


class _StoreGiven(argparse.Action):
    """Store the value and remember that the option was given (``namespace.given_options``)."""

    def __call__(self, parser: Any, namespace: argparse.Namespace, values: Any, option_string: Any = None) -> None:
        setattr(namespace, self.dest, values)
        given: set[str] = set(getattr(namespace, "given_options", set()))
        given.add(self.dest)
        namespace.given_options = given


def add_fleet_arguments(p: argparse.ArgumentParser) -> None:
    """``--fleet FILE`` (an Open-RMF fleet configuration) and ``--fleet-radius footprint|vicinity|none``."""
    p.add_argument(
        "--fleet",
        default=None,
        metavar="FILE",
        help="an Open-RMF fleet configuration: rmf_fleet.limits.linear sets --vmax/--amax unless given, "
        "rmf_fleet.profile the robots' disc footprint",
    )
    p.add_argument(
        "--fleet-radius",
        choices=["footprint", "vicinity", "none"],
        default="footprint",
        help="which radius of the fleet's profile is the robots' disc (default footprint; none: the limits only)",
    )


def apply_fleet(args: argparse.Namespace) -> None:
    """Apply ``--fleet``: ``rmf_fleet.limits.linear`` to ``args.vmax``/``args.amax`` where not given on the command
    line, and the disc of ``--fleet-radius`` (``footprint`` or ``vicinity``) to ``args.footprint`` where
    ``--footprint`` is not given (an explicit option wins, as ``--vmax`` does).

    Raises
    ------
    InvalidInputError
        The fleet file is missing, unreadable or has no limits (or no radius of the kind asked for).
    """
    path = getattr(args, "fleet", None)
    if path is None:
        return
    from mpa.openrmf import read_fleet_file

    fleet = read_fleet_file(path)
    given: set[str] = getattr(args, "given_options", set())
    if "vmax" not in given:
        args.vmax = fleet.vmax
    if "amax" not in given:
        args.amax = fleet.amax
    which = getattr(args, "fleet_radius", "footprint")
    if which == "none" or getattr(args, "footprint", None) is not None:
        return
    args.footprint = repr(float(fleet.radius(which)))  # a disc spec, parsed with --footprint's rules


def add_clearance_argument(p: argparse.ArgumentParser) -> None:
    """``--clearance`` with the one default of every subcommand (:data:`mpa.defaults.CLEARANCE`)."""
    c = TRAJECTORY_DEFAULTS["clearance"]
    p.add_argument("--clearance", type=float, default=c, help=f"required clearance D in metres (default {c:g})")


def track_from_args(args: argparse.Namespace):  # type: ignore[no-untyped-def]
    """The track named by ``--track/--stick/--loop``."""
    return make_track(args.track, args.stick, args.loop)


def output_error(option: str, path: str | os.PathLike[str], exc: OSError) -> InvalidInputError:
    """The error of an output that cannot be written: ``--out: cannot write PATH: reason``."""
    reason = exc.strerror or type(exc).__name__
    return InvalidInputError(f"{option}: cannot write {str(path)!r}: {reason}")


def validate_output_dir(out: str, option: str = "--out") -> Path:
    """Check, before any work, that directory ``out`` can be created (if needed) and written into.

    Probes by creating the missing directories and a temporary file, then removes everything it created, so
    a failing command leaves nothing behind.

    Raises
    ------
    InvalidInputError
        ``out`` is empty, exists and is not a directory, or cannot be written (``--out: cannot write ...``).
    """
    if not isinstance(out, str) or not out.strip():
        raise InvalidInputError(f"{option} is {out!r}, expected a directory path")
    d = Path(out)
    try:
        exists, is_dir = d.exists(), d.is_dir()
    except OSError as exc:  # e.g. a name too long for the file system
        raise output_error(option, d, exc) from None
    if exists and not is_dir:
        raise InvalidInputError(f"{option} is {out!r}, which exists and is not a directory")
    created: list[Path] = []
    try:
        missing = [q for q in (d, *d.parents) if not q.exists()]
        for q in reversed(missing):
            q.mkdir()
            created.append(q)
        fd, tmp = tempfile.mkstemp(dir=d, prefix=".mpa-probe-")
        os.close(fd)
        os.unlink(tmp)
    except OSError as exc:
        if exc.errno == errno.EEXIST:  # raced with another process: fine if it is a directory now
            if d.is_dir():
                return d
        raise output_error(option, d, exc) from None
    finally:
        for q in reversed(created):
            try:
                q.rmdir()
            except OSError:
                pass
    return d


#: Deprecated name of :func:`validate_output_dir` (warns).
check_output_dir = deprecated_alias(validate_output_dir, "check_output_dir")


def add_footprint_argument(p: argparse.ArgumentParser) -> None:
    """``--footprint SPEC``: the robots' bodies in the plane (:func:`mpa.footprint.parse_footprint`)."""
    p.add_argument(
        "--footprint",
        default=None,
        metavar="SPEC",
        help="the robots' bodies in the plane: R (disc radius, m) or LxW (rectangle length x width along the "
        "track, m), one for both or SPEC_A,SPEC_B; needs a layout with vertex coordinates",
    )


def footprint_query(
    args: argparse.Namespace, track: Track | GraphTrack, start: Any, goal: Any
) -> tuple[Track | GraphTrack, Any, Any, Any]:
    """``(track, start, goal, footprints)`` with ``--footprint``: the spec parsed and checked against the drawing.

    A paper track (``--track``) is replaced by its graph form (:meth:`mpa.tracks.Track.as_graph_track`, which is
    drawn) and the query by positions on it. Without ``--footprint`` the arguments come back unchanged, footprints
    None.

    Raises
    ------
    InvalidInputError
        A malformed spec, a layout without vertex coordinates.
    """
    spec = getattr(args, "footprint", None)
    if spec is None:
        return track, start, goal, None
    from mpa.footprint import drawing_of, parse_footprint

    fps = parse_footprint(spec)
    if isinstance(track, Track):
        from mpa.planners.factory import _paper_positions

        start = _paper_positions(track, start, "--start")
        goal = _paper_positions(track, goal, "--goal")
        track = track.as_graph_track()
    drawing_of(track)
    return track, start, goal, fps
