"""Abrams' discretized configuration space D₂(Γ) of two ordered robots on a graph, as a cube complex.

The configuration space ``F(Γ, 2)`` of two distinct ordered points on a finite graph Γ deformation retracts onto
Abrams' discretized configuration space ``D₂(Γ)`` once Γ is *simple* (no loops, no multiple edges): its cells are the
products ``c1 × c2`` of closed cells of Γ (vertices and edges) whose closures are disjoint. So ``D₂(Γ)`` has

- ``V(V - 1)`` vertices ``(v, w)``, ``v != w``;
- ``2 E (V - 2)`` edges ``(e, w)`` and ``(v, e)`` with the vertex not an endpoint of the edge;
- ``2 [C(E, 2) - Σ_v C(d_v, 2)]`` squares ``(e, f)`` with ``e`` and ``f`` disjoint edges.

This module builds Γ's simple subdivision (:func:`simple_subdivision`), the cube complex
(:func:`discretized_configuration_space`), and the elementary collapses of free faces (:func:`collapse_free_faces`)
that shrink it without changing its homotopy type. The algebra (homology, cup products, topological complexity)
lives in :mod:`mpa.topology`.

Conventions
-----------
A :class:`CubeComplex` has dimension at most 2. An edge is stored with an orientation ``tail -> head``. A square is
the product ``I_x × I_y`` of two unit intervals; it stores its four sides in the order *bottom, right, top, left*:

- bottom ``v00 -> v10`` (``I_x × {0}``), right ``v10 -> v11`` (``{1} × I_y``),
- top ``v01 -> v11`` (``I_x × {1}``), left ``v00 -> v01`` (``{0} × I_y``),

and, per side, a sign ``+1`` when the stored edge runs in that direction and ``-1`` when it runs against it.
Its cellular boundary is ``∂ = bottom + right - top - left`` (each side times its sign).
"""

from __future__ import annotations

from collections import deque
from dataclasses import dataclass, field

import numpy as np

from mpa.errors import InvalidInputError, PlanningError
from mpa.graph import MetricGraph

__all__ = [
    "CellCounts",
    "Collapse",
    "CubeComplex",
    "DiscretizedConfigurationSpace",
    "SimpleSubdivision",
    "collapse_free_faces",
    "cubical_subdivision",
    "discretized_configuration_space",
    "expected_cell_counts",
    "simple_subdivision",
]

BOTTOM, RIGHT, TOP, LEFT = 0, 1, 2, 3
"""Positions of the four sides in a row of :attr:`CubeComplex.squares`."""


def _readonly_int_array(values: object, shape_tail: tuple[int, ...], name: str) -> np.ndarray:
    arr = np.asarray(values)
    if arr.size == 0:
        arr = arr.reshape((0, *shape_tail))
    if arr.ndim != 1 + len(shape_tail) or arr.shape[1:] != shape_tail:
        raise InvalidInputError(f"{name} has shape {arr.shape}, expected (n, {', '.join(map(str, shape_tail))})")
    if arr.size and not np.issubdtype(arr.dtype, np.integer):
        raise InvalidInputError(f"{name} has dtype {arr.dtype}, expected integers")
    out = np.array(arr, dtype=np.int64, copy=True)
    out.setflags(write=False)
    return out


@dataclass(frozen=True)
class CellCounts:
    """Numbers of cells of a cube complex of dimension <= 2."""

    vertices: int
    edges: int
    squares: int

    @property
    def euler_characteristic(self) -> int:
        """``vertices - edges + squares``."""
        return self.vertices - self.edges + self.squares

    def to_dict(self) -> dict[str, int]:
        """Plain ``{"vertices", "edges", "squares"}`` dictionary."""
        return {"vertices": self.vertices, "edges": self.edges, "squares": self.squares}


