"""The array types of the annotations of :mod:`mpa` and :mod:`trajopt` (numpy's ``NDArray`` of one dtype)."""

from __future__ import annotations

import numpy as np
from numpy.typing import NDArray

__all__ = ["FloatArray", "IntArray"]

#: An array of float64 (metres, seconds, m/s, ... as the name of the variable says).
FloatArray = NDArray[np.float64]
#: An array of int64 (indices, counts).
IntArray = NDArray[np.int64]
