"""The measurements behind docs/paper.md's departures from the paper, at a small size (seeded)."""

from __future__ import annotations

import sys
from pathlib import Path

from mpa import Lollipop
from tests.helpers.scripts import run_script

ROOT = Path(__file__).resolve().parents[2]
sys.path.insert(0, str(ROOT / "experiments"))


def test_short_stick_plans_keep_the_ell_floor_and_traces_are_monotone() -> None:
    from paper_checks import short_stick_floor

    r = short_stick_floor(Lollipop(0.3, 1.0), 300, seed=1)
    assert r["non_monotone_traces"] == 0
    assert r["below_ell"] == 0
    assert r["below_h"] > 0  # the ℓ ≥ h bound min(d_s, d_g, h) does not hold for a short stick


def test_neighbourhood_trade_off_grows_domain_1_with_epsilon() -> None:
    from paper_checks import neighbourhood_trade_off

    rows = neighbourhood_trade_off(Lollipop(1.0, 1.0), 300, (0.05, 0.4), seed=1)
    for r in rows:
        assert abs(r["domain1"] + r["domain2"] + r["domain3"] - 1.0) < 1e-12
    assert rows[1]["domain1"] > rows[0]["domain1"]
    assert rows[1]["mean_length"] >= rows[0]["mean_length"]


def test_script_runs_headless() -> None:
    res = run_script("experiments/paper_checks.py", "--queries", "20", timeout=120)
    assert res.returncode == 0, res.stderr
    assert "| 0.3 / 1 | 20 |" in res.stdout
