"""CSV text of whole columns in plain numpy: the twins of the compiled kernels of :mod:`trajopt.io.csv_kernels`.

A one-shot command-line process writes one setpoints file. Importing numba and loading its cached kernels costs
such a process about half a second; formatting the file's columns with numpy costs it a few tens of milliseconds
(``experiments/bench_csv_numpy.py``). This module is for those processes: it imports numpy and :mod:`mpa` only,
never numba (nor :mod:`trajopt._numba` or the kernel modules), so a process that formats its CSV with it need not
import numba.

:func:`g12_rows` has the contract of ``csv_kernels._g12`` and :func:`join_rows` that of ``csv_kernels._join``, and
their results are equal to the compiled kernels', byte for byte: the same floating-point operations in the same
order (the decimal exponent ``E`` from ``floor(log10(|x|))`` corrected by the same three comparisons, the power of
ten by the same repeated squaring numba compiles for ``10.0 ** k``, the same rounding and tie test), done on whole
arrays instead of one number at a time. The digits are then laid out with the rows sorted by layout (notation,
decimal exponent, significant digits kept, sign): a few slice assignments per layout, each layout's runs of bytes
derived from the kernel's rules when it is first used.

The one operation that may differ in its last bit is ``log10`` (numpy's vectorised ``log10`` against the C
library's): it gives only the first guess of ``E``, which the three comparisons correct to the exponent that puts
``|x|·10^(11-E)`` in ``[1e11, 1e12)``, so the digits, the numbers left to Python and the bytes are the kernel's
(the tests compare them on hundreds of thousands of numbers and every column the pipeline formats for the example
layouts).
"""

from __future__ import annotations

import numpy as np
from numpy.typing import NDArray

from mpa._arrays import IntArray

__all__ = ["TIE_BAND", "WIDTH", "g12_rows", "join_rows"]

#: Bytes of one formatted number (``-1.23456789012e-308`` is 19); also the compiled kernels' (``csv_kernels``).
WIDTH = 24
#: Distance from a rounding tie (in units of the twelfth digit) below which Python formats the number; also the
#: compiled kernels'.
TIE_BAND = 0.01

ByteMatrix = NDArray[np.uint8]

#: Largest ``|k|`` of a power of ten ``10^k`` the formatting uses (``|x|`` in ``(1e-290, 1e290)``, the decimal
#: exponent corrected by at most three steps: ``|11 - E| <= 304``), with room to spare.
_KMAX = 310


def _powers_of_ten() -> NDArray[np.float64]:
    """``10.0 ** k`` for ``k = 0 .. _KMAX`` as numba computes a float to an integer power (repeated squaring).

    Returns
    -------
    ndarray of float64, shape (_KMAX + 1,)
        Exact up to ``10^22``; above it the rounding of the squaring sequence, which can differ from the C
        library's ``pow`` in the last bit.
    """
    table = np.empty(_KMAX + 1)
    for k in range(_KMAX + 1):
        r, a, ex = 1.0, 10.0, k
        while ex != 0:
            if ex & 1:
                r *= a
            ex >>= 1
            a *= a  # overflows to inf after the last factor it gives above 10^256; never used then
        table[k] = r
    return table


_POW10 = _powers_of_ten()

# Slots of a number's text: its twelve digits and its exponent's three (rows of ``dig`` in :func:`g12_rows`), then
# the constant characters.
_DIGIT0 = 0
_EXP100, _EXP10, _EXP1 = 12, 13, 14
_SLOTS_VAR = 15
_MINUS, _DOT, _ZERO, _E, _PLUS = 15, 16, 17, 18, 19
_BYTE = {_MINUS: 45, _DOT: 46, _ZERO: 48, _E: 101, _PLUS: 43}  # '-', '.', '0', 'e', '+'

#: Layouts: fixed notation ``-4 <= E < 12`` (16 exponents x 12 last digits x 2 signs), then exponent notation
#: (12 last digits x 2 signs x 2 exponent signs x 2: three exponent digits or two).
_N_FIXED = 16 * 12 * 2
_N_LAYOUTS = _N_FIXED + 12 * 2 * 2 * 2


