"""The numpy twins of the CSV kernels (:mod:`trajopt.io.csv_numpy`) equal the compiled kernels, byte for byte.

``g12_rows`` is compared with ``csv_kernels._g12`` (the same bytes in ``out``, the same ``lens``, so the same
numbers left to Python) and, through ``format_g12`` with ``g12_rows`` in place of ``_g12``, with Python's
``"%.12g"``; ``join_rows`` with ``csv_kernels._join``. The inputs: seeded random numbers over all magnitudes and
the hard cases of ``%.12g`` (rounding ties of the twelfth digit, powers of ten, the switches of notation, the digit
carry, zeros, NaN, infinities, subnormals), hypothesis floats, random cell matrices, and the columns and cells the
pipeline formats when it writes the setpoints of example layouts (recorded at the kernels' call sites).
"""

from __future__ import annotations

import json
import subprocess
import sys
from collections.abc import Callable
from decimal import Decimal
from pathlib import Path
from typing import Any

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

import trajopt.io.csv_kernels as ck
from mpa import Circle, GraphTrack, Lollipop
from mpa.footprint import Disc
from trajopt import generate_trajectory
from trajopt.export import Trajectory
from trajopt.io import csv_numpy
from trajopt.io.csv_numpy import g12_rows, join_rows

ROOT = Path(__file__).resolve().parents[2]
TRACKS = ROOT / "examples" / "tracks"


def _python(x: np.ndarray) -> list[str]:
    return ["%.12g" % v for v in x.tolist()]  # noqa: UP031 - the format under test


def _texts(text: np.ndarray, lens: np.ndarray) -> list[str]:
    return [bytes(text[i, : lens[i]]).decode("ascii") for i in range(len(lens))]


def _compare_g12(x: np.ndarray, width: int = csv_numpy.WIDTH, fill: int | None = None) -> None:
    """``g12_rows`` and ``_g12`` write the same bytes and lengths (``out`` zeros, or random bytes seeded ``fill``)."""
    x = np.ascontiguousarray(x, dtype=np.float64)
    if fill is None:
        start = np.zeros((len(x), width), np.uint8)
    else:
        start = np.random.default_rng(fill).integers(0, 256, (len(x), width), dtype=np.uint8)
    out_k, out_t = start.copy(), start.copy()
    lens_k = np.full(len(x), -7, np.int64)
    lens_t = lens_k.copy()
    ck._g12(x, out_k, lens_k)
    g12_rows(x, out_t, lens_t)
    bad = np.flatnonzero((out_k != out_t).any(axis=1) | (lens_k != lens_t))
    shown = [
        (repr(float(x[i])), bytes(out_k[i, : max(lens_k[i], 0)]), int(lens_k[i]), bytes(out_t[i]), int(lens_t[i]))
        for i in bad[:10]
    ]
    assert bad.size == 0, f"{bad.size} of {len(x)} differ (x, kernel text, kernel len, twin row, twin len): {shown}"


def _compare_python(x: np.ndarray, monkeypatch: pytest.MonkeyPatch) -> None:
    """``format_g12`` with ``g12_rows`` in place of ``_g12`` prints every number as Python's ``"%.12g"``."""
    x = np.asarray(x, dtype=np.float64)
    monkeypatch.setattr(ck, "_g12", g12_rows)
    got = _texts(*ck.format_g12(x))
    monkeypatch.undo()
    want = _python(x)
    bad = [(v, g, w) for v, g, w in zip(x.tolist(), got, want, strict=True) if g != w]
    assert not bad, f"{len(bad)} of {len(x)} differ (x, twin, Python): {bad[:10]}"


def _ties(rng: np.random.Generator, n: int, exponents: range) -> np.ndarray:
    """The doubles nearest to ``d.5 · 10^(E-11)`` (twelve digits ``d``) and their neighbours 1 and 2 ulps away."""
    d = rng.integers(10**11, 10**12, n)
    e = rng.choice(np.asarray(exponents), n)
    tie = np.array([float(Decimal(int(di) * 10 + 5).scaleb(int(ei) - 12)) for di, ei in zip(d, e, strict=True)])
    tie *= rng.choice([-1.0, 1.0], n)
    up, down = np.nextafter(tie, 2 * tie), np.nextafter(tie, 0.0)
    return np.concatenate([tie, up, down, np.nextafter(up, 2 * up), np.nextafter(down, 0.0)])