@dataclass(frozen=True, eq=False)
class CubeComplex:
    """A finite cube complex of dimension <= 2 (vertices, oriented edges, squares).

    Parameters
    ----------
    n_vertices : int
        Number of vertices, numbered ``0 .. n_vertices - 1``.
    edges : array_like of int
        Shape (E, 2): ``tail, head`` of each edge. Loops are not allowed.
    squares : array_like of int
        Shape (S, 4): the edges on the sides *bottom, right, top, left* of each square (see the module docstring).
    signs : array_like of int, optional
        Shape (S, 4): ``+1`` when the stored edge runs in the side's direction, ``-1`` otherwise. Default all ``+1``.

    Raises
    ------
    InvalidInputError
        If shapes, indices or signs are out of range, an edge is a loop, or the sides of a square do not meet at
        four corners as described in the module docstring.
    """

    n_vertices: int
    edges: np.ndarray
    squares: np.ndarray = field(default_factory=lambda: np.zeros((0, 4), dtype=np.int64))
    signs: np.ndarray | None = None

    def __post_init__(self) -> None:
        if isinstance(self.n_vertices, bool) or not isinstance(self.n_vertices, (int, np.integer)):
            raise InvalidInputError(f"n_vertices is {self.n_vertices!r}, expected an integer >= 0")
        if self.n_vertices < 0:
            raise InvalidInputError(f"n_vertices is {self.n_vertices}, expected an integer >= 0")
        object.__setattr__(self, "n_vertices", int(self.n_vertices))
        edges = _readonly_int_array(self.edges, (2,), "edges")
        squares = _readonly_int_array(self.squares, (4,), "squares")
        if self.signs is None:
            signs = np.ones(squares.shape, dtype=np.int64)
            signs.setflags(write=False)
        else:
            signs = _readonly_int_array(self.signs, (4,), "signs")
            if signs.shape != squares.shape:
                raise InvalidInputError(f"signs has shape {signs.shape}, expected {squares.shape} like squares")
            if not np.all(np.abs(signs) == 1):
                raise InvalidInputError("signs contains values other than +1 and -1, expected only +1 and -1")
        object.__setattr__(self, "edges", edges)
        object.__setattr__(self, "squares", squares)
        object.__setattr__(self, "signs", signs)
        if edges.size and (edges.min() < 0 or edges.max() >= self.n_vertices):
            raise InvalidInputError(f"edges refer to vertices outside 0..{self.n_vertices - 1}")
        loops = np.nonzero(edges[:, 0] == edges[:, 1])[0]
        if loops.size:
            k = int(loops[0])
            raise InvalidInputError(f"edge {k} is a loop at vertex {int(edges[k, 0])}, expected no loops")
        if squares.size == 0:
            return
        if squares.min() < 0 or squares.max() >= len(edges):
            raise InvalidInputError(f"squares refer to edges outside 0..{len(edges) - 1}")
        start, end = self.side_endpoints()
        # bottom: v00 -> v10, right: v10 -> v11, top: v01 -> v11, left: v00 -> v01
        ok = (
            (start[:, BOTTOM] == start[:, LEFT])
            & (end[:, BOTTOM] == start[:, RIGHT])
            & (end[:, LEFT] == start[:, TOP])
            & (end[:, RIGHT] == end[:, TOP])
        )
        bad = np.nonzero(~ok)[0]
        if bad.size:
            s = int(bad[0])
            raise InvalidInputError(
                f"square {s} has sides {squares[s].tolist()} with signs {signs[s].tolist()} that do not close up, "
                "expected bottom v00->v10, right v10->v11, top v01->v11, left v00->v01"
            )

    @classmethod
    def from_corners(cls, n_vertices: int, corners: object) -> CubeComplex:
        """Build a complex from squares given by their corners ``(v00, v10, v11, v01)`` (counter-clockwise).

        Edges are the pairs of consecutive corners, identified when they join the same two vertices and stored
        from the smaller to the larger vertex index; squares sharing a pair of vertices share that edge. This is
        the convenient way to write down surfaces (a torus or a Klein bottle as a grid with identified sides).

        Parameters
        ----------
        n_vertices : int
        corners : array_like of int
            Shape (S, 4).

        Returns
        -------
        CubeComplex

        Examples
        --------
        >>> torus = [((i, j), ((i + 1) % 3, j), ((i + 1) % 3, (j + 1) % 3), (i, (j + 1) % 3))
        ...          for i in range(3) for j in range(3)]
        >>> cx = CubeComplex.from_corners(9, [[3 * a + b for a, b in sq] for sq in torus])
        >>> cx.cell_counts
        CellCounts(vertices=9, edges=18, squares=9)
        """
        arr = _readonly_int_array(corners, (4,), "corners")
        index: dict[tuple[int, int], int] = {}
        edges: list[tuple[int, int]] = []
        squares: list[list[int]] = []
        signs: list[list[int]] = []
        for v00, v10, v11, v01 in arr.tolist():
            row: list[int] = []
            sgn: list[int] = []
            for a, b in ((v00, v10), (v10, v11), (v01, v11), (v00, v01)):  # bottom, right, top, left
                key = (min(a, b), max(a, b))
                if key not in index:
                    index[key] = len(edges)
                    edges.append(key)
                row.append(index[key])
                sgn.append(1 if a < b else -1)
            squares.append(row)
            signs.append(sgn)
        return cls(
            n_vertices,
            np.array(edges, dtype=np.int64).reshape(-1, 2),
            np.array(squares, dtype=np.int64).reshape(-1, 4),
            np.array(signs, dtype=np.int64).reshape(-1, 4),
        )

    # ----------------------------------------------------------------------------------------------
    @property
    def n_edges(self) -> int:
        """Number of edges."""
        return len(self.edges)

    @property
    def n_squares(self) -> int:
        """Number of squares."""
        return len(self.squares)

    @property
    def cell_counts(self) -> CellCounts:
        """Numbers of vertices, edges and squares."""
        return CellCounts(self.n_vertices, self.n_edges, self.n_squares)

    @property
    def euler_characteristic(self) -> int:
        """``V - E + S``."""
        return self.n_vertices - self.n_edges + self.n_squares

    def side_endpoints(self) -> tuple[np.ndarray, np.ndarray]:
        """Start and end vertex of every side of every square, following the side's direction.

        Returns
        -------
        start, end : numpy.ndarray
            Shape (S, 4) each.
        """
        if self.signs is None:
            raise PlanningError("internal: self.signs is not set")
        tails = self.edges[self.squares, 0]
        heads = self.edges[self.squares, 1]
        forward = self.signs > 0
        return np.where(forward, tails, heads), np.where(forward, heads, tails)

    def boundary_coefficients(self) -> np.ndarray:
        """Coefficient of each side's edge in the boundary of its square: ``sign * (+1, +1, -1, -1)``.

        Returns
        -------
        numpy.ndarray
            Shape (S, 4).
        """
        if self.signs is None:
            raise PlanningError("internal: self.signs is not set")
        return self.signs * np.array([1, 1, -1, -1], dtype=np.int64)

    def vertex_components(self) -> np.ndarray:
        """Label of the connected component of every vertex (labels ``0 .. c-1`` in order of first vertex).

        Returns
        -------
        numpy.ndarray
            Shape (n_vertices,).
        """
        parent = list(range(self.n_vertices))

        def find(v: int) -> int:
            while parent[v] != v:
                parent[v] = parent[parent[v]]
                v = parent[v]
            return v

        for a, b in self.edges.tolist():
            ra, rb = find(a), find(b)
            if ra != rb:
                parent[max(ra, rb)] = min(ra, rb)
        roots = [find(v) for v in range(self.n_vertices)]
        relabel: dict[int, int] = {}
        return np.array([relabel.setdefault(r, len(relabel)) for r in roots], dtype=np.int64)

    def subcomplex(self, vertices: np.ndarray, edges: np.ndarray, squares: np.ndarray) -> CubeComplex:
        """The subcomplex on the given (sorted, closed under faces) vertex, edge and square indices, renumbered.

        Parameters
        ----------
        vertices, edges, squares : numpy.ndarray of int
            Indices of the cells kept; every face of a kept cell must be kept.

        Returns
        -------
        CubeComplex
        """
        vmap = np.full(self.n_vertices, -1, dtype=np.int64)
        vmap[vertices] = np.arange(len(vertices))
        emap = np.full(self.n_edges, -1, dtype=np.int64)
        emap[edges] = np.arange(len(edges))
        if self.signs is None:
            raise PlanningError("internal: self.signs is not set")
        new_edges = vmap[self.edges[edges]].reshape(-1, 2)
        new_squares = emap[self.squares[squares]].reshape(-1, 4)
        if (new_edges < 0).any() or (new_squares < 0).any():
            raise InvalidInputError("subcomplex is not closed under taking faces")
        return CubeComplex(len(vertices), new_edges, new_squares, self.signs[squares].reshape(-1, 4))


