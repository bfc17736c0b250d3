"""The slots of the gate's row pass's result vector, shared by the compiled kernel
(:func:`trajopt.verify.kernels.check_rows`) and its numpy twin (:func:`trajopt.verify.kernels_numpy.check_rows`).

A module of its own, with no import: the twin must not import the compiled kernels' module (it imports numba).
"""

from __future__ import annotations

__all__ = ["NRES", "RES"]

#: Slot of each number in :func:`~trajopt.verify.kernels.check_rows`'s result vector, by name.
RES = {
    name: k
    for k, name in enumerate(
        (
            "bad",  # 0 fine, 1 non-finite values, 2 edge indices out of range
            "grid_ok",  # 1.0 if the time grid is 0, dt, 2 dt, …
            "dmin",
            "dmin_row",
            "bmin",
            "bmin_row",
            "err_a",
            "err_a_row",
            "err_b",
            "err_b_row",
            "v_a",
            "v_b",
            "a_a",
            "a_b",
            "j_a",
            "j_b",
            "v_a_row",
            "v_b_row",
            "a_a_row",
            "a_b_row",
            "j_a_row",
            "j_b_row",
            "first_a",
            "first_b",
            "last_a",
            "last_b",
            "rest_first",  # max |v|, |a| of both robots at the first row
            "rest_last",  # ... at the last row
        )
    )
}


#: Length of the result vector.
NRES = len(RES)
