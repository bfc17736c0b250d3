"""Figure of the tracking margin and the delay tolerance of one motion (docs/img/margins.png).

Left: the separation d(t) of the two carts along the motion, the clearance D, the closest approach d_min and the
tracking margin r = (d_min − D)/2. Right: the smallest separation when cart A (or B) runs late by δ, against δ,
with the delay tolerances τ_A, τ_B found by :func:`trajopt.analysis.margins.margins`.

Usage::

    python experiments/margins_figure.py --out docs/img/margins.png [--dpi 110] [--points 120]

Headless (Agg).
"""

from __future__ import annotations

import argparse
import math
import sys
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt
import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

from mpa import Lollipop
from trajopt import generate_trajectory
from trajopt.analysis.margins import margins
from trajopt.viz.plotting import save_and_close

#: The query drawn: A goes up into the loop while B comes down from it, passing close to each other near P.
START, GOAL = (0.3, 1.2), (1.6, 0.4)


def shifted_separation(traj, robot: int, delay: float, rate: float = 2000.0) -> float:  # type: ignore[no-untyped-def]
    t = np.arange(int((traj.motion_time + delay) * rate) + 2) / rate
    sa = traj.sampler(t - (delay if robot == 0 else 0.0))[0][:, 0]
    sb = traj.sampler(t - (delay if robot == 1 else 0.0))[0][:, 1]
    r = traj.plan.routes
    return float(np.min(traj.plan.track.distance(r[0].position(sa), r[1].position(sb))))


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--out", default="docs/img/margins.png")
    ap.add_argument("--dpi", type=int, default=110)
    ap.add_argument("--points", type=int, default=120, help="delays sampled on the right panel")
    args = ap.parse_args(argv)

    traj = generate_trajectory(Lollipop(1.0, 1.0), START, GOAL)
    m = margins(traj)
    D = traj.clearance
    t = np.linspace(0.0, traj.motion_time, 2000)
    s = traj.sampler(t)[0]
    r = traj.plan.routes
    d = traj.plan.track.distance(r[0].position(s[:, 0]), r[1].position(s[:, 1]))

    fig, (ax1, ax2) = plt.subplots(1, 2, figsize=(11, 4.2))
    ax1.plot(t, d, color="tab:blue", label="separation d(t)")
    ax1.axhline(D, color="tab:red", ls="--", label=f"clearance D = {D:g} m")
    ax1.fill_between(t, D, D + 2 * m.tracking_margin, color="tab:orange", alpha=0.15, label="2 r above D")
    ax1.plot([m.min_separation_time], [m.min_separation], "ko", label=f"d_min = {m.min_separation:.4f} m")
    ax1.set(
        xlabel="t (s)",
        ylabel="graph distance (m)",
        title=f"tracking margin r = (d_min − D)/2 = {m.tracking_margin:.3g} m",
    )
    ax1.legend(loc="upper right", fontsize=8)

    finite = [x for x in (m.delay_a, m.delay_b) if not math.isinf(x)]
    hi = 1.6 * max(finite) if finite else traj.motion_time
    deltas = np.linspace(0.0, hi, args.points)
    for robot, name, tau, colour in ((0, "A", m.delay_a, "tab:green"), (1, "B", m.delay_b, "tab:purple")):
        f = [shifted_separation(traj, robot, x) for x in deltas]
        ax2.plot(deltas, f, color=colour, label=f"{name} late by δ")
        if not math.isinf(tau):
            ax2.axvline(tau, color=colour, ls=":", label=f"τ_{name} = {tau:.4g} s")
    ax2.axhline(D, color="tab:red", ls="--", label="D")
    ax2.set(
        xlabel="delay δ (s)", ylabel="smallest separation (m)", title=f"delay tolerance τ = {m.delay_tolerance:.4g} s"
    )
    ax2.legend(loc="upper right", fontsize=8)
    fig.suptitle(f"Lollipop ℓ = c = 1, {START} → {GOAL}: how far off and how late the carts may be", fontsize=10)
    print(f"wrote {save_and_close(fig, args.out, args.dpi)}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
