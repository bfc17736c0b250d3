"""Options shared by the subcommands that take a query on a track (the query, clearance, limits, rate)."""

from __future__ import annotations

import argparse

from mpa.tracks import make_track

__all__ = ["TRAJECTORY_DEFAULTS", "add_query_arguments", "add_trajectory_arguments", "track_from_args"]


def add_query_arguments(p: argparse.ArgumentParser) -> None:
    """Options shared by every subcommand that takes a query on a track."""
    p.add_argument("--track", required=True, choices=["interval", "circle", "lollipop"], help="track shape")
    p.add_argument("--stick", type=float, default=None, help="stick length ℓ in metres (interval, lollipop; default 1)")
    p.add_argument(
        "--loop", type=float, default=None, help="loop circumference c in metres (circle, lollipop; default 1)"
    )
    p.add_argument("--start", type=float, nargs=2, required=True, metavar=("A", "B"), help="start track coordinates")
    p.add_argument("--goal", type=float, nargs=2, required=True, metavar=("A", "B"), help="goal track coordinates")


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
