"""``mpa._nnls.nnls``: scipy's compiled NNLS routine without importing scipy.optimize, the same numbers."""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from scipy.optimize import nnls as scipy_nnls

import mpa._nnls as routine_module
from mpa._nnls import nnls

ROOT = Path(__file__).resolve().parents[2]


@settings(max_examples=200, deadline=None)
@given(
    seed=st.integers(0, 2**32 - 1),
    m=st.integers(1, 12),
    n=st.integers(1, 10),
    column=st.booleans(),
    scale=st.sampled_from([1e-6, 1.0, 1e4]),
)
def test_the_same_numbers_as_scipy(seed: int, m: int, n: int, column: bool, scale: float) -> None:
    rng = np.random.default_rng(seed)
    A = rng.normal(size=(m, n)) * scale
    if n > 1 and rng.random() < 0.3:  # dependent columns
        A[:, -1] = A[:, 0]
    b = rng.normal(size=(m, 1) if column else m)
    x, r = nnls(A, b, maxiter=50 * n)
    xs, rs = scipy_nnls(A, b, maxiter=50 * n)
    assert x.tobytes() == xs.tobytes(), (x, xs)
    assert r == rs and isinstance(r, float)
    assert np.all(x >= 0.0)


def test_the_same_errors_as_scipy() -> None:
    rng = np.random.default_rng(1)
    A, b = rng.normal(size=(6, 4)), rng.normal(size=6)
    for bad_a, bad_b in ((A[0], b), (A, b[:5]), (A, np.ones((6, 2))), (A, np.append(b[:5], np.nan))):
        with pytest.raises(ValueError):
            scipy_nnls(bad_a, bad_b)
        with pytest.raises(ValueError):
            nnls(bad_a, bad_b)
    A, b = rng.normal(size=(30, 20)), rng.normal(size=30)  # an active set that needs more than one iteration
    with pytest.raises(RuntimeError):
        scipy_nnls(A, b, maxiter=1)
    with pytest.raises(RuntimeError):
        nnls(A, b, maxiter=1)


def test_without_the_routine_scipy_answers(monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setattr(routine_module, "_routine", lambda: None)
    rng = np.random.default_rng(2)
    A, b = rng.normal(size=(7, 5)), rng.normal(size=7)
    x, r = nnls(A, b)
    xs, rs = scipy_nnls(A, b)
    assert x.tobytes() == xs.tobytes() and r == rs


def test_the_routine_is_loaded_without_scipy_optimize() -> None:
    code = (
        "import sys\n"
        "import numpy as np\n"
        "from mpa._nnls import _routine, nnls\n"
        "x, r = nnls(np.eye(3), np.array([1.0, -2.0, 3.0]))\n"
        "print(_routine() is not None, 'scipy.optimize' in sys.modules, x.tolist(), round(r, 12))\n"
        "import scipy.optimize\n"  # imported afterwards, scipy keeps working and shares the routine's module
        "print(scipy.optimize.nnls(np.eye(3), np.array([1.0, -2.0, 3.0]))[0].tolist())\n"
    )
    out = subprocess.run(
        [sys.executable, "-c", code],
        capture_output=True,
        text=True,
        check=True,
        cwd=ROOT,
        env={"PYTHONPATH": str(ROOT)},
    ).stdout.split("\n")
    assert out[0] == "True False [1.0, 0.0, 3.0] 2.0"
    assert out[1] == "[1.0, 0.0, 3.0]"
