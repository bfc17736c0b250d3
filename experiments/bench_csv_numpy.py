"""The numpy twins of the CSV kernels against the compiled kernels, on the columns and cells of a real setpoints CSV.

    python experiments/bench_csv_numpy.py [--layout airport|FILE.json] [--rows 300 43829] [--repeats 31]
        [--out FILE]

Generates one trajectory (by default the query of issue 25 on the airport terminal, level L1, navigation graph 2,
D = 0.6 m: a 438 s motion, 43 829 rows at 100 Hz; or a swap of the first and last vertices of an example layout),
records the arguments of every call of ``csv_kernels._g12`` (one per number column) and ``csv_kernels._join``
while its setpoints CSV is written, then times, on the first ``--rows`` rows of those arguments, each kernel and
its twin (:func:`trajopt.io.csv_numpy.g12_rows`, :func:`trajopt.io.csv_numpy.join_rows`) alternately, call for
call (so both see the same load): median and 90th percentile over ``--repeats`` calls, the kernels already
compiled and loaded. ``g12`` is per number column (the mean over the columns of each statistic). The last line
times the whole CSV (``Trajectory.csv_chunks``) with the kernels and with the twins in their place. Every twin's
output is compared with its kernel's (``equal``). Prints a Markdown table; ``--out FILE`` also writes
``FILE.json``.
"""

from __future__ import annotations

import argparse
import json
import os
import sys
import time
from collections.abc import Callable, Iterator
from contextlib import contextmanager
from functools import partial
from pathlib import Path
from typing import Any

import numpy as np

ROOT = Path(__file__).resolve().parent
sys.path.insert(0, str(ROOT.parent))

import trajopt.io.csv_kernels as ck  # noqa: E402
from mpa import GraphTrack  # noqa: E402
from trajopt import generate_trajectory  # noqa: E402
from trajopt.export import Trajectory  # noqa: E402
from trajopt.io.csv_numpy import g12_rows, join_rows  # noqa: E402

AIRPORT = ROOT.parent / "tests" / "data" / "openrmf" / "airport_terminal.building.yaml"
#: The query of issue 25 on the airport terminal (level L1, navigation graph 2), clearance 0.6 m.
AIRPORT_QUERY = (("lane70:3.102", "lane143:8.848"), ("lane87:1.237", "lane100:0.997"))


def make_trajectory(layout: str) -> Trajectory:
    """The airport's query of issue 25 (``"airport"``), or a swap of the first and last vertices of a layout file."""
    if layout == "airport":
        g = GraphTrack.from_file(AIRPORT, level="L1", nav_graph=2)
        return generate_trajectory(g, *AIRPORT_QUERY, clearance=0.6)
    g = GraphTrack.from_layout(json.loads(Path(layout).read_text(encoding="utf-8")))
    v = list(g.graph.vertices)
    return generate_trajectory(g, (v[0], v[-1]), (v[-1], v[0]), clearance=0.1)


@contextmanager
def kernels(g12: Callable[..., Any], join: Callable[..., Any]) -> Iterator[None]:
    """``csv_kernels._g12`` and ``csv_kernels._join`` replaced by ``g12`` and ``join`` inside the block."""
    saved = ck._g12, ck._join
    ck._g12, ck._join = g12, join
    try:
        yield
    finally:
        ck._g12, ck._join = saved


def record(traj: Trajectory) -> tuple[list[np.ndarray], list[tuple[np.ndarray, np.ndarray, np.ndarray]]]:
    """The arguments of the kernels' calls while ``traj``'s setpoints CSV is written."""
    g12_calls: list[np.ndarray] = []
    join_calls: list[tuple[np.ndarray, np.ndarray, np.ndarray]] = []
    g12, join = ck._g12, ck._join

    def rec_g12(values: np.ndarray, out: np.ndarray, lens: np.ndarray) -> None:
        g12_calls.append(values.copy())
        g12(values, out, lens)

    def rec_join(cells: np.ndarray, lens: np.ndarray, starts: np.ndarray, out: np.ndarray) -> int:
        join_calls.append((cells.copy(), lens.copy(), starts.copy()))
        return int(join(cells, lens, starts, out))

    with kernels(rec_g12, rec_join):
        for _ in traj.csv_chunks():
            pass
    return g12_calls, join_calls


def _alternate(calls: list[Callable[[], Any]], repeats: int) -> list[list[float]]:
    """Seconds of each call, ``repeats`` times, the calls alternating."""
    times: list[list[float]] = [[] for _ in calls]
    for _ in range(repeats):
        for k, call in enumerate(calls):
            t0 = time.perf_counter()
            call()
            times[k].append(time.perf_counter() - t0)
    return times


