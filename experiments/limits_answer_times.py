"""Every limit in the supported range answers within 10 s: a motion or one clear error line.

Draws seeded limits ``(v, a, j)``, each ``10^u`` times its default with ``u`` uniform in ``[-3, 4]``
(:data:`mpa.defaults.LIMIT_RANGE`), plus the eight corners of the range, and runs ``mpa trajectory`` in process
(``trajopt.cli.main.main``, files written to a temporary directory, after one warm-up run at the defaults that
loads the compiled kernels) on the lollipop query
``--start 0.2 0.5 --goal 0.5 0.2`` or (``--query y``) the Y junction's ``b_left:1.5 b_right:2 → b_right:2.5
b_short:1``. Prints each run's exit status, makespan, rows and wall time, then the median,
95th percentile and maximum wall and CPU time (the CPU time is the measure on a shared machine) and how many
took over 10 s.

    python experiments/limits_answer_times.py --queries 40 --seed 28
"""

from __future__ import annotations

import argparse
import contextlib
import io
import itertools
import json
import tempfile
import time
from pathlib import Path

import numpy as np

from mpa import defaults
from trajopt.cli.main import main

QUERY = ["--track", "lollipop", "--start", "0.2", "0.5", "--goal", "0.5", "0.2"]
#: The queries by name: the lollipop's above, and on the Y junction A from b_left to b_right, B from b_right to
#: b_short (the query of the limit property tests).
QUERIES = {
    "lollipop": QUERY,
    "y": [
        "--graph",
        str(Path(__file__).resolve().parents[1] / "examples" / "tracks" / "y_junction.json"),
        "--start",
        "b_left:1.5",
        "b_right:2",
        "--goal",
        "b_right:2.5",
        "b_short:1",
    ],
}
DEFAULTS = np.array([defaults.VMAX, defaults.AMAX, defaults.JMAX])


def run_one(limits: np.ndarray, out: Path, query: list[str] = QUERY) -> dict[str, object]:
    """One ``mpa trajectory`` with these limits: exit status, wall time (s), makespan and rows (if a motion)."""
    argv = ["trajectory", *query, "--vmax", repr(float(limits[0])), "--amax", repr(float(limits[1]))]
    argv += ["--jmax", repr(float(limits[2])), "--out", str(out)]
    err = io.StringIO()
    t0, c0 = time.perf_counter(), time.process_time()
    with contextlib.redirect_stdout(io.StringIO()), contextlib.redirect_stderr(err):
        code = main(argv)
    took, cpu = time.perf_counter() - t0, time.process_time() - c0
    rec: dict[str, object] = {"limits": limits.tolist(), "code": code, "seconds": took, "cpu": cpu}
    if code == 0:
        s = json.loads((out / "summary.json").read_text())
        rec.update(makespan=s["makespan"], rows=s["rows"])
    else:
        rec["message"] = err.getvalue().strip()
    return rec


def main_(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--queries", type=int, default=40, help="random limit triples (plus the 8 corners)")
    ap.add_argument("--seed", type=int, default=28)
    ap.add_argument("--query", choices=sorted(QUERIES), default="lollipop")
    args = ap.parse_args(argv)
    query = QUERIES[args.query]
    rng = np.random.default_rng(args.seed)
    triples = [DEFAULTS * 10.0 ** np.array(c) for c in itertools.product((-3.0, 4.0), repeat=3)]
    triples += [DEFAULTS * 10.0 ** rng.uniform(-3.0, 4.0, 3) for _ in range(args.queries)]
    records = []
    with tempfile.TemporaryDirectory() as tmp:
        run_one(DEFAULTS, Path(tmp) / "warm-up", query)  # imports, compiled kernels loaded (or compiled, first time)
        for i, lim in enumerate(triples):
            rec = run_one(lim, Path(tmp) / f"o{i}", query)
            records.append(rec)
            what = f"makespan {rec['makespan']:.6g} s, {rec['rows']} rows" if rec["code"] == 0 else rec["message"]
            head = f"{i:3d} v {lim[0]:.3g} a {lim[1]:.3g} j {lim[2]:.3g}: exit {rec['code']}"
            print(f"{head}, {rec['seconds']:.2f} s wall, {rec['cpu']:.2f} s CPU, {what}", flush=True)
    codes = [r["code"] for r in records]
    print(f"{len(records)} runs: exits {dict((c, codes.count(c)) for c in sorted(set(codes)))}")
    for key in ("seconds", "cpu"):
        t = np.array([r[key] for r in records], dtype=float)
        print(
            f"{key}: p50 {np.median(t):.2f} s, p95 {np.percentile(t, 95):.2f} s, max {t.max():.2f} s; "
            f"over 10 s: {int(np.sum(t > 10))}"
        )
    return 0 if all(c in (0, 2, 3) for c in codes) else 1


if __name__ == "__main__":
    raise SystemExit(main_())
