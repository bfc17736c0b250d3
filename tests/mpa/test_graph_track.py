"""GraphTrack: layouts, positions, bad input, paper tracks as graphs, and the example layouts."""

from __future__ import annotations

import json
import math
import time
import zlib
from pathlib import Path

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from mpa import Circle, GraphTrack, Interval, InvalidInputError, Lollipop, NoMotionError, free_space, plan_graph
from mpa.graph_track import as_graph_track

EXAMPLES = Path(__file__).resolve().parents[2] / "examples" / "tracks"
LOL = {"edges": [["F", "P", 1.0], ["P", "P", 2.0]]}


def test_layout_forms_names_and_default_lengths() -> None:
    t = GraphTrack.from_layout(
        {
            "vertices": {"a": [0, 0], "b": [3, 4], "c": None},
            "edges": [["a", "b"], ["b", "c"], {"name": "x", "from": "c", "to": "c", "length": 2.5}, ["a", "b", 7]],
        }
    )
    assert t.edge_names == ("e0", "e1", "x", "e3")
    np.testing.assert_allclose(t.lengths, [5.0, 1.0, 2.5, 7.0])
    assert not t.has_coordinates
    assert GraphTrack.from_layout(t.to_dict()) == t


def test_positions_parse_and_canonical_names() -> None:
    t = GraphTrack.from_layout(LOL)
    assert t.parse_position("e1:0.4") == (1, 0.4)
    assert t.parse_position("P") == (0, 1.0)  # lowest-indexed edge at P is e0, P is its head
    assert t.parse_position("F") == (0, 0.0)
    assert t.position(("e1", 2)) == (1, 2.0)
    assert t.position_name(1, 0.0) == "P" and t.position_name(1, 2.0) == "P" and t.position_name(0, 0.25) == "e0:0.25"


BAD_LAYOUTS = [
    ([], "layout is a list"),
    ({}, 'no key "edges"'),
    ({"edges": []}, "empty"),
    ({"edges": "ab"}, '"edges" is a str'),
    ({"edges": [["a"]]}, "edge 0 is"),
    ({"edges": [["a", "b", -1]]}, r"length of edge 'e0' is -1, expected a finite number > 0"),
    ({"edges": [["a", "b", 0]]}, r"length of edge 'e0' is 0"),
    ({"edges": [["a", "b", float("inf")]]}, "length of edge 'e0' is inf"),
    ({"edges": [["a", "b", "long"]]}, "length of edge 'e0' is 'long'"),
    ({"edges": [{"name": "x", "from": "a", "to": "b"}, {"name": "x", "from": "a", "to": "b"}]}, "'x' is used twice"),
    ({"edges": [{"from": "a"}]}, 'no "to"'),
    ({"edges": [{"from": "a", "to": "b", "colour": 1}]}, "unknown keys"),
    ({"vertices": {"a": [0, 0]}, "edges": [["a", "b"]]}, "vertex 'b' of edge 'e0' is unknown"),
    ({"vertices": {"a": [0, "x"]}, "edges": [["a", "a", 1]]}, "coordinates of vertex 'a'"),
    ({"vertices": {"a": [0, 0]}, "edges": [["a", "a"]]}, "straight distance"),
    ({"edges": [[1.5, "b"]]}, "expected a vertex name"),
    ({"edges": [["a", "b"]], "extra": 1}, "unknown keys"),
    ({"edges": [{"name": "x:1", "from": "a", "to": "b"}]}, "contains ':'"),
]


@pytest.mark.parametrize(("layout", "match"), BAD_LAYOUTS)
def test_bad_layouts_name_the_quantity(layout: object, match: str) -> None:
    with pytest.raises(InvalidInputError, match=match):
        GraphTrack.from_layout(layout)


BAD_POSITIONS = [
    ("e7:0.1", "edge of position is 'e7'"),
    ("Q", "expected EDGE:OFFSET or a vertex name"),
    ("e1:abc", "offset of position is 'abc', expected a number"),
    ("e1:2.5", r"offset of position on edge 'e1' is 2.5, expected a number in \[0, 2\]"),
    ("e1:-0.1", "is -0.1"),
    ("e1:nan", "is nan"),
    (("e1", None), "offset of position is None"),
    (("e1", True), "offset of position is True"),
    ((3.5, 0.1), "edge of position is 3.5"),
    (42, "expected \\(edge, offset\\)"),
]


@pytest.mark.parametrize(("pos", "match"), BAD_POSITIONS)
def test_bad_positions_name_the_quantity(pos: object, match: str) -> None:
    with pytest.raises(InvalidInputError, match=match):
        GraphTrack.from_layout(LOL).position(pos)


BAD_QUERIES = [
    ({"clearance": -1.0}, "clearance is -1.0, expected a finite number >= 0"),
    ({"clearance": float("nan")}, "clearance is nan"),
    ({"clearance": "0.1"}, "clearance is '0.1'"),
    ({"objective": "quick"}, "objective is 'quick'"),
    ({"speeds": (1.0, 0.0)}, "speed of robot B is 0.0"),
    ({"speeds": 3}, "speeds is 3"),
    ({"start": ("e0:0.5", "e0:0.55")}, r"start has the robots 0.05 m apart, expected at least the clearance 0.1"),
    ({"goal": ("P", "e1:0.05")}, "goal has the robots"),
    ({"start": "F"}, "start is 'F', expected two positions"),
    ({"goal": ("F", "nowhere")}, "goal of robot B is 'nowhere'"),
]


