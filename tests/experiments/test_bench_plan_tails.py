"""The plan-time tails benchmark: both arms of ``--steps`` plan the same makespans, and the planner is left as it
was."""

from __future__ import annotations

import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]
sys.path.insert(0, str(ROOT / "experiments"))

import bench_plan_tails  # noqa: E402

from mpa.planners.graph import bounds as graph_bounds  # noqa: E402
from mpa.planners.graph import query as graph_query  # noqa: E402
from mpa.planners.graph import search as graph_search  # noqa: E402
from mpa.planners.graph.bounds import PassingBound  # noqa: E402


def _settings() -> tuple[object, ...]:
    return (
        graph_query.PASSING_BOUND_AFTER,
        graph_query.RESUME_WITHOUT_GAIN,
        graph_search.AGAIN_GRID_STEPS,
        graph_bounds.POINTS_FROM_FRONTS,
        PassingBound.least_through,
    )


def test_the_steps_comparison_plans_the_same_makespans_and_restores_the_planner() -> None:
    as_is = _settings()
    records = bench_plan_tails.run(3, 0, {"y_junction", "passing_loop"}, "steps")
    assert sorted(r["layout"] for r in records) == ["passing_loop", "y_junction"]
    for r in records:
        assert r["queries"] == 3 and r["makespan_differences"] == 0, r
        assert r["before"]["cpu_max_ms"] > 0.0 and r["cpu_max_ms"] > 0.0, r
    assert _settings() == as_is


def test_the_earlier_arm_is_the_earlier_scheme() -> None:
    as_is = _settings()
    bench_plan_tails._arm("steps", True)
    try:
        assert graph_query.PASSING_BOUND_AFTER == bench_plan_tails.EARLIER_AFTER
        assert graph_query.RESUME_WITHOUT_GAIN is False and graph_search.AGAIN_GRID_STEPS == 0.0
        assert graph_bounds.POINTS_FROM_FRONTS is False
        assert PassingBound.least_through is PassingBound.least_through_all
    finally:
        bench_plan_tails._arm(None, False)
    assert _settings() == as_is


_CORNER_FLAGS = ("DROP_IMPLIED_ROWS", "ACTIVE_SET_SEED")


@pytest.mark.parametrize(("arm", "flag"), [("seventh", "DROP_IMPLIED_ROWS"), ("eighth", "ACTIVE_SET_SEED")])
def test_the_corner_arms_solve_with_every_row_and_plan_the_same_makespans(arm: str, flag: str) -> None:
    """``--seventh``'s before keeps the rows that others imply, ``--eighth``'s solves every row at once; each turns
    off its own flag only, both plan the same makespans, and the planner is left as it was."""
    from mpa.planners import corners

    bench_plan_tails._arm(arm, True)
    try:
        assert getattr(corners, flag) is False
        assert all(getattr(corners, other) is True for other in _CORNER_FLAGS if other != flag)
    finally:
        bench_plan_tails._arm(None, False)
    assert all(getattr(corners, f) is True for f in _CORNER_FLAGS)
    records = bench_plan_tails.run(4, 0, {"two_sidings", "hotel L2"}, arm)
    assert sorted(r["layout"] for r in records) == ["hotel L2", "two_sidings"]
    for r in records:
        assert r["queries"] == 4 and r["makespan_differences"] == 0, r
    assert all(getattr(corners, f) is True for f in _CORNER_FLAGS)


def test_the_ninth_arm_builds_the_programme_in_the_interpreter_then_compiled(monkeypatch: pytest.MonkeyPatch) -> None:
    """``--ninth``: before, the compiled search with mpa's own programme builder; after, both compiled; the same
    makespans; the planner left with mpa's own search and builder (the tests' default)."""
    from mpa.planners import corners
    from trajopt.plan_kernel import CompiledSearch
    from trajopt.plan_kernel.corners import build_programme

    monkeypatch.setitem(bench_plan_tails.SEARCH, "python", False)
    try:
        bench_plan_tails._arm("ninth", True)
        assert graph_query.compiled_search() is CompiledSearch and corners.compiled_programme() is None
        bench_plan_tails._arm("ninth", False)
        assert graph_query.compiled_search() is CompiledSearch and corners.compiled_programme() is build_programme
        records = bench_plan_tails.run(4, 0, {"two_sidings", "hotel L2"}, "ninth")
        for r in records:
            assert r["queries"] == 4 and r["makespan_differences"] == 0, r
    finally:
        monkeypatch.setitem(bench_plan_tails.SEARCH, "python", True)
        bench_plan_tails._arm(None, False)
    assert graph_query.compiled_search() is None and corners.compiled_programme() is None


def test_the_eleventh_arm_makes_new_node_arrays_and_the_whole_least(monkeypatch: pytest.MonkeyPatch) -> None:
    """``--eleventh``: before, no node arrays kept between searches and the passing bound's whole least at the start;
    after, the code as it is, with the spare arrays it had set aside before; the same makespans; the planner left
    as it was."""
    from trajopt.plan_kernel import search as kernel_search

    limit = kernel_search.SPARE_BYTES
    monkeypatch.setitem(bench_plan_tails.SEARCH, "python", False)
    kernel_search._spare.clear()
    marker = kernel_search._node_arrays()  # 1 024 rows each
    kernel_search._spare[:] = [marker]
    try:
        bench_plan_tails._arm("eleventh", True)
        assert kernel_search.SPARE_BYTES == 0 and not kernel_search._spare
        assert graph_query.passing_bound is bench_plan_tails._whole_passing_bound
        bench_plan_tails._arm("eleventh", False)
        assert kernel_search.SPARE_BYTES == limit and len(kernel_search._spare) == 1
        assert kernel_search._spare[0] is marker
        assert graph_query.passing_bound is graph_bounds.passing_bound
        records = bench_plan_tails.run(4, 0, {"two_sidings", "hotel L2"}, "eleventh")
        for r in records:
            assert r["queries"] == 4 and r["makespan_differences"] == 0, r
    finally:
        monkeypatch.setitem(bench_plan_tails.SEARCH, "python", True)
        bench_plan_tails._arm(None, False)
        kernel_search._spare.clear()
    assert kernel_search.SPARE_BYTES == limit and graph_query.passing_bound is graph_bounds.passing_bound