def _stats(times: list[float]) -> dict[str, float]:
    return {"median_us": float(np.median(times)) * 1e6, "p90_us": float(np.percentile(times, 90)) * 1e6}


def time_g12(columns: list[np.ndarray], rows: int, repeats: int) -> dict[str, Any]:
    """Kernel and twin on the first ``rows`` numbers of every column: the mean over the columns of each statistic."""
    per: dict[str, list[dict[str, float]]] = {"kernel": [], "twin": []}
    equal = True
    for col in columns:
        x = np.ascontiguousarray(col[:rows])
        outs = [np.zeros((len(x), ck.WIDTH), np.uint8) for _ in range(2)]
        lens = [np.zeros(len(x), np.int64) for _ in range(2)]
        tk, tt = _alternate([partial(ck._g12, x, outs[0], lens[0]), partial(g12_rows, x, outs[1], lens[1])], repeats)
        per["kernel"].append(_stats(tk))
        per["twin"].append(_stats(tt))
        equal &= bool(np.array_equal(outs[0], outs[1]) and np.array_equal(lens[0], lens[1]))
    mean = {k: {s: float(np.mean([d[s] for d in v])) for s in v[0]} for k, v in per.items()}
    return {"what": "g12 (per column)", "rows": min(rows, len(columns[0])), **mean, "equal": equal}


def time_join(call: tuple[np.ndarray, np.ndarray, np.ndarray], rows: int, repeats: int) -> dict[str, Any]:
    """Kernel and twin on the first ``rows`` rows of the cells."""
    cells, lens, starts = (np.ascontiguousarray(call[0][:rows]), np.ascontiguousarray(call[1][:rows]), call[2])
    outs = [np.zeros(int(lens.sum()) + lens.size, np.uint8) for _ in range(2)]
    tk, tt = _alternate(
        [lambda: ck._join(cells, lens, starts, outs[0]), lambda: join_rows(cells, lens, starts, outs[1])], repeats
    )
    equal = bool(np.array_equal(outs[0], outs[1]))
    return {
        "what": f"join ({lens.shape[1]} columns)",
        "rows": len(lens),
        "kernel": _stats(tk),
        "twin": _stats(tt),
        "equal": equal,
    }


def time_csv(traj: Trajectory, repeats: int) -> dict[str, Any]:
    """The whole CSV text (``csv_chunks``) with the kernels, then with the twins in their place."""
    texts: list[bytes] = []

    def with_kernels() -> None:
        texts.append(b"".join(traj.csv_chunks()))

    def with_twins() -> None:
        with kernels(g12_rows, join_rows):
            texts.append(b"".join(traj.csv_chunks()))

    tk, tt = _alternate([with_kernels, with_twins], repeats)
    equal = all(t == texts[0] for t in texts)
    return {"what": "whole CSV", "rows": len(traj.t), "kernel": _stats(tk), "twin": _stats(tt), "equal": equal}


def run(layout: str, rows: list[int], repeats: int) -> list[dict[str, Any]]:
    """Every measurement of the table, one record each."""
    traj = make_trajectory(layout)
    g12_calls, join_calls = record(traj)
    records = []
    for n in rows:
        records.append(time_g12(g12_calls, n, repeats))
        records.append(time_join(join_calls[0], n, repeats))
    records.append(time_csv(traj, max(3, repeats // 5)))
    return records


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--layout", default="airport", help="'airport' or a layout JSON file (examples/tracks/...)")
    ap.add_argument("--rows", type=int, nargs="+", default=[300, 43829])
    ap.add_argument("--repeats", type=int, default=31)
    ap.add_argument("--out", default=None)
    args = ap.parse_args()
    print(f"load average {os.getloadavg()[0]:.1f} at the start on {os.cpu_count()} cores")
    records = run(args.layout, args.rows, args.repeats)
    print("| what | rows | kernel median (µs) | kernel p90 (µs) | twin median (µs) | twin p90 (µs) | equal |")
    print("|---|---|---|---|---|---|---|")
    for r in records:
        k, t = r["kernel"], r["twin"]
        print(
            f"| {r['what']} | {r['rows']} | {k['median_us']:.0f} | {k['p90_us']:.0f} | {t['median_us']:.0f} | "
            f"{t['p90_us']:.0f} | {r['equal']} |"
        )
    print(f"load average {os.getloadavg()[0]:.1f} at the end")
    if args.out:
        Path(args.out).with_suffix(".json").write_text(json.dumps(records, indent=1))


if __name__ == "__main__":
    main()
