"""Plain words per cart: the issue's example on synthetic rows, and the paper's canonical queries."""

from __future__ import annotations

import json

import numpy as np
import pytest

from mpa import Circle, Interval, Lollipop
from mpa.routes import Lift, Route
from trajopt import generate_trajectory
from trajopt.analysis.words import describe, describe_rows, describe_text

L = Lollipop(1.0, 1.0)
RATE = 100.0


def rows(*segments):  # type: ignore[no-untyped-def]
    """Route coordinates through ``(σ_target, seconds)`` segments (smooth steps; equal targets = a stop)."""
    s = [0.0]
    for target, dur in segments:
        n = round(dur * RATE)
        u = np.arange(1, n + 1) / n
        s.extend(s[-1] + (target - s[-1]) * (3 * u**2 - 2 * u**3))
    t = np.arange(len(s)) / RATE
    return t, np.array(s)


def test_the_issues_example() -> None:
    rb, sig = Route.through(L, [Lift("stick", 0, 0.5), Lift("line", 0, -0.06), Lift("stick", 0, 0.8)])
    ra, _ = Route.through(L, [Lift("stick", 0, 0.9)])
    t, sb = rows((sig[1], 1.5), (sig[1], 0.4), (sig[2], 1.5))
    words = describe_rows(L, [ra, rb], t, np.column_stack([np.zeros_like(sb), sb]))
    assert words == {
        "A": "stays at 0.10 m on the stick",
        "B": "up the stick to P, 0.06 m into the loop clockwise, waits 0.4 s, back down to 0.20 m",
    }


def test_short_stops_are_not_waits_and_waits_before_the_start_are() -> None:
    rb, sig = Route.through(L, [Lift("stick", 0, 0.5), Lift("stick", 0, 0.1)])
    ra, _ = Route.through(L, [Lift("stick", 0, 0.9), Lift("stick", 0, 0.95)])
    mid = 0.5 * sig[1]
    t, sb = rows((0.0, 0.3), (mid, 1.0), (mid, 0.02), (sig[1], 1.0))
    sa = np.zeros_like(sb)
    sa[-60:] = np.linspace(0.0, 0.05, 60)  # A leaves late and goes down 5 cm
    words = describe_rows(L, [ra, rb], t, np.column_stack([sa, sb]))
    assert words["B"] == "waits 0.3 s, up the stick to 0.90 m"
    assert words["A"].startswith("waits ") and words["A"].endswith("down the stick to 0.05 m")


@pytest.mark.parametrize(
    ("track", "start", "goal", "a", "b"),
    [
        (
            L,
            (0.2, 0.5),
            (0.5, 0.2),
            "up the stick to P, once round the loop counterclockwise, back down to 0.50 m",
            "up the stick to P, once round the loop counterclockwise, back down to 0.20 m",
        ),
        (L, (0.1, 0.6), (0.3, 0.8), "up the stick to 0.30 m", "up the stick to 0.80 m"),
        (
            L,
            (1.25, 1.75),
            (1.75, 1.25),
            "0.50 m counterclockwise along the loop to 1.75 m",
            "0.25 m counterclockwise round the loop to P, 0.25 m into the loop counterclockwise",
        ),
        (L, (0.8, 1.3), (0.7, 1.8), "down the stick to 0.70 m", "0.50 m counterclockwise along the loop to 1.80 m"),
        (Circle(1.0), (0.3, 0.6), (0.25, 0.1), "0.05 m clockwise to 0.25 m", "0.50 m counterclockwise to 0.10 m"),
        (Interval(1.0), (0.1, 0.5), (0.3, 0.9), "up the track to 0.30 m", "up the track to 0.90 m"),
    ],
)
def test_canonical_queries(track, start, goal, a, b) -> None:  # type: ignore[no-untyped-def]
    traj = generate_trajectory(track, start, goal)
    assert describe(traj) == {"A": a, "B": b}
    assert describe_text(traj) == f"A: {a}\nB: {b}"


def test_summary_has_words(tmp_path) -> None:  # type: ignore[no-untyped-def]
    traj = generate_trajectory(L, (0.1, 0.6), (0.3, 0.8))
    traj.to_json(tmp_path / "s.json")
    got = json.loads((tmp_path / "s.json").read_text())
    assert got["words"] == {"A": "up the stick to 0.30 m", "B": "up the stick to 0.80 m"}
