"""The per-node benchmark of the graph search: an earlier revision's search loaded beside this one plans the same,
and the planner is left as it was."""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]
sys.path.insert(0, str(ROOT / "experiments"))

import bench_search_nodes  # noqa: E402

from mpa.planners.graph import query as graph_query  # noqa: E402


def _has_git_head() -> bool:
    try:
        subprocess.run(["git", "show", "HEAD:mpa/planners/graph/search.py"], cwd=ROOT, check=True, capture_output=True)
    except (OSError, subprocess.CalledProcessError):
        return False
    return True


@pytest.mark.skipif(not _has_git_head(), reason="needs the git history of the repository")
def test_the_revision_loaded_beside_this_tree_plans_the_same_and_the_planner_is_restored() -> None:
    as_is = (graph_query.AnyAngleSearch, graph_query._mesh)
    records = bench_search_nodes.run("HEAD", 4, 0, {"y_junction", "passing_loop"}, check=True, repeat=2)
    assert sorted(r["layout"] for r in records) == ["passing_loop", "y_junction"]
    for r in records:
        assert r["queries"] == 4 and r["identical"] == 4, r
        assert r["before"]["cpu_max_ms"] > 0.0 and r["after"]["cpu_max_ms"] > 0.0, r
    assert (graph_query.AnyAngleSearch, graph_query._mesh) == as_is


def test_a_plan_hash_sees_the_last_bit_and_the_node_count() -> None:
    import mpa

    plan = mpa.plan(
        str(ROOT / "examples" / "tracks" / "y_junction.json"),
        ("left", "right"),
        ("right", "left"),
        0.5,
        planner="graph",
    )
    h = bench_search_nodes.plan_hash(plan, [10])
    assert h == bench_search_nodes.plan_hash(plan, [10])
    assert h != bench_search_nodes.plan_hash(plan, [11])
    plan.waypoints[1, 0] = float(plan.waypoints[1, 0]) * (1.0 + 2.0**-52)
    assert h != bench_search_nodes.plan_hash(plan, [10])
    assert bench_search_nodes.plan_hash(None, [10]) != h