def _layout(fixed: bool, e: int, last: int, neg: bool, eneg: bool, big: bool) -> list[int]:
    """The slots of one number's text, following the kernel's rules.

    Parameters
    ----------
    fixed : bool
        Fixed notation (``-4 <= e < 12``) or exponent notation.
    e : int
        Decimal exponent (fixed notation only).
    last : int
        Index (0..11) of the last significant digit kept (trailing zeros dropped).
    neg : bool
        The number is negative.
    eneg, big : bool
        Exponent notation: the exponent is negative; it has three digits.

    Returns
    -------
    list of int
        Slot of each byte of the text, at most :data:`WIDTH` of them.
    """
    s = [_MINUS] if neg else []
    if fixed:
        if e >= 0:
            s += [_DIGIT0 + q for q in range(e + 1)]
            if last > e:
                s += [_DOT] + [_DIGIT0 + q for q in range(e + 1, last + 1)]
        else:
            s += [_ZERO, _DOT] + [_ZERO] * (-e - 1) + [_DIGIT0 + q for q in range(last + 1)]
    else:
        s.append(_DIGIT0)
        if last > 0:
            s += [_DOT] + [_DIGIT0 + q for q in range(1, last + 1)]
        s += [_E, _MINUS if eneg else _PLUS]
        s += ([_EXP100] if big else []) + [_EXP10, _EXP1]
    return s


def _runs(slots: list[int]) -> list[tuple[int, int, int, int]]:
    """A layout as runs: ``(first byte, first slot or -1, bytes, constant byte)``.

    Consecutive slots of the digits (or of the exponent's digits) make one run copied from ``dig``; repeats of one
    constant character one run filled with it.
    """
    runs: list[list[int]] = []
    for pos, slot in enumerate(slots):
        if slot < _SLOTS_VAR:
            if runs and runs[-1][1] >= 0 and runs[-1][1] + runs[-1][2] == slot:
                runs[-1][2] += 1
            else:
                runs.append([pos, slot, 1, 0])
        elif runs and runs[-1][1] < 0 and runs[-1][3] == _BYTE[slot]:
            runs[-1][2] += 1
        else:
            runs.append([pos, -1, 1, _BYTE[slot]])
    return [(r[0], r[1], r[2], r[3]) for r in runs]


def _layout_of(code: int) -> list[tuple[int, int, int, int]]:
    """The runs (:func:`_runs`) of layout ``code``, as :func:`g12_rows` codes the layouts; built once, when first used.

    Parameters
    ----------
    code : int
        ``((E + 4)·12 + last)·2 + negative`` in fixed notation (``-4 <= E < 12``), else
        ``_N_FIXED + ((last·2 + negative)·2 + (E < 0))·2 + (|E| >= 100)``.

    Returns
    -------
    list of (int, int, int, int)
    """
    runs = _LAYOUTS.get(code)
    if runs is None:
        if code < _N_FIXED:
            rest, neg = divmod(code, 2)
            e4, last = divmod(rest, 12)
            slots = _layout(True, e4 - 4, last, bool(neg), False, False)
        else:
            rest, big = divmod(code - _N_FIXED, 2)
            rest, eneg = divmod(rest, 2)
            last, neg = divmod(rest, 2)
            slots = _layout(False, 0, last, bool(neg), bool(eneg), bool(big))
        runs = _LAYOUTS[code] = _runs(slots)
    return runs


#: The layouts built so far, by code.
_LAYOUTS: dict[int, list[tuple[int, int, int, int]]] = {}


def g12_rows(values: NDArray[np.float64], out: ByteMatrix, lens: IntArray) -> None:
    """Write ``"%.12g" % values[i]`` into ``out[i, :lens[i]]``; ``lens[i] = 0`` where Python must format it.

    The numpy twin of ``trajopt.io.csv_kernels._g12``, equal to it: the same bytes in ``out`` (bytes after
    ``lens[i]`` and rows with ``lens[i] = 0`` are left as they were) and the same ``lens``. Python formats (left
    with ``lens[i] = 0``): NaN, infinities, ``0 < |x| <= 1e-290`` (subnormals among them), ``|x| >= 1e290``,
    numbers whose twelve digits ``|x|·10^(11-E)`` lie within :data:`TIE_BAND` of a rounding tie, and a few
    neighbours of powers of ten for which the kernel's three corrections of ``E`` find none (the rounded ``10^k``
    make the product jump over ``[1e11, 1e12)``, as ``9.999999999999999e-31`` does).

    Parameters
    ----------
    values : ndarray of float64, shape (N,)
        The numbers.
    out : ndarray of uint8, shape (N, W), W >= WIDTH
        Zeros on entry (as :func:`~trajopt.io.csv_kernels.format_g12` passes it); row ``i`` receives the ASCII
        text of ``values[i]`` in its first ``lens[i]`` bytes.
    lens : ndarray of int64, shape (N,)
        Receives the bytes of each text, 0 where Python must format the number.
    """
    x = np.asarray(values, dtype=np.float64)
    for r0 in range(0, x.shape[0], _G12_CHUNK):  # a few thousand rows at a time: the temporaries stay in cache
        r1 = r0 + _G12_CHUNK
        _g12_block(x[r0:r1], out[r0:r1], lens[r0:r1])


