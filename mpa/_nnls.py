"""Non-negative least squares by scipy's compiled routine, without importing :mod:`scipy.optimize`.

:func:`scipy.optimize.nnls` checks its arguments and calls a compiled routine, ``nnls`` of the extension module
``scipy.optimize._slsqplib``. Importing it imports the whole of :mod:`scipy.optimize` (its solvers, and with them
:mod:`scipy.sparse`, :mod:`scipy.linalg`, :mod:`scipy.special`): 0.35-0.7 s in a fresh process, most of a
command-line run's plan on the building maps whose plans have their corners re-solved
(:mod:`mpa.planners.corners`). :func:`nnls` loads that extension module from its file in scipy's package (about
2 ms; Python keeps one instance of it, which a later ``import scipy.optimize`` reuses) and applies the same checks,
so it returns the same numbers as :func:`scipy.optimize.nnls`. Where the module is not found, cannot be loaded or
has no ``nnls``, :func:`scipy.optimize.nnls` itself is used.
"""

from __future__ import annotations

import functools
import importlib.machinery
import importlib.util
from collections.abc import Callable
from pathlib import Path
from typing import Any

import numpy as np

from mpa._arrays import FloatArray

__all__ = ["nnls"]

#: The extension module that holds scipy's compiled NNLS routine.
ROUTINE_MODULE = "scipy.optimize._slsqplib"


@functools.cache
def _routine() -> Callable[..., tuple[Any, Any, int]] | None:
    """scipy's compiled ``nnls(A, b, maxiter) -> (x, rnorm, info)``, loaded from its file; None if not found."""
    try:
        import scipy

        folder = Path(scipy.__file__).parent / "optimize"
        path = next(
            (
                folder / f"_slsqplib{s}"
                for s in importlib.machinery.EXTENSION_SUFFIXES
                if (folder / f"_slsqplib{s}").is_file()
            ),
            None,
        )
        if path is None:
            return None
        loader = importlib.machinery.ExtensionFileLoader(ROUTINE_MODULE, str(path))
        spec = importlib.util.spec_from_file_location(ROUTINE_MODULE, path, loader=loader)
        if spec is None:
            return None
        module = importlib.util.module_from_spec(spec)
        loader.exec_module(module)
        routine = getattr(module, "nnls", None)
        return routine if callable(routine) else None
    except (ImportError, OSError):
        return None


def nnls(A: FloatArray, b: FloatArray, *, maxiter: int | None = None) -> tuple[FloatArray, float]:
    """``argmin_x |A x − b|₂`` subject to ``x >= 0``: :func:`scipy.optimize.nnls`, the same routine and checks.

    Parameters
    ----------
    A : ndarray, shape (m, n)
    b : ndarray, shape (m,) or (m, 1)
    maxiter : int, optional
        Most iterations (default ``3 n``).

    Returns
    -------
    x : ndarray, shape (n,)
    rnorm : float
        ``|A x − b|₂``.

    Raises
    ------
    RuntimeError
        The iteration limit was reached.
    ValueError
        ``A`` is not 2-D, ``b`` not 1-D (or one column), or their first dimensions differ; non-finite ``b``.
    """
    routine = _routine()
    if routine is None:
        from scipy.optimize import nnls as scipy_nnls

        x_s, r_s = scipy_nnls(A, b, maxiter=maxiter)
        return x_s, float(r_s)
    b = np.asarray_chkfinite(b, dtype=np.float64)
    if len(A.shape) != 2:
        raise ValueError(f"Expected a 2D array, but the shape of A is {A.shape}")
    if (b.ndim > 2) or ((b.ndim == 2) and (b.shape[1] != 1)):
        raise ValueError(f"Expected a 1D array, (or 2D with one column), but the shape of b is {b.shape}")
    if b.ndim == 2:
        b = b.ravel()
    m, n = A.shape
    if m != b.shape[0]:
        raise ValueError(f"Incompatible dimensions. The first dimension of A is {m}, while the shape of b is {b.shape}")
    x, rnorm, info = routine(A, b, maxiter or 3 * n)
    if info == 3:
        raise RuntimeError("Maximum number of iterations reached.")
    return x, float(rnorm)
