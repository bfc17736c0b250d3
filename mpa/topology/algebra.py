"""Exact linear algebra for homology: sparse integer/mod-p elimination and dense ranks over 𝔽_p."""

from __future__ import annotations

import heapq
from fractions import Fraction

import numpy as np

__all__ = [
    "FIELD_PRIME",
    "Echelon",
    "dense_independent_columns",
    "dense_rank",
    "dense_rank_mod_p",
]

FIELD_PRIME = 524_287
"""The odd prime ``2¹⁹ - 1`` of the second coefficient field 𝔽_p (float64 dot products of residues stay exact)."""


# ==================================================================================================
# Sparse exact elimination
# ==================================================================================================
class Echelon:
    """Incremental sparse row echelon form over 𝔽_p (``p`` prime) or over ℤ with unit pivots (``p = 0``).

    Rows are dictionaries ``coordinate -> coefficient``. Every stored row has coefficient 1 at its pivot and 0 at
    the pivots of the rows stored before it, so reducing a vector by the rows in the order they were stored clears
    every pivot coordinate. Over ℤ only entries ±1 are used as pivots, so all operations are unimodular; a vector
    without such an entry is kept aside in :attr:`residual` (its rank is finished over ℚ by :func:`dense_rank`).
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


def dense_rank(rows: list[dict[int, int]]) -> int:
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


def dense_independent_columns(a: np.ndarray, p: int) -> list[int]:
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


def dense_rank_mod_p(a: np.ndarray, p: int) -> int:
    return len(dense_independent_columns(a, p))
