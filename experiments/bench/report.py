"""Summaries of benchmark records: Markdown tables and PNG plots (matplotlib, Agg, imported lazily)."""

from __future__ import annotations

import math
from collections.abc import Sequence
from pathlib import Path
from typing import Any

import numpy as np

__all__ = [
    "METHOD_LABELS",
    "plot_results",
    "plot_scaling",
    "results_markdown",
    "scaling_markdown",
    "summarize",
]

Record = dict[str, Any]
METHOD_LABELS = {
    "ours": "ours (plan → fast path or corridor QP → filtered timing / ruckig)",
    "raw_plan": "raw plan (rest to rest)",
    "ompl_rest": "OMPL RRTConnect, rest to rest",
    "ompl_bspline": "OMPL + B-spline, timed like ours",
    "ompl_geo": "OMPL, geodesic motions, rest to rest",
    "grid": "grid A*, shortcut, timed like ours",
}
ORDER = tuple(METHOD_LABELS)


def _vals(recs: Sequence[Record], key: str, only_verified: bool = False) -> np.ndarray:
    out = [r[key] for r in recs if r.get(key) is not None and (r["verified"] or not only_verified)]
    return np.asarray(out, dtype=float)


def _q(x: np.ndarray, p: float) -> float:
    return float(np.percentile(x, p)) if len(x) else math.nan


def _by(records: Sequence[Record], *keys: str) -> dict[tuple[Any, ...], list[Record]]:
    out: dict[tuple[Any, ...], list[Record]] = {}
    for r in records:
        out.setdefault(tuple(r[k] for k in keys), []).append(r)
    return out


def _ratios(records: Sequence[Record], method: str, ref: str, key: str = "makespan") -> np.ndarray:
    """Per-query ``key(method) / key(ref)`` over queries where both verified (and ref > 0)."""
    by_q = _by(records, "track", "query")
    out = []
    for recs in by_q.values():
        d = {r["method"]: r for r in recs}
        a, b = d.get(method), d.get(ref)
        if a and b and a["verified"] and b["verified"] and a.get(key) is not None and b.get(key):
            out.append(a[key] / b[key])
    return np.asarray(out, dtype=float)


def summarize(records: Sequence[Record]) -> dict[str, dict[str, dict[str, float]]]:
    """Per track and method: success, timing, makespan, ratios to ours, stability and class statistics."""
    out: dict[str, dict[str, dict[str, float]]] = {}
    for (track, method), recs in sorted(
        _by(records, "track", "method").items(), key=lambda kv: (kv[0][0], ORDER.index(kv[0][1]))
    ):
        ct = _vals(recs, "compute_time")
        mk = _vals(recs, "makespan", only_verified=True)
        lb = _vals(recs, "makespan_ratio", only_verified=True)
        rat = _ratios([r for r in records if r["track"] == track], method, "ours")
        ours_ct = _vals([r for r in records if r["track"] == track and r["method"] == "ours"], "compute_time")
        disc = [r["discontinuous"] for r in recs if r.get("discontinuous") is not None]
        dres = [r["discontinuous_reseeded"] for r in recs if r.get("discontinuous_reseeded") is not None]
        ours_words = {
            r["query"]: r["word"] for r in records if r["track"] == track and r["method"] == "ours" and r["verified"]
        }
        same = [r["word"] == ours_words[r["query"]] for r in recs if r["verified"] and r["query"] in ours_words]
        seps = _vals(recs, "min_separation", only_verified=True)
        out.setdefault(track, {})[method] = {
            "queries": len(recs),
            "success": float(np.mean([r["success"] for r in recs])),
            "verified": float(np.mean([r["verified"] for r in recs])),
            "ct_median": _q(ct, 50),
            "ct_p95": _q(ct, 95),
            "ct_vs_ours": (_q(ct, 50) / _q(ours_ct, 50)) if len(ours_ct) else math.nan,
            "mk_median": _q(mk, 50),
            "mk_p95": _q(mk, 95),
            "ratio_median": _q(rat, 50),
            "ratio_p95": _q(rat, 95),
            "ratio_n": len(rat),
            "lb_median": _q(lb, 50),
            "lb_p95": _q(lb, 95),
            "min_sep": float(np.min(seps)) if len(seps) else math.nan,
            "disc_rate": float(np.mean(disc)) if disc else math.nan,
            "disc_n": len(disc),
            "disc_reseeded_rate": float(np.mean(dres)) if dres else math.nan,
            "same_class": float(np.mean(same)) if same else math.nan,
            "rests_mean": float(np.mean(_vals(recs, "rests", only_verified=True))) if len(mk) else math.nan,
            "fallbacks": float(sum(bool(r["stats"].get("fallback")) for r in recs)),
        }
    return out