@pytest.mark.parametrize(("kw", "match"), BAD_QUERIES)
def test_bad_queries_raise_invalid_input(kw: dict, match: str) -> None:
    args = {"start": ("F", "e1:1.0"), "goal": ("e1:1.0", "F"), "clearance": 0.1}
    args.update(kw)
    with pytest.raises(InvalidInputError, match=match):
        plan_graph(GraphTrack.from_layout(LOL), **args)


def test_missing_and_malformed_files(tmp_path: Path) -> None:
    with pytest.raises(InvalidInputError, match="does not exist"):
        GraphTrack.from_json(tmp_path / "none.json")
    bad = tmp_path / "bad.json"
    bad.write_text("{", encoding="utf-8")
    with pytest.raises(InvalidInputError, match="not valid JSON"):
        GraphTrack.from_json(bad)


@pytest.mark.parametrize("track", [Interval(1.3), Circle(1.7), Lollipop(1.0, 1.0), Lollipop(0.4, 2.5)])
def test_paper_tracks_as_graphs_keep_distances_and_coordinates(track: object) -> None:
    g = track.as_graph_track()  # type: ignore[attr-defined]
    assert set(g.edge_names) <= {"stick", "loop"}
    rng = np.random.default_rng(1)
    lo, hi = 0.0, track.total_length  # type: ignore[attr-defined]
    p = rng.uniform(lo, hi * (1 - 1e-9), 200)
    q = rng.uniform(lo, hi * (1 - 1e-9), 200)
    ep, op = track.to_graph_position(p)  # type: ignore[attr-defined]
    eq_, oq = track.to_graph_position(q)  # type: ignore[attr-defined]
    np.testing.assert_allclose(track.from_graph_position(ep, op), p, atol=1e-12)  # type: ignore[attr-defined]
    np.testing.assert_allclose(g.geometry.distance(ep, op, eq_, oq), track.distance(p, q), atol=1e-12)  # type: ignore[attr-defined]
    np.testing.assert_allclose(g.embed(ep, op), track.embed(p), atol=0.02 * hi)  # type: ignore[attr-defined]


@settings(max_examples=60, deadline=None)
@given(st.floats(0.0, 1.0), st.floats(0.0, 1.0), st.integers(0, 1), st.integers(0, 1))
def test_position_text_round_trip(fa: float, fb: float, ea: int, eb: int) -> None:
    t = GraphTrack.from_layout(LOL)
    off = fa * float(t.lengths[ea])
    name = t.position_name(ea, off)
    e2, o2 = t.parse_position(name)
    assert t.geometry.distance_scalar(ea, off, e2, o2) <= 1e-9
    assert as_graph_track(t) is t


def _examples() -> list[Path]:
    return sorted(EXAMPLES.glob("*.json"))


def test_all_example_layouts_are_shipped() -> None:
    names = {p.name for p in _examples()}
    want = {"lollipop", "circle", "interval", "y_junction", "passing_loop", "two_sidings", "theta", "figure_eight"}
    assert {f"{n}.json" for n in want} | {"warehouse.json"} <= names
    wh = GraphTrack.from_json(EXAMPLES / "warehouse.json")
    assert 60 <= wh.n_edges <= 100 and wh.total_length <= 1000.0


@pytest.mark.parametrize("path", _examples(), ids=lambda p: p.stem)
def test_example_loads_builds_and_plans_a_random_query(path: Path) -> None:
    track = GraphTrack.from_json(path)
    assert track.has_coordinates
    json.loads(path.read_text(encoding="utf-8"))
    D = 0.05 * min(1.0, float(track.lengths.min()))
    fs = free_space(track, D)
    rng = np.random.default_rng(zlib.crc32(path.stem.encode()))
    planned = 0
    for _ in range(200):
        pts = []
        for _ in range(4):
            e = int(rng.integers(track.n_edges))
            pts.append((e, float(rng.uniform(0, track.lengths[e]))))
        start, goal = (pts[0], pts[1]), (pts[2], pts[3])
        if not (fs.is_free(*start) and fs.is_free(*goal)):
            continue
        try:
            p = plan_graph(track, start, goal, D, objective="fastest", speeds=(1.0, 0.8))
        except NoMotionError:
            assert fs.component_of(*start) != fs.component_of(*goal)
            continue
        assert p.min_distance() >= D - 1e-9
        xy = track.embed(*p.positions(np.linspace(0, 1, 5))[0])
        assert xy.shape == (5, 2) and np.all(np.isfinite(xy))
        planned += 1
        if planned >= 3:
            break
    assert planned >= 1


def test_median_plan_time_on_examples_is_reported() -> None:
    times = []
    for path in _examples():
        track = GraphTrack.from_json(path)
        D = 0.05 * min(1.0, float(track.lengths.min()))
        fs = free_space(track, D)
        rng = np.random.default_rng(0)
        n = 0
        while n < 5:
            e = rng.integers(track.n_edges, size=4)
            o = rng.uniform(0, 1, 4) * track.lengths[e]
            s, g = ((int(e[0]), o[0]), (int(e[1]), o[1])), ((int(e[2]), o[2]), (int(e[3]), o[3]))
            if not (fs.is_free(*s) and fs.is_free(*g)) or fs.component_of(*s) != fs.component_of(*g):
                continue
            t0 = time.perf_counter()
            plan_graph(track, s, g, D)
            times.append(time.perf_counter() - t0)
            n += 1
    print(f"plan median {1e3 * float(np.median(times)):.2f} ms over {len(times)} queries")
    assert math.isfinite(float(np.median(times)))