def cubical_subdivision(cx: CubeComplex) -> CubeComplex:
    """Cut every square into four, with every edge directed from the lower- to the higher-dimensional cell.

    New vertices: the old vertices ``0 .. V-1``, then one midpoint per edge, then one centre per square. Every new
    edge runs vertex -> edge midpoint or edge midpoint -> square centre, so all signs are ``+1`` and the directions
    of the edges agree with the coordinates of every square: the result is a cubical set, on which the Serre
    diagonal gives a well-defined cup product (:mod:`mpa.topology` subdivides when some sign is ``-1``).

    Parameters
    ----------
    cx : CubeComplex

    Returns
    -------
    CubeComplex
        Homeomorphic to ``cx``; ``V + E + S`` vertices, ``2E + 4S`` edges, ``4S`` squares.
    """
    v, e_count = cx.n_vertices, cx.n_edges
    mid = v + np.arange(e_count)
    centre = v + e_count + np.arange(cx.n_squares)
    edges = [np.stack([cx.edges[:, 0], mid], axis=1), np.stack([cx.edges[:, 1], mid], axis=1)]
    # midpoint -> centre, one edge per (square, side) so that a side met twice gets two edges
    spoke = 2 * e_count + np.arange(4 * cx.n_squares).reshape(-1, 4)
    edges.append(np.stack([mid[cx.squares.ravel()], np.repeat(centre, 4)], axis=1))
    start, end = cx.side_endpoints()
    tails_side = cx.edges[cx.squares, 0]

    def half(k: np.ndarray, corner: np.ndarray) -> np.ndarray:  # edge corner -> midpoint of side k
        return np.where(tails_side[np.arange(len(k)), k] == corner, 0, e_count) + cx.squares[np.arange(len(k)), k]

    squares = []
    n = cx.n_squares
    corner_sides = {  # each corner of the old square, with its x side and y side in the new small square
        "v00": (start[:, BOTTOM], BOTTOM, LEFT),
        "v10": (start[:, RIGHT], BOTTOM, RIGHT),
        "v11": (end[:, RIGHT], RIGHT, TOP),
        "v01": (start[:, TOP], TOP, LEFT),
    }
    for corner, sx, sy in corner_sides.values():
        kx, ky = np.full(n, sx), np.full(n, sy)
        squares.append(np.stack([half(kx, corner), spoke[:, sx], spoke[:, sy], half(ky, corner)], axis=1))
    return CubeComplex(
        v + e_count + n,
        np.concatenate(edges).reshape(-1, 2),
        np.concatenate(squares).reshape(-1, 4) if n else np.zeros((0, 4), dtype=np.int64),
    )


