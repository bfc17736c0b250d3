"""The interval: robots never change order; one rule, a straight translation (the paper's §5.1)."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike

from mpa.planners.base import FINAL, PRELIM, RULES, Planner
from mpa.plans import Plan, build_plan
from mpa.retraction import retract
from mpa.routes import RobotMove
from mpa.skeleton import skeleton_of

__all__ = ["IntervalPlanner"]


@dataclass(frozen=True)
class IntervalPlanner(Planner):
    """Two robots on an interval: one rule, straight translation, same order only."""

    def plan(self, start: ArrayLike, goal: ArrayLike) -> Plan:
        s, g = self.cspace.validate_query(start, goal)
        tr = self.track
        sk = skeleton_of(tr)
        mv = (RobotMove("stick", s[0], g[0] - s[0]), RobotMove("stick", s[1], g[1] - s[1]))
        on_s = retract(tr, np.array([s, g]))
        return build_plan(
            tr,
            s,
            g,
            self.clearance,
            1,
            RULES[("interval", 1)],
            [
                (PRELIM["interval"], []),
                ("both robots translate straight to their goals", [mv]),
                (FINAL["interval"], []),
            ],
            sk,
            on_s[0],
            on_s[1],
            (),
        )