#: Numbers formatted per step of :func:`g12_rows`.
_G12_CHUNK = 8192


def _g12_block(x: NDArray[np.float64], out: ByteMatrix, lens: IntArray) -> None:
    """:func:`g12_rows` on one block of rows (the same arguments)."""
    lens[:] = 0
    ax = np.abs(x)
    neg = np.signbit(x)
    zero = np.flatnonzero(ax == 0.0)
    if zero.size:
        zneg = zero[neg[zero]]
        zpos = zero[~neg[zero]]
        out[zpos, 0] = 48  # '0'
        lens[zpos] = 1
        out[zneg, 0] = 45  # '-0'
        out[zneg, 1] = 48
        lens[zneg] = 2
    rows = np.flatnonzero((ax > 1e-290) & (ax < 1e290))  # not: subnormal, huge, inf, nan
    if rows.size == 0:
        return
    e, d = _exponents_and_digits(ax[rows] if rows.size < x.size else ax)
    keep = d >= 0
    if not keep.all():
        rows, e, d = rows[keep], e[keep], d[keep]
        if rows.size == 0:
            return
    src, last = _digit_bytes(d, e)
    code = ((e + 4) * 12 + last) * 2 + neg[rows]
    expo = np.flatnonzero((e < -4) | (e >= 12))
    if expo.size:
        ee, le, ne = e[expo], last[expo], neg[rows[expo]]
        code[expo] = _N_FIXED + ((le * 2 + ne) * 2 + (ee < 0)) * 2 + (np.abs(ee) >= 100)
    _lay_out(out, lens, rows, code, src)


def _exponents_and_digits(a: NDArray[np.float64]) -> tuple[IntArray, IntArray]:
    """Decimal exponent ``E`` and twelve digits ``round(a·10^(11-E))`` of each number, as the kernel finds them.

    Parameters
    ----------
    a : ndarray of float64, shape (M,)
        Magnitudes in ``(1e-290, 1e290)``.

    Returns
    -------
    e : ndarray of int64, shape (M,)
        Decimal exponent (after the carry of ``999999999999.5`` to ``1e12``).
    d : ndarray of int64, shape (M,)
        The twelve digits as an integer in ``[1e11, 1e12)``; -1 where Python must format the number (no exponent
        found in three corrections, or ``a·10^(11-E)`` within :data:`TIE_BAND` of a rounding tie).
    """
    e = np.floor(np.log10(a)).astype(np.int64)
    scaled = _scale(a, e)
    pending = np.flatnonzero((scaled >= 1e12) | (scaled < 1e11))
    good = np.ones(a.size, bool)
    for step in range(3):  # the kernel's three corrections of E; the first is done above
        if pending.size == 0:
            break
        s = scaled[pending]
        e[pending] += (s >= 1e12).astype(np.int64) - (s < 1e11)
        if step == 2:
            good[pending] = False
            break
        s = _scale(a[pending], e[pending])
        scaled[pending] = s
        pending = pending[(s >= 1e12) | (s < 1e11)]
    fl = np.floor(scaled)
    frac = scaled - fl
    d = fl.astype(np.int64) + (frac > 0.5)
    d[~good | (np.abs(frac - 0.5) < TIE_BAND)] = -1  # near a tie: Python decides
    carry = np.flatnonzero(d >= 1000000000000)
    if carry.size:
        d[carry] //= 10
        e[carry] += 1
    return e, d


def _scale(a: NDArray[np.float64], e: IntArray) -> NDArray[np.float64]:
    """``a·10^(11-e)`` as the kernel computes it: times ``10^k`` for ``k >= 0``, divided by ``10^-k`` else.

    Parameters
    ----------
    a : ndarray of float64, shape (M,)
    e : ndarray of int64, shape (M,)

    Returns
    -------
    ndarray of float64, shape (M,)
    """
    k = 11 - e
    p = _POW10[np.abs(k)]
    up = k >= 0
    s = np.empty_like(a)
    np.multiply(a, p, out=s, where=up)
    np.divide(a, p, out=s, where=~up)
    return s