# --------------------------------------------------------------------------------------------------
@dataclass(frozen=True, eq=False)
class SimpleSubdivision:
    """A simple graph (no loops, no multiple edges) subdividing a :class:`~mpa.graph.MetricGraph`.

    Attributes
    ----------
    n_vertices : int
        Vertices ``0 .. n_vertices - 1``; the first ``len(graph.vertices)`` are the graph's vertices in order, the
        others are subdivision points.
    edges : numpy.ndarray
        Shape (E, 2): ``tail, head`` of each edge of the subdivision.
    original_vertex_count : int
        Number of vertices of the graph before subdivision.
    component : numpy.ndarray
        Shape (n_vertices,): index of the connected component of the graph containing each vertex.
    """

    n_vertices: int
    edges: np.ndarray
    original_vertex_count: int
    component: np.ndarray

    @property
    def n_edges(self) -> int:
        """Number of edges."""
        return len(self.edges)

    def degrees(self) -> np.ndarray:
        """Degree of every vertex. Shape (n_vertices,)."""
        return np.bincount(self.edges.ravel(), minlength=self.n_vertices)


def simple_subdivision(graph: MetricGraph) -> SimpleSubdivision:
    """Subdivide ``graph`` into a simple graph: every loop into 3 edges, every extra parallel edge into 2 edges.

    For two robots this is enough subdivision for Abrams' theorem (every cycle has at least 3 edges), so
    ``D₂`` of the result is a deformation retract of ``F(graph, 2)``. Edge lengths play no role.

    Parameters
    ----------
    graph : MetricGraph
        Any finite graph; loops and multiple edges are allowed.

    Returns
    -------
    SimpleSubdivision
    """
    index = {v: i for i, v in enumerate(graph.vertices)}
    n = len(graph.vertices)
    edges: list[tuple[int, int]] = []
    seen: set[tuple[int, int]] = set()
    for e in graph.edges:
        u, v = index[e.tail], index[e.head]
        if u == v:
            a, b = n, n + 1
            n += 2
            edges += [(u, a), (a, b), (b, u)]
        elif (min(u, v), max(u, v)) in seen:
            edges += [(u, n), (n, v)]
            n += 1
        else:
            seen.add((min(u, v), max(u, v)))
            edges.append((u, v))
    arr = np.array(edges, dtype=np.int64).reshape(-1, 2)
    arr.setflags(write=False)
    comp = CubeComplex(n, arr).vertex_components()
    comp.setflags(write=False)
    return SimpleSubdivision(n, arr, len(graph.vertices), comp)


