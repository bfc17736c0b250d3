"""Topology of the configuration space F(Γ, 2) of two ordered robots on any finite graph Γ.

Given a graph (loops and multiple edges allowed), :func:`configuration_space_topology` computes for
``F(Γ, 2) = {(x, y) ∈ Γ × Γ : x ≠ y}``:

- the Betti numbers ``b0, b1, b2`` over ℚ (exact integer elimination) and over 𝔽₂, per path component;
- the Euler characteristic, checked against the cell count of Abrams' discretized model ``D₂(Γ)`` and against
  ``χ(Γ)² + χ(Γ) - Σ_v (d_v - 1)(d_v - 2)``;
- bounds on the homotopy dimension: at most ``min(2, m)`` (``m`` = vertices of degree >= 3; 1 for a circle), at
  most 1 when elementary collapses remove every square, at least 2 when ``b2 > 0``;
- Farber's topological complexity ``TC`` (non-reduced: ``TC(point) = 1``) of every path component: exact from
  ``b1`` when the component is homotopy equivalent to a graph, otherwise between ``zcl + 1`` and ``2 hdim + 1``,
  where ``zcl`` is the zero-divisor cup-length of the cohomology ring over 𝔽₂ and over 𝔽_p, ``p = 2¹⁹ - 1``
  (cup products computed on the cube complex with the Serre diagonal). ``TC`` is reported exactly when the two
  bounds meet, ``None`` otherwise.

F(Γ, 2) is disconnected when Γ is an interval or Γ is disconnected. Motion planning only makes sense inside one path
component, so :attr:`ConfigurationSpaceTopology.tc` is the *maximum over the path components* of their TC (Farber's
TC of a disconnected space, with one motion planner for all pairs of points, would be infinite).

The generic part works on any :class:`~mpa.topology.discretized.CubeComplex` of dimension <= 2
(:func:`cube_complex_topology`), which the tests use on a torus and a Klein bottle.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any, NamedTuple

import numpy as np
from numpy.typing import NDArray

from mpa.errors import InvalidInputError, PlanningError
from mpa.graph import MetricGraph, farber_tc_of_graph
from mpa.topology.algebra import FIELD_PRIME
from mpa.topology.cohomology import (
    FieldCohomology,
    field_cohomology,
    rational_rank_of_boundary,
    zero_divisor_cup_length_of,
)
from mpa.topology.discretized import (
    CellCounts,
    CubeComplex,
    DiscretizedConfigurationSpace,
    SimpleSubdivision,
    collapse_free_faces,
    cubical_subdivision,
    discretized_configuration_space,
    expected_cell_counts,
)

__all__ = [
    "ComponentTopology",
    "ConfigurationSpaceTopology",
    "HomotopyDimension",
    "configuration_space_topology",
    "cube_complex_topology",
    "euler_characteristic_formula",
]


# ==================================================================================================
# Results
# ==================================================================================================
@dataclass(frozen=True)
class HomotopyDimension:
    """Bounds on the homotopy dimension (smallest dimension of a homotopy equivalent CW complex).

    Attributes
    ----------
    lower, upper : int
        ``lower <= hdim <= upper``.
    collapsed_to_graph : bool
        True when elementary collapses removed every square (so ``hdim <= 1`` is proved by the collapse).
    """

    lower: int
    upper: int
    collapsed_to_graph: bool

    @property
    def exact(self) -> bool:
        """True when ``lower == upper``."""
        return self.lower == self.upper

    def to_dict(self) -> dict[str, Any]:
        """JSON-friendly dictionary."""
        return {"lower": self.lower, "upper": self.upper, "collapsed_to_graph": self.collapsed_to_graph}


@dataclass(frozen=True)
class ComponentTopology:
    """Topology of one path component of a cube complex (of ``F(Γ, 2)`` in :func:`configuration_space_topology`).

    Attributes
    ----------
    betti, betti_f2 : tuple of int
        ``(b0, b1, b2)`` over ℚ and over 𝔽₂ (``b0 = 1``).
    euler : int
        Euler characteristic.
    h1_torsion_free : bool or None
        True when ``H₁(·; ℤ)`` is proved free, False when 𝔽₂ and ℚ disagree (2-torsion), None when undecided.
    homotopy_dimension : HomotopyDimension
    zcl_f2, zcl_fp : int or None
        Zero-divisor cup-length over 𝔽₂ and over 𝔽_p (``p = FIELD_PRIME``); None when not needed (the component is
        homotopy equivalent to a graph and TC follows from ``b1``).
    tc : int or None
        Farber's (non-reduced) topological complexity when decided, else None.
    tc_bounds : tuple of int
        ``(lower, upper)`` bounds on TC.
    collapsed_cells : CellCounts
        Cells left in this component after the elementary collapses.
    graph_components : tuple of int or None
        For ``F(Γ, 2)``: the components of Γ holding robot 1 and robot 2 (equal unless Γ is disconnected).
    """

    betti: tuple[int, int, int]
    betti_f2: tuple[int, int, int]
    euler: int
    h1_torsion_free: bool | None
    homotopy_dimension: HomotopyDimension
    zcl_f2: int | None
    zcl_fp: int | None
    tc: int | None
    tc_bounds: tuple[int, int]
    collapsed_cells: CellCounts
    graph_components: tuple[int, int] | None = None

    def to_dict(self) -> dict[str, Any]:
        """JSON-friendly dictionary."""
        return {
            "betti": list(self.betti),
            "betti_f2": list(self.betti_f2),
            "euler": self.euler,
            "h1_torsion_free": self.h1_torsion_free,
            "homotopy_dimension": self.homotopy_dimension.to_dict(),
            "zcl_f2": self.zcl_f2,
            "zcl_fp": self.zcl_fp,
            "tc": self.tc,
            "tc_bounds": list(self.tc_bounds),
            "collapsed_cells": self.collapsed_cells.to_dict(),
            "graph_components": None if self.graph_components is None else list(self.graph_components),
        }


@dataclass(frozen=True)
class ConfigurationSpaceTopology:
    """Topology of ``F(Γ, 2)``, two ordered robots on a graph Γ.

    Attributes
    ----------
    betti, betti_f2 : tuple of int
        ``(b0, b1, b2)`` over ℚ and over 𝔽₂ (``b_k = 0`` for ``k >= 3``).
    euler : int
        Euler characteristic from the Betti numbers (equal to the cell count of ``D₂(Γ)``).
    euler_formula : int
        ``χ(Γ)² + χ(Γ) - Σ_v (d_v - 1)(d_v - 2)`` (checked equal to ``euler``).
    connected : bool
        ``b0 == 1``.
    cell_counts : CellCounts
        Cells of ``D₂`` of the simple subdivision of Γ (checked against the closed formulas).
    subdivided_graph : tuple of int
        ``(V, E)`` of the simple subdivision.
    essential_vertices : int
        ``m``, the number of vertices of Γ of degree >= 3.
    homotopy_dimension : HomotopyDimension
        Over all components: ``lower``/``upper`` are maxima, ``collapsed_to_graph`` holds if it holds for all.
    tc : int or None
        Max over path components of their TC, when decided (see the module docstring).
    tc_bounds : tuple of int
        ``(max of lower bounds, max of upper bounds)`` over the components.
    h1_torsion_free : bool or None
        All components torsion-free (True), some 2-torsion found (False), or undecided (None).
    components : tuple of ComponentTopology
        One per path component.
    """

    betti: tuple[int, int, int]
    betti_f2: tuple[int, int, int]
    euler: int
    euler_formula: int
    connected: bool
    cell_counts: CellCounts
    subdivided_graph: tuple[int, int]
    essential_vertices: int
    homotopy_dimension: HomotopyDimension
    tc: int | None
    tc_bounds: tuple[int, int]
    h1_torsion_free: bool | None
    components: tuple[ComponentTopology, ...]

    @property
    def tc_per_component(self) -> tuple[int | None, ...]:
        """TC of every path component (None where undecided)."""
        return tuple(c.tc for c in self.components)

    def to_dict(self) -> dict[str, Any]:
        """JSON-friendly dictionary (tuples become lists)."""
        return {
            "betti": list(self.betti),
            "betti_f2": list(self.betti_f2),
            "euler": self.euler,
            "euler_formula": self.euler_formula,
            "connected": self.connected,
            "tc": self.tc,
            "tc_bounds": list(self.tc_bounds),
            "tc_per_component": list(self.tc_per_component),
            "tc_convention": "Farber, non-reduced (TC(point) = 1); max over path components",
            "homotopy_dimension": self.homotopy_dimension.to_dict(),
            "h1_torsion_free": self.h1_torsion_free,
            "cell_counts": self.cell_counts.to_dict(),
            "subdivided_graph": {"vertices": self.subdivided_graph[0], "edges": self.subdivided_graph[1]},
            "essential_vertices": self.essential_vertices,
            "components": [c.to_dict() for c in self.components],
        }


# ==================================================================================================
# Generic cube complexes
# ==================================================================================================
def _connected_topology(
    cx: CubeComplex,
    *,
    hdim_upper: int,
    collapsed_to_graph: bool,
    tc_upper: int | None = None,
    graph_components: tuple[int, int] | None = None,
) -> ComponentTopology:
    """Topology of a connected (already collapsed) cube complex of homotopy dimension known to be <= hdim_upper."""
    counts = cx.cell_counts
    if cx.n_squares == 0:
        return _graph_topology(cx, hdim_upper, collapsed_to_graph, graph_components)
    rank_q, unit_only = rational_rank_of_boundary(cx)
    n_cycles = cx.n_edges - cx.n_vertices + 1
    betti = (1, n_cycles - rank_q, cx.n_squares - rank_q)
    coh2 = field_cohomology(cx, 2)
    betti_f2 = (1, coh2.b1, coh2.b2)
    torsion_free: bool | None = True if unit_only else (False if betti_f2 != betti else None)
    euler = 1 - betti[1] + betti[2]
    if euler != counts.euler_characteristic or 1 - betti_f2[1] + betti_f2[2] != euler:
        raise PlanningError(
            f"Euler characteristic from Betti numbers {betti} / {betti_f2} differs from the cell count {counts}"
        )
    lower = 2 if (betti[2] or betti_f2[2]) else (1 if (betti[1] or betti_f2[1]) else 0)
    if lower > hdim_upper:
        raise PlanningError(
            f"Betti numbers {betti} need homotopy dimension >= {lower}, but theory bounds it by {hdim_upper}"
        )
    hd = HomotopyDimension(lower, hdim_upper, collapsed_to_graph)
    if hdim_upper <= 1:  # homotopy equivalent to a connected graph: Farber's formula, hdim 1 (or 0 for a tree)
        tc = farber_tc_of_graph(betti[1])
        hd = HomotopyDimension(lower, lower, collapsed_to_graph)
        return ComponentTopology(
            betti, betti_f2, euler, torsion_free, hd, None, None, tc, (tc, tc), counts, graph_components
        )
    zcl2, zclp = _zero_divisor_cup_lengths(cx, coh2, betti, torsion_free)
    lo = max(zcl2, zclp) + 1
    hi = 2 * hdim_upper + 1 if tc_upper is None else min(2 * hdim_upper + 1, tc_upper)
    if lo > hi:
        raise PlanningError(f"TC lower bound {lo} exceeds the upper bound {hi}")
    return ComponentTopology(
        betti,
        betti_f2,
        euler,
        torsion_free,
        hd,
        zcl2,
        zclp,
        lo if lo == hi else None,
        (lo, hi),
        counts,
        graph_components,
    )


def _graph_topology(
    cx: CubeComplex, hdim_upper: int, collapsed_to_graph: bool, graph_components: tuple[int, int] | None
) -> ComponentTopology:
    """Topology of a connected complex without squares (a graph): Betti numbers from the counts, Farber's TC."""
    b1 = cx.n_edges - cx.n_vertices + 1
    betti = (1, b1, 0)
    tc = farber_tc_of_graph(b1)
    hdim = 0 if cx.n_edges == 0 else 1  # a collapsed graph with an edge but no free vertex has a cycle
    if hdim > hdim_upper:
        raise PlanningError(f"a component collapsed to a graph with b1 = {b1} > 0, expected hdim <= {hdim_upper}")
    hd = HomotopyDimension(hdim, hdim, collapsed_to_graph)
    return ComponentTopology(betti, betti, 1 - b1, True, hd, None, None, tc, (tc, tc), cx.cell_counts, graph_components)


