"""Options shared by the subcommands that take a query on a track (the query, clearance, limits, rate)."""

from __future__ import annotations

import argparse
import errno
import os
import tempfile
from pathlib import Path
from typing import Any

from mpa import defaults
from mpa.errors import InvalidInputError
from mpa.graph_track import GraphTrack
from mpa.tracks import Track, make_track

__all__ = [
    "TRAJECTORY_DEFAULTS",
    "add_query_arguments",
    "add_trajectory_arguments",
    "check_output_dir",
    "output_error",
    "parse_coordinates",
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
    p.add_argument("--vmax", type=float, default=d["vmax"], help=f"speed limit per robot, m/s (default {d['vmax']:g})")
    p.add_argument("--amax", type=float, default=d["amax"], help=f"acceleration limit, m/s^2 (default {d['amax']:g})")
    p.add_argument("--jmax", type=float, default=d["jmax"], help=f"jerk limit, m/s^3 (default {d['jmax']:g})")
    p.add_argument("--rate", type=float, default=d["rate"], help=f"setpoint rate in Hz (default {d['rate']:g})")


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


def check_output_dir(out: str, option: str = "--out") -> Path:
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
