"""CSV text of whole columns at once: numbers as ``"%.12g" % x`` would print them, compiled (numba).

The setpoint files hold hundreds of thousands of rows; formatting every number with Python's ``%`` took about
2 µs a number. :func:`format_g12` writes the twelve significant digits of a whole column into a byte matrix, and
:func:`csv_rows` lays the columns out as CSV records with one mask: byte for byte the text ``"%.12g" % x`` (and
``str`` of the text cells) joined by commas gives.

Exactness: the twelve digits are ``round(|x|·10^(11-E))`` for the decimal exponent ``E`` of ``x``; the product is
computed in floating point, within a few units of its last place (below 1e-3 of a digit). Where it lies within
:data:`TIE_BAND` of a rounding tie (and for NaN, infinities, subnormal and huge numbers) the kernel
leaves the number to Python's own ``%.12g`` (:func:`format_g12` fills those in), so every number is printed exactly
as Python prints it.
"""

from __future__ import annotations

import math
from collections.abc import Sequence

import numpy as np
from numpy.typing import NDArray

from mpa._arrays import IntArray
from trajopt._numba import njit, numpy_twins
from trajopt.io.csv_numpy import TIE_BAND, WIDTH  # the numbers' layout, one definition for both forms

__all__ = ["TIE_BAND", "WIDTH", "csv_rows", "format_g12", "text_column"]

ByteMatrix = NDArray[np.uint8]


