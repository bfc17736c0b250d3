"""Speed of the numpy twins of the paper tracks' kernels against the compiled (numba) kernels.

The rows are those of a real motion, resampled: the route coordinates of a Lollipop(1, 1) trajectory (D = 0.05 m,
100 Hz) and of a Circle(1) one, interpolated to each size of ``--rows``. For each of the six kernels of
:mod:`trajopt.verify.kernels` that :mod:`trajopt.verify.paper_numpy` twins and each size, the median and 90th
percentile of ``--repeats`` calls of the compiled kernel (warm: compiled and loaded) and of its twin, and whether
their outputs are equal bit for bit (``dense_polyline`` with a step that cuts the longest leg in three). Then
``--processes`` fresh processes per kind (``TRAJOPT_KERNELS=numpy`` with the twins patched into the kernels' callers,
and numba's kernels): the library imported and the first Lollipop(1, 1) trajectory made, the cost a one-shot
``mpa trajectory --track lollipop`` pays.

    python experiments/bench_paper_twins.py [--rows 300 4000 43829] [--repeats 31] [--processes 5] [--out FILE]
"""

from __future__ import annotations

import argparse
import json
import os
import statistics
import subprocess
import sys
import time
from collections.abc import Callable
from pathlib import Path
from typing import Any

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))

from mpa import Circle, Lollipop  # noqa: E402
from mpa.skeleton import skeleton_of  # noqa: E402
from trajopt.generator import TrajectoryGenerator  # noqa: E402
from trajopt.verify import kernels, paper_numpy  # noqa: E402

NAMES = (
    "track_positions",
    "dense_polyline",
    "needs_densify",
    "word_samples",
    "lollipop_skeleton_points",
    "circle_skeleton_points",
)

#: One fresh process: import the library (the twins patched in, or not), make the first lollipop trajectory.
_FRESH = r"""
import sys, time
t0 = time.perf_counter()
import trajopt.path.planview as planview
import trajopt.verify.gate as gate
import trajopt.verify.kernels as kernels
if sys.argv[1] == "twins":
    from trajopt.verify import paper_numpy
    for module in (kernels, gate):
        for name in paper_numpy.__all__:
            setattr(module, name, getattr(paper_numpy, name))
    planview.track_positions = paper_numpy.track_positions
from mpa import Lollipop
from trajopt import TrajectoryGenerator
t1 = time.perf_counter()
traj = TrajectoryGenerator(Lollipop(1.0, 1.0), clearance=0.05).generate((0.1, 1.6), (1.9, 0.3))
t2 = time.perf_counter()
print(t1 - t0, t2 - t1, "numba" in sys.modules, traj.verification["ok"])
"""


def _resampled(track: Any, start: Any, goal: Any, n: int) -> tuple[Any, np.ndarray]:
    """A trajectory's route coordinates interpolated to ``n`` rows: ``(routes' affine forms, S)`` (shape (n, 2))."""
    traj = TrajectoryGenerator(track, clearance=0.05, rate=100.0).generate(start, goal)
    x, u = np.linspace(0.0, 1.0, len(traj.t)), np.linspace(0.0, 1.0, n)
    S = np.ascontiguousarray(np.stack([np.interp(u, x, traj.s[:, r]) for r in (0, 1)], 1))
    (ba, Aa, Ba, la, interval, stick, loop), (bb, Ab, Bb, lb, *_) = (r.affine_form() for r in traj.plan.routes)
    return (ba, Aa, Ba, la, bb, Ab, Bb, lb, interval, stick, loop), S


def _cases(n: int) -> dict[str, tuple[Any, ...]]:
    """Each kernel's arguments for ``n`` rows (outputs included)."""
    lol, S = _resampled(Lollipop(1.0, 1.0), (0.1, 1.6), (1.9, 0.3), n)
    circ, Sc = _resampled(Circle(1.0), (0.1, 0.6), (0.7, 0.2), n)
    P, Pc = np.empty((n, 2)), np.empty((n, 2))
    kernels.track_positions(S, *lol, P)
    kernels.track_positions(Sc, *circ, Pc)
    sk = skeleton_of(Lollipop(1.0, 1.0))
    ell, c_model, kappa = float(sk.model.stick), float(sk.model.loop), float(sk.kappa)
    degenerate = bool(sk.graph.edges[0].length <= 1e-9)
    edge, t = np.empty(n, dtype=np.int64), np.empty(n)
    kernels.lollipop_skeleton_points(P, ell, c_model, kappa, degenerate, edge, t)
    legs = np.abs(np.diff(S, axis=0)).max() if n > 1 else 1.0
    return {
        "track_positions": (S, *lol, np.empty((n, 2))),
        "dense_polyline": (S, float(legs) / 2.5),
        "needs_densify": (S, 0.004 * Lollipop(1.0, 1.0).total_length),
        "word_samples": (edge, sk.graph.adjacent_edges),
        "lollipop_skeleton_points": (P, ell, c_model, kappa, degenerate, np.empty(n, np.int64), np.empty(n)),
        "circle_skeleton_points": (Pc, 1.0, np.empty(n, np.int64), np.empty(n)),
    }


