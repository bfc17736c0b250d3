"""CI soak on graph layouts: 150 seeded random queries of ``experiments/soak_graphs.py``, every output checked twice."""

from __future__ import annotations

import sys
from collections import Counter
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[2]
sys.path.insert(0, str(ROOT / "experiments"))

from soak_graphs import BUGS, draw_query, layouts, main, run_query  # noqa: E402


def test_graph_soak_has_no_bug() -> None:
    tracks = layouts()
    rng = np.random.default_rng(11)
    seen: Counter[str] = Counter()
    bugs = []
    for _ in range(150):
        q = draw_query(rng, tracks)
        outcome, why = run_query(q, tracks)
        seen[outcome] += 1
        if outcome in BUGS:
            bugs.append((q, why))
    assert not bugs, bugs
    assert seen["ok"] > 50 and seen["fallback"] == 0, seen


def test_graph_soak_script_runs(capsys) -> None:  # type: ignore[no-untyped-def]
    assert main(["--queries", "5", "--seed", "2"]) == 0
    out = capsys.readouterr().out
    assert out.splitlines()[2].startswith("| 5 |"), out
