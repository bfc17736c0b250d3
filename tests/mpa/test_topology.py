"""Topology of F(Γ, 2): the reference examples of docs/conventions.md, random multigraphs, surfaces as cube
complexes, cup-length, CLI, errors."""

from __future__ import annotations

import argparse
import doctest
import importlib.util
import itertools
import json
from pathlib import Path

import numpy as np
import pytest
from hypothesis import HealthCheck, event, given, note, settings
from hypothesis import strategies as st

import mpa.topology
import mpa.topology.cohomology
import mpa.topology.configuration
import mpa.topology.discretized
from mpa.errors import InvalidInputError, PlanningError
from mpa.graph import Edge, MetricGraph
from mpa.topology import (
    FIELD_PRIME,
    configuration_space_topology,
    cube_complex_topology,
    euler_characteristic_formula,
    graph_from_json_data,
    load_graph_json,
    zero_divisor_cup_length,
)
from mpa.topology.algebra import Echelon, dense_independent_columns
from mpa.topology.cohomology import cup_products, field_cohomology
from mpa.topology.discretized import (
    CubeComplex,
    collapse_free_faces,
    cubical_subdivision,
    discretized_configuration_space,
    expected_cell_counts,
    simple_subdivision,
)
from mpa.tracks import Circle, Interval, Lollipop
from trajopt.cli import topology as cli_topology


def seeded(max_examples: int) -> settings:
    """Derandomized (seeded) hypothesis settings: the same cases on every run; failing cases are printed."""
    return settings(
        max_examples=max_examples, derandomize=True, deadline=None, suppress_health_check=[HealthCheck.too_slow]
    )


# --------------------------------------------------------------------------------------------------
# reference examples (docs/conventions.md, "Topology of two robots on a graph"):
# (edge list, (b0, b1, b2), TC of every path component)
EXAMPLES = {
    "interval": ([["F", "P"]], (2, 0, 0), (1, 1)),
    "circle": ([["P", "P"]], (1, 1, 0), (2,)),
    "Y-graph": ([["c", "a"], ["c", "b"], ["c", "d"]], (1, 1, 0), (2,)),
    "lollipop": ([["F", "P"], ["P", "P"]], (1, 3, 0), (3,)),
    "theta": ([["a", "b"], ["a", "b"], ["a", "b"]], (1, 5, 0), (3,)),
    "star4": ([[0, 1], [0, 2], [0, 3], [0, 4]], (1, 5, 0), (3,)),
}


@pytest.mark.parametrize("name", sorted(EXAMPLES))
def test_spec_examples(name: str) -> None:
    edges, betti, tcs = EXAMPLES[name]
    top = configuration_space_topology(graph_from_json_data({"edges": edges}))
    assert top.betti == betti, name
    assert top.betti_f2 == betti, name
    assert top.tc_per_component == tcs, name
    assert top.tc == max(tcs) and top.tc_bounds == (max(tcs), max(tcs))
    assert top.connected == (betti[0] == 1)
    assert top.euler == top.euler_formula == betti[0] - betti[1] + betti[2]
    assert top.homotopy_dimension.collapsed_to_graph and top.h1_torsion_free is True


@pytest.mark.parametrize(
    ("graph", "betti", "tc"),
    [
        (MetricGraph(("F", "P"), (Edge("stick", "F", "P", 1.0),)), (2, 0, 0), 1),
        (MetricGraph(("P",), (Edge("loop", "P", "P", 1.0),)), (1, 1, 0), 2),
        (MetricGraph(("F", "P"), (Edge("stick", "F", "P", 1.0), Edge("loop", "P", "P", 2.0))), (1, 3, 0), 3),
        (Interval(2.0).as_graph(), (2, 0, 0), 1),
        (Circle(1.7).as_graph(), (1, 1, 0), 2),
        (Lollipop(1.0, 1.0).as_graph(), (1, 3, 0), 3),
        (Lollipop(0.3, 2.0), (1, 3, 0), 3),  # a track is accepted directly
    ],
)
def test_the_three_tracks(graph: object, betti: tuple[int, int, int], tc: int) -> None:
    top = configuration_space_topology(graph)  # type: ignore[arg-type]
    assert (top.betti, top.betti_f2, top.tc) == (betti, betti, tc)
    assert all(c.tc == tc for c in top.components)


