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

The generic part works on any :class:`~mpa.discretized.CubeComplex` of dimension <= 2
(:func:`cube_complex_topology`), which the tests use on a torus and a Klein bottle.
"""

from __future__ import annotations

import heapq
import json
import math
from collections import deque
from dataclasses import dataclass
from fractions import Fraction
from pathlib import Path
from typing import Any

import numpy as np

from mpa.discretized import (
    BOTTOM,
    LEFT,
    RIGHT,
    TOP,
    CellCounts,
    CubeComplex,
    collapse_free_faces,
    cubical_subdivision,
    discretized_configuration_space,
    expected_cell_counts,
)
from mpa.errors import InvalidInputError, PlanningError
from mpa.graph import MetricGraph, farber_tc_of_graph

__all__ = [
    "FIELD_PRIME",
    "ComponentTopology",
    "ConfigurationSpaceTopology",
    "HomotopyDimension",
    "configuration_space_topology",
    "cube_complex_topology",
    "euler_characteristic_formula",
    "graph_from_json_data",
    "load_graph_json",
    "zero_divisor_cup_length",
]

FIELD_PRIME = 524_287
"""The odd prime ``2¹⁹ - 1`` of the second coefficient field 𝔽_p (float64 dot products of residues stay exact)."""

_EXHAUSTIVE_LIMIT = 20_000_000
"""Largest ``w⁴ · r(r+1)/2`` for which the four-fold zero-divisor products are checked exhaustively."""

_INTEGER_MATMUL_WORK = 5_000_000
"""Up to this many multiply-adds a product mod p is done in int64 (no BLAS threads), beyond in float64 blocks."""

_SLICE_ENTRIES = 1_000_000
"""Entries of one slice of the four-index array in the exhaustive four-fold check."""

_RANDOM_TRIALS = 64
"""Random trials of the four-fold zero-divisor test when the exhaustive check is too large."""


# ==================================================================================================
# Sparse exact elimination
# ==================================================================================================
class _Echelon:
    """Incremental sparse row echelon form over 𝔽_p (``p`` prime) or over ℤ with unit pivots (``p = 0``).

    Rows are dictionaries ``coordinate -> coefficient``. Every stored row has coefficient 1 at its pivot and 0 at
    the pivots of the rows stored before it, so reducing a vector by the rows in the order they were stored clears
    every pivot coordinate. Over ℤ only entries ±1 are used as pivots, so all operations are unimodular; a vector
    without such an entry is kept aside in :attr:`residual` (its rank is finished over ℚ by :func:`_dense_rank`).
    """

    def __init__(self, p: int) -> None:
        self.p = p
        self.rows: list[dict[int, int]] = []
        self.pivots: list[int] = []
        self.pivot_row: dict[int, int] = {}
        self.residual: list[dict[int, int]] = []

    @property
    def rank(self) -> int:
        return len(self.rows)

    def reduce(self, v: dict[int, int]) -> None:
        """Clear every pivot coordinate of ``v`` in place (rows applied in the order they were stored)."""
        p = self.p
        pivot_row = self.pivot_row
        heap = [pivot_row[k] for k in v if k in pivot_row]
        heapq.heapify(heap)
        while heap:
            i = heapq.heappop(heap)
            c = v.get(self.pivots[i])
            if not c:
                continue
            for k, val in self.rows[i].items():
                old = v.get(k)
                nv = (old or 0) - c * val
                if p:
                    nv %= p
                if nv:
                    v[k] = nv
                    if old is None and k in pivot_row:
                        heapq.heappush(heap, pivot_row[k])
                elif old is not None:
                    del v[k]

    def insert(self, vec: dict[int, int]) -> None:
        """Insert a vector: reduce it and store it as a new row when it is not in the span of the rows."""
        p = self.p
        v = {k: c % p for k, c in vec.items() if c % p} if p else {k: c for k, c in vec.items() if c}
        self.reduce(v)
        if not v:
            return
        if p:
            piv = min(v)
            inv = pow(v[piv], p - 2, p)
        else:
            units = [k for k, c in v.items() if c in (1, -1)]
            if not units:
                self.residual.append(v)
                return
            piv = min(units)
            inv = v[piv]
        if inv != 1:
            v = {k: (c * inv % p if p else c * inv) for k, c in v.items()}
        self.pivot_row[piv] = len(self.rows)
        self.pivots.append(piv)
        self.rows.append(v)

    def annihilator(self, n: int) -> np.ndarray:
        """Basis of ``{x ∈ 𝔽_p^n : <row, x> = 0 for every row}``. Shape (n - rank, n), entries in ``[0, p)``.

        Back substitution (last row first) expresses every fully reduced row through the free (non-pivot)
        coordinates ``F``; the annihilator is spanned by ``e_f - Σ_i F[i, f] e_{pivot i}`` for the free ``f``.
        """
        p = self.p
        free = np.ones(n, dtype=bool)
        free[self.pivots] = False
        free_idx = np.nonzero(free)[0]
        col = np.full(n, -1, dtype=np.int64)
        col[free_idx] = np.arange(free_idx.size)
        f_mat = np.zeros((self.rank, free_idx.size), dtype=np.int64)
        for i in range(self.rank - 1, -1, -1):
            acc = np.zeros(free_idx.size, dtype=np.int64)
            piv = self.pivots[i]
            for k, c in self.rows[i].items():
                if k == piv:
                    continue
                j = self.pivot_row.get(k)
                if j is None:
                    acc[col[k]] += c
                else:
                    acc -= c * f_mat[j]
            f_mat[i] = acc % p
        basis = np.zeros((free_idx.size, n), dtype=np.int64)
        basis[np.arange(free_idx.size), free_idx] = 1
        if self.rank:
            basis[:, self.pivots] = (-f_mat.T) % p
        return basis


def _dense_rank(rows: list[dict[int, int]]) -> int:
    """Exact rank over ℚ of a few sparse integer rows (Gaussian elimination with fractions)."""
    cols = sorted({k for r in rows for k in r})
    index = {k: i for i, k in enumerate(cols)}
    mat = [[Fraction(0)] * len(cols) for _ in rows]
    for i, r in enumerate(rows):
        for k, c in r.items():
            mat[i][index[k]] = Fraction(c)
    rank = 0
    for c in range(len(cols)):
        piv = next((i for i in range(rank, len(mat)) if mat[i][c] != 0), None)
        if piv is None:
            continue
        mat[rank], mat[piv] = mat[piv], mat[rank]
        for i in range(rank + 1, len(mat)):
            if mat[i][c] != 0:
                f = mat[i][c] / mat[rank][c]
                mat[i] = [a - f * b for a, b in zip(mat[i], mat[rank])]
        rank += 1
    return rank


def _dense_independent_columns(a: np.ndarray, p: int) -> list[int]:
    """Indices of a maximal set of linearly independent columns of ``a`` over 𝔽_p (dense elimination)."""
    a = np.array(a, dtype=np.int64) % p
    n_rows = a.shape[0]
    pivots: list[int] = []
    r = 0
    for c in range(a.shape[1]):
        if r == n_rows:
            break
        nz = np.nonzero(a[r:, c])[0]
        if nz.size == 0:
            continue
        k = r + int(nz[0])
        if k != r:
            a[[r, k]] = a[[k, r]]
        a[r] = a[r] * pow(int(a[r, c]), p - 2, p) % p
        below = a[r + 1 :]
        f = below[:, c].copy()
        hit = np.nonzero(f)[0]
        if hit.size:
            below[hit] = (below[hit] - np.outer(f[hit], a[r]) % p) % p
        pivots.append(c)
        r += 1
    return pivots


def _dense_rank_mod_p(a: np.ndarray, p: int) -> int:
    return len(_dense_independent_columns(a, p))


# ==================================================================================================
# Cohomology of a connected cube complex
# ==================================================================================================
def _spanning_tree_mask(cx: CubeComplex) -> np.ndarray:
    """Boolean mask of the edges of a spanning forest of the 1-skeleton (breadth first)."""
    adj: list[list[tuple[int, int]]] = [[] for _ in range(cx.n_vertices)]
    for k, (a, b) in enumerate(cx.edges.tolist()):
        adj[a].append((b, k))
        adj[b].append((a, k))
    seen = np.zeros(cx.n_vertices, dtype=bool)
    tree = np.zeros(cx.n_edges, dtype=bool)
    for root in range(cx.n_vertices):
        if seen[root]:
            continue
        seen[root] = True
        queue = deque([root])
        while queue:
            v = queue.popleft()
            for w, k in adj[v]:
                if not seen[w]:
                    seen[w] = True
                    tree[k] = True
                    queue.append(w)
    return tree


def _coboundaries(cx: CubeComplex, edges: np.ndarray) -> list[dict[int, int]]:
    """``δ(e*)`` for each given edge: the squares having ``e`` on their boundary, with the incidence number."""
    coef = cx.boundary_coefficients().tolist()
    where: dict[int, dict[int, int]] = {int(e): {} for e in edges}
    for s, row in enumerate(cx.squares.tolist()):
        for pos, e in enumerate(row):
            d = where.get(e)
            if d is not None:
                d[s] = d.get(s, 0) + coef[s][pos]
    return [{s: c for s, c in where[int(e)].items() if c} for e in edges]


@dataclass(frozen=True, eq=False)
class _FieldCohomology:
    """``H¹`` and ``H²`` of a connected cube complex over 𝔽_p, with what is needed for cup products.

    There are no 3-cells, so ``H₂ = Z₂`` and, over a field, ``H² = Hom(H₂, 𝔽_p)``: the class of a 2-cochain is given
    by its values on a basis of the 2-cycles.
    """

    p: int
    b1: int
    b2: int
    cocycles: np.ndarray  # shape (b1, E): representatives of a basis of H¹ vanishing on a spanning tree
    cycles: np.ndarray  # shape (b2, S): a basis of the 2-cycles Z₂ = H₂


def _boundaries(cx: CubeComplex) -> list[dict[int, int]]:
    """``∂(square)`` for every square, as ``edge -> coefficient``."""
    coef = cx.boundary_coefficients().tolist()
    out = []
    for s, row in enumerate(cx.squares.tolist()):
        d: dict[int, int] = {}
        for pos, e in enumerate(row):
            d[e] = d.get(e, 0) + coef[s][pos]
        out.append({e: c for e, c in d.items() if c})
    return out


def _field_cohomology(cx: CubeComplex, p: int) -> _FieldCohomology:
    tree = _spanning_tree_mask(cx)
    nontree = np.nonzero(~tree)[0]
    # 1-cocycles vanishing on the tree = vectors on the non-tree edges orthogonal to every restricted ∂(square)
    col = np.full(cx.n_edges, -1, dtype=np.int64)
    col[nontree] = np.arange(nontree.size)
    rows = _Echelon(p)
    for vec in _boundaries(cx):
        rows.insert({int(col[e]): c for e, c in vec.items() if col[e] >= 0})
    cocycles = np.zeros((nontree.size - rows.rank, cx.n_edges), dtype=np.int64)
    cocycles[:, nontree] = rows.annihilator(nontree.size)
    # 2-cycles = vectors on the squares orthogonal to every δ(edge) (the non-tree edges span im δ)
    cols = _Echelon(p)
    for vec in _coboundaries(cx, nontree):
        cols.insert(vec)
    if cols.rank != rows.rank:
        raise PlanningError(f"rank of the boundary map mod {p} is {rows.rank} by rows and {cols.rank} by columns")
    cycles = cols.annihilator(cx.n_squares)
    return _FieldCohomology(p, len(cocycles), len(cycles), cocycles, cycles)


def _rational_rank_of_boundary(cx: CubeComplex) -> tuple[int, bool]:
    """Rank over ℚ of ``∂₂`` (via ``δ`` on the edges off a spanning tree) and whether only unit pivots were needed.

    When only unit pivots were needed, the Smith normal form of ``∂₂`` is all ones, so ``H₁(·; ℤ)`` is free.
    """
    tree = _spanning_tree_mask(cx)
    nontree = np.nonzero(~tree)[0]
    ech = _Echelon(0)
    for vec in _coboundaries(cx, nontree):
        ech.insert(vec)
    residual = []
    for v in ech.residual:
        v = dict(v)
        ech.reduce(v)
        if v:
            residual.append(v)
    return ech.rank + (_dense_rank(residual) if residual else 0), not residual


def _matmul_mod_p(a: np.ndarray, b: np.ndarray, p: int) -> np.ndarray:
    """``a @ b mod p`` for int64 arrays with entries in ``[0, p)``, exactly.

    Small products use integer arithmetic (exact while ``inner · (p-1)² < 2⁶³``); large ones use float64 BLAS on
    blocks of the inner index short enough that every partial sum stays below ``2⁵²``.
    """
    inner = a.shape[1]
    if a.shape[0] * inner * b.shape[1] <= _INTEGER_MATMUL_WORK and inner * (p - 1) ** 2 < 2**62:
        return (a @ b) % p
    block = max(1, (1 << 52) // max(1, (p - 1) ** 2))
    out = np.zeros((a.shape[0], b.shape[1]), dtype=np.int64)
    for k in range(0, inner, block):
        part = a[:, k : k + block].astype(np.float64) @ b[k : k + block].astype(np.float64)
        out = (out + np.fmod(part, p).astype(np.int64)) % p
    return out


def _cup_products(
    cx: CubeComplex,
    coh: _FieldCohomology,
    *,
    projection: np.ndarray | None = None,
    symmetric: bool = True,
    chunk: int = 256,
) -> np.ndarray:
    """Structure constants of ``H¹ × H¹ -> H²``: ``m[i, j]`` is the class of ``a_i ∪ a_j``. Shape (b1, b1, b2).

    On a square with sides bottom, right, top, left the Serre diagonal gives
    ``(α ∪ β)(square) = α(bottom) β(right) - α(left) β(top)``; its class is read off by evaluation on the 2-cycles.
    With ``projection`` (shape (b2, r)) the classes are mapped to ``𝔽_p^r`` (shape (b1, b1, r)): a cheap first look.
    With ``symmetric=True`` only ``i <= j`` is computed and ``m[j, i] = -m[i, j]`` (graded commutativity).
    """
    p = coh.p
    n1 = coh.b1
    target = coh.cycles.T if projection is None else _matmul_mod_p(coh.cycles.T, projection % p, p)
    cycles_t = np.ascontiguousarray(target)
    out = np.zeros((n1, n1, cycles_t.shape[1]), dtype=np.int64)
    if n1 == 0 or coh.b2 == 0:
        return out
    assert cx.signs is not None
    sides = cx.squares
    signs = cx.signs % p

    def side(pos: int) -> np.ndarray:  # shape (b1, S): value of each cocycle on that side of every square
        return coh.cocycles[:, sides[:, pos]] * signs[None, :, pos] % p

    bot, right, top, left = side(BOTTOM), side(RIGHT), side(TOP), side(LEFT)
    pairs = [(i, j) for i in range(n1) for j in range(i if symmetric else 0, n1)]
    for start in range(0, len(pairs), chunk):
        block = pairs[start : start + chunk]
        ii = np.array([i for i, _ in block])
        jj = np.array([j for _, j in block])
        gamma = (bot[ii] * right[jj] % p - left[ii] * top[jj] % p) % p
        out[ii, jj] = _matmul_mod_p(gamma, cycles_t, p)
    if symmetric:
        lower = np.tril_indices(n1, -1)
        out[lower] = (-out.transpose(1, 0, 2)[lower]) % p
    return out


# ==================================================================================================
# Zero-divisor cup-length
# ==================================================================================================
_FOUR_FOLD_TERMS = (
    ("ij,kl->ijkl", 1),
    ("kl,ij->ijkl", 1),
    ("ik,jl->ijkl", -1),
    ("jl,ik->ijkl", -1),
    ("il,jk->ijkl", 1),
    ("jk,il->ijkl", 1),
)
"""The six terms ``± m_S[s] m_{S^c}[t]`` of a product of four zero divisors, as einsum specifications."""


def _four_fold_product_nonzero(m: np.ndarray, p: int, rng: np.random.Generator) -> bool:
    """Whether some product of four zero divisors ``ā = a ⊗ 1 - 1 ⊗ a``, ``a ∈ H¹``, is nonzero in ``H²⊗H²``.

    Expanding, ``ā₁ā₂ā₃ā₄ = Σ_{|S|=2} ± (a_S ⊗ a_{S^c})`` over the six pairs ``S`` of positions, which in terms of
    ``m_ij = a_i a_j`` is ``m12⊗m34 + m34⊗m12 - m13⊗m24 - m24⊗m13 + m14⊗m23 + m23⊗m14``. Classes annihilating all
    of ``H¹`` cannot contribute, so the index set is first cut down to a complement of the annihilator and ``H²``
    to coordinates injective on the image of the cup product.
    """
    n1 = m.shape[0]
    if n1 == 0:
        return False
    cols = _dense_independent_columns(m.reshape(n1 * n1, -1), p)
    if not cols:
        return False
    mp = m[:, :, cols] % p
    r = len(cols)
    rows = _dense_independent_columns(mp.reshape(n1, n1 * r).T, p)
    mw = mp[np.ix_(rows, rows)]
    w = len(rows)
    if w**4 * r * (r + 1) // 2 <= _EXHAUSTIVE_LIMIT:
        step = max(1, _SLICE_ENTRIES // w**3)  # values of the first index per slice, to bound the memory
        for s in range(r):
            for t in range(s, r):
                a, b = mw[:, :, s], mw[:, :, t]
                for i0 in range(0, w, step):
                    part = slice(i0, i0 + step)
                    q = np.zeros((len(range(w)[part]), w, w, w), dtype=np.int64)
                    for spec, sign in _FOUR_FOLD_TERMS:
                        # the index i is the first index of exactly one operand: slice that operand
                        x, y = (a[part], b) if spec.startswith("i") else (a, b[part])
                        q = (q + sign * (np.einsum(spec, x, y) % p)) % p
                    if q.any():
                        return True
        return False
    if p != 2:
        # (φ⊗φ)(Q) = 2·Pfaffian of the 2-form φ∘μ on four classes: Q ≠ 0 iff some φ∘μ has rank >= 4
        for _ in range(_RANDOM_TRIALS):
            phi = rng.integers(0, p, size=r)
            omega = np.zeros((w, w), dtype=np.int64)
            for s in range(r):
                omega = (omega + mw[:, :, s] * int(phi[s]) % p) % p
            if _dense_rank_mod_p(omega, p) >= 4:
                return True
        return False
    # p = 2: evaluate Q(x1, ..., x4) at random classes x_t against random functionals φ, ψ on H²
    for _ in range(_RANDOM_TRIALS * 16):
        x = rng.integers(0, 2, size=(4, w))
        phi, psi = rng.integers(0, 2, size=r), rng.integers(0, 2, size=r)
        prods = {(i, j): np.einsum("a,b,abs->s", x[i], x[j], mw) % 2 for i in range(4) for j in range(i + 1, 4)}
        val = 0
        for first, second in (((0, 1), (2, 3)), ((0, 2), (1, 3)), ((0, 3), (1, 2))):
            u, v = prods[first], prods[second]
            val += int(phi @ u) * int(psi @ v) + int(phi @ v) * int(psi @ u)
        if val % 2:
            return True
    return False


def zero_divisor_cup_length(m: np.ndarray, b2: int, p: int, seed: int = 0) -> int:
    """Zero-divisor cup-length of ``H = 𝔽_p ⊕ H¹ ⊕ H²`` (``H^{≥3} = 0``) from its cup-product structure constants.

    Parameters
    ----------
    m : numpy.ndarray
        Shape (b1, b1, r): ``m[i, j]`` is the image of ``a_i ∪ a_j`` under a linear map ``H² -> 𝔽_p^r``, for a
        basis ``a_i`` of ``H¹``. Exact when the map is injective (e.g. coordinates in a basis, ``r = b2``);
        otherwise the result is a lower bound.
    b2 : int
        Dimension of ``H²``.
    p : int
        The prime of the coefficient field.
    seed : int
        Seed of the random test used only when the four-fold check is too large to be exhaustive (it can then miss
        a nonzero product, which only weakens the bound).

    Returns
    -------
    int
        The largest ``k`` such that a product of ``k`` elements of ``ker(H ⊗ H -> H)`` is nonzero (0 to 4).
        ``TC >= zcl + 1``.

    Notes
    -----
    The ideal of zero divisors is generated by ``ā = a ⊗ 1 - 1 ⊗ a``; products of two generators are nonzero as
    soon as ``b1 >= 2``, or ``b1, b2 >= 1``, or ``b2 >= 1`` (p odd) / ``b2 >= 2`` (p = 2), or some ``a² ≠ 0``;
    products of three are nonzero iff some ``a_i a_j ≠ 0`` and (``b1 >= 3`` or ``b2 >= 2`` or some ``a² ≠ 0``);
    products of four lie in ``H² ⊗ H²`` and are checked by :func:`_four_fold_product_nonzero`.

    Examples
    --------
    The torus: ``H¹ = <a, b>``, ``ab = -ba = ω``.

    >>> m = np.zeros((2, 2, 1), dtype=np.int64); m[0, 1, 0] = 1; m[1, 0, 0] = FIELD_PRIME - 1
    >>> zero_divisor_cup_length(m, 1, FIELD_PRIME)
    2
    """
    m = np.asarray(m, dtype=np.int64) % p
    n1 = m.shape[0]
    if m.ndim != 3 or m.shape[1] != n1:
        raise InvalidInputError(f"cup-product array has shape {m.shape}, expected (b1, b1, r)")
    if n1 == 0 and b2 == 0:
        return 0
    squares_nonzero = p == 2 and bool(np.any(m[np.arange(n1), np.arange(n1)]))
    two = n1 >= 2 or (n1 >= 1 and b2 >= 1) or (b2 >= (1 if p != 2 else 2)) or squares_nonzero
    if not two:
        return 1
    if not (m.any() and (n1 >= 3 or b2 >= 2 or squares_nonzero)):
        return 2
    return 4 if _four_fold_product_nonzero(m, p, np.random.default_rng(seed)) else 3


def _zero_divisor_cup_length_of(cx: CubeComplex, coh: _FieldCohomology, seed: int = 0) -> int:
    """Zero-divisor cup-length over 𝔽_p: first with the products projected to a few random functionals on ``H²``
    (enough when that already reaches the maximum 4), then with the full products."""
    if coh.b2 > 16 and coh.b1:
        rng = np.random.default_rng(seed)
        phi = rng.integers(0, coh.p, size=(coh.b2, 16))
        if zero_divisor_cup_length(_cup_products(cx, coh, projection=phi), coh.b2, coh.p, seed) == 4:
            return 4
    return zero_divisor_cup_length(_cup_products(cx, coh), coh.b2, coh.p, seed)


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
        b1 = cx.n_edges - cx.n_vertices + 1
        betti = (1, b1, 0)
        tc = farber_tc_of_graph(b1)
        hdim = 0 if cx.n_edges == 0 else 1  # a collapsed graph with an edge but no free vertex has a cycle
        if hdim > hdim_upper:
            raise PlanningError(f"a component collapsed to a graph with b1 = {b1} > 0, expected hdim <= {hdim_upper}")
        hd = HomotopyDimension(hdim, hdim, collapsed_to_graph)
        return ComponentTopology(betti, betti, 1 - b1, True, hd, None, None, tc, (tc, tc), counts, graph_components)
    rank_q, unit_only = _rational_rank_of_boundary(cx)
    n_cycles = cx.n_edges - cx.n_vertices + 1
    betti = (1, n_cycles - rank_q, cx.n_squares - rank_q)
    coh2 = _field_cohomology(cx, 2)
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
    # the Serre diagonal needs edge directions that agree with the coordinates of every square (all signs +1)
    assert cx.signs is not None
    if np.any(cx.signs != 1):
        cx = cubical_subdivision(cx)
        coh2 = _field_cohomology(cx, 2)
    zcl2 = _zero_divisor_cup_length_of(cx, coh2)
    cohp = _field_cohomology(cx, FIELD_PRIME)
    if (cohp.b1, cohp.b2) != betti[1:] and torsion_free:
        raise PlanningError(f"Betti numbers over F_p {(cohp.b1, cohp.b2)} differ from those over Q {betti[1:]}")
    zclp = _zero_divisor_cup_length_of(cx, cohp)
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


def cube_complex_topology(cx: CubeComplex, max_homotopy_dimension: int = 2) -> tuple[ComponentTopology, ...]:
    """Homology, homotopy-dimension bounds and TC bounds of every path component of a cube complex.

    The complex is first collapsed through free faces (:func:`~mpa.discretized.collapse_free_faces`).

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

    >>> from mpa.discretized import CubeComplex
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
    if not isinstance(graph, MetricGraph) and callable(getattr(graph, "as_graph", None)):
        graph = graph.as_graph()
    if not isinstance(graph, MetricGraph):
        raise InvalidInputError(f"graph is a {type(graph).__name__}, expected a MetricGraph or a track")
    if graph.n_vertices == 0 or (graph.n_vertices == 1 and graph.n_edges == 0):
        raise InvalidInputError(
            f"graph has {graph.n_vertices} vertices and no edges: two robots do not fit, expected at least one edge "
            "or two vertices"
        )
    d2 = discretized_configuration_space(graph)
    sub = d2.subdivision
    counts = d2.complex.cell_counts
    expected = expected_cell_counts(sub)
    if counts != expected:
        raise PlanningError(f"D2 has cell counts {counts}, expected {expected} from the formulas")
    euler_formula = euler_characteristic_formula(graph)
    if counts.euler_characteristic != euler_formula:
        raise PlanningError(f"D2 has Euler characteristic {counts.euler_characteristic}, formula gives {euler_formula}")

    # per component of Γ: essential vertices, whether it is a circle, b1 and TC of the graph itself
    n_orig = sub.original_vertex_count
    deg = np.array([graph.degree(v) for v in graph.vertices], dtype=np.int64)
    comp_of = sub.component
    n_gc = int(comp_of.max()) + 1
    essential = np.bincount(comp_of[:n_orig], weights=(deg >= 3), minlength=n_gc).astype(int)
    gverts = np.bincount(comp_of, minlength=n_gc)
    gedges = np.bincount(comp_of[sub.edges[:, 0]], minlength=n_gc) if sub.n_edges else np.zeros(n_gc, dtype=int)
    gb1 = gedges - gverts + 1
    has_high_or_leaf = np.bincount(comp_of, weights=(sub.degrees() != 2), minlength=n_gc)
    is_circle = (gb1 == 1) & (has_high_or_leaf == 0)

    col = collapse_free_faces(d2.complex)
    comps: list[ComponentTopology] = []
    for cx, verts in _components(col.complex):
        v1, v2 = d2.vertex_cells[col.vertices[verts[0]]]
        ci, cj = int(comp_of[v1]), int(comp_of[v2])
        tc_upper: int | None = None
        if ci != cj:  # the product Γ_i × Γ_j of two components of Γ
            hdim = int(gb1[ci] > 0) + int(gb1[cj] > 0)
            tc_upper = farber_tc_of_graph(int(gb1[ci])) + farber_tc_of_graph(int(gb1[cj])) - 1
        elif is_circle[ci]:
            hdim = 1
        else:
            hdim = min(2, int(essential[ci]))
        comps.append(
            _connected_topology(
                cx,
                hdim_upper=hdim,
                collapsed_to_graph=cx.n_squares == 0,
                tc_upper=tc_upper,
                graph_components=(ci, cj),
            )
        )
    betti = tuple(int(sum(c.betti[k] for c in comps)) for k in range(3))
    betti_f2 = tuple(int(sum(c.betti_f2[k] for c in comps)) for k in range(3))
    euler = betti[0] - betti[1] + betti[2]
    if euler != euler_formula:
        raise PlanningError(f"Euler characteristic from the Betti numbers {betti} is {euler}, formula {euler_formula}")
    lo = max(c.tc_bounds[0] for c in comps)
    hi = max(c.tc_bounds[1] for c in comps)
    flags = [c.h1_torsion_free for c in comps]
    torsion_free = False if False in flags else (True if all(flags) else None)
    hd = HomotopyDimension(
        max(c.homotopy_dimension.lower for c in comps),
        max(c.homotopy_dimension.upper for c in comps),
        all(c.homotopy_dimension.collapsed_to_graph for c in comps),
    )
    return ConfigurationSpaceTopology(
        betti=betti,  # type: ignore[arg-type]
        betti_f2=betti_f2,  # type: ignore[arg-type]
        euler=euler,
        euler_formula=euler_formula,
        connected=betti[0] == 1,
        cell_counts=counts,
        subdivided_graph=(sub.n_vertices, sub.n_edges),
        essential_vertices=int(essential.sum()),
        homotopy_dimension=hd,
        tc=lo if lo == hi else None,
        tc_bounds=(lo, hi),
        h1_torsion_free=torsion_free,
        components=tuple(comps),
    )


