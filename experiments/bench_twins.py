"""Speed of the numpy twins of the gate's row pass and of the sampling against the compiled (numba) kernels.

The arguments are the pipeline's own, recorded while it makes the airport terminal's motion of issue 25 (level L1,
navigation graph 2, D = 0.6 m: 438 s, 43 829 rows at 100 Hz): the whole grid and its first 300 rows. For each kernel
and size, the median of ``--repeat`` calls of the compiled kernel (warm: compiled and loaded) and of its twin
(:mod:`trajopt.verify.kernels_numpy`, :mod:`trajopt.verify.sampling_numpy`), and whether their outputs are equal bit
for bit. Then ``--processes`` fresh processes per kind: the module imported and the three kernels called once on the
whole grid (numpy already imported; the compiled kernels from numba's on-disk cache), the cost a one-shot
command-line process pays.

    python experiments/bench_twins.py [--repeat 7] [--processes 3]
"""

from __future__ import annotations

import argparse
import os
import pickle
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path
from typing import Any

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))

import trajopt.timing.scaling as scaling  # noqa: E402
import trajopt.verify.gate as gate  # noqa: E402
from mpa.graph_track import GraphTrack  # noqa: E402
from trajopt.generator import TrajectoryGenerator  # noqa: E402
from trajopt.verify import kernels, kernels_numpy, sampling, sampling_numpy  # noqa: E402

AIRPORT = ROOT / "tests" / "data" / "openrmf" / "airport_terminal.building.yaml"
QUERY = (["lane70:3.102", "lane143:8.848"], ["lane87:1.237", "lane100:0.997"])

#: One fresh process: import numpy, then time importing ``argv[1]``'s modules and one call of each kernel.
_FRESH = r"""
import pickle, sys, time
import numpy as np
args = pickle.loads(open(sys.argv[2], "rb").read())
t0 = time.perf_counter()
if sys.argv[1] == "numba":
    from trajopt.verify.kernels import check_rows, between_rows
    from trajopt.verify.sampling import sample_rows
else:
    from trajopt.verify.kernels_numpy import check_rows, between_rows
    from trajopt.verify.sampling_numpy import sample_rows
n = len(args["sample"][0])
sample_rows(*args["sample"], *(np.empty((n, 2)) for _ in range(4)))
check_rows(*args["check"][:-1], np.empty(len(args["check"][3]) - 1))
between_rows(*args["between"])
print(time.perf_counter() - t0, "numba" in sys.modules)
"""


def record() -> dict[str, tuple[Any, ...]]:
    """The arguments of ``sample_rows`` (without its outputs) and ``check_rows`` on the airport's motion, and of
    ``between_rows`` on the same rows."""
    got: dict[str, tuple[Any, ...]] = {}
    check, sample = gate.check_rows, scaling.sample_rows

    def check_spy(*args: Any) -> Any:
        got["check"] = tuple(a.copy() if isinstance(a, np.ndarray) else a for a in args)
        return check(*args)

    def sample_spy(*args: Any) -> Any:
        got.setdefault("sample", tuple(a.copy() if isinstance(a, np.ndarray) else a for a in args[:-4]))
        return sample(*args)

    gate.check_rows, scaling.sample_rows = check_spy, sample_spy
    try:
        track = GraphTrack.from_file(AIRPORT, level="L1", nav_graph=2)
        TrajectoryGenerator(track, clearance=0.6).generate(*QUERY)
    finally:
        gate.check_rows, scaling.sample_rows = check, sample
    c = got["check"]
    got["between"] = (c[0], c[1], c[2], c[6], c[8], c[11], c[10][2:4].copy(), c[10][4:6].copy())
    return got


def head(args: dict[str, tuple[Any, ...]], n: int) -> dict[str, tuple[Any, ...]]:
    """The first ``n`` rows of every per-row argument."""
    c, s, b = args["check"], args["sample"], args["between"]
    rows = [np.ascontiguousarray(x[:n]) for x in c[3:10]]
    return {
        "check": (*c[:3], *rows, *c[10:14], np.empty(n - 1)),
        "sample": (np.ascontiguousarray(s[0][:n]), *s[1:]),
        "between": (*b[:3], rows[3], rows[5], *b[5:]),
    }


def calls(args: dict[str, tuple[Any, ...]], k: Any, s: Any) -> dict[str, Any]:
    """The three kernels of modules ``k`` (row pass) and ``s`` (sampling) as calls returning their outputs."""
    n = len(args["sample"][0])

    def sample() -> list[Any]:
        out = [np.empty((n, 2)) for _ in range(4)]
        s.sample_rows(*args["sample"], *out)
        return out

    def check() -> list[Any]:
        between = np.empty(len(args["check"][3]) - 1)
        return [k.check_rows(*args["check"][:-1], between), between]

    return {"sample_rows": sample, "check_rows": check, "between_rows": lambda: [k.between_rows(*args["between"])]}


def median_time(f: Any, repeat: int) -> float:
    times = []
    for _ in range(repeat):
        t0 = time.perf_counter()
        f()
        times.append(time.perf_counter() - t0)
    return statistics.median(times)


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--repeat", type=int, default=7)
    ap.add_argument("--processes", type=int, default=3)
    opts = ap.parse_args()
    whole = record()
    print("| kernel | rows | numba (warm) | numpy twin | equal |")
    print("|---|---:|---:|---:|---|")
    for n in (300, len(whole["sample"][0])):
        args = head(whole, n)
        compiled, twin = calls(args, kernels, sampling), calls(args, kernels_numpy, sampling_numpy)
        for name in ("sample_rows", "check_rows", "between_rows"):
            same = all(
                np.array_equal(x, y, equal_nan=True) for x, y in zip(compiled[name](), twin[name](), strict=True)
            )
            t_c, t_t = median_time(compiled[name], opts.repeat), median_time(twin[name], opts.repeat)
            print(f"| {name} | {n} | {t_c * 1e3:.3f} ms | {t_t * 1e3:.3f} ms | {same} |")
    with tempfile.TemporaryDirectory() as tmp:
        path = Path(tmp) / "args.pickle"
        path.write_bytes(pickle.dumps(whole))
        print("\n| fresh process, import + one call of each | median | numba imported |")
        print("|---|---:|---|")
        for kind in ("numba", "numpy"):
            runs = []
            for _ in range(opts.processes):
                done = subprocess.run(
                    [sys.executable, "-c", _FRESH, kind, str(path)],
                    cwd=ROOT,
                    env={**os.environ, "PYTHONPATH": str(ROOT)},
                    capture_output=True,
                    text=True,
                    check=True,
                )
                seconds, imported = done.stdout.split()
                runs.append(float(seconds))
            print(f"| {kind} | {statistics.median(runs) * 1e3:.0f} ms | {imported} |")


if __name__ == "__main__":
    main()
