"""`mpa trajectory` end to end on the converted building maps: process start, imports, map read, free space, plan,
timing, gate, margins, files written.

    python experiments/bench_cli_maps.py [--runs 3] [--queries 3] [--root DIR] [--before DIR | --numba-before]
        [--cold] [--no-bytecode] [--out FILE]

Maps: the Open-RMF sample maps of ``tests/data/openrmf`` (office L1, hotel L1 / L2 / L3 at D = 0.3 m, the airport
terminal's level L1, navigation graph 2, at D = 0.6 m). Queries: on the airport the query of issue 25 (a 438 s
motion) then, on every map, seeded queries of ``bench.graph_runner.make_graph_queries`` that are not swaps (the swaps'
plan time is measured by ``bench_plan_tails.py``). Each query runs ``--runs`` times as a fresh process
(``python -m trajopt.cli trajectory ... --out DIR``), after one unrecorded warm-up run (numba compiles and
caches its kernels on the first run of a checkout); per map the median wall time and the median CPU time of the
process (user + system, ``resource.getrusage(RUSAGE_CHILDREN)``: on a shared machine the wall time includes the
waits for a core). ``--root DIR`` runs the code of another checkout (``PYTHONPATH=DIR``); ``--before DIR`` runs a
second checkout alternately with it, run for run, so that both see the same load (a before/after table);
``--numba-before`` runs the same checkout twice instead, before with numba's compiled kernels
(``TRAJOPT_KERNELS=numba``), after as the command runs by default (their numpy twins, numba not imported:
:mod:`trajopt._numba`).

The checkout's modules are byte-compiled first (``compileall``) and the processes run with bytecode enabled
(``PYTHONDONTWRITEBYTECODE`` removed from their environment), as an installed package runs: compiling the
pipeline's ~80 modules from source costs a process 0.4-0.7 s CPU that no installed ``mpa`` pays. The layout
cache (:mod:`mpa.openrmf.cache`) goes to a fresh temporary directory per run of this script (``MPA_CACHE_DIR``):
the warm-up run fills it, the recorded runs find the map's layout there, as every run after a user's first does;
``--cold`` disables it (``MPA_CACHE_DIR=off``) to measure the first run on a map; ``--no-bytecode`` deletes the
checkout's compiled modules of ``mpa`` and ``trajopt`` and runs the processes with ``PYTHONDONTWRITEBYTECODE=1`` (a
source checkout in an environment that never writes bytecode).
Prints a Markdown table; ``--out FILE`` also writes ``FILE.json``.
"""

from __future__ import annotations

import argparse
import compileall
import json
import os
import resource
import subprocess
import sys
import tempfile
import time
from pathlib import Path
from typing import Any

import numpy as np

ROOT = Path(__file__).resolve().parent
sys.path.insert(0, str(ROOT))
sys.path.insert(0, str(ROOT.parent))

from bench.graph_runner import make_graph_queries  # noqa: E402

from mpa.graph_track import GraphTrack  # noqa: E402

DATA = ROOT.parent / "tests" / "data" / "openrmf"
AIRPORT = DATA / "airport_terminal.building.yaml"
#: The query of issue 25 on the airport terminal (level L1, navigation graph 2), clearance 0.6 m.
AIRPORT_QUERY = (("lane70:3.102", "lane143:8.848"), ("lane87:1.237", "lane100:0.997"))
MAPS: tuple[tuple[str, Path, list[str], float], ...] = (
    ("office L1", DATA / "office.building.yaml", ["--level", "L1"], 0.3),
    ("hotel L1", DATA / "hotel.building.yaml", ["--level", "L1"], 0.3),
    ("hotel L2", DATA / "hotel.building.yaml", ["--level", "L2"], 0.3),
    ("hotel L3", DATA / "hotel.building.yaml", ["--level", "L3"], 0.3),
    ("airport L1 graph 2", AIRPORT, ["--level", "L1", "--nav-graph", "2"], 0.6),
)


def _queries(name: str, path: Path, options: list[str], clearance: float, n: int) -> list[tuple[Any, Any]]:
    level = options[options.index("--level") + 1]
    nav = int(options[options.index("--nav-graph") + 1]) if "--nav-graph" in options else None
    track = GraphTrack.from_file(path, level=level, nav_graph=nav)
    out: list[tuple[Any, Any]] = [AIRPORT_QUERY] if path == AIRPORT else []
    for q in make_graph_queries(track, 4 * n, 25, [clearance]):
        if len(out) >= n:
            break
        if q["swap"]:
            continue
        out.append(tuple(tuple(track.position_name(*p) for p in pair) for pair in (q["start"], q["goal"])))
    return out


#: Whether the processes run with bytecode (``--no-bytecode`` clears it).
BYTECODE = {"on": True}


def _env(root: Path, cache: str, kernels: str | None = None) -> dict[str, str]:
    """The processes' environment: ``root``'s code, bytecode enabled (or not), the layout cache in ``cache``, the
    kernels' mode ``kernels`` (None: the command's default)."""
    env = {k: v for k, v in os.environ.items() if k not in ("PYTHONDONTWRITEBYTECODE", "TRAJOPT_KERNELS")}
    if kernels is not None:
        env["TRAJOPT_KERNELS"] = kernels
    if not BYTECODE["on"]:
        env["PYTHONDONTWRITEBYTECODE"] = "1"
    return {**env, "PYTHONPATH": str(root), "MPA_CACHE_DIR": cache}