def _digit_bytes(d: IntArray, e: IntArray) -> tuple[ByteMatrix, IntArray]:
    """The ASCII digits of ``d`` and of ``|e|``, and the last significant digit of ``d``.

    Four-digit groups are split into digits with multiply-and-shift divisions inside 64-bit words (two digits a
    16-bit lane, then one a byte): exact for the ranges they see (``(x·5243) >> 19 = x // 100`` for
    ``x < 43699``, ``(x·103) >> 10 = x // 10`` for ``x < 100``).

    Parameters
    ----------
    d : ndarray of int64, shape (M,)
        Twelve-digit integers in ``[1e11, 1e12)``.
    e : ndarray of int64, shape (M,)
        Decimal exponents, ``|e| < 1000``.

    Returns
    -------
    src : ndarray of uint8, shape (M, 16)
        Bytes 0..11: the digits of ``d``; byte 12: ``'0'``; bytes 13..15: the hundreds, tens and ones of ``|e|``.
    last : ndarray of int64, shape (M,)
        Index (0..11) of the last nonzero digit of ``d``.
    """
    m = d.size
    words = np.empty((m, 2), np.int64)  # lanes of 32 bits: digits 0..3 | 4..7, digits 8..11 | |e|
    w0, w1 = words[:, 0], words[:, 1]
    hi = d // 10000  # digits 0..7
    np.multiply(hi, -10000, out=w1)
    w1 += d
    top = hi // 10000  # digits 0..3
    np.multiply(top, -10000, out=w0)
    w0 += hi
    w0 <<= 32
    w0 |= top
    ae = np.abs(e)
    ae <<= 32
    w1 |= ae
    q = words * 5243  # to 16-bit lanes of two digits
    q >>= 19
    q &= 0x0000007F0000007F
    r = q * -100
    r += words
    r <<= 16
    r |= q
    np.multiply(r, 103, out=q)  # to bytes of one digit, the first digit lowest
    q >>= 10
    q &= 0x000F000F000F000F
    np.multiply(q, -10, out=words)
    words += r
    words <<= 8
    words |= q
    # last significant digit: the highest nonzero byte among digits 8..11 (word 1's low half), else of word 0
    tail = w1 & 0xFFFFFFFF
    has_tail = tail != 0
    _, bit = np.frexp(np.where(has_tail, tail, w0).astype(np.float64))
    last = bit.astype(np.int64)
    last -= 1
    last >>= 3
    last += has_tail * 8
    words += 0x3030303030303030
    return words.astype("<i8", copy=False).view(np.uint8).reshape(m, 16), last


#: Slot of each byte of ``_digit_bytes``' rows: the twelve digits, then (after a '0') the exponent's three digits.
_SRC_COLUMN = {**{_DIGIT0 + q: q for q in range(12)}, _EXP100: 13, _EXP10: 14, _EXP1: 15}


def _lay_out(out: ByteMatrix, lens: IntArray, rows: IntArray, code: IntArray, src: ByteMatrix) -> None:
    """Write each number's text into ``out`` and its length into ``lens``: rows sorted by layout, each layout's rows
    one block of slices.

    Parameters
    ----------
    out : ndarray of uint8, shape (N, W), W >= WIDTH
    lens : ndarray of int64, shape (N,)
    rows : ndarray of int64, shape (M,)
        Rows of ``out`` to write.
    code : ndarray of int64, shape (M,)
        Layout of each (:func:`_layout_of`).
    src : ndarray of uint8, shape (M, 16)
        Digits as :func:`_digit_bytes` returns them.
    """
    order = np.argsort(code.astype(np.int16), kind="stable")
    counts = np.bincount(code, minlength=_N_LAYOUTS)
    present = np.flatnonzero(counts)
    ends = np.cumsum(counts[present])
    target = rows[order]
    src = src.view(_V16).reshape(-1)[order].view(np.uint8).reshape(-1, 16)
    whole = out.shape[1] == WIDTH and out.flags.c_contiguous
    if whole:  # rows of WIDTH bytes moved as single items
        view = out.view(_VW).reshape(-1)
        block = view[target].view(np.uint8).reshape(-1, WIDTH)
    else:
        block = out[target, :WIDTH]
    b0 = 0
    for c, b1 in zip(present.tolist(), ends.tolist(), strict=True):
        runs = _layout_of(c)
        for dst, slot, n, byte in runs:
            if slot < 0:
                block[b0:b1, dst : dst + n] = byte
            else:
                col = _SRC_COLUMN[slot]
                block[b0:b1, dst : dst + n] = src[b0:b1, col : col + n]
        lens[target[b0:b1]] = runs[-1][0] + runs[-1][2]
        b0 = b1
    if whole:
        view[target] = block.view(_VW).reshape(-1)
    else:
        out[target, :WIDTH] = block