def _zero_divisor_cup_lengths(
    cx: CubeComplex, coh2: FieldCohomology, betti: tuple[int, int, int], torsion_free: bool | None
) -> tuple[int, int]:
    """Zero-divisor cup-lengths over F_2 (from ``coh2``) and over F_p, on a subdivision if the complex's edge
    directions disagree with a square's coordinates (the Serre diagonal needs all signs +1)."""
    if cx.signs is None:
        raise PlanningError("internal: cx.signs is not set")
    if np.any(cx.signs != 1):
        cx = cubical_subdivision(cx)
        coh2 = field_cohomology(cx, 2)
    zcl2 = zero_divisor_cup_length_of(cx, coh2)
    cohp = field_cohomology(cx, FIELD_PRIME)
    if (cohp.b1, cohp.b2) != betti[1:] and torsion_free:
        raise PlanningError(f"Betti numbers over F_p {(cohp.b1, cohp.b2)} differ from those over Q {betti[1:]}")
    return zcl2, zero_divisor_cup_length_of(cx, cohp)


def cube_complex_topology(cx: CubeComplex, max_homotopy_dimension: int = 2) -> tuple[ComponentTopology, ...]:
    """Homology, homotopy-dimension bounds and TC bounds of every path component of a cube complex.

    The complex is first collapsed through free faces (:func:`~mpa.topology.discretized.collapse_free_faces`).

    Parameters
    ----------
    cx : CubeComplex
        Any finite cube complex of dimension <= 2.
    max_homotopy_dimension : int
        A known upper bound on the homotopy dimension of every component (default 2, the dimension).

    Returns
    -------
    tuple of ComponentTopology
        In the order of the components' first vertex in the collapsed complex.

    Examples
    --------
    A square ``[0, 2]²`` made of four unit squares is contractible.

    >>> from mpa.topology.discretized import CubeComplex
    >>> grid = lambda i, j: 3 * j + i
    >>> edges = [(grid(i, j), grid(i + 1, j)) for j in range(3) for i in range(2)]
    >>> edges += [(grid(i, j), grid(i, j + 1)) for j in range(2) for i in range(3)]
    >>> x = lambda i, j: 2 * j + i
    >>> y = lambda i, j: 6 + 3 * j + i
    >>> squares = [(x(i, j), y(i + 1, j), x(i, j + 1), y(i, j)) for j in range(2) for i in range(2)]
    >>> [c.tc for c in cube_complex_topology(CubeComplex(9, edges, squares))]
    [1]
    """
    if max_homotopy_dimension not in (0, 1, 2):
        raise InvalidInputError(f"max_homotopy_dimension is {max_homotopy_dimension!r}, expected 0, 1 or 2")
    col = collapse_free_faces(cx)
    return tuple(
        _connected_topology(sub, hdim_upper=max_homotopy_dimension, collapsed_to_graph=sub.n_squares == 0)
        for sub, _ in _components(col.complex)
    )