def test_interval_has_two_contractible_components() -> None:
    top = configuration_space_topology(Interval(1.0).as_graph())
    assert not top.connected and len(top.components) == 2
    assert [c.homotopy_dimension.upper for c in top.components] == [0, 0]
    assert top.to_dict()["tc_per_component"] == [1, 1]


def test_nonplanar_graphs_give_closed_orientable_surfaces_with_tc_5() -> None:
    # Abrams: D₂(K₅) and D₂(K₃,₃) are closed orientable surfaces (genus 6 and 4), so TC = 5
    k5 = [[a, b] for a, b in itertools.combinations(range(5), 2)]
    k33 = [[a, b] for a in range(3) for b in range(3, 6)]
    for edges, genus in ((k5, 6), (k33, 4)):
        top = configuration_space_topology(graph_from_json_data({"edges": edges}))
        assert top.betti == top.betti_f2 == (1, 2 * genus, 1)
        assert top.tc == 5 and top.tc_bounds == (5, 5)
        (comp,) = top.components
        assert comp.homotopy_dimension.lower == comp.homotopy_dimension.upper == 2
        assert comp.zcl_fp == 4  # ā₁b̄₁ā₂b̄₂ ≠ 0 over an odd prime
        cx = discretized_configuration_space(graph_from_json_data({"edges": edges})).complex
        per_edge = np.bincount(cx.squares.ravel(), minlength=cx.n_edges)
        assert np.all(per_edge == 2), "every edge lies on exactly two squares: a closed surface"


def test_disconnected_graph_products() -> None:
    # two circles: F has F(S¹,2) ≃ S¹ twice and the torus S¹ × S¹ twice (robots on different circles)
    top = configuration_space_topology(graph_from_json_data({"edges": [[0, 0], [1, 1]]}))
    assert top.betti == (4, 6, 2)
    tori = [c for c in top.components if c.graph_components[0] != c.graph_components[1]]
    assert len(tori) == 2
    for c in tori:
        assert c.betti == (1, 2, 1) and c.tc == 3  # zcl + 1 = 3 meets TC(S¹) + TC(S¹) - 1 = 3
    assert top.tc == 3


def test_cell_counts_match_formulas_and_collapse_keeps_euler() -> None:
    g = graph_from_json_data({"edges": [[0, 1], [1, 2], [2, 0], [0, 0], [1, 3], [1, 3], [3, 4], [4, 2]]})
    d2 = discretized_configuration_space(g)
    assert d2.complex.cell_counts == expected_cell_counts(d2.subdivision)
    col = collapse_free_faces(d2.complex)
    assert col.complex.euler_characteristic == d2.complex.euler_characteristic == euler_characteristic_formula(g)
    sub = d2.subdivision
    pairs = {tuple(sorted(e)) for e in sub.edges.tolist()}
    assert len(pairs) == sub.n_edges and all(a != b for a, b in pairs), "subdivision is a simple graph"


# --------------------------------------------------------------------------------------------------
# random multigraphs with loops


@st.composite
def multigraphs(draw: st.DrawFn, max_vertices: int = 10, max_edges: int = 12) -> list[list[int]]:
    n = draw(st.integers(1, max_vertices))
    m = draw(st.integers(1, max_edges))
    return [[draw(st.integers(0, n - 1)), draw(st.integers(0, n - 1))] for _ in range(m)]


def _expected_b0(graph: MetricGraph) -> int:
    """b0 of F(Γ,2): per component 0 (point), 2 (interval), 1 (otherwise); plus ordered pairs of components."""
    comps = graph.components()
    total = len(comps) * (len(comps) - 1)
    for vs in comps:
        es = [e for e in graph.edges if e.tail in vs]
        if not es:
            continue
        is_tree = len(es) == len(vs) - 1
        is_path = is_tree and all(graph.degree(v) <= 2 for v in vs)
        total += 2 if is_path else 1
    return total


