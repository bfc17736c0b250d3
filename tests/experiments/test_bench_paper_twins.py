"""The paper twins' benchmark: it times every twin and its kernel, finds them equal, and a fresh process with the
twins patched in makes its lollipop trajectory without importing numba."""

from __future__ import annotations

import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
sys.path.insert(0, str(ROOT / "experiments"))

import bench_paper_twins  # noqa: E402


def test_the_benchmark_times_equal_twins() -> None:
    records = bench_paper_twins.run([1, 300], 2)
    assert [(r["rows"], r["kernel"]) for r in records] == [(n, k) for n in (1, 300) for k in bench_paper_twins.NAMES]
    for r in records:
        assert r["equal"] is True, r
        for side in ("kernel_time", "twin_time"):
            assert 0.0 < r[side]["median_us"] <= r[side]["p90_us"], r


def test_a_fresh_twins_process_does_not_import_numba() -> None:
    procs = bench_paper_twins.fresh(1)
    assert procs["twins"]["numba_imported"] is False and procs["numba"]["numba_imported"] is True, procs
    assert procs["twins"]["verified"] and procs["numba"]["verified"], procs
    assert all(p["total_s"] > 0.0 for p in procs.values()), procs
