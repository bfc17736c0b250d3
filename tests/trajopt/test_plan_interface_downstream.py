"""Downstream code reads plans through ``mpa.MotionPlan``: what it computes the same way for both planners works for
a paper plan on its track's layout as for a graph plan."""

from __future__ import annotations

import numpy as np
from matplotlib.figure import Figure

from mpa import Lollipop, MPAError, plan
from trajopt import Limits, TrajectoryGenerator
from trajopt.generator import route_speed_limits
from trajopt.path.planview import plan_view
from trajopt.testing import check_graph_trajectory
from trajopt.viz.layout import draw_graph_plan, plan_title

TRACK = Lollipop(1.0, 1.0)


def test_a_paper_plan_is_drawn_on_its_layout() -> None:
    p = plan(TRACK, (0.1, 0.6), (0.8, 1.3), 0.1, planner="paper")
    g = plan(TRACK, (0.1, 0.6), (0.8, 1.3), 0.1, planner="graph")
    for q in (p, g):
        ax = Figure().subplots()
        draw_graph_plan(ax, q, name="lollipop")
        labels = {t.get_text() for t in ax.texts}
        assert {"A start", "B start", "A goal", "B goal"} <= labels, labels
        assert ax.get_title().startswith("lollipop — stick:0.1, stick:0.6 → stick:0.8, loop:0.3"), ax.get_title()
    assert plan_title(p).endswith(f"D = 0.1 m, domain {p.domain}")
    assert "fastest, makespan" in plan_title(g)


def test_the_independent_layout_checker_passes_paper_trajectories() -> None:
    """``check_graph_trajectory`` reads the plan's layout, routes and ends: a paper track's trajectory checked on
    the track's graph form passes."""
    rng = np.random.default_rng(11)
    gen = TrajectoryGenerator(TRACK, clearance=0.1, limits=Limits(), rate=100.0)
    done = 0
    while done < 8:
        try:
            tr = gen.generate(rng.uniform(0, 2, 2), rng.uniform(0, 2, 2))
        except MPAError:
            continue
        done += 1
        assert check_graph_trajectory(tr) == [], check_graph_trajectory(tr)
        assert route_speed_limits(tr.plan, tr.limits) is tr.limits  # no lane rules on a paper track
        view = plan_view(tr.plan)
        assert view.endpoints() == (tr.plan.layout_start, tr.plan.layout_goal)