@seeded(400)
@given(multigraphs())
def test_random_multigraphs_rational_f2_and_euler_agree(edges: list[list[int]]) -> None:
    note(f"edges = {edges}")
    g = MetricGraph.from_edge_list(edges)
    top = configuration_space_topology(g)
    assert top.betti == top.betti_f2, f"Q and F2 Betti numbers differ for edges {edges}"
    assert top.h1_torsion_free is True, edges
    assert top.euler == top.euler_formula == top.cell_counts.euler_characteristic, edges
    assert top.cell_counts == expected_cell_counts(simple_subdivision(g)), edges
    assert top.betti[0] == _expected_b0(g), edges
    lo, hi = top.tc_bounds
    assert 1 <= lo <= hi <= 5, edges
    event(f"b2 > 0: {top.betti[2] > 0}, TC bounds {top.tc_bounds}")
    m = sum(g.degree(v) >= 3 for v in g.vertices)
    if len(g.components()) == 1 and m <= 1:
        assert top.tc is not None and top.betti[2] == 0, edges  # homotopy equivalent to a graph
    for c in top.components:
        assert c.betti[0] == 1 and c.homotopy_dimension.lower <= c.homotopy_dimension.upper, edges
        if c.tc is not None:
            assert c.tc_bounds == (c.tc, c.tc), edges


@seeded(60)
@given(multigraphs(max_vertices=7, max_edges=9), st.data())
def test_subdividing_an_edge_changes_nothing(edges: list[list[int]], data: st.DataObject) -> None:
    k = data.draw(st.integers(0, len(edges) - 1))
    u, v = edges[k]
    finer = [*edges[:k], [u, "mid"], ["mid", v], *edges[k + 1 :]]
    note(f"edges = {edges}, subdivided edge {k}")
    a = configuration_space_topology(graph_from_json_data({"edges": edges}))
    b = configuration_space_topology(graph_from_json_data({"edges": finer}))
    assert (a.betti, a.betti_f2, a.euler) == (b.betti, b.betti_f2, b.euler), (edges, k)
    assert (a.tc, a.tc_bounds) == (b.tc, b.tc_bounds), (edges, k)


# --------------------------------------------------------------------------------------------------
# surfaces as cube complexes: the generic homology and cup-length code


def torus_or_klein(n: int, twist: bool) -> CubeComplex:
    """An n × n grid with opposite sides identified (the top side flipped for the Klein bottle)."""

    def vid(i: int, j: int) -> int:
        if j == n:
            j, i = 0, (-i if twist else i)
        return (i % n) * n + j

    corners = [(vid(i, j), vid(i + 1, j), vid(i + 1, j + 1), vid(i, j + 1)) for i in range(n) for j in range(n)]
    return CubeComplex.from_corners(n * n, corners)


def cube_surface(k: int, antipodal: bool) -> CubeComplex:
    """The boundary of the cube [-k, k]³ cut into unit-2 squares (a sphere), or its antipodal quotient (RP²)."""
    coords = list(range(-k, k + 1, 2))

    def cls(p: tuple[int, ...]) -> tuple[int, ...]:
        q = tuple(-x for x in p)
        return min(p, q) if antipodal else p

    points = sorted({cls(p) for p in itertools.product(coords, repeat=3) if max(map(abs, p)) == k})
    index = {p: i for i, p in enumerate(points)}
    seen: set[frozenset[int]] = set()
    corners = []
    for axis, s in itertools.product(range(3), (-k, k)):
        o1, o2 = (a for a in range(3) if a != axis)
        for x, y in itertools.product(coords[:-1], repeat=2):
            c = []
            for dx, dy in ((0, 0), (2, 0), (2, 2), (0, 2)):
                p = [0, 0, 0]
                p[axis], p[o1], p[o2] = s, x + dx, y + dy
                c.append(index[cls(tuple(p))])
            if frozenset(c) not in seen:
                seen.add(frozenset(c))
                corners.append(tuple(c))
    return CubeComplex.from_corners(len(points), corners)