# ==================================================================================================
# Graph input
# ==================================================================================================
def graph_from_json_data(data: object) -> MetricGraph:
    """Build a graph from decoded JSON ``{"edges": [[u, v], [u, v, length], ...]}``.

    Parameters
    ----------
    data : object
        Decoded JSON. Vertex names are strings or integers; loops and multiple edges are allowed; the default
        length is 1.

    Returns
    -------
    MetricGraph

    Raises
    ------
    InvalidInputError
        If ``edges`` is missing or empty, or an item is not ``[u, v]`` / ``[u, v, length]`` with string or integer
        vertices and a finite length >= 0.

    Examples
    --------
    >>> graph_from_json_data({"edges": [["F", "P"], ["P", "P", 2.5]]}).n_edges
    2
    """
    if not isinstance(data, dict):
        raise InvalidInputError(f'graph JSON is a {type(data).__name__}, expected an object with key "edges"')
    if "edges" not in data:
        raise InvalidInputError(f'graph JSON has keys {sorted(map(str, data))}, expected the key "edges"')
    edges = data["edges"]
    if not isinstance(edges, list):
        raise InvalidInputError(f'graph "edges" is a {type(edges).__name__}, expected a list of [u, v] pairs')
    if not edges:
        raise InvalidInputError('graph "edges" is empty, expected at least one edge [u, v]')
    for i, item in enumerate(edges):
        if not isinstance(item, list) or len(item) not in (2, 3):
            raise InvalidInputError(f"edge {i} is {item!r}, expected [u, v] or [u, v, length]")
        for w in item[:2]:
            if isinstance(w, bool) or not isinstance(w, (str, int)):
                raise InvalidInputError(f"vertex {w!r} of edge {i} is not a string or an integer")
        if len(item) == 3:
            length = item[2]
            if isinstance(length, bool) or not isinstance(length, (int, float)) or not math.isfinite(length):
                raise InvalidInputError(f"length of edge {i} is {length!r}, expected a finite number >= 0")
            if length < 0:
                raise InvalidInputError(f"length of edge {i} is {length!r}, expected a finite number >= 0")
    return MetricGraph.from_edge_list(edges)


def load_graph_json(path: str | Path) -> MetricGraph:
    """Read a graph from a JSON file ``{"edges": [[u, v], [u, v, length], ...]}``.

    Parameters
    ----------
    path : str or Path

    Returns
    -------
    MetricGraph

    Raises
    ------
    InvalidInputError
        If the file is missing or unreadable, is not JSON, or does not describe a graph.
    """
    p = Path(path)
    try:
        text = p.read_text(encoding="utf-8")
    except FileNotFoundError:
        raise InvalidInputError(f"graph file {str(p)!r} does not exist, expected a JSON file") from None
    except (OSError, UnicodeDecodeError) as exc:
        raise InvalidInputError(f"graph file {str(p)!r} cannot be read ({exc}), expected a UTF-8 JSON file") from None
    try:
        data = json.loads(text)
    except json.JSONDecodeError as exc:
        raise InvalidInputError(
            f"graph file {str(p)!r} is not valid JSON ({exc.msg} at line {exc.lineno} column {exc.colno})"
        ) from None
    return graph_from_json_data(data)