def _f(x: float, fmt: str = "{:.2f}") -> str:
    return "—" if x is None or (isinstance(x, float) and not math.isfinite(x)) else fmt.format(x)


def _pct(x: float) -> str:
    return _f(100 * x if x is not None and math.isfinite(x) else math.nan, "{:.0f} %")


def results_markdown(records: Sequence[Record], meta: dict[str, Any]) -> str:
    """The Markdown report: per track a method table, the per-domain gap of ours vs the grid, and the
    lollipop queries that change the robots' coordinate order."""
    summ = summarize(records)
    lines = ["# Benchmark: ours against the planners a user would pick instead", ""]
    if meta.get("command"):
        lines += ["Command:", "", "```", meta["command"], "```", ""]
    for k in ("machine", "versions", "wall_time_s", "workers"):
        if k in meta:
            lines.append(f"- {k.replace('_', ' ')}: {meta[k]}")
    if "config" in meta:
        c = meta["config"]
        lines.append(
            f"- clearance D = {c['clearance']} m, limits v/a/j = {c['vmax']}/{c['amax']}/{c['jmax']}, "
            f"{c['rate']:g} Hz, OMPL budget {c['ompl_time']} s, grid spacing {c['grid']} m, seed {c['seed']}, "
            f"twin δ = {c['delta']:g} m, discontinuity threshold {c['threshold']} m"
        )
    lines.append("")
    lines += [
        "Times are measured inside the worker around each method's whole pipeline (query → verified setpoints). "
        "Makespan = motion time (s); medians and p95 over verified results; `/ ours` = median (p95) of the "
        "per-query ratio over queries both verified; `/ LB` = makespan over the lower bound (max over robots of "
        "the jerk-limited rest-to-rest time along its own shortest route); `disc.` = share of perturbed twins "
        "(start and goal moved by δ) whose trajectories differ by more than the threshold (sup over normalised "
        "time of the larger robot's graph distance); for OMPL `disc. (reseeded)` solves the twin with another "
        "seed, as a re-planning robot would; `class = ours` = share of verified results in our homotopy class.",
        "",
    ]
    for track, methods in summ.items():
        lines += [f"## {track}", ""]
        lines.append(
            "| method | queries | success | verified | compute median ms | p95 ms | compute ÷ ours | "
            "makespan median s | p95 s | / ours median | / ours p95 | / LB median | min sep. m | "
            "disc. | disc. (reseeded) | class = ours | mean rests |"
        )
        lines.append("|" + "---|" * 17)
        for m in ORDER:
            if m not in methods:
                continue
            s = methods[m]
            lines.append(
                f"| {METHOD_LABELS[m]} | {s['queries']} | {_pct(s['success'])} | {_pct(s['verified'])} | "
                f"{_f(1e3 * s['ct_median'], '{:.1f}')} | {_f(1e3 * s['ct_p95'], '{:.1f}')} | "
                f"{_f(s['ct_vs_ours'], '{:.2f}×')} | {_f(s['mk_median'])} | {_f(s['mk_p95'])} | "
                f"{_f(s['ratio_median'], '{:.3f}')} | {_f(s['ratio_p95'], '{:.3f}')} | "
                f"{_f(s['lb_median'], '{:.3f}')} | "
                f"{_f(s['min_sep'], '{:.4f}')} | {_pct(s['disc_rate'])} ({s['disc_n']}) | "
                f"{_pct(s['disc_reseeded_rate'])} | {_pct(s['same_class'])} | {_f(s['rests_mean'], '{:.1f}')} |"
            )
        lines.append("")
        trecs = [r for r in records if r["track"] == track]
        if "ours" in methods:
            lines += _ratio_table(trecs)
            lines += _stage_table(trecs)
        if "grid" in methods and "ours" in methods:
            lines += _domain_table(trecs)
        if track == "lollipop" and any(m.startswith("ompl") for m in methods):
            lines += _order_table(trecs)
    return "\n".join(lines) + "\n"