@pytest.mark.parametrize(
    ("name", "cx", "betti", "betti_f2", "torsion_free", "zcl_f2", "zcl_fp"),
    [
        ("torus", torus_or_klein(3, False), (1, 2, 1), (1, 2, 1), True, 2, 2),
        ("torus 4x4", torus_or_klein(4, False), (1, 2, 1), (1, 2, 1), True, 2, 2),
        ("Klein bottle", torus_or_klein(3, True), (1, 1, 0), (1, 2, 1), False, 3, 1),
        ("sphere", cube_surface(1, False), (1, 0, 1), (1, 0, 1), True, 1, 2),
        ("RP2", cube_surface(3, True), (1, 0, 0), (1, 1, 1), False, 3, 0),
    ],
)
def test_surfaces(
    name: str,
    cx: CubeComplex,
    betti: tuple[int, ...],
    betti_f2: tuple[int, ...],
    torsion_free: bool,
    zcl_f2: int,
    zcl_fp: int,
) -> None:
    (c,) = cube_complex_topology(cx)
    assert c.betti == betti and c.betti_f2 == betti_f2, name
    assert c.h1_torsion_free is torsion_free, name
    assert (c.zcl_f2, c.zcl_fp) == (zcl_f2, zcl_fp), name
    # known TC: torus 3, Klein bottle 5, sphere 3, RP² 4; the cup-length gives the lower bound, hdim <= 2 the upper
    assert c.tc_bounds == (max(zcl_f2, zcl_fp) + 1, 5), name
    assert c.homotopy_dimension.lower == (2 if betti_f2[2] else 1)


def test_contractible_cube_complex_collapses() -> None:
    # the 3 x 3 square grid [0, 3]² collapses to a point
    corners = [(4 * j + i, 4 * j + i + 1, 4 * (j + 1) + i + 1, 4 * (j + 1) + i) for i in range(3) for j in range(3)]
    (c,) = cube_complex_topology(CubeComplex.from_corners(16, corners))
    assert c.betti == (1, 0, 0) and c.tc == 1 and c.homotopy_dimension.upper == 0
    assert c.collapsed_cells.to_dict() == {"vertices": 1, "edges": 0, "squares": 0}


def test_cubical_subdivision_is_a_consistent_cube_complex() -> None:
    for cx in (torus_or_klein(3, True), cube_surface(3, True)):
        sub = cubical_subdivision(cx)
        assert np.all(sub.signs == 1)
        assert sub.cell_counts.to_dict() == {
            "vertices": cx.n_vertices + cx.n_edges + cx.n_squares,
            "edges": 2 * cx.n_edges + 4 * cx.n_squares,
            "squares": 4 * cx.n_squares,
        }
        assert sub.euler_characteristic == cx.euler_characteristic


# --------------------------------------------------------------------------------------------------
# cup products: cochain-level checks


def _d2_collapsed(edges: list[list[object]]) -> CubeComplex:
    col = collapse_free_faces(discretized_configuration_space(graph_from_json_data({"edges": edges})).complex)
    return col.complex


PRISM = [[0, 1], [1, 2], [2, 0], [3, 4], [4, 5], [5, 3], [0, 3], [1, 4], [2, 5]]
K5 = [[a, b] for a, b in itertools.combinations(range(5), 2)]


@pytest.mark.parametrize("edges", [PRISM, K5], ids=["prism", "K5"])
@pytest.mark.parametrize("p", [2, FIELD_PRIME])
def test_cup_product_is_well_defined_and_graded_commutative(edges: list[list[object]], p: int) -> None:
    cx = _d2_collapsed(edges)
    coh = field_cohomology(cx, p)
    assert coh.b1 and coh.b2
    # cocycles and cycles really are cocycles and cycles
    coef = cx.boundary_coefficients()
    delta = (coh.cocycles[:, cx.squares] * coef[None]).sum(axis=2) % p
    assert not delta.any(), "δ(cocycle) = 0"
    bd = np.zeros((coh.b2, cx.n_edges), dtype=np.int64)
    for pos in range(4):
        np.add.at(bd.T, cx.squares[:, pos], (coh.cycles * coef[:, pos][None]).T)
    assert not (bd % p).any(), "∂(cycle) = 0"
    # graded commutativity on cohomology: a_j a_i = -a_i a_j
    m = cup_products(cx, coh, symmetric=False)
    assert not ((m + m.transpose(1, 0, 2)) % p).any()
    # (α + δf) ∪ β has the class of α ∪ β (Leibniz rule of the Serre diagonal)
    rng = np.random.default_rng(7)
    f = rng.integers(0, p, size=cx.n_vertices)
    df = (f[cx.edges[:, 1]] - f[cx.edges[:, 0]]) % p
    shifted = type(coh)(p, coh.b1, coh.b2, (coh.cocycles + df[None]) % p, coh.cycles)
    assert np.array_equal(cup_products(cx, shifted, symmetric=False), m)
    # a closed orientable surface (K5): the cup pairing H¹ × H¹ -> H² = F_p is nondegenerate
    if edges is K5:
        assert len(dense_independent_columns(m[:, :, 0], p)) == coh.b1


