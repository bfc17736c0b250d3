"""Soak: many seeded random queries through the API and the command line, every output checked twice.

Each query draws a track (interval, circle or lollipop of random size), a clearance (0 to 40 % of the feasible
range), per-robot limits (v 0.1–2 m/s, a 0.2–5 m/s², j 1–50 m/s³), a rate (1 Hz to 1 kHz) and a start and goal,
all from ``numpy.random.default_rng([seed, index])`` (so any query can be re-run alone with ``--only INDEX``).
Most go through :class:`trajopt.TrajectoryGenerator` (a third of them also re-export at a second rate through
:meth:`trajopt.Trajectory.at_rate`); a fraction through ``mpa trajectory`` in process (``trajopt.cli.main``), a
few of those as a subprocess. Every output is checked by the gate's report and by the independent checker
:mod:`trajopt.testing` (for the command line: the CSV read back).

Outcomes: ``ok``, ``fallback`` (verified re-timed plan; the reason is kept), ``no_motion`` (NoMotionError, exit 3),
``rate_too_low`` (InvalidInputError naming the lowest usable rate, exit 2), ``invalid`` (other InvalidInputError:
a bug of the query generator), ``rejected`` (an output that fails a check: a bug), ``crash`` (anything else, or
exit 4: a bug). Reports counts, time percentiles, resident memory and log handlers at the start and the end.

Usage::

    python experiments/soak.py --queries 300 --out soak.json
    python experiments/soak.py --queries 100000 --out soak.json --checkpoint 1000
    python experiments/soak.py --queries 20000 --dask tcp://scheduler:8786 --out soak.json
    python experiments/soak.py --only 1234 --seed 0

Writes ``--out`` (JSON: the summary and every non-``ok`` record) atomically, also every ``--checkpoint``
queries, and prints the summary table (markdown). Resident memory, log handlers and warnings filters are those of
the process that runs the queries (with ``--dask``, of the client only). Exit status 1 if any query is a bug
(crash, rejected, invalid) or an unexpected fallback.
"""

from __future__ import annotations

import argparse
import contextlib
import io
import json
import logging
import os
import re
import subprocess
import sys
import tempfile
import time
import warnings
from pathlib import Path
from typing import Any

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
if str(ROOT) not in sys.path:  # run as a script from a checkout
    sys.path.insert(0, str(ROOT))

from mpa import Circle, Interval, Lollipop, Track  # noqa: E402
from mpa.errors import InvalidInputError, NoMotionError, PlanningError  # noqa: E402
from trajopt import Limits, TrajectoryGenerator  # noqa: E402
from trajopt.export import atomic_write_text  # noqa: E402
from trajopt.testing import check_setpoints, check_trajectory, read_setpoint_rows  # noqa: E402

__all__ = ["EXPECTED_FALLBACK_MARGIN", "draw_query", "expected_fallback", "run_chunk", "run_query", "summarize"]

#: Rates (Hz) the queries draw from.
RATES = (1.0, 2.0, 5.0, 10.0, 20.0, 50.0, 100.0, 100.0, 100.0, 250.0, 1000.0)
#: Share of the queries run through the command line (in process).
CLI_FRACTION = 0.02
#: Outcomes that are bugs.
BAD = ("crash", "rejected", "invalid")
#: A fallback is expected (not counted as a regression) when the separation margin the rate needs,
#: :func:`trajopt.generator.separation_margin`, is at least this (m): the optimised path must then keep the robots
#: a centimetre or more beyond the clearance between rows, more than the plan's corridor offers near tight spots.
#: At 100 Hz the margin is below 0.1 mm for every limit of the soak; it reaches 1 cm only at 10 Hz and below.
EXPECTED_FALLBACK_MARGIN = 0.01


