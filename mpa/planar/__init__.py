"""Free space of two robots with bodies in the plane, exactly, and the complete planner in it.

**The model.** Robot A at offset ``s`` on a straight piece of the drawing (:class:`mpa.footprint.Drawing`) stands at
``p(s) = p0 + s·u`` (affine), robot B at ``q(t)`` likewise; each body is its footprint oriented along its piece. The
bodies overlap iff ``q(t) - p(s)`` lies in the interior of ``Q = K_A ⊕ (−K_B)`` (the Minkowski difference of the
placed bodies: a convex polygon, an octagon at most for two rectangles). The preimage of a convex set under the
affine map ``(s, t) ↦ q(t) − p(s)`` is convex: in each *sub-cell* (a piece of A's edge × a piece of B's edge) the
*obstacle* ``O`` is a convex polygon given by at most ``|Q|`` half-planes (a strip when the pieces are parallel, e.g.
``|s − t| < (L_A + L_B)/2`` on one straight piece). Discs use the polygon of :data:`mpa.footprint.DISC_SIDES` sides
circumscribed about the disc of the summed radius, one side normal to A's piece (exact across parallel tracks,
at most 0.48 % of the summed radius conservative elsewhere). Bodies that touch (distance 0, within 1e-9 m) count as
apart.

**Free pieces.** The free part of a sub-cell is the along-track free polygon of :mod:`mpa.freespace` (the clearance D
in graph distance, unchanged) minus the interior of ``O``: with ``O = {g_1 <= 0, ..., g_m <= 0}`` it is the union of
the closed convex pieces ``{g_k >= 0, g_j <= 0 for j < k}`` (cut along the obstacle's supporting lines).

**Corners.** A robot's body takes the orientation of the piece it is on. A configuration where a robot stands on a
corner (a polyline corner or a vertex) belongs to the sub-cells of every piece there; the planner moves from one to
the other only through configurations free in both (the two pieces touch there), so at the instant the body turns
it is clear of the other body in both orientations. The turn itself is instantaneous in this model: the gate
(:mod:`trajopt.verify.planar`) bounds the sweep of a real turn between rows.

**Gluing and completeness.** Two free pieces are adjacent when they share a point: inside one cell (they touch
along a cut, across a polyline corner, or at a point), or across a face (a robot on a vertex, the pieces of the
cells of two edges at that vertex meeting in an interval or a point of the other robot's offsets), or at a corner
(both robots on vertices). Path components are the connected components of this adjacency (union-find): two
configurations are joined by a motion in the model iff their pieces are in one component, and the planner then finds
one (**complete**; a shortest path through the pieces' shared points, straight inside each convex piece). The path
is not the optimum of the objective (it bends only at the pieces' shared points: the ends and middle of each shared
segment), but it is free by construction. Before any search, the robots' own shortest routes driven at once (a
straight line in route coordinates) are tried: when every segment of it lies in its cell's free pieces and a
turning rectangle's sweep clears the other body wherever it passes a corner, that motion is the answer; its cost is
the bound no motion undercuts, an optimum of the objective (:mod:`mpa.planar.shortcut`).

**Modules.** :mod:`mpa.planar.polygons` (convex polygons of offsets), :mod:`mpa.planar.corners` (bodies at corners),
:mod:`mpa.planar.build` (the free pieces), :mod:`mpa.planar.glue` (their adjacency and components),
:mod:`mpa.planar.space` (:class:`PlanarFreeSpace`), :mod:`mpa.planar.shortcut` (the robots' own routes at once,
checked), :mod:`mpa.planar.search` (the search over shared points),
:mod:`mpa.planar.oneway` (the search under one-way lanes), :mod:`mpa.planar.plan` (:func:`plan_planar`).
"""

from __future__ import annotations

# the helpers that tests, benchmarks and docs name mpa.planar._name, re-exported explicitly
from mpa.planar.corners import bodies_gap, corner_sweep, start_refusal
from mpa.planar.oneway import _pins as _pins
from mpa.planar.oneway import _search_sets as _search_sets
from mpa.planar.plan import plan_planar
from mpa.planar.polygons import TOUCH as TOUCH
from mpa.planar.polygons import _area as _area
from mpa.planar.polygons import _halfplanes as _halfplanes
from mpa.planar.polygons import _meet as _meet
from mpa.planar.search import _cell_speeds as _cell_speeds
from mpa.planar.search import _move_cost as _move_cost
from mpa.planar.search import _Moves as _Moves
from mpa.planar.search import _search as _search
from mpa.planar.space import PlanarFreeSpace, planar_free_space

__all__ = ["PlanarFreeSpace", "bodies_gap", "corner_sweep", "plan_planar", "planar_free_space", "start_refusal"]
