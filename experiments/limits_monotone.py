"""Counterexamples to "the makespan never grows when a limit is loosened", counted over seeded draws.

The distribution of ``test_makespan_never_grows_when_a_limit_is_loosened`` (tests/reliability): a query (the
paper's lollipop ``(0.1, 0.6) → (0.8, 0.3)`` or the Y junction, A from b_left to b_right, B from b_right to
b_short), limits ``(v, a, j)`` each ``10^u`` times its default with ``u`` uniform in ``[-3, 4]``, one of them
loosened by a factor uniform in ``[1, 100]`` (at most ``1e4`` times its default). Each draw generates both
motions in process; a counterexample is a looser makespan above the tighter one by more than 1e-9 s. Prints
every counterexample, the counts per query and per loosened limit, and the CPU time per draw (median, max).

    python experiments/limits_monotone.py --draws 300 --seed 28
"""

from __future__ import annotations

import argparse
import json
import time
from pathlib import Path

import numpy as np

from mpa import GraphTrack, Lollipop
from mpa.errors import InvalidInputError
from trajopt import generate_trajectory

ROOT = Path(__file__).resolve().parents[1]
DEFAULTS = np.array([0.5, 1.0, 5.0])
NAMES = ("vmax", "amax", "jmax")


def queries() -> dict[str, tuple[object, tuple[object, object]]]:
    """The two queries of the property test."""
    y = GraphTrack.from_layout(json.loads((ROOT / "examples" / "tracks" / "y_junction.json").read_text()))
    return {
        "lollipop": (Lollipop(1, 1), ((0.1, 0.6), (0.8, 0.3))),
        "y": (y, (((1, 1.5), (2, 2.0)), ((2, 2.5), (1, 1.0)))),
    }


def draw(rng: np.random.Generator, cases: list[str]) -> tuple[str, np.ndarray, np.ndarray, int]:
    """One seeded draw: the query, the tighter and the looser limits, which limit was loosened."""
    case = cases[int(rng.integers(len(cases)))]
    base = DEFAULTS * 10.0 ** rng.uniform(-3.0, 4.0, 3)
    which = int(rng.integers(3))
    looser = base.copy()
    looser[which] = min(looser[which] * rng.uniform(1.0, 100.0), DEFAULTS[which] * 1e4)
    return case, base, looser, which


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--draws", type=int, default=100)
    ap.add_argument("--seed", type=int, default=28)
    ap.add_argument("--case", choices=["both", "lollipop", "y"], default="both")
    args = ap.parse_args()
    qs = queries()
    cases = sorted(qs) if args.case == "both" else [args.case]
    rng = np.random.default_rng(args.seed)
    bad: dict[str, int] = {}
    drawn: dict[str, int] = {}
    cpu: list[float] = []
    errors = 0
    for i in range(args.draws):
        case, base, looser, which = draw(rng, cases)
        key = f"{case} {NAMES[which]}"
        drawn[key] = drawn.get(key, 0) + 1
        track, (start, goal) = qs[case]
        c0 = time.process_time()
        try:
            spans = [
                generate_trajectory(track, start, goal, vmax=x[0], amax=x[1], jmax=x[2]).makespan
                for x in (base, looser)
            ]
        except InvalidInputError as exc:  # a rate too low for the motion: a clear error, not a wrong motion
            errors += 1
            print(f"{i}: {case} {base.tolist()} -> {looser.tolist()}: error {exc}"[:200], flush=True)
            continue
        cpu.append(time.process_time() - c0)
        if spans[1] > spans[0] + 1e-9:
            bad[key] = bad.get(key, 0) + 1
            print(f"{i}: COUNTEREXAMPLE {case} {base.tolist()} -> {looser.tolist()}: {spans}", flush=True)
        if (i + 1) % 100 == 0:
            print(f"after {i + 1} draws: {sum(bad.values())} counterexamples", flush=True)
    print(f"draws {args.draws}, seed {args.seed}, rate errors {errors}, counterexamples {sum(bad.values())}")
    for key in sorted(drawn):
        print(f"  {key}: {bad.get(key, 0)} of {drawn[key]}")
    if cpu:
        print(f"CPU per draw (two motions): median {np.median(cpu):.3f} s, max {max(cpu):.2f} s")


if __name__ == "__main__":
    main()
