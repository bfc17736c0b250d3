"""Standard tracks, tolerances and query generators shared by the tests."""

from __future__ import annotations

import numpy as np

from mpa import Circle, Interval, Lollipop, MPAError, Plan, Track, make_planner

#: Tolerances, named once.
EXACT = 1e-9  # floating-point identities (metres)
CONTINUITY_DELTA = 1e-6  # perturbation of start/goal in continuity tests (metres)
#: Lipschitz constant of each rule on its domain for states at least MIN_GAP apart (measured worst ~18).
LIPSCHITZ_K = 60.0
MIN_GAP = 0.05

LOLLIPOPS = [
    Lollipop(1.0, 1.0),  # the paper's
    Lollipop(2.0, 1.3),  # long stick
    Lollipop(0.5, 1.0),  # stick = loop/2: I1 and I2 are single points
    Lollipop(0.3, 1.0),  # stick < loop/2: planner conjugated through the model lollipop
    Lollipop(3.0, 5.0),  # big loop (stick < h)
]
CIRCLES = [Circle(1.0), Circle(1.7), Circle(6.0)]
INTERVALS = [Interval(1.0), Interval(2.5)]
ALL_TRACKS: list[Track] = [*LOLLIPOPS, *CIRCLES, *INTERVALS]


def random_states(track: Track, n: int, rng: np.random.Generator, min_gap: float = 1e-6) -> np.ndarray:
    """``n`` uniformly random states with the robots at least ``min_gap`` apart. Shape (n, 2)."""
    out = np.empty((0, 2))
    L = track.total_length
    hi = L if isinstance(track, Interval) else np.nextafter(L, 0)
    while len(out) < n:
        cand = rng.uniform(0.0, hi, size=(2 * n, 2))
        cand = cand[track.distance(cand[:, 0], cand[:, 1]) >= min_gap]
        out = np.vstack([out, cand])
    return out[:n]


def same_order_goals(track: Track, starts: np.ndarray, goals: np.ndarray) -> np.ndarray:
    """On an interval, flip goals so that every query keeps the robots' order (the only solvable case)."""
    if not isinstance(track, Interval):
        return goals
    flip = np.sign(starts[:, 1] - starts[:, 0]) != np.sign(goals[:, 1] - goals[:, 0])
    g = goals.copy()
    g[flip] = g[flip][:, ::-1]
    return g


def path_gap(track: Track, p, q, n: int = 801) -> float:  # type: ignore[no-untyped-def]
    """Sup over u of the larger robot's graph distance between the paths of plans ``p`` and ``q`` (metres)."""
    u = np.linspace(0.0, 1.0, n)
    a, b = p.path(u), q.path(u)
    return float(max(track.distance(a[:, 0], b[:, 0]).max(), track.distance(a[:, 1], b[:, 1]).max()))


def random_plans(track: Track, clearance: float, n: int, seed: int) -> list[Plan]:
    """``n`` plans of seeded uniformly random queries on ``track`` (queries the planner refuses are skipped)."""
    rng = np.random.default_rng(seed)
    planner = make_planner(track, clearance)
    out: list[Plan] = []
    while len(out) < n:
        s, g = rng.uniform(0, track.total_length, 2), rng.uniform(0, track.total_length, 2)
        try:
            out.append(planner.plan(s, g))
        except MPAError:  # invalid random queries (closer than the clearance, no motion) are skipped
            continue
    return out