def expected_cell_counts(subdivision: SimpleSubdivision) -> CellCounts:
    """Cell counts of ``D₂`` predicted by the formulas ``V(V-1)``, ``2E(V-2)``, ``2[C(E,2) - Σ_v C(d_v,2)]``.

    Parameters
    ----------
    subdivision : SimpleSubdivision

    Returns
    -------
    CellCounts
    """
    v, e = subdivision.n_vertices, subdivision.n_edges
    d = subdivision.degrees().astype(np.int64)
    pairs = e * (e - 1) // 2 - int(np.sum(d * (d - 1) // 2))
    return CellCounts(v * (v - 1), 2 * e * (v - 2), 2 * pairs)


@dataclass(frozen=True, eq=False)
class DiscretizedConfigurationSpace:
    """Abrams' discretized configuration space ``D₂(Γ)`` of two ordered robots.

    Attributes
    ----------
    subdivision : SimpleSubdivision
        The simple graph Γ' the cells are built from.
    complex : CubeComplex
        The cube complex. Square ``(e, f)`` has robot 1 moving along ``e`` in the x direction and robot 2 along
        ``f`` in the y direction; all signs are ``+1``.
    vertex_cells : numpy.ndarray
        Shape (V(V-1), 2): vertex of Γ' occupied by robot 1 and by robot 2 at each vertex of the complex.
    """

    subdivision: SimpleSubdivision
    complex: CubeComplex
    vertex_cells: np.ndarray


def discretized_configuration_space(graph: MetricGraph | SimpleSubdivision) -> DiscretizedConfigurationSpace:
    """Build ``D₂(Γ)`` for a graph (subdivided first) or for an already simple subdivision.

    Parameters
    ----------
    graph : MetricGraph or SimpleSubdivision

    Returns
    -------
    DiscretizedConfigurationSpace

    Examples
    --------
    >>> from mpa.graph import MetricGraph
    >>> y_graph = MetricGraph.from_edge_list([["c", "a"], ["c", "b"], ["c", "d"]])
    >>> discretized_configuration_space(y_graph).complex.cell_counts
    CellCounts(vertices=12, edges=12, squares=0)
    """
    sub = graph if isinstance(graph, SimpleSubdivision) else simple_subdivision(graph)
    n = sub.n_vertices
    ge = sub.edges.tolist()
    vid = np.full((n, n), -1, dtype=np.int64)
    pairs = [(v, w) for v in range(n) for w in range(n) if v != w]
    for i, (v, w) in enumerate(pairs):
        vid[v, w] = i
    edges: list[tuple[int, int]] = []
    eid1: dict[tuple[int, int], int] = {}  # (graph edge, robot-2 vertex) -> complex edge, robot 1 moves
    eid2: dict[tuple[int, int], int] = {}  # (robot-1 vertex, graph edge) -> complex edge, robot 2 moves
    for k, (a, b) in enumerate(ge):
        for w in range(n):
            if w != a and w != b:
                eid1[(k, w)] = len(edges)
                edges.append((int(vid[a, w]), int(vid[b, w])))
    for k, (c, d) in enumerate(ge):
        for v in range(n):
            if v != c and v != d:
                eid2[(v, k)] = len(edges)
                edges.append((int(vid[v, c]), int(vid[v, d])))
    squares: list[tuple[int, int, int, int]] = []
    for k, (a, b) in enumerate(ge):
        for m, (c, d) in enumerate(ge):
            if len({a, b, c, d}) == 4:
                squares.append((eid1[(k, c)], eid2[(b, m)], eid1[(k, d)], eid2[(a, m)]))
    cx = CubeComplex(
        len(pairs), np.array(edges, dtype=np.int64).reshape(-1, 2), np.array(squares, dtype=np.int64).reshape(-1, 4)
    )
    cells = np.array(pairs, dtype=np.int64).reshape(-1, 2)
    cells.setflags(write=False)
    return DiscretizedConfigurationSpace(sub, cx, cells)