def _components(cx: CubeComplex) -> list[tuple[CubeComplex, np.ndarray]]:
    """Path components as (subcomplex, vertex indices) pairs."""
    label = cx.vertex_components()
    n = int(label.max()) + 1 if cx.n_vertices else 0
    edge_label = label[cx.edges[:, 0]]
    square_label = edge_label[cx.squares[:, 0]] if cx.n_squares else np.zeros(0, dtype=np.int64)
    out = []
    for c in range(n):
        verts = np.nonzero(label == c)[0]
        out.append((cx.subcomplex(verts, np.nonzero(edge_label == c)[0], np.nonzero(square_label == c)[0]), verts))
    return out


# ==================================================================================================
# Configuration spaces of graphs
# ==================================================================================================
def _summed_betti(per_component: list[tuple[int, int, int]]) -> tuple[int, int, int]:
    """Betti numbers b0, b1, b2 of a disjoint union: the sums over its components."""
    b0, b1, b2 = (int(sum(b[k] for b in per_component)) for k in range(3))
    return b0, b1, b2


def euler_characteristic_formula(graph: MetricGraph) -> int:
    """``χ(F(Γ, 2)) = χ(Γ)² + χ(Γ) - Σ_v (d_v - 1)(d_v - 2)`` (a loop adds 2 to the degree).

    Parameters
    ----------
    graph : MetricGraph

    Returns
    -------
    int

    Examples
    --------
    >>> theta = MetricGraph.from_edge_list([["a", "b"], ["a", "b"], ["a", "b"]])
    >>> euler_characteristic_formula(theta)
    -4
    """
    chi = graph.euler_characteristic()
    return chi * chi + chi - sum((graph.degree(v) - 1) * (graph.degree(v) - 2) for v in graph.vertices)


