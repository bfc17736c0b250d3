"""numba's ``njit`` for the compiled kernels (:mod:`trajopt.verify.kernels`, :mod:`trajopt.verify.sampling`).

The kernels ask for numba's on-disk cache (``cache=True``: compiled once per install, in ``__pycache__`` beside
the source or in numba's user cache directory). Where numba finds no writable place for it (a read-only install
without a writable home), it refuses to decorate the function; the kernel is then compiled in memory in every
process instead (about 6 s on the first query) rather than failing the import. numba is a dependency; should it
be missing (an interpreter it does not support yet), ``njit`` is a no-op and the kernels run as plain Python: the
same results, about a hundred times slower.
"""

from __future__ import annotations

from collections.abc import Callable
from typing import Any

__all__ = ["HAVE_NUMBA", "njit"]

_njit: Any
try:
    from numba import njit as _njit

    HAVE_NUMBA = True
except ImportError:  # pragma: no cover - numba is a dependency; this keeps the library working without it
    HAVE_NUMBA = False
    _njit = None


def njit(*args: Any, **kwargs: Any) -> Any:
    """:func:`numba.njit` (``njit(f)`` or ``njit(**options)(f)``), without its cache where it has no place for it;
    a no-op without numba."""

    def decorate(f: Callable[..., Any]) -> Any:
        if _njit is None:
            return f
        try:
            return _njit(**kwargs)(f)
        except RuntimeError:  # "cannot cache function …: no locator available": compile in memory instead
            return _njit(**{k: v for k, v in kwargs.items() if k != "cache"})(f)

    if args and callable(args[0]):
        return decorate(args[0])
    return decorate