def expected_fallback(rec: dict[str, Any], seed: int = 0) -> bool:
    """Whether a ``fallback`` record is expected, i.e. the optimised path cannot keep the rate's margin:

    - the separation margin of the rate reaches :data:`EXPECTED_FALLBACK_MARGIN`, or
    - the plan itself (start and goal included) comes closer to the clearance than that margin: the optimiser
      keeps no more room than the plan has there, and the gate's bound between rows then fails.

    The rate is the query's, or the second rate's when the fallback happened there (``"at R Hz: ..."``).
    """
    from mpa import make_planner
    from trajopt.generator import separation_margin

    q = rec.get("query") or draw_query(seed, rec["index"])
    m = re.match(r"at ([0-9.e+]+) Hz: ", rec.get("reason", ""))
    rate = float(m.group(1)) if m else float(q["rate"])
    margin = separation_margin(_limits(q), rate)
    if margin >= EXPECTED_FALLBACK_MARGIN:
        return True
    plan = make_planner(_track(q), q["clearance"]).plan(q["start"], q["goal"])
    return bool(plan.min_distance() < q["clearance"] + margin)


def draw_query(seed: int, index: int) -> dict[str, Any]:
    """The random query number ``index`` of the soak with ``seed`` (plain data)."""
    rng = np.random.default_rng([seed, index])
    kind = ("interval", "circle", "lollipop")[int(rng.integers(3))]
    stick = float(rng.uniform(0.2, 3.0))
    loop = float(rng.uniform(0.5, 3.0))
    if kind == "interval":
        track: Track = Interval(stick)
        feasible = stick / 2
    elif kind == "circle":
        track = Circle(loop)
        feasible = loop / 2
    else:
        track = Lollipop(stick, loop)
        feasible = loop / 2
    D = 0.0 if rng.random() < 0.05 else float(rng.uniform(0.0, 0.4)) * feasible
    per_robot = rng.random() < 0.2
    size = 2 if per_robot else 1
    v = rng.uniform(0.1, 2.0, size)
    a = rng.uniform(0.2, 5.0, size)
    j = rng.uniform(1.0, 50.0, size)
    rate = float(RATES[int(rng.integers(len(RATES)))])
    L = track.total_length
    for _ in range(1000):
        s, g = rng.uniform(0.0, L, 2), rng.uniform(0.0, L, 2)
        if track.distance(*s) >= max(D, 1e-6) and track.distance(*g) >= max(D, 1e-6):
            break
    u = rng.random()
    mode = "cli" if u < CLI_FRACTION else "api"
    return {
        "index": index,
        "kind": kind,
        "stick": stick,
        "loop": loop,
        "clearance": D,
        "vmax": v.tolist(),
        "amax": a.tolist(),
        "jmax": j.tolist(),
        "rate": rate,
        "rate2": float(RATES[int(rng.integers(len(RATES)))]) if rng.random() < 1 / 3 else None,
        "start": s.tolist(),
        "goal": g.tolist(),
        "mode": mode,
    }


def _track(q: dict[str, Any]) -> Track:
    if q["kind"] == "interval":
        return Interval(q["stick"])
    if q["kind"] == "circle":
        return Circle(q["loop"])
    return Lollipop(q["stick"], q["loop"])


def _limits(q: dict[str, Any]) -> Limits:
    def one(x: list[float]) -> Any:
        return x[0] if len(x) == 1 else tuple(x)

    return Limits(one(q["vmax"]), one(q["amax"]), one(q["jmax"]))


def _api(q: dict[str, Any]) -> dict[str, Any]:
    track = _track(q)
    gen = TrajectoryGenerator(track, clearance=q["clearance"], limits=_limits(q), rate=q["rate"])
    traj = gen.generate(q["start"], q["goal"])
    fails = [] if traj.verification["ok"] else ["gate report not ok"]
    fails += check_trajectory(traj, q["start"], q["goal"])
    out: dict[str, Any] = {"fallback_reason": traj.fallback_reason if traj.fallback else ""}
    if q["rate2"] is not None and not fails:
        try:
            t2 = traj.at_rate(q["rate2"])
        except InvalidInputError as exc:
            if "lowest usable rate" not in str(exc):
                raise
            out["rate2"] = "too low"
        else:
            fails += [f"at {q['rate2']:g} Hz: {f}" for f in check_trajectory(t2, q["start"], q["goal"])]
            out["rate2"] = "retimed" if "retimed_for_rate" in t2.solver_stats else "resampled"
            if t2.fallback and not traj.fallback:
                out["fallback_reason"] = f"at {q['rate2']:g} Hz: {t2.fallback_reason}"
    out["fails"] = fails
    return out


