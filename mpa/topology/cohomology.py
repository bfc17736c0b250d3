"""Cohomology of a connected cube complex over a field, cup products (Serre diagonal), zero-divisor cup-length."""

from __future__ import annotations

from collections import deque
from dataclasses import dataclass

import numpy as np

from mpa.errors import InvalidInputError, PlanningError
from mpa.topology.algebra import Echelon, dense_independent_columns, dense_rank, dense_rank_mod_p
from mpa.topology.discretized import (
    BOTTOM,
    LEFT,
    RIGHT,
    TOP,
    CubeComplex,
)

__all__ = [
    "FieldCohomology",
    "cup_products",
    "field_cohomology",
    "rational_rank_of_boundary",
    "zero_divisor_cup_length",
    "zero_divisor_cup_length_of",
]

_EXHAUSTIVE_LIMIT = 20_000_000
"""Largest ``w⁴ · r(r+1)/2`` for which the four-fold zero-divisor products are checked exhaustively."""

_INTEGER_MATMUL_WORK = 5_000_000
"""Up to this many multiply-adds a product mod p is done in int64 (no BLAS threads), beyond in float64 blocks."""

_SLICE_ENTRIES = 1_000_000
"""Entries of one slice of the four-index array in the exhaustive four-fold check."""

_RANDOM_TRIALS = 64
"""Random trials of the four-fold zero-divisor test when the exhaustive check is too large."""


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
class FieldCohomology:
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


def field_cohomology(cx: CubeComplex, p: int) -> FieldCohomology:
    tree = _spanning_tree_mask(cx)
    nontree = np.nonzero(~tree)[0]
    # 1-cocycles vanishing on the tree = vectors on the non-tree edges orthogonal to every restricted ∂(square)
    col = np.full(cx.n_edges, -1, dtype=np.int64)
    col[nontree] = np.arange(nontree.size)
    rows = Echelon(p)
    for vec in _boundaries(cx):
        rows.insert({int(col[e]): c for e, c in vec.items() if col[e] >= 0})
    cocycles = np.zeros((nontree.size - rows.rank, cx.n_edges), dtype=np.int64)
    cocycles[:, nontree] = rows.annihilator(nontree.size)
    # 2-cycles = vectors on the squares orthogonal to every δ(edge) (the non-tree edges span im δ)
    cols = Echelon(p)
    for vec in _coboundaries(cx, nontree):
        cols.insert(vec)
    if cols.rank != rows.rank:
        raise PlanningError(f"rank of the boundary map mod {p} is {rows.rank} by rows and {cols.rank} by columns")
    cycles = cols.annihilator(cx.n_squares)
    return FieldCohomology(p, len(cocycles), len(cycles), cocycles, cycles)


def rational_rank_of_boundary(cx: CubeComplex) -> tuple[int, bool]:
    """Rank over ℚ of ``∂₂`` (via ``δ`` on the edges off a spanning tree) and whether only unit pivots were needed.

    When only unit pivots were needed, the Smith normal form of ``∂₂`` is all ones, so ``H₁(·; ℤ)`` is free.
    """
    tree = _spanning_tree_mask(cx)
    nontree = np.nonzero(~tree)[0]
    ech = Echelon(0)
    for vec in _coboundaries(cx, nontree):
        ech.insert(vec)
    residual = []
    for v in ech.residual:
        v = dict(v)
        ech.reduce(v)
        if v:
            residual.append(v)
    return ech.rank + (dense_rank(residual) if residual else 0), not residual


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


def cup_products(
    cx: CubeComplex,
    coh: FieldCohomology,
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
    if cx.signs is None:
        raise PlanningError("internal: cx.signs is not set")
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
    cols = dense_independent_columns(m.reshape(n1 * n1, -1), p)
    if not cols:
        return False
    mp = m[:, :, cols] % p
    r = len(cols)
    rows = dense_independent_columns(mp.reshape(n1, n1 * r).T, p)
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
            if dense_rank_mod_p(omega, p) >= 4:
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

    >>> import numpy as np
    >>> from mpa.topology.algebra import FIELD_PRIME
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


def zero_divisor_cup_length_of(cx: CubeComplex, coh: FieldCohomology, seed: int = 0) -> int:
    """Zero-divisor cup-length over 𝔽_p: first with the products projected to a few random functionals on ``H²``
    (enough when that already reaches the maximum 4), then with the full products."""
    if coh.b2 > 16 and coh.b1:
        rng = np.random.default_rng(seed)
        phi = rng.integers(0, coh.p, size=(coh.b2, 16))
        if zero_divisor_cup_length(cup_products(cx, coh, projection=phi), coh.b2, coh.p, seed) == 4:
            return 4
    return zero_divisor_cup_length(cup_products(cx, coh), coh.b2, coh.p, seed)
