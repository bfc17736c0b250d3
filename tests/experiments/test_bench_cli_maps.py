"""The command line's benchmark on the converted building maps: its queries and one timed run."""

from __future__ import annotations

import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]
sys.path.insert(0, str(ROOT / "experiments"))

from bench_cli_maps import AIRPORT, AIRPORT_QUERY, MAPS, _queries, _run  # noqa: E402

from mpa.graph_track import GraphTrack  # noqa: E402


@pytest.mark.parametrize("i", range(len(MAPS)))
def test_queries_are_valid_positions_at_least_the_clearance_apart(i: int) -> None:
    name, path, options, clearance = MAPS[i]
    qs = _queries(name, path, options, clearance, 2)
    assert len(qs) == 2, qs  # on the airport the query first
    if path == AIRPORT:
        assert qs[0] == AIRPORT_QUERY
    level = options[options.index("--level") + 1]
    nav = int(options[options.index("--nav-graph") + 1]) if "--nav-graph" in options else None
    track = GraphTrack.from_file(path, level=level, nav_graph=nav)
    for start, goal in qs:
        for pair in (start, goal):
            a, b = (track.parse_position(p) for p in pair)
            assert track.geometry.distance_scalar(*a, *b) >= clearance, (name, pair)
        assert tuple(start) != tuple(reversed(goal)), (name, start, goal)  # not a swap


@pytest.mark.slow
def test_one_run_of_the_command_line_is_timed(tmp_path: Path) -> None:
    name, path, options, clearance = MAPS[1]
    query = _queries(name, path, options, clearance, 1)[0]
    wall, cpu = _run(ROOT, path, options, clearance, query, str(tmp_path))
    assert 0.0 < cpu and 0.0 < wall, (wall, cpu)
    assert len(list(tmp_path.glob("*.json"))) == 1  # the map's layout cached for the recorded runs