_V16 = np.dtype((np.void, 16))
_VW = np.dtype((np.void, WIDTH))


def join_rows(cells: ByteMatrix, lens: IntArray, starts: IntArray, out: ByteMatrix) -> int:
    """Copy row ``i``'s cells (column ``k`` at ``cells[i, starts[k]:starts[k] + lens[i, k]]``) into ``out``,
    joined by ``,``, each row ending in ``\\n``; returns the bytes written.

    The numpy twin of ``trajopt.io.csv_kernels._join``, equal to it: the same bytes in ``out[:n]`` (the rest of
    ``out`` left as it was) and the same ``n``. A block of rows at a time (:data:`_JOIN_CHUNK_BYTES` gathered
    bytes), the cells' bytes are gathered into one matrix with a separator after each column (each column as wide
    as its longest cell), and one boolean mask (byte ``q`` of column ``k`` kept where ``q < lens[i, k]``,
    separators always) selects the records' bytes in row-major order.

    Parameters
    ----------
    cells : ndarray of uint8, shape (N, W)
        The cells' bytes; column ``k`` of row ``i`` in ``cells[i, starts[k]:starts[k] + lens[i, k]]``.
    lens : ndarray of int64, shape (N, C)
        Bytes of each cell.
    starts : ndarray of int64, shape (C,)
        First byte of each column in a row of ``cells``.
    out : ndarray of uint8, shape (M,), M >= lens.sum() + N·C
        Receives the records.

    Returns
    -------
    int
        Bytes written, ``lens.sum() + N·C``.
    """
    cells, lens, starts = np.asarray(cells), np.asarray(lens), np.asarray(starts, dtype=np.int64)
    nrow, ncol = lens.shape[0], starts.shape[0]
    if nrow == 0 or ncol == 0:
        return 0
    width = lens.max(axis=0)
    kind = np.uint8 if width.max() < 255 else np.int64
    # per byte of a gathered row: the column of ``cells`` it comes from, and its place in its cell
    source = np.concatenate([np.append(np.arange(starts[k], starts[k] + width[k]), 0) for k in range(ncol)])
    place = np.concatenate([np.append(np.arange(width[k]), 0) for k in range(ncol)]).astype(kind)
    seps = np.cumsum(width + 1) - 1
    sep_bytes = np.full(ncol, 44, np.uint8)  # ','
    sep_bytes[-1] = 10  # '\n'
    bound = np.empty((nrow, 2 * ncol), kind)  # each cell's length, then the separator's (always kept)
    bound[:, 0::2] = lens
    bound[:, 1::2] = np.iinfo(kind).max
    repeat = np.ones(2 * ncol, np.int64)
    repeat[0::2] = width
    if cells.shape[1] == 0:  # every cell empty: the separators only
        cells = np.zeros((nrow, 1), np.uint8)
    chunk = max(1, _JOIN_CHUNK_BYTES // source.size)
    gathered = np.empty((min(chunk, nrow), source.size), np.uint8)
    keep = np.empty(gathered.shape, bool)
    n = 0
    for r0 in range(0, nrow, chunk):
        r1 = min(nrow, r0 + chunk)
        g, kp = gathered[: r1 - r0], keep[: r1 - r0]
        np.take(cells[r0:r1], source, axis=1, out=g, mode="clip")
        g[:, seps] = sep_bytes
        np.less(place, np.repeat(bound[r0:r1], repeat, axis=1), out=kp)
        text = g[kp]
        out[n : n + text.size] = text
        n += text.size
    return n


#: Bytes of the gathered cells per step of :func:`join_rows` (in the processor's cache).
_JOIN_CHUNK_BYTES = 1 << 18
