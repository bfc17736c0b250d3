"""Start-up wall time of the ``mpa`` command in fresh processes.

Usage::

    python experiments/bench_startup.py [--rounds 15]

Runs, interleaved and repeated, ``python -c pass`` (the interpreter's own start-up, the baseline at the same
time), ``mpa --help``, ``mpa plan ...`` (a lollipop query, JSON) and ``mpa trajectory ...`` (verified setpoints
written to a temporary directory), each as ``python -m trajopt.cli`` of this checkout, and prints the medians
and the cumulative ``-X importtime`` of the top-level imports of ``mpa --help`` and ``mpa plan``.

The checkout's ``mpa`` and ``trajopt`` are byte-compiled first (``compileall``) and the processes run with bytecode
enabled (``PYTHONDONTWRITEBYTECODE`` removed from their environment), as an installed package runs.
"""

from __future__ import annotations

import argparse
import compileall
import os
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
PLAN = ["plan", "--track", "lollipop", "--start", "0.1", "0.6", "--goal", "0.8", "0.3", "--json"]
TRAJ = ["trajectory", "--track", "lollipop", "--start", "0.1", "0.6", "--goal", "0.8", "0.3"]


def _env() -> dict[str, str]:
    env = {k: v for k, v in os.environ.items() if k != "PYTHONDONTWRITEBYTECODE"}
    return {**env, "PYTHONPATH": str(ROOT)}


def _wall(cmd: list[str]) -> float:
    t0 = time.perf_counter()
    subprocess.run(cmd, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL, check=True, env=_env())
    return time.perf_counter() - t0


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
    args = ap.parse_args()
    for package in ("mpa", "trajopt"):
        compileall.compile_dir(str(ROOT / package), quiet=1)
    py = [sys.executable]
    with tempfile.TemporaryDirectory() as tmp:
        cmds = {
            "python -c pass": [*py, "-c", "pass"],
            "mpa --help": [*py, "-m", "trajopt.cli", "--help"],
            "mpa plan ... --json": [*py, "-m", "trajopt.cli", *PLAN],
            "mpa trajectory ...": [*py, "-m", "trajopt.cli", *TRAJ, "--out", str(Path(tmp) / "t")],
            "mpa demo": [*py, "-m", "trajopt.cli", "demo", "--out", str(Path(tmp) / "d")],
        }
        times: dict[str, list[float]] = {k: [] for k in cmds}
        for _ in range(args.rounds):
            for k, c in cmds.items():
                times[k].append(_wall(c))
    print(f"{'command':<24}{'median s':>10}{'min s':>8}{'max s':>8}   ({args.rounds} rounds, interleaved)")
    for k, v in times.items():
        print(f"{k:<24}{statistics.median(v):>10.3f}{min(v):>8.3f}{max(v):>8.3f}")
    for label, a in (("mpa --help", ["--help"]), ("mpa plan", PLAN)):
        top = ", ".join(f"{n} {c / 1000:.0f} ms" for c, n in _importtime(a))
        print(f"-X importtime, {label}: {top}")


if __name__ == "__main__":
    main()