def _hard_cases() -> np.ndarray:
    """Powers of ten and their neighbours, the switches of notation, the digit carry, zeros, non-finite numbers,
    subnormals, the kernel's own limits (1e-290, 1e290), integers and numbers with few digits."""
    p = 10.0 ** np.arange(-323, 309)
    near = [p, np.nextafter(p, 0.0), np.nextafter(p, np.inf), np.nextafter(np.nextafter(p, 0.0), 0.0)]
    k = np.arange(-300, 290)
    carry = [
        np.array([float(Decimal(s).scaleb(int(i))) for i in k])
        for s in ("9.99999999999", "9.999999999994", "9.999999999995", "9.9999999999951", "9.99999999999949")
    ]
    switch = np.array(
        [
            *(1e-5, 1e-4, 9.99999999999e-5, 9.999999999995e-5, 9.9999999999949e-5, 0.0001000000000005, 1e11, 1e12),
            *(99999999999.95, 99999999999.949, 999999999999.4, 999999999999.5, 999999999999.6, 9.999999999995e11),
            *(1e12 - 1, 1e12 + 1, 123456789012.5, 0.1 + 0.2, 1 / 3, 2 / 3, 5e-5, 5e-4),
        ]
    )
    special = np.array(
        [
            *(0.0, -0.0, np.nan, -np.nan, np.inf, -np.inf, 5e-324, -5e-324, 2.2250738585072014e-308),
            *(np.nextafter(2.2250738585072014e-308, 0.0), 2.2250738585072014e-308 / 3, 1.7976931348623157e308),
            *(1e-290, np.nextafter(1e-290, 0.0), np.nextafter(1e-290, 1.0), 1e290, np.nextafter(1e290, 0.0)),
            *(np.nextafter(1e290, np.inf), 0.5, 1.25, 100.0, 0.001, 123.456, 2.0**53, 2.0**53 + 2, 2.0**63),
        ]
    )
    ints = np.concatenate([np.arange(-1000, 1001), np.arange(99999999990, 100000000011)])
    ints = np.concatenate([ints, np.arange(999999999990, 1000000000011)]).astype(np.float64)
    every = np.concatenate([*near, *carry, switch, special, ints])
    return np.concatenate([every, -every])


