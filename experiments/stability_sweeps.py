"""Stability sweeps: the fast/hard switch on the paper tracks and δ-twins on every example layout (headless).

(a) Switch (:func:`trajopt.analysis.stability.switch_points`): per track and clearance, ``--draws`` seeded draws of a
start and
    two nearby goals; where the straight route-coordinate line stops keeping the separation between them (same
    domain and word), bisection to a bracket of 1e-9 m and the gap of the trajectories on both sides (sup over
    normalised time of the robots' graph distance, and the motion-time change). Tracks: circle 1; lollipops 1/1,
    1.3/0.9, 0.4/1.7; clearances 0.05 and 0.15.
(b) Layout twins (:func:`trajopt.analysis.stability.layout_twins`): per example layout ``--queries`` seeded queries
(clearances
    0.05, 0.2, 0.5, 1 × the median edge length; every fourth a swap) and their twins with every position moved by
    δ = 1e-3, 1e-5, 1e-7 along its edge; counts, for random queries and for swap queries apart (a swap with equal
    speeds lies on a tie of the objective: its mirror motion is as fast), the twins whose routes change and, among
    the others, the plans that move by more than max(1e-3 m, 10 δ) (plan level, the graph planner's ``fastest``
    plans, speeds 1 m/s).

Usage::

    python experiments/stability_sweeps.py [--draws 2000] [--queries 100] [--parts switch,layouts] [--md out.md]
"""

from __future__ import annotations

import argparse
import sys
import time
from collections.abc import Sequence
from pathlib import Path

import numpy as np

from mpa.graph_track import GraphTrack
from mpa.tracks import Circle, Lollipop, Track
from trajopt import TrajectoryGenerator
from trajopt.analysis.stability import layout_queries, layout_twins, switch_points

ROOT = Path(__file__).resolve().parents[1]
TRACKS: tuple[Track, ...] = (Circle(1.0), Lollipop(1.0, 1.0), Lollipop(1.3, 0.9), Lollipop(0.4, 1.7))
CLEARANCES = (0.05, 0.15)
LAYOUTS = ("y_junction", "passing_loop", "two_sidings", "theta", "figure_eight", "warehouse", "lollipop", "circle")
DELTAS = (1e-3, 1e-5, 1e-7)
#: Goals of the issue: switch gap (m) and motion-time change (s); share of 1e-7 twins changing routes; same-route jump.
GAP_GOAL, TIME_GOAL, ROUTE_GOAL, JUMP_GOAL = 1e-4, 1e-3, 0.01, 1e-3


def switch_table(draws: int, seed: int) -> list[str]:
    """Markdown rows of the switch sweep (one per track and clearance)."""
    rows = [
        "| track | D | draws | switch points | gap > 1e-4 m | gap > 1 cm | largest gap (m) | Δt > 1e-3 s "
        "| largest Δt (s) |",
        "|---|---|---|---|---|---|---|---|---|",
    ]
    for track in TRACKS:
        for D in CLEARANCES:
            gen = TrajectoryGenerator(track, clearance=D)
            sp = switch_points(gen, draws, np.random.default_rng(seed))
            gaps = np.array([x.gap for x in sp])
            dts = np.array([x.time_gap for x in sp])
            big = float(gaps.max()) if len(sp) else 0.0
            bigt = float(dts.max()) if len(sp) else 0.0
            rows.append(
                f"| {track!r} | {D:g} | {draws} | {len(sp)} | {int(np.sum(gaps > GAP_GOAL))} | "
                f"{int(np.sum(gaps > 1e-2))} | {big:.3g} | {int(np.sum(dts > TIME_GOAL))} | {bigt:.3g} |"
            )
            print(rows[-1], file=sys.stderr, flush=True)
    return rows


def layout_table(queries: int, seed: int) -> list[str]:
    """Markdown rows of the layout twins (one per layout and δ): random queries and swap queries apart."""
    rows = [
        "| layout | δ (m) | random: twins | routes changed | same route, moved > max(1e-3 m, 10 δ) | largest "
        "same-route move (m) | swaps: twins | routes changed | same route, moved > max(1e-3 m, 10 δ) | largest "
        "same-route move (m) |",
        "|---|---|---|---|---|---|---|---|---|---|",
    ]
    for name in LAYOUTS:
        track = GraphTrack.from_json(ROOT / "examples" / "tracks" / f"{name}.json")
        med = float(np.median(track.lengths))
        Ds = tuple(round(f * med, 6) for f in (0.05, 0.2, 0.5, 1.0))
        qs = layout_queries(track, queries, np.random.default_rng(seed), Ds)
        twins = layout_twins(track, qs, DELTAS, np.random.default_rng(seed + 1))
        for d in DELTAS:
            cols = []
            for swap in (False, True):
                r = [x for x in twins if x.delta == d and x.swap == swap]
                changed = sum(x.route_changed for x in r)
                same = [x.gap for x in r if not x.route_changed]
                cols.append(
                    f"{len(r)} | {changed} ({100.0 * changed / max(len(r), 1):.1f} %) | "
                    f"{sum(g > max(JUMP_GOAL, 10.0 * d) for g in same)} | {max(same, default=0.0):.3g}"
                )
            rows.append(f"| {name} | {d:g} | {cols[0]} | {cols[1]} |")
            print(rows[-1], file=sys.stderr, flush=True)
    return rows


def main(argv: Sequence[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=(__doc__ or "").splitlines()[0])
    ap.add_argument("--draws", type=int, default=2000, help="switch sweep: draws per track and clearance")
    ap.add_argument("--queries", type=int, default=100, help="layout twins: queries per layout")
    ap.add_argument("--seed", type=int, default=21)
    ap.add_argument("--parts", default="switch,layouts", help="comma list from switch,layouts")
    ap.add_argument("--md", type=Path, default=None, help="write the tables to this markdown file")
    args = ap.parse_args(argv)
    parts = set(args.parts.split(","))
    t0 = time.perf_counter()
    md: list[str] = []
    if "switch" in parts:
        md += ["## Fast/hard switch (paper tracks)", "", *switch_table(args.draws, args.seed), ""]
    if "layouts" in parts:
        md += ["## δ-twins on the example layouts (plan level)", "", *layout_table(args.queries, args.seed), ""]
    md.append(
        f"Command: `python experiments/stability_sweeps.py {' '.join(sys.argv[1:])}`; wall "
        f"{time.perf_counter() - t0:.0f} s."
    )
    text = "\n".join(md) + "\n"
    if args.md:
        args.md.write_text(text)
    print(text)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
