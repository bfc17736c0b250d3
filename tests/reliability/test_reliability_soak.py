"""CI soak: 300 seeded random queries of ``experiments/soak.py`` (API and command line), every output checked
by the gate and the independent checker; no crash, no rejected output, no unexpected fallback."""

from __future__ import annotations

import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]
sys.path.insert(0, str(ROOT / "experiments"))

from soak import EXPECTED_FALLBACK_MARGIN, draw_query, expected_fallback, run_query, summarize  # noqa: E402

import mpa.errors as mpa_errors  # noqa: E402

#: Queries of the CI run (the full soak is documented in docs/reliability.md).
N = 300


@pytest.fixture(scope="module")
def records() -> list[dict]:  # type: ignore[type-arg]
    return [run_query(1, i, subproc=(i == 7)) for i in range(N)]


def test_soak_no_crash_no_rejected(records) -> None:  # type: ignore[no-untyped-def]
    s = summarize(records)
    bad = [r for r in records if r["outcome"] in ("crash", "rejected", "invalid")]
    assert not bad, bad
    assert s["queries"] == N
    assert s["counts"]["ok"] > N // 2
    assert {r["mode"] for r in records} == {"api", "cli", "subprocess"}


def test_soak_no_unexpected_fallback(records) -> None:  # type: ignore[no-untyped-def]
    unexpected = [r for r in records if r["outcome"] == "fallback" and not expected_fallback(r)]
    assert not unexpected, unexpected


def test_expected_fallback_rule() -> None:
    """Expected only where the rate's margin reaches 1 cm or the plan itself is within the margin of D."""
    from soak import _limits, _track

    from mpa import make_planner
    from trajopt.generator import separation_margin

    seen = set()
    for i in range(60):
        q = draw_query(1, i)
        if q["kind"] == "interval":
            continue
        for reason in ("IPOPT failed: test", "at 1 Hz: IPOPT failed: test"):
            rec = {"index": i, "rate": q["rate"], "outcome": "fallback", "reason": reason, "query": q}
            rate = 1.0 if reason.startswith("at 1 Hz") else q["rate"]
            margin = separation_margin(_limits(q), rate)
            try:
                dmin = make_planner(_track(q), q["clearance"]).plan(q["start"], q["goal"]).min_distance()
            except mpa_errors.NoMotionError:
                continue
            want = margin >= EXPECTED_FALLBACK_MARGIN or dmin < q["clearance"] + margin
            assert expected_fallback(rec, seed=1) == want
            seen.add(want)
    assert seen == {True, False}


def test_soak_script_on_a_dask_cluster(tmp_path) -> None:  # type: ignore[no-untyped-def]
    """`--dask ADDRESS` runs the queries on a cluster (here a local one) and reports the same summary."""
    import json
    import os
    import subprocess

    distributed = pytest.importorskip("dask.distributed")
    out = tmp_path / "soak.json"
    with distributed.LocalCluster(n_workers=1, threads_per_worker=1, processes=True, dashboard_address=":0") as c:
        env = {**os.environ, "PYTHONPATH": str(ROOT)}
        args = ["--queries", "12", "--chunk", "5", "--subprocess", "0", "--dask", c.scheduler_address]
        cp = subprocess.run(
            [sys.executable, str(ROOT / "experiments" / "soak.py"), *args, "--no-progress", "--out", str(out)],
            capture_output=True,
            text=True,
            env=env,
            timeout=600,
        )
    assert cp.returncode == 0, cp.stderr[-2000:]
    s = json.loads(out.read_text())
    assert s["queries"] == 12 and s["where"].startswith("dask ")
    assert s["counts"]["crash"] == s["counts"]["rejected"] == 0
