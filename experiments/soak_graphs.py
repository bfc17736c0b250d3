"""Soak on graph layouts: seeded random queries on every ``examples/tracks/*.json`` layout, every output checked twice.

Each query draws a layout, two positions per robot (on an edge, or on a vertex in 10 % of the draws), a clearance
(0, up to 0.3 or 0.3–1.2 times the layout's median edge), per-robot speed limits in 30 % of the queries, a = 0.2–5
m/s², j = 1–50 m/s³ and a rate (5 to 250 Hz), and runs :class:`trajopt.TrajectoryGenerator` on it. Every output
must pass the gate (``verification["ok"]``) and the independent checker
:func:`trajopt.testing.check_graph_trajectory` (its own Dijkstra distance at every row and on a denser grid,
limits, endpoints at rest, consistency of s with v and a, edges switched only at shared vertices). Outcomes:
``ok``, ``fallback``, ``invalid input`` (robots closer than D at start or goal, a rate too low for the motion),
``no motion``; ``planning error``, ``crash`` and ``checker failure`` are bugs.

Usage::

    python experiments/soak_graphs.py [--queries N | --seconds S] [--seed 0]

Prints one table row (markdown) and the first failing queries; exits 1 if there is a bug.
"""

from __future__ import annotations

import argparse
import sys
import time
import traceback
from collections import Counter
from pathlib import Path
from typing import Any

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))

from mpa import GraphTrack  # noqa: E402
from mpa.errors import InvalidInputError, NoMotionError, PlanningError  # noqa: E402
from trajopt import Limits, TrajectoryGenerator  # noqa: E402
from trajopt.testing import check_graph_trajectory  # noqa: E402

BUGS = ("planning error", "crash", "checker failure")


def layouts() -> dict[str, GraphTrack]:
    """The example layouts by name."""
    return {p.stem: GraphTrack.from_json(p) for p in sorted((ROOT / "examples" / "tracks").glob("*.json"))}


def draw_query(rng: np.random.Generator, tracks: dict[str, GraphTrack]) -> dict[str, Any]:
    """One random query (plain data)."""
    name = list(tracks)[int(rng.integers(len(tracks)))]
    tr = tracks[name]
    lengths = tr.lengths

    def pos() -> tuple[str, float]:
        e = int(rng.integers(len(lengths)))
        off = float(rng.uniform(0, lengths[e])) if rng.random() > 0.1 else float(rng.choice([0.0, lengths[e]]))
        return (tr.edge_names[e], off)

    med = float(np.median(lengths))
    clearance = float(rng.choice([0.0, rng.uniform(0, 0.3) * med, rng.uniform(0.3, 1.2) * med]))
    v = rng.uniform(0.1, 2.0, 2).tolist() if rng.random() < 0.3 else [float(rng.uniform(0.1, 2.0))] * 2
    return {
        "layout": name,
        "start": (pos(), pos()),
        "goal": (pos(), pos()),
        "clearance": clearance,
        "vmax": v,
        "amax": float(rng.uniform(0.2, 5.0)),
        "jmax": float(rng.uniform(1.0, 50.0)),
        "rate": float(rng.choice([5, 10, 20, 50, 100, 100, 100, 250])),
    }


def run_query(q: dict[str, Any], tracks: dict[str, GraphTrack]) -> tuple[str, str]:
    """The outcome of one query and, for a bug, what went wrong."""
    try:
        gen = TrajectoryGenerator(
            tracks[q["layout"]],
            clearance=q["clearance"],
            limits=Limits(q["vmax"], q["amax"], q["jmax"]),
            rate=q["rate"],
        )
        traj = gen.generate(q["start"], q["goal"])
    except InvalidInputError:
        return "invalid input", ""
    except NoMotionError:
        return "no motion", ""
    except PlanningError as exc:
        return "planning error", str(exc)
    except Exception:  # a bug: recorded with its traceback
        return "crash", traceback.format_exc(limit=3)
    fails = check_graph_trajectory(traj)
    if fails or not traj.verification["ok"]:
        return "checker failure", "; ".join(fails) or "gate report not ok"
    return ("fallback" if traj.fallback else "ok"), ""


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--queries", type=int, default=0, help="number of queries (0: run for --seconds)")
    ap.add_argument("--seconds", type=float, default=60.0)
    ap.add_argument("--seed", type=int, default=0)
    args = ap.parse_args(argv)
    tracks = layouts()
    rng = np.random.default_rng(args.seed)
    counts: Counter[str] = Counter()
    bugs: list[tuple[int, dict[str, Any], str]] = []
    times: list[float] = []
    t_end = time.perf_counter() + args.seconds
    i = 0
    while (args.queries and i < args.queries) or (not args.queries and time.perf_counter() < t_end):
        q = draw_query(rng, tracks)
        t0 = time.perf_counter()
        outcome, why = run_query(q, tracks)
        times.append(time.perf_counter() - t0)
        counts[outcome] += 1
        if outcome in BUGS:
            bugs.append((i, q, why))
        i += 1
    print(
        "| queries | ok | fallbacks | invalid input | no motion | planning errors | crashes | checker failures "
        "| p50 | p95 |"
    )
    print("|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|")
    p50, p95 = (float(np.percentile(times, p)) * 1e3 if times else float("nan") for p in (50, 95))
    print(
        f"| {i} | {counts['ok']} | {counts['fallback']} | {counts['invalid input']} | {counts['no motion']} | "
        f"{counts['planning error']} | {counts['crash']} | {counts['checker failure']} | {p50:.1f} ms | {p95:.1f} ms |"
    )
    for k, q, why in bugs[:10]:
        print(f"query {k}: {q}\n  {why}")
    return 1 if bugs else 0


if __name__ == "__main__":
    raise SystemExit(main())