def configuration_space_topology(graph: MetricGraph) -> ConfigurationSpaceTopology:
    """Betti numbers, Euler characteristic, homotopy dimension and TC of ``F(Γ, 2)`` for any finite graph Γ.

    Parameters
    ----------
    graph : MetricGraph
        Loops, multiple edges, isolated vertices and several components are allowed; lengths are ignored.
        A track (anything with an ``as_graph()`` method returning a MetricGraph) is accepted too.

    Returns
    -------
    ConfigurationSpaceTopology

    Raises
    ------
    InvalidInputError
        If the graph is a single point or empty (then ``F(Γ, 2)`` is empty).
    PlanningError
        If an internal consistency check fails (cell counts, Euler characteristic, TC bounds): a bug.

    Examples
    --------
    >>> lollipop = MetricGraph.from_edge_list([["F", "P"], ["P", "P"]])
    >>> top = configuration_space_topology(lollipop)
    >>> top.betti, top.tc
    ((1, 3, 0), 3)
    """
    graph = _as_metric_graph(graph)
    d2, euler_formula = _checked_discretization(graph)
    per_graph_component = _graph_components(graph, d2.subdivision)
    comps = _component_topologies(d2, per_graph_component)
    betti = _summed_betti([c.betti for c in comps])
    euler = betti[0] - betti[1] + betti[2]
    if euler != euler_formula:
        raise PlanningError(f"Euler characteristic from the Betti numbers {betti} is {euler}, formula {euler_formula}")
    lo = max(c.tc_bounds[0] for c in comps)
    hi = max(c.tc_bounds[1] for c in comps)
    return ConfigurationSpaceTopology(
        betti=betti,
        betti_f2=_summed_betti([c.betti_f2 for c in comps]),
        euler=euler,
        euler_formula=euler_formula,
        connected=betti[0] == 1,
        cell_counts=d2.complex.cell_counts,
        subdivided_graph=(d2.subdivision.n_vertices, d2.subdivision.n_edges),
        essential_vertices=int(per_graph_component.essential.sum()),
        homotopy_dimension=HomotopyDimension(
            max(c.homotopy_dimension.lower for c in comps),
            max(c.homotopy_dimension.upper for c in comps),
            all(c.homotopy_dimension.collapsed_to_graph for c in comps),
        ),
        tc=lo if lo == hi else None,
        tc_bounds=(lo, hi),
        h1_torsion_free=_all_torsion_free([c.h1_torsion_free for c in comps]),
        components=tuple(comps),
    )