def _ratio_table(recs: Sequence[Record]) -> list[str]:
    """Ours against every other method, on all queries and on the interacting ones."""
    out = [
        "Ours against each method on the queries both verified: makespan ours ÷ method (median and p95 of the "
        "per-query ratio, ratio of the medians, share of queries where ours is faster by more than 0.1 %); "
        "the same on the *interacting* queries (the naive motion, each robot along its own shortest path at "
        "proportional speed, collides); compute time method ÷ ours (ratio of the medians on those queries).",
        "",
        "| method | n | median | p95 | ratio of medians | ours faster | interacting n | median | p95 | "
        "ratio of medians | compute method ÷ ours |",
        "|---|---|---|---|---|---|---|---|---|---|---|",
    ]
    by_m = _by(recs, "method")
    ours = {r["query"]: r for r in by_m.get(("ours",), [])}
    for m in ORDER:
        if m == "ours" or (m,) not in by_m:
            continue
        pairs = [
            (ours[r["query"]], r)
            for r in by_m[(m,)]
            if r["query"] in ours and ours[r["query"]]["verified"] and r["verified"]
        ]
        if not pairs:
            out.append(f"| {METHOD_LABELS[m]} | 0 | — | — | — | — | — | — | — | — | — |")
            continue
        a = np.array([p[0]["makespan"] for p in pairs])
        b = np.array([p[1]["makespan"] for p in pairs])
        inter = np.array([bool(p[0].get("interacting")) for p in pairs])
        ca = np.array([p[0]["compute_time"] for p in pairs])
        cb = np.array([p[1]["compute_time"] for p in pairs])
        rr = a / b
        ri = rr[inter]
        cells = ["—"] * 3
        if len(ri):
            cells = [
                f"{np.median(ri):.3f}",
                f"{np.percentile(ri, 95):.3f}",
                f"{np.median(a[inter]) / np.median(b[inter]):.3f}",
            ]
        out.append(
            f"| {METHOD_LABELS[m]} | {len(pairs)} | {np.median(rr):.3f} | {np.percentile(rr, 95):.3f} | "
            f"{np.median(a) / np.median(b):.3f} | {_pct(float(np.mean(rr < 1 - 1e-3)))} | {int(inter.sum())} | "
            f"{' | '.join(cells)} | {np.median(cb) / np.median(ca):.2f}× |"
        )
    return [*out, ""]


def _stage_table(recs: Sequence[Record]) -> list[str]:
    """Where our compute time goes (the generator's own stage timings), on the fast and the hard path."""
    ours = [r for r in recs if r["method"] == "ours" and r["success"]]
    if not ours:
        return []

    stages = ("plan", "smooth", "blend", "jerk", "sample", "verify", "total")
    n_fast = sum(_path_kind(r) == "fast" for r in ours)
    out = [
        "Where our time goes (stage timings of `TrajectoryGenerator`, ms; smooth = the corridor QPs, blend = the "
        "B-spline, jerk = one ruckig profile on the fast path or the filtered timing on the hard path, verify = "
        f"the gate); fast path {n_fast} of {len(ours)} queries:",
        "",
        "| " + " | ".join(("", *stages)) + " |",
        "|---" * (len(stages) + 1) + "|",
    ]
    for kind in ("fast", "hard"):
        sel = [r for r in ours if _path_kind(r) == kind]
        if not sel:
            continue
        for name, q in (("median", 50), ("p95", 95)):
            vals = [_q(np.array([1e3 * r["stats"].get("timings", {}).get(s, 0.0) for r in sel]), q) for s in stages]
            out.append("| " + " | ".join((f"{kind} path {name}", *(f"{v:.2f}" for v in vals))) + " |")
    return [*out, ""]


