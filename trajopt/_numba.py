"""numba's ``njit`` for the compiled kernels, and the per-process choice between them and their numpy twins.

The kernels (:mod:`trajopt.verify.kernels`, :mod:`trajopt.verify.sampling`, :mod:`trajopt.io.csv_kernels`) are
loops over a trajectory's rows, compiled by numba: microseconds a trajectory where numpy's many small array calls
cost milliseconds. numba itself costs a process about 0.5 s before the first kernel runs (its import, the modules
it imports on its first kernel, the kernel's load from the on-disk cache): nothing to a library process or a batch
that makes many trajectories, most of a command that makes one. So a process runs its kernels one of two ways,
chosen before the first kernel module is imported:

- ``"numba"`` (the default): compiled with numba's on-disk cache (``cache=True``: compiled once per install, in
  ``__pycache__`` beside the source or in numba's user cache directory). Where numba finds no writable place for
  it (a read-only install without a writable home), it refuses to decorate the function; the kernel is then
  compiled in memory in every process instead (about 6 s on the first query) rather than failing the import.
  Should numba be missing (an interpreter it does not support yet), the kernels run as plain Python: the same
  results, about a hundred times slower.
- ``"numpy"`` (:func:`use_numpy_twins`, or the environment variable ``TRAJOPT_KERNELS=numpy``; the ``mpa``
  command does it for every subcommand but ``batch`` and ``serve``): every kernel the pipeline calls is replaced by
  its numpy twin, which gives the same results bit for bit (:mod:`trajopt.verify.kernels_numpy`,
  :mod:`trajopt.verify.sampling_numpy`, :mod:`trajopt.verify.paper_numpy`, :mod:`trajopt.io.csv_numpy`), and numba
  is not imported. A kernel without a twin would be compiled by numba the first time one is called
  (:class:`Deferred`): numba is imported then.
"""

from __future__ import annotations

import functools
import importlib.util
import os
import sys
from collections.abc import Callable
from typing import Any

__all__ = ["ENV", "HAVE_NUMBA", "Deferred", "kernel_mode", "njit", "numpy_twins", "use_numpy_twins"]

#: The environment variable that chooses the kernels' mode at import (``numba`` or ``numpy``).
ENV = "TRAJOPT_KERNELS"


def _numba_found() -> bool:
    """Whether numba can be imported (found, not imported; False where the import is blocked)."""
    if "numba" in sys.modules:
        return sys.modules["numba"] is not None
    try:
        return importlib.util.find_spec("numba") is not None
    except (ImportError, ValueError):  # pragma: no cover - a broken install
        return False


#: Whether numba is installed (found, not imported).
HAVE_NUMBA = _numba_found()

_state: dict[str, Any] = {"mode": "numpy" if os.environ.get(ENV, "").strip().lower() == "numpy" else "numba"}
_decorated: list[Any] = []  # every kernel decorated so far (numba dispatchers, plain functions or Deferred)
_deferred: list[Deferred] = []


def kernel_mode() -> str:
    """``"numba"`` or ``"numpy"``: how this process runs its kernels (module docstring)."""
    return str(_state["mode"])


def numpy_twins() -> bool:
    """Whether the kernel modules use their numpy twins (the ``"numpy"`` mode)."""
    return _state["mode"] == "numpy"


def use_numpy_twins() -> bool:
    """Run this process's kernels as numpy twins, numba not imported (the ``"numpy"`` mode), if no kernel module has
    been imported yet; a process whose kernels are already decorated keeps its mode.

    Returns
    -------
    bool
        Whether the process is in the ``"numpy"`` mode after the call.
    """
    if not _decorated:
        _state["mode"] = "numpy"
    return numpy_twins()


def _numba_options(options: dict[str, Any]) -> dict[str, Any]:
    """numba's options for ours: ``no_alloc=True`` is numba's ``_nrt=False`` (:func:`njit`)."""
    out = {k: v for k, v in options.items() if k != "no_alloc"}
    if options.get("no_alloc"):
        out["_nrt"] = False
    return out


def _compile(f: Callable[..., Any], options: dict[str, Any]) -> Any:
    """``numba.njit(**options)(f)``, without the cache where numba has no place for it, with reference counts where
    this numba has no ``_nrt`` option; ``f`` itself where numba cannot be imported."""
    try:
        from numba import njit as numba_njit
    except ImportError:  # pragma: no cover - numba is a dependency; this keeps the library working without it
        return f

    opts = _numba_options(options)
    try:
        return numba_njit(**opts)(f)
    except KeyError:  # pragma: no cover - a numba without the private ``_nrt`` option: counted, the same results
        opts.pop("_nrt", None)
        return _compile(f, opts)
    except RuntimeError:  # "cannot cache function …: no locator available": compile in memory instead
        return numba_njit(**{k: v for k, v in opts.items() if k != "cache"})(f)


class Deferred:
    """A kernel of a ``"numpy"``-mode process, compiled by numba on its first call.

    On the first call of any deferred kernel, numba is imported and every deferred kernel becomes a numba
    dispatcher; the names that hold a :class:`Deferred` in the modules loaded so far are rebound to the dispatchers,
    as numba resolves a kernel's callees (``_piece`` inside ``_position``) from its module's globals when it
    compiles. Later calls go straight to the dispatcher.
    """

    def __init__(self, f: Callable[..., Any], options: dict[str, Any]) -> None:
        self.py_func = f
        self.options = options
        self.compiled: Any = None
        functools.update_wrapper(self, f)

    def __call__(self, *args: Any) -> Any:
        if self.compiled is None:
            _compile_deferred()
        return self.compiled(*args)


def _compile_deferred() -> None:
    for d in _deferred:
        if d.compiled is None:
            d.compiled = _compile(d.py_func, d.options)
    for module in list(sys.modules.values()):
        names = getattr(module, "__dict__", None)
        if not isinstance(names, dict):
            continue
        for name, value in list(names.items()):
            if isinstance(value, Deferred):
                names[name] = value.compiled


def njit(*args: Any, **kwargs: Any) -> Any:
    """:func:`numba.njit` (``njit(f)`` or ``njit(**options)(f)``) in the ``"numba"`` mode, without its cache where it
    has no place for it, a no-op without numba; a :class:`Deferred` kernel in the ``"numpy"`` mode.

    One option is ours: ``no_alloc=True`` compiles the kernel without numba's reference counts (numba's own
    ``_nrt=False``, as numba compiles some of its own helpers). Every array a function takes, numba otherwise counts
    on entry and releases on return, each array of each tuple it is handed included: a small kernel that takes a
    tuple of ten arrays pays twenty atomic counts a call, which is most of what a call of
    :mod:`trajopt.plan_kernel`'s node functions cost. The kernel must allocate no array, return none and keep none
    (only its caller's arrays, which the caller holds for the call); numba refuses to compile one that allocates or
    returns an array, and so one that calls such a function. Where a numba lacks the option the kernel is compiled
    with the counts: the same results."""

    def decorate(f: Callable[..., Any]) -> Any:
        out: Any
        if numpy_twins():
            out = Deferred(f, kwargs)
            _deferred.append(out)
        else:
            out = _compile(f, kwargs)
        _decorated.append(out)
        return out

    if args and callable(args[0]):
        return decorate(args[0])
    return decorate
