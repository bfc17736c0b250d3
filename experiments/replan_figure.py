"""Figure of a re-plan from a moving state (docs/img/replan.png).

The paper's lollipop (ℓ = c = 1), D = 0.05: the carts swap order, (0.2, 0.5) → (0.5, 0.2); at t = 1.3 s, while
both move, the goal changes to (0.7, 0.35). Left: the old and the new motion in the configuration space (track
coordinates of A and B), the splice point and where the braking ends. Middle and right: the velocities and
accelerations along the routes (the new motion's time shifted by 1.3 s; its route coordinates oriented as the
old ones), continuous at the splice.

Usage::

    python experiments/replan_figure.py --out docs/img/replan.png [--dpi 110]

Headless (Agg).
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt
import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

from mpa import Lollipop
from trajopt import TrajectoryGenerator
from trajopt.viz.plotting import save_and_close

START, GOAL, AT, NEW_GOAL = (0.2, 0.5), (0.5, 0.2), 1.3, (0.7, 0.35)


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--out", default="docs/img/replan.png")
    ap.add_argument("--dpi", type=int, default=110)
    args = ap.parse_args(argv)

    track = Lollipop(1.0, 1.0)
    gen = TrajectoryGenerator(track, clearance=0.05)
    old = gen.generate(START, GOAL)
    new = gen.replan(old, AT, NEW_GOAL)
    info = new.solver_stats["replan"]
    o = np.array(info["orientation"], dtype=float)
    tb = info["brake_duration"]

    fig, axes = plt.subplots(1, 3, figsize=(14, 4.4))
    ax = axes[0]
    ax.plot(old.track[:, 0], old.track[:, 1], ".", ms=2, color="0.6", label="old motion")
    ax.plot(new.track[:, 0], new.track[:, 1], ".", ms=2, color="tab:blue", label="re-planned motion")
    kb = min(int(np.ceil(tb * new.rate)), len(new.t) - 1)
    ax.plot(*new.track[0], "o", color="tab:red", label=f"splice, t = {AT} s")
    ax.plot(*new.track[kb], "s", color="tab:orange", label=f"at rest after braking ({tb:.2f} s)")
    ax.plot(*old.plan.goal, "x", color="0.4", ms=9, label="old goal")
    ax.plot(*new.plan.goal, "x", color="tab:blue", ms=9, label="new goal")
    ax.axvline(1.0, color="0.85", lw=0.8)
    ax.axhline(1.0, color="0.85", lw=0.8)
    ax.set(xlabel="A: track coordinate (m)", ylabel="B: track coordinate (m)", title="configuration space (P at 1.0)")
    ax.legend(fontsize=7, loc="lower right")

    for ax, k, name in ((axes[1], 1, "velocity (m/s)"), (axes[2], 2, "acceleration (m/s²)")):
        t_old = np.linspace(0.0, old.motion_time, 3000)
        t_new = np.linspace(0.0, new.motion_time, 3000)
        x_old = old.sampler(t_old)[k]
        x_new = new.sampler(t_new)[k] * o
        for r, colour in ((0, "tab:green"), (1, "tab:purple")):
            ax.plot(t_old, x_old[:, r], "--", color=colour, alpha=0.5, lw=1, label=f"{'AB'[r]} old")
            ax.plot(AT + t_new, x_new[:, r], color=colour, lw=1.4, label=f"{'AB'[r]} re-planned")
        ax.axvline(AT, color="tab:red", ls=":", lw=1)
        ax.axvline(AT + tb, color="tab:orange", ls=":", lw=1)
        ax.set(xlabel="t (s, old clock)", ylabel=name, title=name.split(" ")[0] + " along the routes")
        ax.legend(fontsize=7, loc="upper right")
    fig.suptitle(
        f"Re-plan at t = {AT} s from {START} → {GOAL} to the new goal {NEW_GOAL}: brake on the current routes "
        "(jerk-limited, continuous in p, v, a), then the new plan",
        fontsize=10,
    )
    print(f"wrote {save_and_close(fig, args.out, args.dpi)}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