def _domain_table(recs: Sequence[Record]) -> list[str]:
    out = [
        "Per domain of our plan: makespan ours ÷ grid (the price of keeping the plan's homotopy class; the "
        "grid is resolution-complete for its time-like L∞ cost, not for the jerk-limited makespan, so ratios "
        "below 1 occur).",
        "",
        "| domain | n | median | p95 | max | ours within 1 % of the grid or better |",
        "|---|---|---|---|---|---|",
    ]
    for (dom,), drecs in sorted(_by(recs, "domain").items(), key=lambda kv: (kv[0][0] is None, kv[0][0] or 0)):
        r = _ratios(drecs, "ours", "grid")
        if len(r) == 0:
            continue
        out.append(
            f"| {dom} | {len(r)} | {np.median(r):.3f} | {np.percentile(r, 95):.3f} | {np.max(r):.3f} | "
            f"{_pct(float(np.mean(r <= 1.01)))} |"
        )
    r = _ratios(recs, "ours", "grid")
    if len(r):
        out.append(
            f"| all | {len(r)} | {np.median(r):.3f} | {np.percentile(r, 95):.3f} | {np.max(r):.3f} | "
            f"{_pct(float(np.mean(r <= 1.01)))} |"
        )
    return [*out, ""]


def _order_table(recs: Sequence[Record]) -> list[str]:
    out = [
        "Success by whether the query changes the robots' order in track coordinates (a planner in a vector "
        "space of track coordinates cannot: the robots would have to meet).",
        "",
        "| method | same order: success | n | order change: success | n |",
        "|---|---|---|---|---|",
    ]
    by_m = _by(recs, "method")
    for m in ORDER:
        if (m,) not in by_m:
            continue
        same = [r["verified"] for r in by_m[(m,)] if not r["order_change"]]
        chg = [r["verified"] for r in by_m[(m,)] if r["order_change"]]
        out.append(
            f"| {METHOD_LABELS[m]} | {_pct(float(np.mean(same)) if same else math.nan)} | {len(same)} | "
            f"{_pct(float(np.mean(chg)) if chg else math.nan)} | {len(chg)} |"
        )
    return [*out, ""]


# ---------------------------------------------------------------------------------------------------
def _plt() -> Any:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    return plt


