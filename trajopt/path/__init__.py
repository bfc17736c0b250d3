"""Stages 1-2, the geometric path of a plan's motion.

:mod:`~trajopt.path.planview` reads every :class:`mpa.MotionPlan` in one route geometry;
:mod:`~trajopt.path.planning` adapts the layout planner (route speed limits, waypoints);
:mod:`~trajopt.path.fastpath` times the straight route-coordinate motion when it keeps the clearance;
:mod:`~trajopt.path.corridor` solves the hard path, a strictly convex QP in a corridor fixed by the plan;
:mod:`~trajopt.path.switch` blends the two in a band so the motion is continuous across the switch;
:mod:`~trajopt.path.braking` brings a motion to rest.
"""