def _as_metric_graph(graph: object) -> MetricGraph:
    """The graph itself, or a track's graph (``as_graph()``); InvalidInputError if ``F(Γ, 2)`` would be empty."""
    as_graph = getattr(graph, "as_graph", None)
    if not isinstance(graph, MetricGraph) and callable(as_graph):
        graph = as_graph()
    if not isinstance(graph, MetricGraph):
        raise InvalidInputError(f"graph is a {type(graph).__name__}, expected a MetricGraph or a track")
    if graph.n_vertices == 0 or (graph.n_vertices == 1 and graph.n_edges == 0):
        raise InvalidInputError(
            f"graph has {graph.n_vertices} vertices and no edges: two robots do not fit, expected at least one edge "
            "or two vertices"
        )
    return graph


def _checked_discretization(graph: MetricGraph) -> tuple[DiscretizedConfigurationSpace, int]:
    """Abrams' ``D₂(Γ)`` and the Euler characteristic of the formula, after checking its cells against both."""
    d2 = discretized_configuration_space(graph)
    counts = d2.complex.cell_counts
    expected = expected_cell_counts(d2.subdivision)
    if counts != expected:
        raise PlanningError(f"D2 has cell counts {counts}, expected {expected} from the formulas")
    euler_formula = euler_characteristic_formula(graph)
    if counts.euler_characteristic != euler_formula:
        raise PlanningError(f"D2 has Euler characteristic {counts.euler_characteristic}, formula gives {euler_formula}")
    return d2, euler_formula