def plot_results(records: Sequence[Record], out: Path, dpi: int = 90) -> list[Path]:
    """``makespan.png`` (makespan ÷ lower bound), ``compute_time.png`` (ECDF) and ``discontinuity.png``."""
    plt = _plt()
    from matplotlib.ticker import LogLocator, NullFormatter, ScalarFormatter

    tracks = sorted({r["track"] for r in records})
    files = []
    fig, axes = plt.subplots(1, len(tracks), figsize=(5.5 * len(tracks), 4.2), squeeze=False)
    for ax, tr in zip(axes[0], tracks):
        by_m = _by([r for r in records if r["track"] == tr], "method")
        ms = [m for m in ORDER if (m,) in by_m]
        data = [_vals(by_m[(m,)], "makespan_ratio", only_verified=True) for m in ms]
        ax.boxplot(
            [d if len(d) else [np.nan] for d in data], whis=(5, 95), showfliers=True, flierprops={"markersize": 2}
        )
        ax.set_xticks(
            range(1, len(ms) + 1), [f"{m} ({len(d)})" for m, d in zip(ms, data)], rotation=30, ha="right", fontsize=8
        )
        ax.set_yscale("log")
        ax.yaxis.set_major_locator(LogLocator(base=10, subs=(1.0, 1.5, 2.0, 3.0, 5.0)))
        ax.yaxis.set_major_formatter(ScalarFormatter())
        ax.yaxis.set_minor_formatter(NullFormatter())
        ax.set_ylabel("makespan ÷ lower bound")
        ax.set_title(f"{tr}: makespan of the verified results (count); whiskers 5–95 %", fontsize=9)
        ax.grid(alpha=0.3, which="both")
    fig.tight_layout()
    files.append(out / "makespan.png")
    fig.savefig(files[-1], dpi=dpi)
    plt.close(fig)

    fig, axes = plt.subplots(1, len(tracks), figsize=(5.5 * len(tracks), 4.2), squeeze=False)
    for ax, tr in zip(axes[0], tracks):
        by_m = _by([r for r in records if r["track"] == tr], "method")
        for m in ORDER:
            if (m,) not in by_m:
                continue
            x = np.sort(1e3 * _vals(by_m[(m,)], "compute_time"))
            ax.step(x, np.arange(1, len(x) + 1) / len(x), where="post", label=m)
        ax.set_xscale("log")
        ax.set_xlabel("compute time per query (ms, inside the worker)")
        ax.set_ylabel("share of queries")
        ax.set_title(f"{tr}: compute time (all attempts)", fontsize=9)
        ax.grid(alpha=0.3, which="both")
        ax.legend(fontsize=7)
    fig.tight_layout()
    files.append(out / "compute_time.png")
    fig.savefig(files[-1], dpi=dpi)
    plt.close(fig)

    summ = summarize(records)
    fig, axes = plt.subplots(1, len(tracks), figsize=(5.5 * len(tracks), 3.8), squeeze=False)
    for ax, tr in zip(axes[0], tracks):
        ms = [m for m in ORDER if m in summ[tr]]
        x = np.arange(len(ms), dtype=float)
        same = np.array([100 * summ[tr][m]["disc_rate"] for m in ms])
        res = np.array([100 * summ[tr][m]["disc_reseeded_rate"] for m in ms])
        ax.bar(x - 0.2, np.nan_to_num(same), 0.4, color="C0", label="twin, same seed")
        ax.bar(
            x + 0.2,
            np.nan_to_num(res),
            0.4,
            color="C1",
            hatch="//",
            edgecolor="k",
            linewidth=0.5,
            label="OMPL twin, another seed",
        )
        for xi, v in zip(x, same):
            ax.annotate(f"{v:.0f}", (xi - 0.2, v), ha="center", va="bottom", fontsize=7)
        for xi, v in zip(x, res):
            if np.isfinite(v):
                ax.annotate(f"{v:.0f}", (xi + 0.2, v), ha="center", va="bottom", fontsize=7)
        ax.set_xticks(x, ms, rotation=30, ha="right", fontsize=8)
        ax.set_ylabel("discontinuity rate (%)")
        ax.set_ylim(0, max(10.0, float(np.nanmax(np.concatenate([same, res, [0.0]]))) * 1.15))
        ax.set_title(f"{tr}: twins (start, goal moved by δ) farther apart than the threshold", fontsize=9)
        ax.legend(fontsize=7)
        ax.grid(alpha=0.3, axis="y")
    fig.tight_layout()
    files.append(out / "discontinuity.png")
    fig.savefig(files[-1], dpi=dpi)
    plt.close(fig)
    return files


# ---------------------------------------------------------------------------------------------------
def _common_verified(recs: Sequence[Record]) -> set[Any]:
    """Queries verified by every method present."""
    by_q = _by(recs, "query")
    methods = {r["method"] for r in recs}
    return {q for (q,), rs in by_q.items() if {r["method"] for r in rs if r["verified"]} == methods}


