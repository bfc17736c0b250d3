"""The circle: two domains of continuity, TC = 2 (the paper's §5.2): ccw when B's positions are antipodal, else
B's shortest path."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike

from mpa.errors import InvalidInputError, PlanningError
from mpa.planners.base import FINAL, PRELIM, RULES, Planner, circle_pieces, pieces_word, reverse_moves
from mpa.plans import Plan, build_plan
from mpa.retraction import trace_moves
from mpa.skeleton import CircleSkeleton, skeleton_of
from mpa.tracks import Circle

__all__ = ["CirclePlanner"]


@dataclass(frozen=True)
class CirclePlanner(Planner):
    """Two robots on a circle: the paper's algorithm with TC = 2 rules (§5.2)."""

    def _main_delta(self, b_i: float, b_f: float) -> tuple[int, float]:
        tr = self.track
        if not isinstance(tr, Circle):
            raise InvalidInputError(f"track is {tr!r}, expected a Circle")
        c, h = tr.loop, tr.half
        eps = self.neighbourhood * h
        dccw = (b_f - b_i) % c
        if dccw >= c - 1e-15:
            dccw = 0.0
        if abs(dccw - h) < eps:
            return 1, dccw
        return 2, dccw if dccw <= h else dccw - c

    def plan(self, start: ArrayLike, goal: ArrayLike) -> Plan:
        s, g = self.cspace.validate_query(start, goal)
        tr = self.track
        if not isinstance(tr, Circle):
            raise InvalidInputError(f"track is {tr!r}, expected a Circle")
        sk = skeleton_of(tr)
        if not isinstance(sk, CircleSkeleton):
            raise PlanningError(f"internal: sk is a {type(sk).__name__}, expected a CircleSkeleton")
        h = tr.half
        xi = np.array([(s[1] + h) % tr.loop, s[1]])
        xf = np.array([(g[1] + h) % tr.loop, g[1]])
        domain, delta = self._main_delta(float(xi[1]), float(xf[1]))
        pieces = circle_pieces(float(xi[1]), delta, h, lambda a: "Aa" if a == 0 else "Ab")
        main = [sk.edge_moves(e, t0, t1) for e, t0, t1 in pieces]
        word = pieces_word(sk.graph, pieces)
        what = "both robots move counterclockwise" if domain == 1 else "both robots move along B's shortest path"
        return build_plan(
            tr,
            s,
            g,
            self.clearance,
            domain,
            RULES[("circle", domain)],
            [
                (PRELIM["circle"], [trace_moves(tr, s)]),
                (f"{what} until B reaches its final position", main),
                (FINAL["circle"], [reverse_moves(trace_moves(tr, g))]),
            ],
            sk,
            xi,
            xf,
            word,
        )
