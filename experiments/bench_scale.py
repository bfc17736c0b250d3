"""The scaling table of the graph planner on seeded warehouse aisle grids and planar road maps.

    python experiments/bench_scale.py [--sizes 10,30,100,300,1000,3000] [--queries 20] [--clearance 1]
        [--budget S] [--above-plan] [--python] [--out FILE]

Prints (and with ``--out`` writes) the Markdown table of :func:`bench.graph_scale.scale_markdown`; with
``--above-plan`` instead the table of :func:`bench.graph_scale.trajectory_above_plan` (the verified trajectory's
time above its plan on ``--queries`` seeded queries that are not swaps, per layout; no plan of a swap, so it runs
at 1 000 edges in about a minute). Plans search with the compiled search (:func:`trajopt.plan_kernel.install`,
warmed before the clock starts; the same plans as mpa's own search); ``--python``: with mpa's own.
"""

from __future__ import annotations

import argparse
import json
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parent
sys.path.insert(0, str(ROOT))
sys.path.insert(0, str(ROOT.parent))

from bench.graph_scale import (  # noqa: E402
    KINDS,
    above_plan_markdown,
    run_scale,
    scale_markdown,
    trajectory_above_plan,
)

from trajopt import plan_kernel  # noqa: E402


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--sizes", default="10,30,100,300,1000,3000")
    ap.add_argument("--kinds", default=",".join(KINDS))
    ap.add_argument("--queries", type=int, default=20)
    ap.add_argument("--trajectories", type=int, default=5)
    ap.add_argument("--clearance", type=float, default=1.0)
    ap.add_argument("--seed", type=int, default=0)
    ap.add_argument(
        "--budget", type=float, default=None, help="stop a plan after this many seconds (wall) and count it as over"
    )
    ap.add_argument("--out", default=None, help="write the table (Markdown) and FILE.json with the records")
    ap.add_argument(
        "--above-plan", action="store_true", help="only the verified trajectory's time above its plan, per layout"
    )
    ap.add_argument("--python", action="store_true", help="plan with mpa's own search, not the compiled one")
    args = ap.parse_args()
    if not args.python and plan_kernel.install():
        plan_kernel.warm()
    if args.above_plan:
        recs = []
        for kind in [k.strip() for k in args.kinds.split(",")]:
            for n_e in [int(x) for x in args.sizes.split(",")]:
                track = KINDS[kind](n_e, args.seed * 100_003 + n_e)
                recs.append({"kind": kind, **trajectory_above_plan(track, args.clearance, args.queries, args.seed)})
                print(above_plan_markdown(recs[-1:]).splitlines()[2], file=sys.stderr, flush=True)
        text = above_plan_markdown(recs)
        print(text)
        if args.out:
            Path(args.out).write_text(text)
            Path(args.out).with_suffix(".json").write_text(json.dumps(recs, indent=1))
        return
    records = run_scale(
        [int(x) for x in args.sizes.split(",")],
        [k.strip() for k in args.kinds.split(",")],
        args.queries,
        args.trajectories,
        args.clearance,
        args.seed,
        progress=lambda m: print(m, file=sys.stderr, flush=True),
        budget=args.budget,
    )
    text = scale_markdown(records)
    print(text)
    if args.out:
        Path(args.out).write_text(text)
        Path(args.out).with_suffix(".json").write_text(json.dumps(records, indent=1))


if __name__ == "__main__":
    main()