def _argv(q: dict[str, Any], out: str) -> list[str]:
    def fmt(x: list[float]) -> str:
        return repr(float(x[0]))

    argv = ["trajectory", "--track", q["kind"]]
    if q["kind"] != "circle":
        argv += ["--stick", repr(q["stick"])]
    if q["kind"] != "interval":
        argv += ["--loop", repr(q["loop"])]
    argv += ["--start", *map(repr, q["start"]), "--goal", *map(repr, q["goal"])]
    argv += ["--clearance", repr(q["clearance"]), "--vmax", fmt(q["vmax"]), "--amax", fmt(q["amax"])]
    argv += ["--jmax", fmt(q["jmax"]), "--rate", repr(q["rate"]), "--out", out]
    return argv


def _cli(q: dict[str, Any], subproc: bool) -> dict[str, Any]:
    from trajopt.cli import main

    q = {**q, **{k: q[k][:1] for k in ("vmax", "amax", "jmax")}}  # the command line takes one limit per kind
    with tempfile.TemporaryDirectory() as tmp:
        out = os.path.join(tmp, "run")
        argv = _argv(q, out)
        if subproc:
            env = {**os.environ, "PYTHONPATH": str(ROOT)}
            cp = subprocess.run(
                [sys.executable, "-m", "trajopt.cli", *argv], capture_output=True, text=True, env=env, check=False
            )
            code, err = cp.returncode, cp.stderr
        else:
            buf_out, buf_err = io.StringIO(), io.StringIO()
            with contextlib.redirect_stdout(buf_out), contextlib.redirect_stderr(buf_err):
                code = main(argv)
            err = buf_err.getvalue()
        lines = err.strip().splitlines()
        res: dict[str, Any] = {"exit": code, "fails": [], "fallback_reason": ""}
        if code != 0:
            if len(lines) != 1 or "Traceback" in err:
                res["fails"].append(f"exit {code} with stderr {err!r}")
            res["message"] = err.strip()
            if os.path.exists(out):
                res["fails"].append(f"exit {code} left {os.listdir(out)}")
            return res
        summary = json.loads(Path(out, "summary.json").read_text())
        lim = summary["limits"]
        res["fails"] = check_setpoints(
            _track(q),
            *read_setpoint_rows(Path(out, "setpoints.csv")),
            rate=q["rate"],
            clearance=q["clearance"],
            vmax=lim["vmax"],
            amax=lim["amax"],
            jmax=lim["jmax"],
            start=summary["start"],
            goal=summary["goal"],
        )
        # the CSV holds 12 significant digits: relax nothing but the endpoint and consistency checks' round-off
        res["fails"] = [f for f in res["fails"] if not _csv_rounding(f)]
        if not summary["verification"]["ok"]:
            res["fails"].append("summary says the gate failed")
        res["fallback_reason"] = summary["fallback_reason"] if summary["fallback"] else ""
        return res


def _csv_rounding(msg: str) -> bool:
    """Failures explained by the CSV's 12 significant digits (rows re-read from text)."""
    return msg.startswith(("first row at", "last row at", "first row not at rest", "last row not at rest")) and all(
        abs(float(x)) < 1e-9 for x in _numbers(msg.split(" is ")[-1] if " is " in msg else msg)
    )


def _numbers(text: str) -> list[float]:
    return [float(x) for x in re.findall(r"-?\d+\.?\d*(?:e-?\d+)?", text.split("from")[0])][-2:]


