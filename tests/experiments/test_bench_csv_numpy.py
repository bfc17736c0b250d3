"""The CSV twins' benchmark: it times what it says on a small layout, finds every twin equal to its kernel, and
leaves the kernels in place."""

from __future__ import annotations

import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
sys.path.insert(0, str(ROOT / "experiments"))

import bench_csv_numpy  # noqa: E402

import trajopt.io.csv_kernels as ck  # noqa: E402


def test_the_benchmark_times_equal_twins_and_restores_the_kernels() -> None:
    kernels = ck._g12, ck._join
    records = bench_csv_numpy.run(str(ROOT / "examples" / "tracks" / "y_junction.json"), [50, 10**6], 2)
    assert ck._g12 is kernels[0] and ck._join is kernels[1]
    assert [r["what"].split()[0] for r in records] == ["g12", "join", "g12", "join", "whole"]
    assert [r["rows"] for r in records[:2]] == [50, 50]
    assert records[2]["rows"] == records[3]["rows"] == records[4]["rows"] > 50
    for r in records:
        assert r["equal"] is True, r
        assert 0.0 < r["kernel"]["median_us"] <= r["kernel"]["p90_us"], r
        assert 0.0 < r["twin"]["median_us"] <= r["twin"]["p90_us"], r
