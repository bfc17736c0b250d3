"""Start-up wall and CPU time of the ``mpa`` command in fresh processes.

Usage::

    python experiments/bench_startup.py [--rounds 15] [--before OTHER_CHECKOUT]

Runs, interleaved and repeated, ``python -c pass`` (the interpreter's own start-up, the baseline at the same
time), ``mpa --help``, ``mpa plan ...`` (a lollipop query, JSON), ``mpa trajectory ...`` (verified setpoints
written to a temporary directory) and ``mpa demo``, each as ``python -m trajopt.cli`` of this checkout (with
``--before DIR``: each command of the other checkout right before this one's, so both see the same load), and
prints the medians of the wall time and of the process's CPU time (user + system), and the cumulative
``-X importtime`` of the top-level imports of ``mpa --help`` and ``mpa plan``.

The checkouts' ``mpa`` and ``trajopt`` are byte-compiled first (``compileall``) and the processes run with bytecode
enabled (``PYTHONDONTWRITEBYTECODE`` removed from their environment), as an installed package runs.
"""

from __future__ import annotations

import argparse
import compileall
import os
import resource
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
PLAN = ["plan", "--track", "lollipop", "--start", "0.1", "0.6", "--goal", "0.8", "0.3", "--json"]
TRAJ = ["trajectory", "--track", "lollipop", "--start", "0.1", "0.6", "--goal", "0.8", "0.3"]


def _env(root: Path = ROOT) -> dict[str, str]:
    env = {k: v for k, v in os.environ.items() if k != "PYTHONDONTWRITEBYTECODE"}
    return {**env, "PYTHONPATH": str(root)}


def _wall(cmd: list[str], root: Path = ROOT) -> tuple[float, float]:
    """Wall and CPU (user + system) seconds of one process of ``root``'s code."""
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    t0 = time.perf_counter()
    subprocess.run(cmd, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL, check=True, env=_env(root), cwd=root)
    wall = time.perf_counter() - t0
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    return wall, (after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime)


def _importtime(args: list[str]) -> list[tuple[int, str]]:
    out = subprocess.run(
        [sys.executable, "-X", "importtime", "-m", "trajopt.cli", *args], capture_output=True, text=True, env=_env()
    ).stderr
    rows = []
    for line in out.splitlines():
        if not line.startswith("import time:") or "|" not in line:
            continue
        _self, cum, name = line[len("import time:") :].split("|")
        if cum.strip().isdigit() and len(name) - len(name.lstrip()) <= 3:  # top-level imports only
            rows.append((int(cum), name.strip()))
    return sorted(rows, reverse=True)[:6]


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--rounds", type=int, default=15)
    ap.add_argument("--before", default=None, help="another checkout, its commands interleaved with this one's")
    args = ap.parse_args()
    roots = {"": ROOT} if args.before is None else {"before: ": Path(args.before).resolve(), "after: ": ROOT}
    for root in roots.values():
        for package in ("mpa", "trajopt"):
            compileall.compile_dir(str(root / package), quiet=1)
    py = [sys.executable]
    print(f"load average {os.getloadavg()[0]:.1f} at the start on {os.cpu_count()} cores")
    with tempfile.TemporaryDirectory() as tmp:
        cmds = {
            "python -c pass": [*py, "-c", "pass"],
            "mpa --help": [*py, "-m", "trajopt.cli", "--help"],
            "mpa plan ... --json": [*py, "-m", "trajopt.cli", *PLAN],
            "mpa trajectory ...": [*py, "-m", "trajopt.cli", *TRAJ, "--out", str(Path(tmp) / "t")],
            "mpa demo": [*py, "-m", "trajopt.cli", "demo", "--out", str(Path(tmp) / "d")],
        }
        times: dict[str, list[tuple[float, float]]] = {p + k: [] for k in cmds for p in roots}
        for _ in range(args.rounds):
            for k, c in cmds.items():
                for p, root in roots.items():
                    times[p + k].append(_wall(c, root))
    print(f"{'command':<32}{'wall median s':>14}{'min s':>8}{'max s':>8}{'CPU median s':>14}   ({args.rounds} rounds)")
    for k, v in times.items():
        walls = [w for w, _ in v]
        cpu = statistics.median(c for _, c in v)
        print(f"{k:<32}{statistics.median(walls):>14.3f}{min(walls):>8.3f}{max(walls):>8.3f}{cpu:>14.3f}")
    print(f"load average {os.getloadavg()[0]:.1f} at the end")
    for label, a in (("mpa --help", ["--help"]), ("mpa plan", PLAN)):
        top = ", ".join(f"{n} {c / 1000:.0f} ms" for c, n in _importtime(a))
        print(f"-X importtime, {label}: {top}")


if __name__ == "__main__":
    main()
