"""The setpoint grid: a rate checked (:func:`validate_rate`), the times ``k / rate`` of a motion
(:func:`time_grid`), and the memory budget the rows must fit (:func:`memory_budget`).
"""

from __future__ import annotations

import os
from typing import Any

import numpy as np

from mpa._arrays import FloatArray
from mpa._deprecation import deprecated_alias
from mpa.errors import InvalidInputError, positive_number

#: Largest number of rows a grid may have.
MAX_ROWS = 20_000_000
#: Memory one row takes at its peak (bytes): sampling and the gate (the CSV text is formatted and written in pieces
#: of :data:`CSV_CHUNK_ROWS` rows, :class:`Streamed`). Measured on the Y junction at 200 kHz (2 933 598 rows, 19
#: columns): peak resident memory 797 MB, 272 B per row with the interpreter; ``--format csv,ros2-yaml`` adds about
#: 400 B per row (20 kHz: 351 -> 470 MB for 294 286 rows), which 1 000 leaves room for.
ROW_BYTES = 1000
#: Default memory budget of a trajectory's rows (bytes): 4 GiB, about 4.3 million rows.
MEMORY_BUDGET = 4.0 * 2**30
#: Environment variable that overrides :data:`MEMORY_BUDGET` (bytes; suffix K, M or G).
BUDGET_ENV = "MPA_MEMORY_BUDGET"


def validate_rate(rate: Any, name: str = "rate") -> float:
    """Validate a setpoint rate (Hz): a positive finite number.

    Raises
    ------
    InvalidInputError
    """
    return positive_number(rate, name, "Hz")


#: Deprecated name of :func:`validate_rate` (warns).
check_rate = deprecated_alias(validate_rate, "check_rate")


def memory_budget() -> float:
    """The memory (bytes) a trajectory's rows may take: ``$MPA_MEMORY_BUDGET`` (bytes; suffix K, M or G allowed),
    else :data:`MEMORY_BUDGET` (4 GiB)."""
    text = os.environ.get(BUDGET_ENV, "").strip().upper()
    if not text:
        return MEMORY_BUDGET
    scale = {"K": 2.0**10, "M": 2.0**20, "G": 2.0**30}.get(text[-1:], 1.0)
    try:
        value = float(text[:-1] if scale != 1.0 else text) * scale
    except ValueError:
        raise InvalidInputError(f"${BUDGET_ENV} is {text!r}, expected a number of bytes (suffix K, M or G)") from None
    if not np.isfinite(value) or value <= 0:
        raise InvalidInputError(f"${BUDGET_ENV} is {text!r}, expected a positive number of bytes")
    return value


def time_grid(duration: float, rate: float) -> FloatArray:
    """``k / rate`` for ``k = 0 … ceil(duration·rate)`` (s). Shape (N,).

    Checked before any row is made: the rows' memory, estimated as :data:`ROW_BYTES` per row (the peak of
    sampling, the gate and the export, measured), must fit :func:`memory_budget`, and there are at most
    :data:`MAX_ROWS` rows.

    Raises
    ------
    InvalidInputError
        Too many rows for the budget: the message names ``--rate`` and the largest rate that fits.
    """
    with np.errstate(over="ignore"):
        steps = float(np.ceil(duration * rate - 1e-9)) if duration > 0 else 0.0
    budget = memory_budget()
    fit = int(min(MAX_ROWS, budget // ROW_BYTES))
    if not steps + 1 <= fit:  # also an infinite count
        n = steps
        best = (fit - 1) / duration
        digits = 10 ** np.floor(np.log10(best)) / 10 if best > 0 else 1.0
        best = float(np.floor(best / digits) * digits)
        raise InvalidInputError(
            f"rate (--rate) {rate:g} Hz gives {n + 1:.0f} rows for the {duration:.6g} s motion, about "
            f"{(n + 1) * ROW_BYTES / 2**30:.3g} GiB, above the memory budget of {budget / 2**30:.3g} GiB "
            f"({fit} rows; ${BUDGET_ENV} sets it); the largest rate that fits is {best:g} Hz"
        )
    return np.arange(int(steps) + 1) / rate