def scaling_markdown(records: Sequence[Record], meta: dict[str, Any]) -> str:
    """Compute time and makespan against the track scale, the grid resolution, and ours by path (fast / hard)."""
    lines = ["# Scaling: compute time and makespan against track size and solver grid size", ""]
    if meta.get("command"):
        lines += ["Command:", "", "```", meta["command"], "```", ""]
    lines += [
        "## Track scale (lollipop ℓ = c = scale; grid spacing scaled with the track)",
        "",
        "Compute times over all attempts and over verified results only (a failed OMPL query costs its "
        "whole budget); makespans over the queries every method verified (`common`).",
        "",
        "| scale | method | n | verified | compute median ms (all) | verified: median ms | p95 ms | "
        "makespan median s (common) | / ours median |",
        "|---|---|---|---|---|---|---|---|---|",
    ]
    sweep = [r for r in records if r.get("sweep") == "scale"]
    for (scale,), srecs in sorted(_by(sweep, "scale").items()):
        common = _common_verified(srecs)
        for m in ORDER:
            mr = [r for r in srecs if r["method"] == m]
            if not mr:
                continue
            ct = _vals(mr, "compute_time")
            cv = _vals([r for r in mr if r["verified"]], "compute_time")
            mk = _vals([r for r in mr if r["query"] in common], "makespan", only_verified=True)
            rat = _ratios(srecs, m, "ours")
            lines.append(
                f"| {scale:g} | {m} | {len(mr)} | {_pct(float(np.mean([r['verified'] for r in mr])))} | "
                f"{1e3 * _q(ct, 50):.1f} | {_f(1e3 * _q(cv, 50), '{:.1f}')} | "
                f"{_f(1e3 * _q(cv, 95), '{:.1f}')} | {_f(_q(mk, 50))} ({len(common)}) | "
                f"{_f(_q(rat, 50), '{:.3f}')} |"
            )
    lines += [
        "",
        "## Grid resolution (base track)",
        "",
        "| spacing m | product nodes | edges | n | compute median ms | p95 ms | makespan median s | "
        "ours ÷ grid median |",
        "|---|---|---|---|---|---|---|---|",
    ]
    gsw = [r for r in records if r.get("sweep") == "grid"]
    for (h,), grecs in sorted(_by(gsw, "grid_h").items(), reverse=True):
        g = [r for r in grecs if r["method"] == "grid"]
        if not g:
            continue
        ct, mk = _vals(g, "compute_time"), _vals(g, "makespan", only_verified=True)
        st = g[0]["stats"].get("grid", {})
        rat = _ratios(grecs, "ours", "grid")
        lines.append(
            f"| {h:g} | {st.get('nodes', '—')} | {st.get('edges', '—')} | {len(g)} | {1e3 * _q(ct, 50):.1f} | "
            f"{1e3 * _q(ct, 95):.1f} | {_f(_q(mk, 50))} | {_f(_q(rat, 50), '{:.3f}')} |"
        )
    lines += [
        "",
        "## Ours by path (fast: one ruckig profile on the straight line; hard: corridor QP; track-scale sweep)",
        "",
        "| scale | path | n | compute median ms | p95 ms |",
        "|---|---|---|---|---|",
    ]
    ours = [r for r in sweep if r["method"] == "ours" and r["success"]]
    for (scale, kind), orecs in sorted(_by([{**r, "path": _path_kind(r)} for r in ours], "scale", "path").items()):
        ct = _vals(orecs, "compute_time")
        lines.append(f"| {scale:g} | {kind} | {len(orecs)} | {1e3 * _q(ct, 50):.1f} | {1e3 * _q(ct, 95):.1f} |")
    return "\n".join(lines) + "\n"


def _path_kind(r: Record) -> str:
    """Which path ours took on a record: "fast" or "hard" (older records: inferred from the stage timings)."""
    st = r["stats"]
    return str(st.get("path") or ("hard" if "smooth" in st.get("timings", {}) else "fast"))


