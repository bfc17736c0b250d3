"""The graph search's expansion written plainly, as the reference of its fast paths.

:class:`ReferenceSearch` is :class:`mpa.planners.graph.search.AnyAngleSearch` with :meth:`open_face` and
:meth:`expand_interval` in their generic form: every page and side read from the mesh (:meth:`_Mesh.pages`,
:meth:`_Mesh.sides`, :meth:`_Mesh.point_key`), every cost through :func:`cost_function`, every point through
:meth:`push_point`, every face through :meth:`push_face` (:meth:`face_lower_bound`, :meth:`queue_key`), every interval
through :func:`_uncovered`. The fast search must make the same nodes in the same order, bit for bit.
"""

from __future__ import annotations

from mpa.planners.graph.search import GOAL, AnyAngleSearch, FaceEntry, IntervalNode, _uncovered


class ReferenceSearch(AnyAngleSearch):
    """The search with the generic expansion (see the module docstring)."""

    def open_face(self, entry: FaceEntry) -> None:
        mesh, r, sig, ax, a, pid = self.mesh, entry.r, entry.sig, entry.ax, entry.a, entry.polygon
        n1 = 1.0 if a == 0.0 else -1.0
        for pid2, b in mesh.pages(entry.face):
            if pid2 == pid and b == a:
                continue
            if len(mesh.sides(pid2)) == 1 and pid2 not in self.goal_at:
                continue
            sg = -n1 if b == 0.0 else n1
            if ax == 0:
                r2 = (b + sg * (r[0] - a), r[1])
                sig2 = (sg * sig[0], sig[1])
            else:
                r2 = (r[0], b + sg * (r[1] - a))
                sig2 = (sig[0], sg * sig[1])
            sk = (entry.root, pid2, ax, b, round(r2[0] * self.quantum), round(r2[1] * self.quantum))
            for z0, z1 in _uncovered(self.seen, sk, entry.y0, entry.y1, self.eps):
                node = IntervalNode(
                    entry.root, entry.root_key, entry.g_root, r2, sig2, ax, b, z0, z1, pid2, pid, a,
                    entry.lo, entry.hi, entry.parent, entry.origin,
                )  # fmt: skip
                self.nodes.append(node)
                self.expand_interval(len(self.nodes) - 1, node)

    def expand_interval(self, nid: int, nd: IntervalNode) -> None:
        mesh, cost, eps, ctol = self.mesh, self.cost, self.eps, self.ctol
        rid, r, ax, a, y0, y1, pid, groot = nd.root, nd.r, nd.ax, nd.a, nd.y0, nd.y1, nd.polygon, nd.g_root
        rs, rt = r
        u0 = (a - rs, y0 - rt) if ax == 0 else (y0 - rs, a - rt)
        u1 = (a - rs, y1 - rt) if ax == 0 else (y1 - rs, a - rt)
        cr = u0[0] * u1[1] - u0[1] * u1[0]
        if abs(cr) <= ctol:
            return
        sgn = 1.0 if cr > 0 else -1.0
        for pt in self.goal_at.get(pid, ()):
            dx, dy = pt[0] - rs, pt[1] - rt
            if sgn * (u0[0] * dy - u0[1] * dx) >= -ctol and -sgn * (u1[0] * dy - u1[1] * dx) >= -ctol:
                self.push_point(GOAL, groot + cost(pt[0] - rs, pt[1] - rt), rid, nid, pid, None, pt)
        for ax2, a2, face2, lo2, hi2 in mesh.sides(pid):
            if ax2 == ax and a2 == a:
                continue
            if (r[ax2] - a2 if a2 == 0.0 else a2 - r[ax2]) <= eps:
                continue
            yl, yh = lo2, hi2
            for u, sg in ((u0, sgn), (u1, -sgn)):
                if ax2 == 0:
                    ca, cb = u[0], -u[0] * rt - u[1] * (a2 - rs)
                else:
                    ca, cb = -u[1], u[0] * (a2 - rt) + u[1] * rs
                ca, cb = sg * ca, sg * cb
                if ca > 0.0:
                    yl = max(yl, (-ctol - cb) / ca)
                elif ca < 0.0:
                    yh = min(yh, (-ctol - cb) / ca)
                elif cb < -ctol:
                    yl, yh = 1.0, 0.0
            if yl > yh + eps:
                continue
            for end, y in ((yl <= lo2 + eps, lo2), (yh >= hi2 - eps, hi2)):
                if end:
                    pt = (a2, y) if ax2 == 0 else (y, a2)
                    cost_end = groot + cost(pt[0] - rs, pt[1] - rt)
                    self.push_point(mesh.point_key(face2, y), cost_end, rid, nid, pid, None, pt)
            yl = lo2 if yl <= lo2 + eps else yl
            yh = hi2 if yh >= hi2 - eps else yh
            if yh - yl <= eps:
                continue
            self.push_face(
                FaceEntry(rid, nd.root_key, groot, r, nd.sig, ax2, a2, yl, yh, pid, face2, lo2, hi2, nid, nd.origin)
            )


class EagerBoundSearch(ReferenceSearch):
    """:class:`ReferenceSearch` with the passing bound taken into a node's key when the node is queued (the search
    takes it in when the node is first taken from the queue: the same keys, so the same nodes in the same order)."""

    def push_point(self, key: object, gval: float, root: int, last: int, pid: object, frm: object, pt: object) -> None:
        import heapq
        import math

        from mpa.planners.graph.search import PointNode

        best = self.best
        if gval < best.get(key, math.inf) - (0.0 if key is GOAL else self.again):  # type: ignore[call-overload]
            best[key] = gval  # type: ignore[index]
            nodes = self.nodes
            nodes.append(PointNode(key, gval, root, last, pid, frm, pt))  # type: ignore[arg-type]
            f = gval if key is GOAL else gval + self.lower_bound(pid, pt)  # type: ignore[arg-type]
            if self.bound is not None and key is not GOAL:
                f = max(f, gval + self.bound.point(key))  # type: ignore[arg-type]
            heapq.heappush(self.heap, self.queue_key(f, gval, len(nodes) - 1))

    def push_face(self, entry: FaceEntry) -> None:
        import heapq

        nodes = self.nodes
        nodes.append(entry)
        g_root = entry.g_root
        f = g_root + self.face_lower_bound(entry.r, entry.ax, entry.a, entry.face, entry.y0, entry.y1)
        if self.bound is not None:
            r, a, y0, y1 = entry.r, entry.a, entry.y0, entry.y1
            x_a, x_b = (
                (abs(r[0] - a), max(0.0, y0 - r[1], r[1] - y1))
                if entry.ax == 0
                else (max(0.0, y0 - r[0], r[0] - y1), abs(r[1] - a))
            )
            f = max(
                f,
                g_root + self.bound.point(entry.root_key),
                g_root + self.cost(x_a, x_b) + self.bound.entry(entry.face, y0, y1),
            )
        heapq.heappush(self.heap, self.queue_key(f, g_root, len(nodes) - 1))