def run_query(seed: int, index: int, subproc: bool = False) -> dict[str, Any]:
    """Run one soak query; returns its record (``outcome``, ``time`` in s, details)."""
    q = draw_query(seed, index)
    t0 = time.perf_counter()
    rec: dict[str, Any] = {k: q[k] for k in ("index", "kind", "clearance", "rate", "mode")}
    if subproc:
        rec["mode"] = "subprocess"
    try:
        res = _cli(q, subproc) if q["mode"] == "cli" or subproc else _api(q)
    except NoMotionError as exc:
        rec.update(outcome="no_motion", reason=str(exc))
    except InvalidInputError as exc:
        rec.update(outcome="rate_too_low" if "lowest usable rate" in str(exc) else "invalid", reason=str(exc))
    except PlanningError as exc:
        rec.update(outcome="crash", reason=f"PlanningError: {exc}")
    except Exception as exc:
        rec.update(outcome="crash", reason=f"{type(exc).__name__}: {exc}")
    else:
        code = res.get("exit", 0)
        if res["fails"]:
            rec.update(outcome="rejected", reason="; ".join(res["fails"])[:2000])
        elif code == 3:
            rec.update(outcome="no_motion", reason=res["message"])
        elif code == 2:
            msg = res["message"]
            rec.update(outcome="rate_too_low" if "lowest usable rate" in msg else "invalid", reason=msg)
        elif code != 0:
            rec.update(outcome="crash", reason=res["message"])
        elif res["fallback_reason"]:
            rec.update(outcome="fallback", reason=res["fallback_reason"])
        else:
            rec.update(outcome="ok")
        if "rate2" in res:
            rec["rate2"] = res["rate2"]
    rec["time"] = time.perf_counter() - t0
    if rec["outcome"] != "ok":
        rec["query"] = q
    return rec


def run_chunk(seed: int, indices: list[int], subproc: set[int] | None = None) -> list[dict[str, Any]]:
    """Run several queries (one Dask task)."""
    sub = subproc or set()
    return [run_query(seed, i, i in sub) for i in indices]


def _rss_mb() -> float:
    try:
        with open("/proc/self/statm") as fh:
            return int(fh.read().split()[1]) * os.sysconf("SC_PAGE_SIZE") / 2**20
    except (OSError, ValueError):
        return float("nan")


def _handlers() -> int:
    loggers = [logging.getLogger(), *(logging.getLogger(n) for n in list(logging.root.manager.loggerDict))]
    return sum(len(lg.handlers) for lg in loggers)


def summarize(records: list[dict[str, Any]], extra: dict[str, Any] | None = None) -> dict[str, Any]:
    """Counts per outcome, time percentiles (s) and the non-``ok`` records."""
    times = np.array([r["time"] for r in records]) if records else np.zeros(1)
    outcomes = ["ok", "fallback", "no_motion", "rate_too_low", "invalid", "rejected", "crash"]
    counts = {o: sum(r["outcome"] == o for r in records) for o in outcomes}
    modes = {m: sum(r["mode"] == m for r in records) for m in ("api", "cli", "subprocess")}
    by_kind = {
        k: {o: sum(r["outcome"] == o and r["kind"] == k for r in records) for o in outcomes}
        for k in ("interval", "circle", "lollipop")
    }
    retimed = sum(r.get("rate2") == "retimed" for r in records)
    seed = int((extra or {}).get("seed", 0))
    unexpected = [r["index"] for r in records if r["outcome"] == "fallback" and not expected_fallback(r, seed)]
    return {
        "queries": len(records),
        "counts": counts,
        "unexpected_fallbacks": unexpected,
        "modes": modes,
        "by_kind": by_kind,
        "second_rate": {
            "resampled": sum(r.get("rate2") == "resampled" for r in records),
            "retimed": retimed,
            "too_low": sum(r.get("rate2") == "too low" for r in records),
        },
        "time_s": {
            "p50": float(np.percentile(times, 50)),
            "p95": float(np.percentile(times, 95)),
            "max": float(np.max(times)),
            "total": float(np.sum(times)),
            "slowest": sorted(((r["time"], r["index"]) for r in records), reverse=True)[:5],
        },
        **(extra or {}),
        "problems": [r for r in records if r["outcome"] in (*BAD, "fallback")],
    }