def plot_scaling(records: Sequence[Record], path: Path, dpi: int = 90) -> Path:
    """Four panels: compute time (verified results) and makespan (queries every method verified) against the
    track scale, grid compute time against the number of product nodes, our compute time against the track scale
    by path (fast or hard)."""
    plt = _plt()
    from matplotlib.ticker import LogLocator, NullFormatter, ScalarFormatter

    fig, axes = plt.subplots(2, 2, figsize=(10, 7))
    sweep = [r for r in records if r.get("sweep") == "scale"]
    scales = sorted({r["scale"] for r in sweep})
    commons = {s: _common_verified([r for r in sweep if r["scale"] == s]) for s in scales}
    for m in ORDER:
        ct, mk = [], []
        for s in scales:
            mr = [r for r in sweep if r["scale"] == s and r["method"] == m]
            cv = _vals([r for r in mr if r["verified"]], "compute_time")
            ct.append(1e3 * _q(cv, 50) if len(cv) else np.nan)
            mv = _vals([r for r in mr if r["query"] in commons[s]], "makespan", only_verified=True)
            mk.append(_q(mv, 50) if len(mv) else np.nan)
        if np.all(np.isnan(ct)):
            continue
        axes[0, 0].plot(scales, ct, "o-", label=m)
        axes[0, 1].plot(scales, mk, "o-", label=m)
    labels = ("compute time median, verified (ms)", "makespan median, queries all verified (s)")
    for ax, lab in zip(axes[0], labels):
        ax.set_xscale("log", base=2)
        ax.set_yscale("log")
        ax.set_xticks(scales, [f"{s:g}" for s in scales])
        ax.set_xlabel("track scale (lollipop ℓ = c, m)")
        ax.set_ylabel(lab)
        ax.grid(alpha=0.3, which="both")
        ax.legend(fontsize=7)
    gsw = [r for r in records if r.get("sweep") == "grid" and r["method"] == "grid"]
    hs = sorted({r["grid_h"] for r in gsw}, reverse=True)
    if hs:
        nodes = [next(r["stats"].get("grid", {}).get("nodes", np.nan) for r in gsw if r["grid_h"] == h) for h in hs]
        gct = [1e3 * _q(_vals([r for r in gsw if r["grid_h"] == h], "compute_time"), 50) for h in hs]
        axes[1, 0].plot(nodes, gct, "o-", color="C5")
        for h, x, y in zip(hs, nodes, gct):
            axes[1, 0].annotate(f"h = {h:g} m", (x, y), fontsize=7, xytext=(4, -10), textcoords="offset points")
        axes[1, 0].set_xscale("log")
        axes[1, 0].set_yscale("log")
    axes[1, 0].set_xlabel("grid A*: product nodes")
    axes[1, 0].set_ylabel("grid compute median (ms)")
    axes[1, 0].grid(alpha=0.3, which="both")
    ours = [r for r in sweep if r["method"] == "ours" and r["success"]]
    jit = 1 + 0.04 * np.random.default_rng(0).standard_normal(len(ours))
    for kind, color in (("fast", "C0"), ("hard", "C3")):
        sel = [k for k, r in enumerate(ours) if _path_kind(r) == kind]
        xs = np.array([float(ours[k]["scale"]) for k in sel]) * jit[sel]
        axes[1, 1].scatter(xs, [1e3 * ours[k]["compute_time"] for k in sel], s=6, alpha=0.5, color=color, label=kind)
    axes[1, 1].set_xscale("log", base=2)
    axes[1, 1].set_yscale("log")
    axes[1, 1].legend(fontsize=7)
    axes[1, 1].set_xlabel("ours: track scale (jittered), by path")
    axes[1, 1].set_ylabel("ours compute time (ms)")
    axes[1, 1].grid(alpha=0.3, which="both")
    for ax in axes.flat:
        axes_log = [a for a in (ax.yaxis, *([ax.xaxis] if ax is axes[1, 0] else [])) if a.get_scale() == "log"]
        for axis in axes_log:
            axis.set_major_locator(LogLocator(base=10, subs=(1.0, 2.0, 5.0)))
            axis.set_major_formatter(ScalarFormatter())
            axis.set_minor_formatter(NullFormatter())
    fig.tight_layout()
    fig.savefig(path, dpi=dpi)
    plt.close(fig)
    return path