def _times(f: Callable[[], Any], repeats: int) -> dict[str, float]:
    """Median and 90th percentile of ``repeats`` calls (µs)."""
    ts = []
    for _ in range(repeats):
        t0 = time.perf_counter()
        f()
        ts.append((time.perf_counter() - t0) * 1e6)
    ts.sort()
    return {"median_us": statistics.median(ts), "p90_us": ts[min(len(ts) - 1, int(0.9 * len(ts)))]}


def _outputs(name: str, args: tuple[Any, ...], module: Any) -> list[np.ndarray]:
    """What ``module``'s kernel ``name`` returns and fills, as arrays."""
    copy = tuple(a.copy() if isinstance(a, np.ndarray) else a for a in args)
    got = getattr(module, name)(*copy)
    arrays = [a for a in copy if isinstance(a, np.ndarray)]
    returned = list(got) if isinstance(got, tuple) else [got]
    return arrays + [np.asarray(r) for r in returned]


def _equal(x: list[np.ndarray], y: list[np.ndarray]) -> bool:
    """The same arrays, NaN equal to NaN, signs of zeros included."""
    return len(x) == len(y) and all(
        a.shape == b.shape
        and a.dtype == b.dtype
        and np.array_equal(a, b, equal_nan=a.dtype.kind == "f")
        and (a.dtype.kind != "f" or np.array_equal(np.signbit(a), np.signbit(b)))
        for a, b in zip(x, y, strict=True)
    )


def run(rows: list[int], repeats: int) -> list[dict[str, Any]]:
    """One record per size and kernel: ``{"kernel", "rows", "kernel_time", "twin_time", "equal"}``."""
    out = []
    for n in rows:
        for name, args in _cases(n).items():
            compiled, twin = getattr(kernels, name), getattr(paper_numpy, name)
            out.append(
                {
                    "kernel": name,
                    "rows": n,
                    "kernel_time": _times(lambda f=compiled, a=args: f(*a), repeats),
                    "twin_time": _times(lambda f=twin, a=args: f(*a), repeats),
                    "equal": _equal(_outputs(name, args, kernels), _outputs(name, args, paper_numpy)),
                }
            )
    return out


def fresh(processes: int) -> dict[str, dict[str, Any]]:
    """Fresh processes per kind (``"twins"``, ``"numba"``): import and first trajectory (s), medians and maxima."""
    out = {}
    for kind, mode in (("twins", "numpy"), ("numba", "numba")):
        env = {**os.environ, "PYTHONPATH": str(ROOT), "TRAJOPT_KERNELS": mode}
        runs = []
        for _ in range(processes):
            done = subprocess.run(
                [sys.executable, "-c", _FRESH, kind], cwd=ROOT, env=env, capture_output=True, text=True, check=True
            )
            imp, first, numba, ok = done.stdout.split()
            runs.append((float(imp), float(first), numba == "True", ok == "True"))
        out[kind] = {
            "import_s": statistics.median(r[0] for r in runs),
            "first_trajectory_s": statistics.median(r[1] for r in runs),
            "total_s": statistics.median(r[0] + r[1] for r in runs),
            "total_max_s": max(r[0] + r[1] for r in runs),
            "numba_imported": any(r[2] for r in runs),
            "verified": all(r[3] for r in runs),
        }
    return out


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--rows", type=int, nargs="+", default=[300, 4000, 43829])
    ap.add_argument("--repeats", type=int, default=31)
    ap.add_argument("--processes", type=int, default=5)
    ap.add_argument("--out", default=None, help="write the records as JSON here")
    a = ap.parse_args()
    records = run(a.rows, a.repeats)
    for r in records:
        k, t = r["kernel_time"], r["twin_time"]
        print(
            f"{r['rows']:6d} {r['kernel']:25s} numba {k['median_us']:9.1f} µs (p90 {k['p90_us']:9.1f})  "
            f"numpy {t['median_us']:9.1f} µs (p90 {t['p90_us']:9.1f})  equal {r['equal']}"
        )
    procs = fresh(a.processes) if a.processes else {}
    for kind, p in procs.items():
        print(
            f"fresh process, {kind}: import {p['import_s']:.3f} s + first trajectory {p['first_trajectory_s']:.3f} s "
            f"= {p['total_s']:.3f} s (max {p['total_max_s']:.3f} s), numba imported {p['numba_imported']}"
        )
    if a.out:
        Path(a.out).write_text(json.dumps({"kernels": records, "fresh": procs}, indent=1))


if __name__ == "__main__":
    main()
