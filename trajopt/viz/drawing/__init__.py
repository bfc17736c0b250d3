"""Drawing the paper's objects with matplotlib: tracks, robots, flat configuration spaces, skeletons, traces of H.

Everything drawn here is computed by :mod:`mpa` (track embeddings, distances, skeleton edges, the retraction H,
plans), so a picture doubles as a visual check of the implementation. Nothing in :mod:`mpa` imports this module.

Conventions of the *flat configuration space* picture: the x axis is robot A's track coordinate, the y axis robot
B's, over ``[0, ℓ]`` (interval), ``[0, c)`` (circle) or ``[0, ℓ + c)`` (lollipop; the stick is ``[0, ℓ]``, the
loop lies beyond the dashed lines at ``ℓ``). The collision set (the diagonal, or ``d < D`` for a clearance D) is
shaded red. The loop coordinates are periodic: a path that leaves the square at ``ℓ + c`` (or ``c``) comes back at
``ℓ`` (or 0), and every polyline is broken there (:func:`split_wraps`) instead of being drawn as a long chord.

Robot A is blue, robot B orange; a filled triangle is a robot's initial position, an empty one its final position
(the paper's icons). On the track A is drawn on the outer side (outside the loop, above the stick) and B on the
inner side; where both robots' curves share axes, A is solid and B dashed (:data:`ROBOT_LINESTYLES`).
"""

from __future__ import annotations

from trajopt.viz.drawing.cspace import draw_flat_cspace, draw_flat_path, draw_state, draw_traces
from trajopt.viz.drawing.labels import free_offset
from trajopt.viz.drawing.skeleton import block_of_edge, chain_layout, draw_chain, draw_skeleton, sample_skeleton
from trajopt.viz.drawing.steps import StepStyle, draw_plan_step
from trajopt.viz.drawing.style import (
    BLOCK_COLORS,
    COLLISION_COLOR,
    ROBOT_COLORS,
    ROBOT_LINESTYLES,
    STEP_COLORS,
    TRACK_COLOR,
    TRAJECTORY_COLOR,
    coordinate_extent,
    embed_offset,
    lane_unit,
    loop_period,
    new_figure,
    split_wraps,
    track_normal,
    track_title,
)
from trajopt.viz.drawing.track import (
    arrow_along,
    draw_motion,
    draw_robot,
    draw_robots,
    draw_track,
    draw_track_geodesic,
    motion_lanes,
)

__all__ = [
    "BLOCK_COLORS",
    "COLLISION_COLOR",
    "ROBOT_COLORS",
    "ROBOT_LINESTYLES",
    "STEP_COLORS",
    "TRACK_COLOR",
    "TRAJECTORY_COLOR",
    "StepStyle",
    "arrow_along",
    "block_of_edge",
    "chain_layout",
    "coordinate_extent",
    "draw_chain",
    "draw_flat_cspace",
    "draw_flat_path",
    "draw_motion",
    "draw_plan_step",
    "draw_robot",
    "draw_robots",
    "draw_skeleton",
    "draw_state",
    "draw_traces",
    "draw_track",
    "draw_track_geodesic",
    "embed_offset",
    "free_offset",
    "lane_unit",
    "loop_period",
    "motion_lanes",
    "new_figure",
    "sample_skeleton",
    "split_wraps",
    "track_normal",
    "track_title",
]