def table(summary: dict[str, Any]) -> str:
    """The summary as a markdown table."""
    c, t = summary["counts"], summary["time_s"]
    lines = [
        "| queries | crashes | rejected | invalid | fallbacks (unexpected) | no motion | rate too low "
        "| p50 | p95 | max |",
        "|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|",
        f"| {summary['queries']} | {c['crash']} | {c['rejected']} | {c['invalid']} | {c['fallback']} "
        f"({len(summary['unexpected_fallbacks'])}) | "
        f"{c['no_motion']} | {c['rate_too_low']} | {1e3 * t['p50']:.1f} ms | {1e3 * t['p95']:.1f} ms | "
        f"{1e3 * t['max']:.0f} ms |",
    ]
    return "\n".join(lines)


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=(__doc__ or "").splitlines()[0])
    ap.add_argument("--queries", type=int, default=300, help="number of queries (default 300)")
    ap.add_argument("--seed", type=int, default=0)
    ap.add_argument("--out", type=Path, default=None, help="summary JSON (written atomically)")
    ap.add_argument("--checkpoint", type=int, default=0, help="rewrite --out every N queries (0: at the end only)")
    ap.add_argument("--subprocess", type=int, default=5, help="queries run as a subprocess `mpa` (default 5)")
    ap.add_argument("--dask", default=None, metavar="ADDRESS", help="run on an existing Dask cluster")
    ap.add_argument("--chunk", type=int, default=50, help="queries per Dask task")
    ap.add_argument("--only", type=int, default=None, help="run query INDEX alone and print its record")
    ap.add_argument("--no-progress", action="store_true")
    args = ap.parse_args(argv)
    if args.only is not None:
        print(json.dumps(run_query(args.seed, args.only), indent=2, default=str))
        return 0
    from tqdm import tqdm

    n = args.queries
    sub = set(np.linspace(0, n - 1, min(args.subprocess, n)).astype(int).tolist()) if args.subprocess > 0 else set()
    rss0, h0, w0 = _rss_mb(), _handlers(), len(warnings.filters)
    records: list[dict[str, Any]] = []
    t_start = time.time()

    def extra() -> dict[str, Any]:
        return {
            "seed": args.seed,
            "wall_s": time.time() - t_start,
            "rss_mb": {"start": rss0, "end": _rss_mb()},
            "log_handlers": {"start": h0, "end": _handlers()},
            "warnings_filters": {"start": w0, "end": len(warnings.filters)},
            "where": f"dask {args.dask}" if args.dask else "1 process",
        }

    def save() -> None:
        if args.out is not None:
            atomic_write_text(args.out, json.dumps(summarize(records, extra()), indent=1, default=str) + "\n")

    bar = tqdm(total=n, disable=args.no_progress, desc="soak", unit="query", dynamic_ncols=True)
    try:
        if args.dask:
            from dask.distributed import Client, as_completed

            with Client(args.dask) as client:
                client.upload_file(__file__)
                chunks = [list(range(i, min(n, i + args.chunk))) for i in range(0, n, args.chunk)]
                futs = [client.submit(run_chunk, args.seed, ch, sub & set(ch), pure=False) for ch in chunks]
                for f in as_completed(futs):
                    recs = f.result()
                    records.extend(recs)
                    bar.update(len(recs))
        else:
            for i in range(n):
                rec = run_query(args.seed, i, i in sub)
                records.append(rec)
                bar.update()
                if rec["outcome"] in BAD:
                    bar.write(f"query {i}: {rec['outcome']}: {rec.get('reason', '')[:300]}")
                if args.checkpoint and (i + 1) % args.checkpoint == 0:
                    save()
    finally:
        bar.close()
        records.sort(key=lambda r: r["index"])
        save()
    summary = summarize(records, extra())
    print(table(summary))
    print(
        f"memory {summary['rss_mb']['start']:.0f} -> {summary['rss_mb']['end']:.0f} MB, log handlers "
        f"{summary['log_handlers']['start']} -> {summary['log_handlers']['end']}, warnings filters "
        f"{summary['warnings_filters']['start']} -> {summary['warnings_filters']['end']}"
    )
    return 1 if any(summary["counts"][b] for b in BAD) or summary["unexpected_fallbacks"] else 0


if __name__ == "__main__":
    sys.exit(main())
