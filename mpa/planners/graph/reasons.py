"""Why no motion exists: the reason a user understands (a goal on another part of the track, a clearance that does
not fit, robots that can never change order).
"""

from __future__ import annotations

import math

from mpa.freespace import FreeSpace
from mpa.graph_track import GraphTrack, Position


# ------------------------------------------------------------------------------------------ diagnosis
def _path_like(track: GraphTrack) -> bool:
    _, b1 = track.graph.betti()
    degrees = [track.degree(v) for v in range(track.graph.n_vertices)]
    return b1 == 0 and max(degrees) <= 2


def _why_no_motion(track: GraphTrack, fs: FreeSpace, start: tuple[Position, ...], goal: tuple[Position, ...]) -> str:
    g = track.geometry
    for robot, s, t in (("A", start[0], goal[0]), ("B", start[1], goal[1])):
        if not math.isfinite(g.distance_scalar(s[0], s[1], t[0], t[1])):
            return f"robot {robot}'s goal is on another part of the track, not connected to its start"
    names = f"{track.position_name(*start[0])}, {track.position_name(*start[1])}"
    gnames = f"{track.position_name(*goal[0])}, {track.position_name(*goal[1])}"
    if _path_like(track):
        return (
            f"the robots' order cannot change on a path-like layout (no vertex of degree >= 3 and no cycle): "
            f"start ({names}) and goal ({gnames}) have them in different orders"
        )
    tiny = FreeSpace(track, 0.0)
    if tiny.component_of(*start) != tiny.component_of(*goal):
        return (
            f"start ({names}) and goal ({gnames}) are in different components of the free space, even for a "
            "vanishing clearance"
        )
    lo, hi = 0.0, fs.clearance
    iters = 30 if track.n_edges <= 40 else 10
    for _ in range(iters):
        mid = 0.5 * (lo + hi)
        trial = FreeSpace(track, mid)
        ca, cb = trial.component_of(*start), trial.component_of(*goal)
        if ca is not None and ca == cb:
            lo = mid
        else:
            hi = mid
    _, b1 = track.graph.betti()
    branch = sum(track.degree(v) >= 3 for v in range(track.graph.n_vertices))
    where = "the layout"
    if b1 == 1 and branch <= 1:
        where = "the only loop"
    elif b1 == 0 and branch == 1:
        where = "the only siding"
    digits = next((k for k in range(6, 18) if f"{lo:.{k}g}" != f"{fs.clearance:.{k}g}"), 17)
    return (
        f"the clearance {fs.clearance!r} m does not fit {where}: start ({names}) and goal ({gnames}) are in "
        f"different components of the free space; they are connected only for clearances up to about "
        f"{lo:.{digits}g} m"
    )