class _GraphComponents(NamedTuple):
    """Per component of Γ (arrays indexed by component): essential vertices, first Betti number, circle or not;
    and the component of every vertex of the subdivision."""

    essential: NDArray[np.int64]
    b1: NDArray[np.int64]
    is_circle: NDArray[np.bool_]
    of_vertex: NDArray[np.int64]


def _graph_components(graph: MetricGraph, sub: SimpleSubdivision) -> _GraphComponents:
    """Essential vertices (degree >= 3), b1 and circle-ness of each component of Γ (from its subdivision)."""
    n_orig = sub.original_vertex_count
    deg = np.array([graph.degree(v) for v in graph.vertices], dtype=np.int64)
    comp_of = sub.component
    n_gc = int(comp_of.max()) + 1
    essential = np.bincount(comp_of[:n_orig], weights=(deg >= 3), minlength=n_gc).astype(np.int64)
    gverts = np.bincount(comp_of, minlength=n_gc)
    gedges = np.bincount(comp_of[sub.edges[:, 0]], minlength=n_gc) if sub.n_edges else np.zeros(n_gc, dtype=int)
    gb1 = (gedges - gverts + 1).astype(np.int64)
    has_high_or_leaf = np.bincount(comp_of, weights=(sub.degrees() != 2), minlength=n_gc)
    is_circle = (gb1 == 1) & (has_high_or_leaf == 0)
    return _GraphComponents(essential, gb1, is_circle, comp_of)


def _component_topologies(d2: DiscretizedConfigurationSpace, gc: _GraphComponents) -> list[ComponentTopology]:
    """Collapse ``D₂(Γ)`` and compute the topology of each of its components, with the bounds on homotopy
    dimension and TC that the components of Γ holding the two robots give."""
    col = collapse_free_faces(d2.complex)
    comps: list[ComponentTopology] = []
    for cx, verts in _components(col.complex):
        v1, v2 = d2.vertex_cells[col.vertices[verts[0]]]
        ci, cj = int(gc.of_vertex[v1]), int(gc.of_vertex[v2])
        tc_upper: int | None = None
        if ci != cj:  # the product Γ_i × Γ_j of two components of Γ
            hdim = int(gc.b1[ci] > 0) + int(gc.b1[cj] > 0)
            tc_upper = farber_tc_of_graph(int(gc.b1[ci])) + farber_tc_of_graph(int(gc.b1[cj])) - 1
        elif gc.is_circle[ci]:
            hdim = 1
        else:
            hdim = min(2, int(gc.essential[ci]))
        comps.append(
            _connected_topology(
                cx,
                hdim_upper=hdim,
                collapsed_to_graph=cx.n_squares == 0,
                tc_upper=tc_upper,
                graph_components=(ci, cj),
            )
        )
    return comps


def _all_torsion_free(flags: list[bool | None]) -> bool | None:
    """H1 torsion-free for all components: False if one is not, None if one is unknown, else True."""
    return False if False in flags else (True if all(flags) else None)