@pytest.mark.parametrize("p", [2, FIELD_PRIME])
def test_cup_length_is_invariant_under_subdivision(p: int) -> None:
    cx = _d2_collapsed(PRISM)
    for k in (cx, cubical_subdivision(cx)):
        coh = field_cohomology(k, p)
        m = cup_products(k, coh)
        assert (coh.b1, coh.b2) == (9, 2)
        assert len(dense_independent_columns(m.reshape(-1, coh.b2), p)) == 2  # cup products span H²
        assert zero_divisor_cup_length(m, coh.b2, p) == 4


# --------------------------------------------------------------------------------------------------
# zero-divisor cup-length against a brute-force computation in H ⊗ H


def _brute_force_zcl(m: np.ndarray, p: int) -> int:
    """Largest k with I^k ≠ 0, I = ker(H ⊗ H -> H), by spanning products of bases of I^(k-1) and I."""
    n1, _, n2 = m.shape
    d = 1 + n1 + n2
    deg = [0] + [1] * n1 + [2] * n2
    mult = np.zeros((d, d, d), dtype=np.int64)
    for x in range(d):
        mult[0, x, x] = mult[x, 0, x] = 1
    mult[1 : 1 + n1, 1 : 1 + n1, 1 + n1 :] = m % p
    dd = d * d
    tensor = np.zeros((dd, dd, dd), dtype=np.int64)  # structure constants of the graded tensor product
    for x, y, x2, y2 in itertools.product(range(d), repeat=4):
        u, v = mult[x, x2], mult[y, y2]
        if u.any() and v.any():
            sign = -1 if deg[y] * deg[x2] % 2 else 1
            tensor[x * d + y, x2 * d + y2] = sign * np.outer(u, v).ravel() % p
    ech = Echelon(p)
    for col in range(d):
        ech.insert({r: int(mult[r // d, r % d, col]) for r in range(dd) if mult[r // d, r % d, col]})
    ideal = ech.annihilator(dd)
    power, k = ideal, 0
    while len(power) and k < 6:
        k += 1
        prods = np.einsum("ua,vb,abc->uvc", power, ideal, tensor, optimize=True).reshape(-1, dd) % p
        power = prods[dense_independent_columns(prods.T, p)] if len(prods) else prods
    return k


def _random_algebra(rng: np.random.Generator, p: int) -> np.ndarray:
    n1, n2 = int(rng.integers(0, 5)), int(rng.integers(0, 3))
    m = rng.integers(0, p, size=(n1, n1, n2)) * (rng.random((n1, n1, 1)) < rng.random())
    upper = np.triu(np.ones((n1, n1), dtype=bool), k=0 if p == 2 else 1)[:, :, None]
    m = np.where(upper, m, 0)
    return (m + (1 if p == 2 else -1) * m.transpose(1, 0, 2) * (~np.eye(n1, dtype=bool))[:, :, None]) % p


@pytest.mark.parametrize("p", [2, 3, 5])
def test_zero_divisor_cup_length_matches_brute_force(p: int) -> None:
    rng = np.random.default_rng(2024 + p)
    seen = set()
    for trial in range(60):
        m = _random_algebra(rng, p)
        fast, slow = zero_divisor_cup_length(m, m.shape[2], p), _brute_force_zcl(m, p)
        assert fast == slow, f"trial {trial}, p = {p}: fast {fast} != brute force {slow} for m = {m.tolist()}"
        seen.add(fast)
    assert seen >= {1, 2, 3}


@pytest.mark.parametrize("p", [2, 5])
@pytest.mark.parametrize(("limit", "slice_entries"), [(0, 1_000_000), (10**9, 8)], ids=["random", "sliced"])
def test_four_fold_check_random_and_sliced_paths(
    p: int, limit: int, slice_entries: int, monkeypatch: pytest.MonkeyPatch
) -> None:
    # the random path (used when the exhaustive check is too big) and the memory-sliced exhaustive path agree with
    # brute force on these small rings (the random path can only miss with a tiny probability; seeded here)
    monkeypatch.setattr(mpa.topology.cohomology, "_EXHAUSTIVE_LIMIT", limit)
    monkeypatch.setattr(mpa.topology.cohomology, "_SLICE_ENTRIES", slice_entries)
    rng = np.random.default_rng(99 + p)
    for trial in range(25):
        m = _random_algebra(rng, p)
        fast, slow = zero_divisor_cup_length(m, m.shape[2], p), _brute_force_zcl(m, p)
        assert fast == slow, f"trial {trial}, p = {p}: fast {fast} != brute force {slow} for m = {m.tolist()}"


def test_zero_divisor_cup_length_known_rings() -> None:
    p = FIELD_PRIME
    torus = np.zeros((2, 2, 1), dtype=np.int64)
    torus[0, 1, 0], torus[1, 0, 0] = 1, p - 1
    assert zero_divisor_cup_length(torus, 1, p) == 2
    genus2 = np.zeros((4, 4, 1), dtype=np.int64)
    for a, b in ((0, 1), (2, 3)):
        genus2[a, b, 0], genus2[b, a, 0] = 1, p - 1
    assert zero_divisor_cup_length(genus2, 1, p) == 4  # TC(genus 2) = 5
    assert zero_divisor_cup_length(genus2 % 2, 1, 2) == 3  # over F2 the four-fold product vanishes
    rp2 = np.ones((1, 1, 1), dtype=np.int64)
    assert zero_divisor_cup_length(rp2, 1, 2) == 3  # TC(RP²) = 4
    assert zero_divisor_cup_length(np.zeros((0, 0, 1), dtype=np.int64), 1, p) == 2  # S²: TC = 3
    assert zero_divisor_cup_length(np.zeros((0, 0, 0), dtype=np.int64), 0, p) == 0  # point


# --------------------------------------------------------------------------------------------------
# bad input


@pytest.mark.parametrize(
    ("data", "match"),
    [
        ([["a", "b"]], r"graph JSON is a list, expected an object with key \"edges\""),
        ({"vertices": [1]}, r"graph JSON has keys \['vertices'\], expected the key \"edges\""),
        ({"edges": []}, r"\"edges\" is empty, expected at least one edge"),
        ({"edges": {"a": "b"}}, r"\"edges\" is a dict, expected a list"),
        ({"edges": [["a"]]}, r"edge 0 is \['a'\], expected \[u, v\] or \[u, v, length\]"),
        ({"edges": ["ab"]}, r"edge 0 is 'ab', expected \[u, v\]"),
        ({"edges": [["a", "b"], ["a", None]]}, r"vertex None of edge 1 is not a string or an integer"),
        ({"edges": [[True, "b"]]}, r"vertex True of edge 0"),
        ({"edges": [["a", "b", -1]]}, r"length of edge 0 is -1, expected a finite number >= 0"),
        ({"edges": [["a", "b", "long"]]}, r"length of edge 0 is 'long'"),
    ],
)
def test_bad_graph_json(data: object, match: str) -> None:
    with pytest.raises(InvalidInputError, match=match):
        graph_from_json_data(data)


def test_bad_graph_files(tmp_path: Path) -> None:
    with pytest.raises(InvalidInputError, match=r"graph file .*missing\.json' does not exist"):
        load_graph_json(tmp_path / "missing.json")
    bad = tmp_path / "bad.json"
    bad.write_text('{"edges": [[1, 2]', encoding="utf-8")
    with pytest.raises(InvalidInputError, match=r"is not valid JSON \(.* at line 1 column"):
        load_graph_json(bad)


def test_graphs_without_room_for_two_robots() -> None:
    with pytest.raises(InvalidInputError, match=r"graph has 1 vertices and no edges: two robots do not fit"):
        configuration_space_topology(MetricGraph(("P",), ()))
    with pytest.raises(InvalidInputError, match=r"graph is a str, expected a MetricGraph or a track"):
        configuration_space_topology("P--P")  # type: ignore[arg-type]
    top = configuration_space_topology(MetricGraph(("a", "b"), ()))  # two isolated points: two configurations
    assert top.betti == (2, 0, 0) and top.euler == top.euler_formula == 2


def test_bad_cube_complexes() -> None:
    with pytest.raises(InvalidInputError, match=r"edge 0 is a loop at vertex 1"):
        CubeComplex(2, [[1, 1]])
    with pytest.raises(InvalidInputError, match=r"edges refer to vertices outside 0..1"):
        CubeComplex(2, [[0, 2]])
    with pytest.raises(InvalidInputError, match=r"square 0 has sides .* do not close up"):
        CubeComplex(4, [[0, 1], [1, 2], [2, 3], [0, 3]], [[0, 1, 2, 3]])
    with pytest.raises(InvalidInputError, match=r"max_homotopy_dimension is 3, expected 0, 1 or 2"):
        cube_complex_topology(torus_or_klein(3, False), max_homotopy_dimension=3)
    # a wrong theoretical bound is caught by the consistency checks, never silently used
    with pytest.raises(PlanningError, match=r"need homotopy dimension >= 2, but theory bounds it by 1"):
        cube_complex_topology(torus_or_klein(3, False), max_homotopy_dimension=1)


# --------------------------------------------------------------------------------------------------
# command line


def _parser() -> argparse.ArgumentParser:
    parser = argparse.ArgumentParser(prog="mpa")
    cli_topology.register(parser.add_subparsers(dest="command", required=True))
    return parser


def test_cli_json(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    path = tmp_path / "lollipop.json"
    path.write_text(json.dumps({"edges": [["F", "P", 1.0], ["P", "P", 2.0]]}), encoding="utf-8")
    args = _parser().parse_args(["topology", "--graph", str(path), "--json"])
    assert args.func(args) == 0
    out = json.loads(capsys.readouterr().out)
    assert out["betti"] == [1, 3, 0] and out["euler"] == -2 and out["connected"] is True
    assert out["tc"] == 3 and out["tc_bounds"] == [3, 3]


def test_cli_text_and_undecided_json(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    path = tmp_path / "interval.json"
    path.write_text('{"edges": [[0, 1]]}', encoding="utf-8")
    args = _parser().parse_args(["topology", "--graph", str(path)])
    assert args.func(args) == 0
    text = capsys.readouterr().out
    assert "b0 = 2, b1 = 0, b2 = 0" in text and "component 1" in text
    top = configuration_space_topology(graph_from_json_data({"edges": [[0, 0], [1, 2], [1, 2], [1, 2]]}))
    out = json.loads(json.dumps(top.to_dict()))
    assert out["tc"] == 4 and out["tc_bounds"] == [4, 4]  # S¹ × theta: zcl + 1 = 4 = 2 + 3 - 1


def test_cli_errors(tmp_path: Path) -> None:
    parser = _parser()
    args = parser.parse_args(["topology", "--graph", str(tmp_path / "nope.json")])
    with pytest.raises(InvalidInputError, match="does not exist"):
        args.func(args)
    bad = tmp_path / "bad.json"
    bad.write_text("not json", encoding="utf-8")
    args = parser.parse_args(["topology", "--graph", str(bad), "--json"])
    with pytest.raises(InvalidInputError, match="is not valid JSON"):
        args.func(args)
    empty = tmp_path / "empty.json"
    empty.write_text('{"edges": []}', encoding="utf-8")
    args = parser.parse_args(["topology", "--graph", str(empty)])
    with pytest.raises(InvalidInputError, match="is empty"):
        args.func(args)


# --------------------------------------------------------------------------------------------------
# docs and the timing experiment


@pytest.mark.parametrize("module", [mpa.topology.discretized, mpa.topology.configuration])
def test_doctests(module: object) -> None:
    result = doctest.testmod(module, optionflags=doctest.ELLIPSIS)  # type: ignore[arg-type]
    assert result.attempted > 0 and result.failed == 0


def test_timing_experiment_smoke(capsys: pytest.CaptureFixture[str]) -> None:
    path = Path(__file__).resolve().parents[2] / "experiments" / "topology_timing.py"
    spec = importlib.util.spec_from_file_location("topology_timing", path)
    assert spec is not None and spec.loader is not None
    mod = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(mod)
    rows = mod.main(["--sizes", "6", "10"])
    assert [r["vertices"] for r in rows] == [6, 10]
    assert "betti" in capsys.readouterr().out