# --------------------------------------------------------------------------------------------------
@dataclass(frozen=True, eq=False)
class Collapse:
    """Result of :func:`collapse_free_faces`.

    Attributes
    ----------
    complex : CubeComplex
        The collapsed subcomplex (renumbered); homotopy equivalent to the input.
    vertices : numpy.ndarray
        Shape (V',): index in the input complex of each remaining vertex.
    squares_removed : int
        Squares removed together with a free edge.
    edges_removed : int
        Edges removed in total (with a square, or with a free vertex).
    """

    complex: CubeComplex
    vertices: np.ndarray
    squares_removed: int
    edges_removed: int


def collapse_free_faces(cx: CubeComplex) -> Collapse:
    """Greedy elementary collapses: squares through free edges, then edges through free vertices.

    A free edge is a side of exactly one remaining square; removing the pair (square, edge) is a deformation
    retraction. Removing one square never makes another free edge non-free, so the set of squares that can be
    collapsed away does not depend on the order. Then edges lying on no square are removed with a vertex that
    lies on exactly one edge, which prunes trees hanging off the complex.

    Parameters
    ----------
    cx : CubeComplex

    Returns
    -------
    Collapse
    """
    n_sq = cx.n_squares
    sq_alive = np.ones(n_sq, dtype=bool)
    edge_alive = np.ones(cx.n_edges, dtype=bool)
    on_edge: list[list[int]] = [[] for _ in range(cx.n_edges)]
    for s, row in enumerate(cx.squares.tolist()):
        for e in set(row):
            on_edge[e].append(s)
    count = np.array([len(x) for x in on_edge], dtype=np.int64)
    queue = deque(int(e) for e in np.nonzero(count == 1)[0])
    removed_sq = 0
    sides = cx.squares.tolist()
    while queue:
        e = queue.popleft()
        if not edge_alive[e] or count[e] != 1:
            continue
        s = next(s for s in on_edge[e] if sq_alive[s])
        sq_alive[s] = False
        edge_alive[e] = False
        removed_sq += 1
        for f in set(sides[s]):
            if f != e:
                count[f] -= 1
                if count[f] == 1:
                    queue.append(f)
    # edges through free vertices (edges lying on no remaining square)
    vert_alive = np.ones(cx.n_vertices, dtype=bool)
    incident: list[list[int]] = [[] for _ in range(cx.n_vertices)]
    for k, (a, b) in enumerate(cx.edges.tolist()):
        if edge_alive[k]:
            incident[a].append(k)
            incident[b].append(k)
    vdeg = np.array([len(x) for x in incident], dtype=np.int64)
    vqueue = deque(int(v) for v in np.nonzero(vdeg == 1)[0])
    ends = cx.edges.tolist()
    removed_free = 0
    while vqueue:
        v = vqueue.popleft()
        if not vert_alive[v] or vdeg[v] != 1:
            continue
        k = next(k for k in incident[v] if edge_alive[k])
        if count[k] > 0:  # the edge still bounds a square
            continue
        edge_alive[k] = False
        vert_alive[v] = False
        removed_free += 1
        vdeg[v] -= 1
        w = ends[k][0] if ends[k][1] == v else ends[k][1]
        vdeg[w] -= 1
        if vdeg[w] == 1:
            vqueue.append(w)
    vertices = np.nonzero(vert_alive)[0]
    sub = cx.subcomplex(vertices, np.nonzero(edge_alive)[0], np.nonzero(sq_alive)[0])
    vertices.setflags(write=False)
    return Collapse(sub, vertices, removed_sq, removed_sq + removed_free)