def _run(
    root: Path,
    path: Path,
    options: list[str],
    clearance: float,
    query: tuple[Any, Any],
    cache: str,
    kernels: str | None = None,
) -> tuple[float, float]:
    """Wall and CPU seconds of one ``mpa trajectory`` process (``kernels``: the kernels' mode, None: the
    command's default)."""
    (a0, b0), (a1, b1) = query
    env = _env(root, cache, kernels)
    with tempfile.TemporaryDirectory() as tmp:
        cmd = [sys.executable, "-m", "trajopt.cli", "trajectory", "--graph", str(path), *options]
        cmd += ["--start", a0, b0, "--goal", a1, b1, "--clearance", str(clearance), "--out", str(Path(tmp) / "o")]
        before = resource.getrusage(resource.RUSAGE_CHILDREN)
        t0 = time.perf_counter()
        proc = subprocess.run(cmd, env=env, cwd=root, capture_output=True, text=True, check=False)
        wall = time.perf_counter() - t0
        after = resource.getrusage(resource.RUSAGE_CHILDREN)
        if proc.returncode != 0:
            raise RuntimeError(f"{' '.join(cmd)} exited {proc.returncode}: {proc.stderr.strip()}")
    cpu = (after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime)
    return wall, cpu


def _prepare(root: Path, bytecode: bool) -> None:
    """Byte-compile ``root``'s packages, or delete their compiled modules (``--no-bytecode``)."""
    for package in ("mpa", "trajopt"):
        if bytecode:
            compileall.compile_dir(str(root / package), quiet=1)
        else:
            for pyc in (root / package).rglob("__pycache__/*.pyc"):
                pyc.unlink()


def _stats(walls: list[float], cpus: list[float]) -> dict[str, float]:
    return {
        "wall_median_s": float(np.median(walls)),
        "wall_max_s": float(np.max(walls)),
        "cpu_median_s": float(np.median(cpus)),
        "cpu_max_s": float(np.max(cpus)),
    }


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--runs", type=int, default=3)
    ap.add_argument("--queries", type=int, default=3)
    ap.add_argument("--root", default=str(ROOT.parent), help="the checkout whose code runs")
    ap.add_argument(
        "--before", default=None, help="another checkout, run alternately with --root (the same load on both)"
    )
    ap.add_argument(
        "--numba-before",
        action="store_true",
        help="before: this checkout with numba's compiled kernels (TRAJOPT_KERNELS=numba); after: the default",
    )
    ap.add_argument("--out", default=None)
    ap.add_argument("--cold", action="store_true", help="no layout cache (MPA_CACHE_DIR=off): every run reads the map")
    ap.add_argument("--no-bytecode", action="store_true", help="run without compiled modules (PYTHONDONTWRITEBYTECODE)")
    args = ap.parse_args()
    os.environ["MPA_CACHE_DIR"] = "off"  # this process reads the maps for the queries only: no user cache written
    roots: dict[str, tuple[Path, str | None]] = {"after": (Path(args.root).resolve(), None)}
    if args.before:
        roots = {"before": (Path(args.before).resolve(), None), **roots}
    elif args.numba_before:
        roots = {"before": (roots["after"][0], "numba"), **roots}
    BYTECODE["on"] = not args.no_bytecode
    for root, _ in roots.values():
        _prepare(root, BYTECODE["on"])
    cache_dir = tempfile.TemporaryDirectory()
    cache = "off" if args.cold else cache_dir.name
    print(f"load average {os.getloadavg()[0]:.1f} at the start on {os.cpu_count()} cores")
    cols = ["wall median (s)", "wall max (s)", "CPU median (s)", "CPU max (s)"]
    head = [f"{c} {k}" for k in roots for c in cols] if len(roots) > 1 else cols
    print("| map | queries x runs | " + " | ".join(head) + " |")
    print("|---" * (2 + len(head)) + "|")
    records = []
    for name, path, options, clearance in MAPS:
        queries = _queries(name, path, options, clearance, args.queries)
        for root, kernels in roots.values():
            # a warm-up run per map, not recorded: numba's kernels compiled and cached once, the map's layout cached
            _run(root, path, options, clearance, queries[0], cache, kernels)
        times: dict[str, tuple[list[float], list[float]]] = {k: ([], []) for k in roots}
        for query in queries:
            for _ in range(args.runs):
                for key, (root, kernels) in roots.items():  # alternately: both arms see the same load
                    w, c = _run(root, path, options, clearance, query, cache, kernels)
                    times[key][0].append(w)
                    times[key][1].append(c)
        rec: dict[str, Any] = {"map": name, "runs": len(times["after"][0])}
        for key in roots:
            rec[key] = _stats(*times[key])
        records.append(rec)
        cells = [f"{v:.2f}" for k in roots for v in rec[k].values()]
        print(f"| {name} | {rec['runs']} | " + " | ".join(cells) + " |", flush=True)
    print(f"load average {os.getloadavg()[0]:.1f} at the end")
    cache_dir.cleanup()
    if args.out:
        Path(args.out).with_suffix(".json").write_text(json.dumps(records, indent=1))


if __name__ == "__main__":
    main()
