"""Measurements behind the departures from the paper listed in docs/paper.md (seeded, headless, numpy only).

1. Short stick (ℓ < h): along the traces of the retraction H the graph distance is monotone, but a whole plan may come
   closer than ``min(d_start, d_goal, h)`` (the bound for ℓ ≥ h); it never comes closer than
   ``min(d_start, d_goal, ℓ, h)``.
2. The neighbourhood ε = neighbourhood · h: the share of queries in each domain and the mean length of the plans
   (travel of the robot that travels more) for several values, on the paper's lollipop.

Usage::

    python experiments/paper_checks.py                  # 20 000 queries per case (about 40 s)
    python experiments/paper_checks.py --queries 200    # a quick run
"""

from __future__ import annotations

import argparse
import sys
from collections.abc import Sequence

import numpy as np

from mpa import Lollipop, make_planner, retract

__all__ = ["main", "neighbourhood_trade_off", "short_stick_floor"]

#: Tolerance of the distance comparisons (metres).
TOL = 1e-9


def _random_queries(track: Lollipop, n: int, rng: np.random.Generator) -> tuple[np.ndarray, np.ndarray]:
    """``n`` seeded start and goal states with the robots more than 1e-6 apart. Shapes (n, 2) and (n, 2)."""
    hi = np.nextafter(track.total_length, 0)
    out = []
    for _ in range(2):
        x = np.empty((0, 2))
        while len(x) < n:
            cand = rng.uniform(0.0, hi, size=(2 * n, 2))
            x = np.vstack([x, cand[track.distance(cand[:, 0], cand[:, 1]) > 1e-6]])
        out.append(x[:n])
    return out[0], out[1]


def short_stick_floor(track: Lollipop, n: int, seed: int = 0, samples: int = 400) -> dict[str, int]:
    """Count, over ``n`` seeded queries, the traces of H with a non-monotone distance and the plans that dip below
    ``min(d_s, d_g, h)`` and below ``min(d_s, d_g, ℓ, h)``.

    Returns
    -------
    dict
        ``queries``, ``non_monotone_traces`` (of the 2n start and goal states, 41 samples per trace),
        ``below_h`` and ``below_ell`` (plans, ``samples`` points each).
    """
    rng = np.random.default_rng(seed)
    starts, goals = _random_queries(track, n, rng)
    states = np.vstack([starts, goals])
    ts = np.linspace(0.0, 1.0, 41)
    d = np.array([track.distance(*retract(track, states, t).T) for t in ts])
    steps = np.diff(d, axis=0)
    monotone = np.all(steps >= -TOL, axis=0) | np.all(steps <= TOL, axis=0)
    planner = make_planner(track)
    below_h = below_ell = 0
    for s, g in zip(starts, goals):
        x = planner.plan(s, g).sample(samples)
        dmin = float(np.min(track.distance(x[:, 0], x[:, 1])))
        ends = min(float(track.distance(*s)), float(track.distance(*g)))
        below_h += dmin < min(ends, track.half) - TOL
        below_ell += dmin < min(ends, track.stick, track.half) - TOL
    return {
        "queries": n,
        "non_monotone_traces": int(np.sum(~monotone)),
        "below_h": int(below_h),
        "below_ell": int(below_ell),
    }


def neighbourhood_trade_off(
    track: Lollipop, n: int, neighbourhoods: Sequence[float], seed: int = 0
) -> list[dict[str, float]]:
    """Share of queries per domain and mean plan length for each neighbourhood (fraction of h), same queries."""
    rng = np.random.default_rng(seed)
    starts, goals = _random_queries(track, n, rng)
    rows = []
    for nb in neighbourhoods:
        planner = make_planner(track, 0.0, nb)
        doms, lengths = [], []
        for s, g in zip(starts, goals):
            p = planner.plan(s, g)
            doms.append(p.domain)
            lengths.append(p.length)
        dom = np.array(doms)
        rows.append(
            {
                "neighbourhood": float(nb),
                "domain1": float(np.mean(dom == 1)),
                "domain2": float(np.mean(dom == 2)),
                "domain3": float(np.mean(dom == 3)),
                "mean_length": float(np.mean(lengths)),
            }
        )
    return rows


def main(argv: Sequence[str] | None = None) -> int:
    """Command-line entry point; returns the exit status."""
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--queries", type=int, default=20_000, help="queries per case (default 20 000)")
    ap.add_argument("--seed", type=int, default=0)
    args = ap.parse_args(argv)
    if args.queries < 1:
        print(f"error: queries is {args.queries}, expected a positive integer", file=sys.stderr)
        return 2
    print("short stick: traces of H and the distance floor of plans")
    print(
        "| ℓ / c | queries | non-monotone traces (2 per query) | below min(d_s, d_g, h) | below min(d_s, d_g, ℓ, h) |"
    )
    print("|---|---|---|---|---|")
    for track in (Lollipop(0.3, 1.0), Lollipop(0.2, 1.0), Lollipop(0.45, 1.0), Lollipop(1.0, 1.0)):
        r = short_stick_floor(track, args.queries, args.seed)
        print(
            f"| {track.stick:g} / {track.loop:g} | {r['queries']} | {r['non_monotone_traces']} | {r['below_h']} "
            f"| {r['below_ell']} |"
        )
    print()
    print("neighbourhood ε = k·h on the lollipop ℓ = c = 1: share of queries per domain, mean plan length (m)")
    print("| k | domain 1 | domain 2 | domain 3 | mean length |")
    print("|---|---|---|---|---|")
    for r in neighbourhood_trade_off(Lollipop(1.0, 1.0), args.queries, (0.02, 0.05, 0.1, 0.2, 0.4), args.seed):
        print(
            f"| {r['neighbourhood']:g} | {r['domain1']:.1%} | {r['domain2']:.1%} | {r['domain3']:.1%} "
            f"| {r['mean_length']:.3f} |"
        )
    return 0


if __name__ == "__main__":
    sys.exit(main())
