"""Deprecated names: an old public name kept as an alias that warns and calls the function under its new name.

Naming (docs/conventions.md, "Naming"): ``validate_*`` checks the caller's input and raises
:class:`mpa.errors.InvalidInputError`; ``check_*`` and ``verify_*`` check what the library computed.
"""

from __future__ import annotations

import functools
import inspect
import warnings
from collections.abc import Callable
from typing import Any, TypeVar

__all__ = ["deprecated_alias"]

F = TypeVar("F", bound=Callable[..., Any])


def deprecated_alias(func: F, old_name: str) -> F:
    """``func`` under its former name ``old_name``: each call warns (:class:`DeprecationWarning`), then calls it.

    Parameters
    ----------
    func : callable
        The function (or method, when the alias is assigned in a class body) under its current name.
    old_name : str
        The former name as a caller wrote it, e.g. ``"check_rate"`` or ``"ConfigurationSpace.check_state"``.

    Returns
    -------
    callable
        A function with ``func``'s signature that warns with ``stacklevel=2`` (at the caller's line).
    """
    new_name = func.__qualname__

    @functools.wraps(func)
    def alias(*args: Any, **kwargs: Any) -> Any:
        warnings.warn(
            f"{old_name} is deprecated, use {new_name} (validate_* checks input)", DeprecationWarning, stacklevel=2
        )
        return func(*args, **kwargs)

    short = old_name.rsplit(".", 1)[-1]
    alias.__name__ = short
    alias.__qualname__ = func.__qualname__.rsplit(".", 1)[0] + "." + short if "." in func.__qualname__ else short
    alias.__doc__ = f"Deprecated alias of :func:`{func.__module__}.{new_name}` (warns)."
    alias.__signature__ = inspect.signature(func)  # type: ignore[attr-defined]
    del alias.__wrapped__  # doctest and help() read this function, not func
    return alias  # type: ignore[return-value]