@njit(cache=True)
def _g12(values: NDArray[np.float64], out: ByteMatrix, lens: IntArray) -> None:  # pragma: no cover - compiled
    """Write ``"%.12g" % values[i]`` into ``out[i, :lens[i]]``; ``lens[i] = 0`` where Python must format it."""
    digits = np.empty(12, np.uint8)
    for i in range(values.shape[0]):
        x = values[i]
        lens[i] = 0
        ax = abs(x)
        if ax == 0.0:
            if math.copysign(1.0, x) < 0:
                out[i, 0] = 45  # '-0'
                out[i, 1] = 48
                lens[i] = 2
            else:
                out[i, 0] = 48
                lens[i] = 1
            continue
        if not (1e-290 < ax < 1e290):  # subnormal, huge, inf, nan: Python's formatting
            continue
        e = math.floor(math.log10(ax))
        scaled = 0.0
        good = False
        for _ in range(3):
            k = 11 - e
            p = 10.0 ** abs(k)
            scaled = ax * p if k >= 0 else ax / p
            if scaled >= 1e12:
                e += 1
            elif scaled < 1e11:
                e -= 1
            else:
                good = True
                break
        if not good:
            continue
        fl = math.floor(scaled)
        if abs(scaled - fl - 0.5) < TIE_BAND:  # near a tie: Python decides
            continue
        d = np.int64(fl) + (1 if scaled - fl > 0.5 else 0)
        if d >= 1000000000000:
            d = d // 10
            e += 1
        for q in range(11, -1, -1):
            digits[q] = 48 + d % 10
            d //= 10
        n = 0
        if x < 0:
            out[i, n] = 45  # '-'
            n += 1
        last = 11  # last significant digit kept (trailing zeros dropped)
        while last > 0 and digits[last] == 48:
            last -= 1
        if -4 <= e < 12:
            if e >= 0:
                for q in range(e + 1):
                    out[i, n] = digits[q]
                    n += 1
                if last > e:
                    out[i, n] = 46  # '.'
                    n += 1
                    for q in range(e + 1, last + 1):
                        out[i, n] = digits[q]
                        n += 1
            else:
                out[i, n] = 48
                out[i, n + 1] = 46
                n += 2
                for _ in range(-e - 1):
                    out[i, n] = 48
                    n += 1
                for q in range(last + 1):
                    out[i, n] = digits[q]
                    n += 1
        else:
            out[i, n] = digits[0]
            n += 1
            if last > 0:
                out[i, n] = 46
                n += 1
                for q in range(1, last + 1):
                    out[i, n] = digits[q]
                    n += 1
            out[i, n] = 101  # 'e'
            out[i, n + 1] = 45 if e < 0 else 43
            n += 2
            ae = abs(e)
            if ae >= 100:
                out[i, n] = 48 + ae // 100
                n += 1
            out[i, n] = 48 + (ae // 10) % 10
            out[i, n + 1] = 48 + ae % 10
            n += 2
        lens[i] = n


def format_g12(values: NDArray[np.float64]) -> tuple[ByteMatrix, IntArray]:
    """``"%.12g" % x`` of every ``x`` in ``values``, as ASCII bytes.

    Parameters
    ----------
    values : ndarray, shape (N,)
        Numbers (any float; cast to float64).

    Returns
    -------
    text : ndarray of uint8, shape (N, WIDTH)
        Row ``i`` holds the text of ``values[i]`` in its first ``lens[i]`` bytes.
    lens : ndarray of int64, shape (N,)
    """
    x = np.ascontiguousarray(values, dtype=np.float64)
    out = np.zeros((len(x), WIDTH), np.uint8)
    lens = np.zeros(len(x), np.int64)
    _g12(x, out, lens)
    for i in np.flatnonzero(lens == 0):
        b = ("%.12g" % float(x[i])).encode("ascii")  # noqa: UP031 - the format the kernel follows
        out[i, : len(b)] = np.frombuffer(b, np.uint8)
        lens[i] = len(b)
    return out, lens


def text_column(cells: Sequence[str], index: IntArray) -> tuple[ByteMatrix, IntArray]:
    """A column of text cells drawn from ``cells`` (already CSV fields) by ``index``, as UTF-8 bytes.

    Parameters
    ----------
    cells : sequence of str, length M
        The distinct cells.
    index : ndarray of int, shape (N,)
        Which cell each row holds.

    Returns
    -------
    text : ndarray of uint8, shape (N, W)
    lens : ndarray of int64, shape (N,)
    """
    enc = [c.encode("utf-8") for c in cells]
    width = max([1, *(len(b) for b in enc)])
    table = np.zeros((max(1, len(enc)), width), np.uint8)
    tlen = np.zeros(max(1, len(enc)), np.int64)
    for k, b in enumerate(enc):
        table[k, : len(b)] = np.frombuffer(b, np.uint8)
        tlen[k] = len(b)
    idx = np.asarray(index, dtype=np.int64)
    return table[idx], tlen[idx]


@njit(cache=True)
def _join(cells: ByteMatrix, lens: IntArray, starts: IntArray, out: ByteMatrix) -> int:  # pragma: no cover
    """Copy row ``i``'s cells (column ``k`` at ``cells[i, starts[k]:starts[k] + lens[i, k]]``) into ``out``,
    joined by ``,``, each row ending in ``\n``; returns the bytes written."""
    n = 0
    ncol = starts.shape[0]
    for i in range(cells.shape[0]):
        for k in range(ncol):
            c0 = starts[k]
            for q in range(lens[i, k]):
                out[n] = cells[i, c0 + q]
                n += 1
            out[n] = 10 if k == ncol - 1 else 44
            n += 1
    return n


def csv_rows(columns: Sequence[tuple[ByteMatrix, IntArray]]) -> bytes:
    """CSV records of formatted columns: the cells of each row joined by ``,``, each row ending in ``\n``.

    Parameters
    ----------
    columns : sequence of (text, lens)
        Per column, as :func:`format_g12` and :func:`text_column` return them, all with N rows.

    Returns
    -------
    bytes
        N records (empty when N is 0).
    """
    if not columns or len(columns[0][1]) == 0:
        return b""
    cells = np.ascontiguousarray(np.concatenate([text for text, _ in columns], axis=1))
    lens = np.ascontiguousarray(np.stack([ln for _, ln in columns], axis=1).astype(np.int64))
    starts = np.cumsum([0] + [text.shape[1] for text, _ in columns[:-1]]).astype(np.int64)
    out = np.empty(int(lens.sum()) + lens.size, np.uint8)
    n = _join(cells, lens, starts, out)
    return out[:n].tobytes()


if numpy_twins():  # a process that runs without numba (trajopt._numba): the numpy twins, the same bytes
    import trajopt.io.csv_numpy as csv_numpy

    _g12 = csv_numpy.g12_rows
    _join = csv_numpy.join_rows
