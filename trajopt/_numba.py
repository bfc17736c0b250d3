"""numba's ``njit`` for the compiled kernels (:mod:`trajopt.gate_kernels`, :mod:`trajopt.sample_kernels`).

numba is a dependency; should it be missing (an interpreter it does not support yet), ``njit`` is a no-op and the
kernels run as plain Python: the same results, about a hundred times slower.
"""

from __future__ import annotations

from typing import Any

__all__ = ["HAVE_NUMBA", "njit"]

try:
    from numba import njit

    HAVE_NUMBA = True
except ImportError:  # pragma: no cover - numba is a dependency; this keeps the library working without it
    HAVE_NUMBA = False

    def njit(*args: Any, **kwargs: Any) -> Any:  # type: ignore[no-redef]
        """No-op stand-in for :func:`numba.njit`."""
        if args and callable(args[0]):
            return args[0]
        return lambda f: f
