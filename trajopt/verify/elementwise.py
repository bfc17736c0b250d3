"""What the numpy twins of the compiled kernels share (:mod:`trajopt.verify.kernels_numpy`,
:mod:`trajopt.verify.sampling_numpy`, :mod:`trajopt.verify.paper_numpy`): Python's two-argument ``min`` and ``max``
elementwise, and the block of rows they work in. numpy only: importing it never imports numba.
"""

from __future__ import annotations

import numpy as np

from mpa._arrays import FloatArray

__all__ = ["BLOCK", "pmax", "pmin"]

#: Rows per block of the passes over the rows. A block's temporaries (32 KiB each) are reused by the allocator
#: and stay in the CPU's caches; a temporary of a whole grid of 43 829 rows is fresh memory from the operating
#: system each time (a page fault every 4 KiB), which cost more than the arithmetic.
BLOCK = 4096


def pmin(a: FloatArray | float, b: FloatArray | float) -> FloatArray:
    """Python's (and numba's) ``min(a, b)`` elementwise: ``b`` where ``b < a``, else ``a`` (NaN in ``b`` gives
    ``a``; of two equal zeros the first). Shape: ``a`` and ``b`` broadcast."""
    return np.where(b < a, b, a)


def pmax(a: FloatArray | float, b: FloatArray | float) -> FloatArray:
    """Python's (and numba's) ``max(a, b)`` elementwise: ``b`` where ``b > a``, else ``a``. Shape: ``a`` and ``b``
    broadcast."""
    return np.where(b > a, b, a)