def _seeded(seed: int) -> np.ndarray:
    rng = np.random.default_rng(seed)
    n = 6000
    with np.errstate(over="ignore", under="ignore"):
        wide = rng.normal(size=n) * 10.0 ** rng.uniform(-300, 300, n)
    return np.concatenate(
        [
            wide,
            rng.choice([-1.0, 1.0], n) * 10.0 ** rng.uniform(-330, 308.25, n),  # subnormals to the largest
            rng.normal(size=n) * 10.0 ** rng.uniform(-6, 14, n),  # both notations, near their switches
            rng.integers(-(10**7), 10**7, n) / 10.0 ** rng.integers(0, 7, n),  # few digits
            rng.integers(-(10**15), 10**15, n).astype(np.float64),  # integers
            rng.integers(-1000, 1000, n) / 8.0,  # exact binary fractions
            rng.uniform(0.0, 500.0, n),  # times, offsets, speeds
            _ties(rng, n // 5, range(-30, 30)),
            _ties(rng, n // 10, range(-300, 290)),
        ]
    )


def test_the_constants_are_the_kernels() -> None:
    assert (csv_numpy.WIDTH, csv_numpy.TIE_BAND) == (ck.WIDTH, ck.TIE_BAND)


def test_importing_the_module_imports_no_numba() -> None:
    code = (
        "import importlib.util, sys\n"
        f"spec = importlib.util.spec_from_file_location('csv_numpy', {str(ROOT / 'trajopt/io/csv_numpy.py')!r})\n"
        "m = importlib.util.module_from_spec(spec); spec.loader.exec_module(m)\n"
        "print(sorted(n for n in sys.modules if n.split('.')[0] in ('numba', 'trajopt', 'llvmlite')))\n"
    )
    env = {"PYTHONPATH": str(ROOT)}
    proc = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, env=env, check=True)
    assert proc.stdout.strip() == "[]", proc.stdout + proc.stderr


def test_powers_of_ten_are_numbas() -> None:
    numba = pytest.importorskip("numba")

    @numba.njit
    def power(k: int) -> float:  # pragma: no cover - compiled
        return 10.0 ** abs(k)

    got = np.array([power(k) for k in range(csv_numpy._KMAX + 1)])
    bad = np.flatnonzero(got != csv_numpy._POW10)
    assert bad.size == 0, [(int(k), got[k], csv_numpy._POW10[k]) for k in bad[:10]]


@pytest.mark.parametrize("seed", [0, 1, 2])
def test_g12_rows_equals_the_kernel_on_seeded_numbers(seed: int) -> None:
    x = _seeded(seed)
    _compare_g12(x)
    _compare_g12(x[::-1], fill=seed)  # bytes after the text and rows left to Python keep what they held


def test_g12_rows_equals_the_kernel_on_the_hard_cases(monkeypatch: pytest.MonkeyPatch) -> None:
    x = _hard_cases()
    _compare_g12(x)
    monkeypatch.setattr(csv_numpy, "_G12_CHUNK", 777)  # blocks of rows, the last one shorter
    _compare_g12(x)
    monkeypatch.undo()
    _compare_g12(x, width=31, fill=5)
    _compare_g12(x[:0])
    for v in x[:50]:
        _compare_g12(np.array([v]))


@pytest.mark.parametrize("seed", [0, 1, 2])
def test_format_with_the_twin_is_pythons_on_seeded_numbers(seed: int, monkeypatch: pytest.MonkeyPatch) -> None:
    _compare_python(_seeded(seed), monkeypatch)


def test_format_with_the_twin_is_pythons_on_the_hard_cases(monkeypatch: pytest.MonkeyPatch) -> None:
    _compare_python(_hard_cases(), monkeypatch)


def test_the_twin_leaves_to_python_exactly_what_the_kernel_leaves() -> None:
    """``lens == 0`` on the same numbers, and only on NaN, infinities, ``0 < |x| <= 1e-290``, ``|x| >= 1e290`` and
    numbers whose twelve digits lie within TIE_BAND of a rounding tie, or that are a power of ten's neighbours for
    which the kernel's three corrections of the exponent find none."""
    x = np.concatenate([_hard_cases(), _seeded(3)])
    lens_k = np.zeros(len(x), np.int64)
    lens_t = np.zeros(len(x), np.int64)
    ck._g12(x, np.zeros((len(x), ck.WIDTH), np.uint8), lens_k)
    g12_rows(x, np.zeros((len(x), ck.WIDTH), np.uint8), lens_t)
    assert np.array_equal(lens_k == 0, lens_t == 0)
    left = x[lens_t == 0]
    ax = np.abs(left)
    tied = (ax > 1e-290) & (ax < 1e290)
    assert np.all(np.isnan(left[~tied]) | (ax[~tied] >= 1e290) | ((ax[~tied] <= 1e-290) & (ax[~tied] > 0)))
    assert tied.sum() >= 3000  # the ties of _ties are left to Python: the fill-in is exercised
    band = Decimal(csv_numpy.TIE_BAND) + Decimal("0.001")  # the kernel's product is within 1e-3 of a digit
    for v in left[tied].tolist():  # each near a tie, or a power of ten's neighbour (exactly, in decimal)
        a = abs(Decimal(v))
        scaled = a.scaleb(11 - a.adjusted())
        if abs(scaled - scaled.to_integral_value(rounding="ROUND_FLOOR") - Decimal("0.5")) < band:
            continue
        gap = min(abs(a / Decimal(1).scaleb(a.adjusted() + up) - 1) for up in (0, 1))
        assert gap < Decimal("1e-15"), v


@settings(max_examples=2500, deadline=None)
@given(st.lists(st.floats(allow_nan=True, allow_infinity=True, width=64), min_size=1, max_size=40))
def test_g12_rows_on_hypothesis_floats(values: list[float]) -> None:
    x = np.asarray(values, dtype=np.float64)
    _compare_g12(x)
    with pytest.MonkeyPatch.context() as mp:
        _compare_python(x, mp)


# --- join_rows ---------------------------------------------------------------------------------------------------


def _cell_matrix(
    rng: np.random.Generator, nrow: int, ncol: int, wide: bool = False
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Random cells (any bytes, garbage after each cell), lengths from 0 to the column's width, contiguous or
    shuffled and overlapping columns."""
    widths = rng.integers(0, 300 if wide else 30, ncol)
    lens = (rng.random((nrow, ncol)) * (widths + 1)).astype(np.int64)
    full = rng.random(ncol) < 0.2  # columns whose every cell is as wide as the column
    lens[:, full] = widths[full]
    starts = np.concatenate([[0], np.cumsum(widths)[:-1]]).astype(np.int64)
    total = int(widths.sum())
    if rng.random() < 0.3:  # columns in another order, some sharing bytes
        starts = rng.integers(0, total + 1, ncol) if total else np.zeros(ncol, np.int64)
        starts = np.minimum(starts, total - widths).astype(np.int64)
    cells = rng.integers(0, 256, (nrow, max(total, 1)), dtype=np.uint8)
    return cells, lens, starts


def _compare_join(cells: np.ndarray, lens: np.ndarray, starts: np.ndarray, seed: int) -> None:
    size = int(lens.sum()) + lens.size + 13
    start = np.random.default_rng(seed).integers(0, 256, size, dtype=np.uint8)
    out_k, out_t = start.copy(), start.copy()
    n_k = ck._join(cells, lens, starts, out_k)
    n_t = join_rows(cells, lens, starts, out_t)
    assert n_t == n_k == int(lens.sum()) + lens.size
    bad = np.flatnonzero(out_k != out_t)
    assert bad.size == 0, (
        f"{bad.size} bytes differ, first at {bad[:5]}: shape {cells.shape}, starts {starts.tolist()}, "
        f"lens {lens[:3].tolist()}; kernel {bytes(out_k[bad[0] : bad[0] + 20])!r}, twin "
        f"{bytes(out_t[bad[0] : bad[0] + 20])!r}"
    )


@pytest.mark.parametrize("seed", range(6))
def test_join_rows_equals_the_kernel_on_random_cells(seed: int) -> None:
    rng = np.random.default_rng(100 + seed)
    for nrow in (0, 1, 2, 7, 300, 5000):
        for _ in range(4):
            ncol = int(rng.integers(1, 21))
            cells, lens, starts = _cell_matrix(rng, nrow, ncol)
            _compare_join(cells, lens, starts, seed)


def test_join_rows_with_cells_of_255_bytes_and_more() -> None:
    rng = np.random.default_rng(7)
    for nrow in (1, 3, 400):
        cells, lens, starts = _cell_matrix(rng, nrow, 5, wide=True)
        _compare_join(cells, lens, starts, 1)
    cells = rng.integers(0, 256, (9, 600), dtype=np.uint8)
    lens = np.array([[255, 345]] * 4 + [[0, 254]] * 5, np.int64)
    _compare_join(cells, lens, np.array([0, 255], np.int64), 2)


def test_join_rows_of_no_rows_or_no_columns_writes_nothing() -> None:
    out = np.full(4, 9, np.uint8)
    assert join_rows(np.zeros((0, 5), np.uint8), np.zeros((0, 2), np.int64), np.array([0, 3]), out) == 0
    assert join_rows(np.zeros((3, 0), np.uint8), np.zeros((3, 0), np.int64), np.zeros(0, np.int64), out) == 0
    assert out.tolist() == [9, 9, 9, 9]
    _compare_join(np.zeros((3, 0), np.uint8), np.zeros((3, 2), np.int64), np.zeros(2, np.int64), 3)  # ",\n" each


def test_join_rows_steps_through_the_rows_a_chunk_at_a_time(monkeypatch: pytest.MonkeyPatch) -> None:
    rng = np.random.default_rng(8)
    cells, lens, starts = _cell_matrix(rng, 1000, 6)
    for chunk_bytes in (1, 50, 997, 1 << 30):
        monkeypatch.setattr(csv_numpy, "_JOIN_CHUNK_BYTES", chunk_bytes)
        _compare_join(cells, lens, starts, chunk_bytes)


@settings(max_examples=300, deadline=None)
@given(st.integers(0, 40), st.integers(1, 20), st.integers(0, 2**32 - 1))
def test_join_rows_on_hypothesis_shapes(nrow: int, ncol: int, seed: int) -> None:
    rng = np.random.default_rng(seed)
    cells, lens, starts = _cell_matrix(rng, nrow, ncol)
    _compare_join(cells, lens, starts, seed)


# --- the pipeline's own columns and cells ------------------------------------------------------------------------


def _layout(name: str) -> GraphTrack:
    return GraphTrack.from_layout(json.loads((TRACKS / name).read_text()))


def _swap(name: str, **kw: Any) -> Callable[[], Trajectory]:
    def make() -> Trajectory:
        g = _layout(name)
        v = list(g.graph.vertices)
        return generate_trajectory(g, (v[0], v[-1]), (v[-1], v[0]), clearance=kw.pop("clearance", 0.1), **kw)

    return make


PIPELINE: dict[str, Callable[[], Trajectory]] = {
    "lollipop 1 kHz": lambda: generate_trajectory(Lollipop(1, 1), (0.1, 0.6), (0.8, 0.3), rate=1000),
    "lollipop 1 Hz": lambda: generate_trajectory(Lollipop(2, 1.5), (0.1, 1.3), (1.9, 0.4), rate=1),
    "circle": lambda: generate_trajectory(Circle(3), (0.2, 1.7), (1.6, 0.1), rate=250),
    "warehouse": _swap("warehouse.json"),
    "rail yard": _swap("rail_yard.json"),
    "y junction": _swap("y_junction.json", rate=500),
    "theta": _swap("theta.json"),
    "two sidings": _swap("two_sidings.json", rate=30),
    "passing loop, disc": _swap("passing_loop.json", footprint=Disc(0.3), clearance=0.0),
}


def _recording(kernel: Callable[..., Any], calls: list[Any], inputs: int) -> Callable[..., Any]:
    """``kernel``, keeping a copy of its first ``inputs`` arguments (the ones it reads) at every call."""

    def call(*args: np.ndarray) -> Any:
        calls.append(tuple(np.copy(a) for a in args[:inputs]))
        return kernel(*args)

    return call


def _record(make: Callable[[], Trajectory], monkeypatch: pytest.MonkeyPatch) -> tuple[list[Any], list[Any], bytes]:
    """The arguments of every kernel call while the setpoints CSV of ``make()`` is written, and its bytes; the CSV
    written with the twins in the kernels' place is the same."""
    g12_calls: list[Any] = []
    join_calls: list[Any] = []
    traj = make()
    monkeypatch.setattr(ck, "_g12", _recording(ck._g12, g12_calls, 1))
    monkeypatch.setattr(ck, "_join", _recording(ck._join, join_calls, 3))
    data = b"".join(traj.csv_chunks())
    monkeypatch.setattr(ck, "_g12", g12_rows)
    monkeypatch.setattr(ck, "_join", join_rows)
    twin = b"".join(traj.csv_chunks())
    monkeypatch.undo()
    assert twin == data, "the setpoints CSV written with the twins differs"
    return [c[0] for c in g12_calls], join_calls, data


@pytest.mark.parametrize("case", list(PIPELINE))
def test_the_twins_equal_the_kernels_on_the_pipelines_columns(case: str, monkeypatch: pytest.MonkeyPatch) -> None:
    g12_calls, join_calls, data = _record(PIPELINE[case], monkeypatch)
    assert g12_calls and join_calls and data.count(b"\n") >= 2
    for k, values in enumerate(g12_calls):
        _compare_g12(values)
        _compare_g12(values, fill=k)
    for k, (cells, lens, starts) in enumerate(join_calls):
        _compare_join(cells, lens, starts, k)


@pytest.mark.slow
def test_the_twins_write_the_airports_setpoints(monkeypatch: pytest.MonkeyPatch) -> None:
    """The query of issue 25 on the airport terminal (level L1, navigation graph 2, D = 0.6 m): 43 829 rows."""
    path = ROOT / "tests" / "data" / "openrmf" / "airport_terminal.building.yaml"
    g = GraphTrack.from_file(path, level="L1", nav_graph=2)
    g12_calls, join_calls, data = _record(
        lambda: generate_trajectory(
            g, ("lane70:3.102", "lane143:8.848"), ("lane87:1.237", "lane100:0.997"), clearance=0.6
        ),
        monkeypatch,
    )
    assert data.count(b"\n") == 43829 + 1
    for values in g12_calls:
        _compare_g12(values)
    for cells, lens, starts in join_calls:
        _compare_join(cells, lens, starts, 0)
