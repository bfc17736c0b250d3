"""What asking for a delay tolerance costs: ``TrajectoryGenerator.generate(..., delay_tolerance=T)``.

For a few lollipop queries (ℓ = c = 1, D = 0.05, default limits, 100 Hz) and requested tolerances T, prints the
ordinary motion's delay tolerance and makespan, then for each T: the tolerance reached, the effective clearance
and slowdown used (:mod:`trajopt.analysis.delay`), the makespan, the candidates tried and the wall time, or the
``NoMotionError`` message.

Usage::

    python experiments/delay_tolerance.py [--tolerances 0.05,0.2,0.5]

Headless, no files written.
"""

from __future__ import annotations

import argparse
import sys
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

from mpa import Lollipop
from mpa.errors import NoMotionError
from trajopt import TrajectoryGenerator

QUERIES = [((0.43, 1.83), (1.68, 0.22)), ((0.3, 1.2), (1.6, 0.4)), ((0.2, 0.5), (0.5, 0.2)), ((0.1, 0.6), (0.8, 0.3))]


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--tolerances", default="0.05,0.2,0.5", help="comma list of requested tolerances (s)")
    args = ap.parse_args(argv)
    tolerances = [float(x) for x in args.tolerances.split(",")]
    gen = TrajectoryGenerator(Lollipop(1.0, 1.0), clearance=0.05)
    for start, goal in QUERIES:
        base = gen.generate(start, goal)
        m = base.margins()
        print(f"{start} -> {goal}: delay tolerance {m.delay_tolerance:.4g} s, makespan {base.makespan:.2f} s")
        for T in tolerances:
            t0 = time.perf_counter()
            try:
                tr = gen.generate(start, goal, delay_tolerance=T)
            except NoMotionError as exc:
                print(f"  T = {T:g} s: no motion: {exc} ({time.perf_counter() - t0:.1f} s)")
                continue
            st = tr.solver_stats["delay_tolerance"]
            got = "unbounded" if st["achieved"] is None else f"{st['achieved']:.4g} s"
            print(
                f"  T = {T:g} s: reached {got}, effective clearance {st['effective_clearance']:.4g} m, "
                f"slowdown {st['slowdown']:g}, makespan {tr.makespan:.2f} s, {len(st['tried'])} candidates, "
                f"{time.perf_counter() - t0:.1f} s"
            )
    return 0


if __name__ == "__main__":
    sys.exit(main())
