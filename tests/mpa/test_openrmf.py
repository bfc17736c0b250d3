"""Open-RMF maps: building maps and navigation graphs read as layouts, fleet files, ``mpa layout convert|show``.

The shared maps in ``tests/data/openrmf`` are from ``open-rmf/rmf_demos`` (Apache 2.0; see the README there).
"""

from __future__ import annotations

import json
import math
from pathlib import Path
from typing import Any

import numpy as np
import pytest
import yaml

import mpa
from mpa.openrmf import building_layout, fleet_config, read_fleet_file, read_layout_file
from trajopt.cli.main import main

DATA = Path(__file__).resolve().parents[1] / "data" / "openrmf"
OFFICE = DATA / "office.building.yaml"
HOTEL = DATA / "hotel.building.yaml"


def _lane(i: int, j: int, graph: int = 0, bidirectional: bool = True, speed: float = 0.0) -> list[Any]:
    return [
        i,
        j,
        {
            "bidirectional": [4, bidirectional],
            "graph_idx": [2, graph],
            "orientation": [1, ""],
            "speed_limit": [3, speed],
        },
    ]


def _building(
    vertices: list[list[Any]],
    lanes: list[list[Any]],
    system: str | None = "reference_image",
    measurements: list[list[Any]] | None = None,
    **extra_levels: Any,
) -> dict[str, Any]:
    level: dict[str, Any] = {"vertices": vertices, "lanes": lanes, "elevation": 0}
    if measurements is not None:
        level["measurements"] = measurements
    out: dict[str, Any] = {"name": "test", "levels": {"L1": level, **extra_levels}, "lifts": {}}
    if system is not None:
        out["coordinate_system"] = system
    return out


def _write(tmp_path: Path, data: object, name: str = "map.building.yaml") -> Path:
    p = tmp_path / name
    p.write_text(yaml.safe_dump(data), encoding="utf-8")
    return p


def _cli(capsys: pytest.CaptureFixture[str], *args: str) -> tuple[int, str, str]:
    rc = main([str(a) for a in args])
    out, err = capsys.readouterr()
    return rc, out, err


# ------------------------------------------------------------------------------------------ shared maps
def test_office_map_reads_with_names_and_the_measured_scale() -> None:
    track = mpa.GraphTrack.from_file(OFFICE)
    assert track.n_edges == 30
    for name in ("pantry", "patrol_A1", "tinyRobot1_charger", "supplies", "coe", "lounge"):
        assert name in track.graph.vertices
    raw = yaml.safe_load(OFFICE.read_text())
    lvl = raw["levels"]["L1"]
    # the reference scale: mean over the measurements of distance / pixel length
    ratios = []
    for i, j, params in lvl["measurements"]:
        (x0, y0), (x1, y1) = lvl["vertices"][i][:2], lvl["vertices"][j][:2]
        ratios.append(params["distance"][1] / math.hypot(x1 - x0, y1 - y0))
    scale = float(np.mean(ratios))
    by_name = {v[3]: v for v in lvl["vertices"] if v[3]}
    for name in ("pantry", "coe"):
        x, y = track.coords[track.vertex_index(name)]
        assert x == pytest.approx(by_name[name][0] * scale, rel=1e-12)
        assert y == pytest.approx(-by_name[name][1] * scale, rel=1e-12)
    # every edge is straight, its length the distance of its ends
    for e in track.graph.edges:
        a, b = track.coords[track.vertex_index(e.tail)], track.coords[track.vertex_index(e.head)]
        assert e.length == pytest.approx(math.dist(a, b), rel=1e-12)


def test_hotel_levels_graphs_and_errors_listing_what_exists() -> None:
    default = mpa.GraphTrack.from_file(HOTEL)
    l1 = mpa.GraphTrack.from_file(HOTEL, level="L1", nav_graph=0)
    assert default == l1  # the reference level is the first one here
    assert mpa.GraphTrack.from_file(HOTEL, level="L1", nav_graph=1).n_edges == 19
    assert mpa.GraphTrack.from_file(HOTEL, level="L2", nav_graph=2).n_edges == 16
    with pytest.raises(mpa.InvalidInputError, match=r"level is 'L9'.*\['L1', 'L2', 'L3'\]"):
        mpa.GraphTrack.from_file(HOTEL, level="L9")
    with pytest.raises(mpa.InvalidInputError, match=r"nav graph is 5.*\[0, 2\]"):
        mpa.GraphTrack.from_file(HOTEL, level="L2", nav_graph=5)


def test_hotel_upper_levels_are_aligned_to_the_reference_level_by_fiducials() -> None:
    """Fiducials of one name lie at one point in metres on every level after the alignment."""
    raw = yaml.safe_load(HOTEL.read_text())
    from mpa.openrmf import _pixel_transform

    levels = raw["levels"]
    s0, r0, tx0, ty0 = _pixel_transform(levels, "L1", "L1")
    s2, r2, tx2, ty2 = _pixel_transform(levels, "L2", "L1")

    def metres(f: list[Any], s: float, r: float, tx: float, ty: float) -> np.ndarray:
        x, y = f[0], -f[1]
        return np.array([(math.cos(r) * x - math.sin(r) * y) * s + tx, (math.sin(r) * x + math.cos(r) * y) * s + ty])

    f1 = {f[2]: metres(f, s0, r0, tx0, ty0) for f in levels["L1"]["fiducials"]}
    f2 = {f[2]: metres(f, s2, r2, tx2, ty2) for f in levels["L2"]["fiducials"]}
    worst = max(float(np.hypot(*(f1[k] - f2[k]))) for k in f1)
    print("largest fiducial misfit (m):", worst)
    assert worst < 0.2  # the drawings' fiducials are hand-placed: they agree to a few pixels


# ------------------------------------------------------------------------------------- coordinate systems
def test_reference_image_scale_flip_and_similarity_alignment() -> None:
    """A level drawn rotated, scaled and shifted against the reference is mapped back exactly."""
    rng = np.random.default_rng(7)
    ref_px = np.array([[0.0, 0.0], [100.0, 0.0], [0.0, 100.0], [60.0, 40.0]])  # pixel (x, y), y down
    theta, k, c = 0.7, 1.8, np.array([35.0, -12.0])
    rot = np.array([[math.cos(theta), -math.sin(theta)], [math.sin(theta), math.cos(theta)]])

    def to_level2(p: np.ndarray) -> np.ndarray:  # in the flipped frame (x, -y)
        q = k * rot @ np.array([p[0], -p[1]]) + c
        return np.array([q[0], -q[1]])

    points = rng.uniform(0, 100, size=(3, 2))
    l2_vertices = [[*to_level2(p).tolist(), 0, f"w{i}"] for i, p in enumerate(points)]
    data = _building(
        [[0, 0, 0, "a"], [100, 0, 0, "b"], [0, 50, 0, "c"]],
        [_lane(0, 1), _lane(0, 2)],
        measurements=[[0, 1, {"distance": [3, 10.0]}]],
        L2={
            "vertices": l2_vertices,
            "lanes": [_lane(0, 1), _lane(1, 2)],
            "fiducials": [[*to_level2(p).tolist(), f"f{i}"] for i, p in enumerate(ref_px)],
        },
    )
    data["levels"]["L1"]["fiducials"] = [[*p.tolist(), f"f{i}"] for i, p in enumerate(ref_px)]
    l1, _ = building_layout(data)
    assert l1["vertices"] == {"a": [0.0, 0.0], "b": [10.0, 0.0], "c": [0.0, -5.0]}
    l2, info = building_layout(data, level="L2")
    assert info["level"] == "L2"
    for i, p in enumerate(points):
        np.testing.assert_allclose(l2["vertices"][f"w{i}"], [0.1 * p[0], -0.1 * p[1]], atol=1e-9)


def test_cartesian_meters_keeps_coordinates() -> None:
    data = _building([[1.5, 2.0, 0, "a"], [4.5, 6.0, 0, "b"]], [_lane(0, 1)], system="cartesian_meters")
    layout, _ = building_layout(data)
    assert layout["vertices"] == {"a": [1.5, 2.0], "b": [4.5, 6.0]}
    assert layout["edges"][0]["length"] == pytest.approx(5.0)


def test_wgs84_local_tangent_plane_distances_within_the_stated_error() -> None:
    """Metres along a meridian and a parallel at 45° against the WGS 84 ellipsoid's arc lengths."""
    lat0, dlat, dlon = 45.0, 0.004, 0.006
    data = _building(
        [[7.0, lat0 - dlat / 2, 0, "s"], [7.0, lat0 + dlat / 2, 0, "n"], [7.0 + dlon, lat0 - dlat / 2, 0, "e"]],
        [_lane(0, 1), _lane(0, 2)],
        system="wgs84",
    )
    layout, info = building_layout(data)
    a, e2 = 6378137.0, 6.69437999014e-3
    phi = math.radians(lat0)
    m = a * (1 - e2) / (1 - e2 * math.sin(phi) ** 2) ** 1.5  # meridional radius of curvature
    expected_ns = m * math.radians(dlat)  # about 444.6 m
    got_ns = math.dist(layout["vertices"]["s"], layout["vertices"]["n"])
    phi_s = math.radians(lat0 - dlat / 2)
    n_s = a / math.sqrt(1 - e2 * math.sin(phi_s) ** 2)
    expected_ew = n_s * math.cos(phi_s) * math.radians(dlon)  # the parallel at the vertices' latitude
    got_ew = math.dist(layout["vertices"]["s"], layout["vertices"]["e"])
    err = info["projection_error"]
    print("projection error bound", err, "ns", got_ns, expected_ns, "ew", got_ew, expected_ew)
    assert 0 < err < 1e-4
    assert abs(got_ns / expected_ns - 1) <= 1e-9 + err
    assert abs(got_ew / expected_ew - 1) <= err


def test_wgs84_vertex_outside_the_degree_ranges_is_an_error() -> None:
    data = _building([[200.0, 1.0, 0, "a"], [1.0, 1.0, 0, "b"]], [_lane(0, 1)], system="wgs84")
    with pytest.raises(mpa.InvalidInputError, match=r"longitude 200\.0"):
        building_layout(data)


# -------------------------------------------------------------------------------------------- lanes
def test_lanes_merge_drop_and_keep_rules() -> None:
    verts = [[0, 0, 0, "a"], [3, 4, 0, "b"], [6, 8, 0, ""], [0, 0, 0, "a2"], [9, 9, 0, "b"]]
    lanes = [
        _lane(0, 1, speed=0.5),  # lane0: two-way, limit 0.5
        _lane(1, 0, speed=0.8),  # lane1: the same pair: merged, the larger limit
        _lane(1, 2, bidirectional=False),  # lane2: one-way b -> v2
        _lane(1, 2, bidirectional=False, speed=0.3),  # lane3: repeated one-way, one without limit: no limit
        _lane(0, 3),  # lane4: zero length: dropped
        _lane(2, 4, bidirectional=False),  # lane5: one-way v2 -> b_ (a second vertex named "b")
        _lane(4, 2, bidirectional=False),  # lane6: the other way: merged into a two-way edge
        _lane(0, 2, graph=1),  # another graph: ignored
    ]
    layout, info = building_layout(_building(verts, lanes, system="cartesian_meters"))
    edges = {e["name"]: e for e in layout["edges"]}
    assert set(edges) == {"lane0", "lane2", "lane5"}
    assert edges["lane0"]["speed_limit"] == 0.8 and "oneway" not in edges["lane0"]
    assert edges["lane2"]["oneway"] is True and "speed_limit" not in edges["lane2"]
    assert (edges["lane2"]["from"], edges["lane2"]["to"]) == ("b", "v2")
    assert "oneway" not in edges["lane5"] and edges["lane5"]["to"] == "v4"
    assert info["merged_lanes"] == 3 and info["dropped_lanes"] == 1 and info["lanes"] == 7
    track = mpa.GraphTrack.from_layout(layout)
    assert track.oneway == (False, True, False)
    assert track.speed_limits == (0.8, None, None)
    assert "a2" not in track.graph.vertices  # only on the dropped lane


@pytest.mark.parametrize(
    ("lanes", "match"),
    [
        ([_lane(0, 7)], r"vertex 7 of lane 0 of level 'L1' does not exist"),
        ([_lane(0, 1, speed=-1.0)], r"speed_limit of lane 0 of level 'L1' is -1.0"),
        ([_lane(0, 1, graph=3)], r"nav graph is 0, expected one of the graph indices with lanes .*\[3\]"),
        ([_lane(0, 0)], r"no lane of positive length"),
    ],
)
def test_bad_lanes_are_invalid_input(lanes: list[Any], match: str) -> None:
    data = _building([[0, 0, 0, "a"], [1, 0, 0, "b"]], lanes, system="cartesian_meters")
    with pytest.raises(mpa.InvalidInputError, match=match):
        building_layout(data)


def test_disconnected_graph_is_kept_whole_and_queries_across_parts_have_no_motion() -> None:
    verts = [[0, 0, 0, "a"], [4, 0, 0, "b"], [0, 5, 0, "c"], [4, 5, 0, "d"]]
    data = _building(verts, [_lane(0, 1), _lane(2, 3)], system="cartesian_meters")
    track = mpa.GraphTrack.from_layout(building_layout(data)[0])
    assert track.graph.betti()[0] == 2
    plan = mpa.plan(track, ("a", "c"), ("b", "d"), 0.5)
    assert plan.min_distance() >= 0.5 - 1e-9
    with pytest.raises(mpa.NoMotionError, match="another part of the track"):
        mpa.plan(track, ("a", "c"), ("d", "b"), 0.5)


# ---------------------------------------------------------------------------------------- nav graphs
def test_nav_graph_two_one_way_lanes_are_one_two_way_edge(tmp_path: Path) -> None:
    nav = {
        "building_name": "test",
        "levels": {
            "L1": {
                "vertices": [[0.0, 0.0, {"name": "a"}], [3.0, 4.0, {"name": "b"}], [3.0, 8.0, {"name": ""}]],
                "lanes": [
                    [0, 1, {"speed_limit": 0.0}],
                    [1, 0, {"speed_limit": 0.0}],
                    [1, 2, {"speed_limit": 0.4}],
                ],
            }
        },
    }
    path = _write(tmp_path, nav, "nav.yaml")
    layout, info = read_layout_file(path)
    assert info["kind"] == "nav_graph"
    assert layout["edges"] == [
        {"name": "lane0", "from": "a", "to": "b", "length": 5.0},
        {"name": "lane2", "from": "b", "to": "v2", "length": 4.0, "oneway": True, "speed_limit": 0.4},
    ]
    with pytest.raises(mpa.InvalidInputError, match=r"level is 'L2'.*\['L1'\]"):
        read_layout_file(path, level="L2")
    with pytest.raises(mpa.InvalidInputError, match=r"nav graph is 1"):
        read_layout_file(path, nav_graph=1)


def test_files_of_no_known_kind_are_invalid_input(tmp_path: Path) -> None:
    for text in ("just: [a, mapping]\n", "- 1\n- 2\n", "{levels: {L1: 3}}\n", "key: [unclosed\n"):
        p = tmp_path / "x.yaml"
        p.write_text(text, encoding="utf-8")
        with pytest.raises(mpa.InvalidInputError, match="expected"):
            mpa.GraphTrack.from_file(p)
    with pytest.raises(mpa.InvalidInputError, match="fleet_manager"):
        mpa.GraphTrack.from_file(DATA / "office_tinyRobot_config.yaml")


def test_our_json_layout_round_trips_with_oneway_and_speed_limit(tmp_path: Path) -> None:
    layout = {
        "vertices": {"a": [0, 0], "b": [2, 0]},
        "edges": [{"name": "ab", "from": "a", "to": "b", "oneway": True, "speed_limit": 0.25}],
    }
    p = tmp_path / "l.json"
    p.write_text(json.dumps(layout))
    track = mpa.GraphTrack.from_file(p)
    assert track.oneway == (True,) and track.speed_limits == (0.25,)
    assert mpa.GraphTrack.from_layout(track.to_dict()) == track
    for bad, match in (({"oneway": 1}, "oneway of edge 'ab' is 1"), ({"speed_limit": 0}, "speed_limit of edge")):
        edge = {"name": "ab", "from": "a", "to": "b", **bad}
        with pytest.raises(mpa.InvalidInputError, match=match):
            mpa.GraphTrack.from_layout({"edges": [edge]})


# ---------------------------------------------------------------------------------------------- fleets
def test_fleet_files() -> None:
    office = read_fleet_file(DATA / "office_tinyRobot_config.yaml")
    assert (office.vmax, office.amax, office.footprint, office.vicinity) == (0.5, 0.75, 0.3, 0.5)
    assert office.radius("vicinity") == 0.5
    hotel = read_fleet_file(DATA / "hotel_deliveryRobot_config.yaml")
    assert hotel.vmax > 0 and hotel.amax > 0
    with pytest.raises(mpa.InvalidInputError, match=r"rmf_fleet.limits.linear .* is None"):
        fleet_config({"rmf_fleet": {"name": "x", "profile": {"footprint": 0.3}}})
    with pytest.raises(mpa.InvalidInputError, match="no rmf_fleet section"):
        fleet_config({"levels": {}})


# ------------------------------------------------------------------------------------------ command line
def test_cli_convert_writes_our_json_and_show_draws(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    out = tmp_path / "hotel_l2.json"
    rc, text, err = _cli(capsys, "layout", "convert", HOTEL, "--level", "L2", "--nav-graph", "2", "--out", out)
    assert rc == 0, err
    assert "16 edges" in text
    layout = json.loads(out.read_text())
    assert mpa.GraphTrack.from_layout(layout) == mpa.GraphTrack.from_file(HOTEL, level="L2", nav_graph=2)
    assert all(e["oneway"] is False and e["speed_limit"] is None for e in layout["edges"])
    ruled = _write(
        tmp_path,
        _building(
            [[0, 0, 0, "a"], [4, 3, 0, "b"], [4, 0, 0, "c"]],
            [_lane(0, 1, bidirectional=False), _lane(1, 2, speed=0.4)],
            system="cartesian_meters",
        ),
    )
    rc, _, err = _cli(capsys, "layout", "convert", ruled, "--out", tmp_path / "ruled.json")
    assert rc == 0, err
    edges = json.loads((tmp_path / "ruled.json").read_text())["edges"]
    assert [(e["from"], e["to"], e["length"], e["oneway"], e["speed_limit"]) for e in edges] == [
        ("a", "b", 5.0, True, None),
        ("b", "c", 3.0, False, 0.4),
    ]
    png = tmp_path / "office.png"
    rc, text, err = _cli(capsys, "layout", "show", OFFICE, "--plot", png)
    assert rc == 0, err
    assert png.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    assert "30 edges" in text


@pytest.mark.parametrize(
    "args",
    [
        ("layout", "convert", HOTEL, "--level", "L7", "--out", "{out}"),
        ("layout", "convert", HOTEL, "--nav-graph", "4", "--out", "{out}"),
        ("layout", "convert", DATA / "office_tinyRobot_config.yaml", "--out", "{out}"),
        ("layout", "convert", DATA / "missing.building.yaml", "--out", "{out}"),
        ("layout", "show", OFFICE, "--level", "L2", "--plot", "{out}.png"),
    ],
)
def test_cli_bad_maps_exit_2_and_write_nothing(
    tmp_path: Path, capsys: pytest.CaptureFixture[str], args: tuple[object, ...]
) -> None:
    out = tmp_path / "out.json"
    rc, _, err = _cli(capsys, *(str(a).replace("{out}", str(out)) for a in args))
    assert rc == 2
    assert err.startswith("error: ") and err.count("\n") == 1, err
    assert list(tmp_path.iterdir()) == []


def test_cli_plan_and_topology_on_a_building_map(capsys: pytest.CaptureFixture[str]) -> None:
    rc, text, err = _cli(
        capsys, "plan", "--graph", OFFICE, "--start", "pantry", "patrol_A1", "--goal", "patrol_A1", "pantry",
        "--clearance", "0.5", "--json",
    )  # fmt: skip
    assert rc == 0, err
    assert json.loads(text)["min_distance"] >= 0.5 - 1e-9
    rc, text, err = _cli(capsys, "topology", "--graph", HOTEL, "--level", "L2", "--nav-graph", "2", "--json")
    assert rc == 0, err
    assert json.loads(text)["betti"] == [1, 5, 0]
    rc, _, err = _cli(capsys, "plan", "--graph", HOTEL, "--level", "nope", "--start", "a", "b", "--goal", "b", "a")
    assert rc == 2 and "['L1', 'L2', 'L3']" in err


def test_cli_fleet_limits_unless_given_and_disc_footprint(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    query = ["--graph", OFFICE, "--start", "pantry", "patrol_A1", "--goal", "patrol_A1", "pantry", "--clearance", "0.5"]
    fleet = DATA / "office_tinyRobot_config.yaml"
    out = tmp_path / "o"
    rc, _, err = _cli(
        capsys, "trajectory", *query, "--fleet", fleet, "--fleet-radius", "none", "--vmax", "0.4", "--out", out
    )
    assert rc == 0, err
    summary = json.loads((out / "summary.json").read_text())
    limits = summary["limits"]
    assert limits["vmax"] == [0.4, 0.4] and limits["amax"] == [0.75, 0.75]  # --vmax given, amax from the fleet
    assert summary.get("footprint") is None
    # the fleet's disc (rmf_fleet.profile.footprint 0.3 m, vicinity 0.5 m) unless --footprint is given
    for args, radius in (
        (("--fleet-radius", "footprint"), 0.3),
        (("--fleet-radius", "footprint", "--footprint", "0.2"), 0.2),
    ):
        out2 = tmp_path / f"r{radius}"
        rc, _, err = _cli(capsys, "trajectory", *query, "--fleet", fleet, *args, "--out", out2)
        assert rc == 0, err
        fp = json.loads((out2 / "summary.json").read_text())["footprint"]
        assert str(radius) in json.dumps(fp), fp
    out3 = tmp_path / "vicinity"
    rc, _, err = _cli(capsys, "trajectory", *query, "--fleet", fleet, "--fleet-radius", "vicinity", "--out", out3)
    assert rc in (0, 3), err  # discs of 0.5 m may not pass on this map; either a verified motion or "no motion"
    if rc == 0:
        assert "0.5" in json.dumps(json.loads((out3 / "summary.json").read_text())["footprint"])
    else:
        assert err.startswith("no motion: ") and not out3.exists()
    no_limits = tmp_path / "fleet.yaml"
    no_limits.write_text("rmf_fleet:\n  name: x\n  profile: {footprint: 0.3}\n", encoding="utf-8")
    rc, _, err = _cli(capsys, "trajectory", *query, "--fleet", no_limits, "--fleet-radius", "none", "--out", out / "x")
    assert rc == 2 and "rmf_fleet.limits.linear" in err


def test_serve_opens_with_a_building_map() -> None:
    import argparse

    from trajopt.cli.serve import _initial

    args = argparse.Namespace(graph=str(HOTEL), track=None, level="L2", nav_graph=2, stick=None, loop=None)
    init = _initial(args)
    assert init["name"] == "hotel.building" and len(init["layout"]["edges"]) == 16
    assert mpa.GraphTrack.from_layout(init["layout"]) == mpa.GraphTrack.from_file(HOTEL, level="L2", nav_graph=2)


def test_the_c_loader_reads_what_the_python_loader_reads() -> None:
    """libyaml's loader (used when the nesting is bounded) gives the same data as PyYAML's on the shared maps."""
    from mpa.openrmf import C_LOADER_DEPTH, _nesting_bound, _safe_load

    for path in sorted(DATA.glob("*.yaml")):
        text = path.read_text(encoding="utf-8")
        assert _nesting_bound(text) <= C_LOADER_DEPTH, path.name  # these maps take the C loader
        assert _safe_load(text) == yaml.safe_load(text), path.name


@pytest.mark.parametrize("text", ["[" * 30_000 + "]" * 30_000, "- " * 30_000 + "x"])
def test_deeply_nested_yaml_is_refused_not_a_crash(tmp_path: Path, text: str) -> None:
    """Past the C loader's nesting bound the Python loader answers: an error naming the file, no crash."""
    from mpa.errors import InvalidInputError
    from mpa.openrmf import C_LOADER_DEPTH, _nesting_bound

    assert _nesting_bound(text) > C_LOADER_DEPTH
    path = tmp_path / "deep.building.yaml"
    path.write_text(text, encoding="utf-8")
    with pytest.raises(InvalidInputError, match="nested too deeply") as info:
        read_layout_file(path)
    print(info.value)


def test_nesting_bound_is_an_upper_bound() -> None:
    """Seeded random nestings of flow and block collections: the bound is never below the true depth."""
    rng = np.random.default_rng(7)

    def depth(x: Any) -> int:
        if isinstance(x, dict):
            return 1 + max((depth(v) for v in x.values()), default=0)
        if isinstance(x, list):
            return 1 + max((depth(v) for v in x), default=0)
        return 0

    from mpa.openrmf import _nesting_bound

    for _ in range(200):
        x: Any = int(rng.integers(10))
        for _ in range(int(rng.integers(1, 40))):
            x = [x, "a-b"] if rng.random() < 0.5 else {"k": x, "q": "x?"}
        for flow in (True, False, None):
            text = yaml.safe_dump(x, default_flow_style=flow)
            assert _nesting_bound(text) >= depth(yaml.safe_load(text)), text


def test_invalid_yaml_is_named_as_pyyaml_names_it(tmp_path: Path) -> None:
    """A text the C loader refuses gets PyYAML's message and position in the error."""
    from mpa.errors import InvalidInputError

    text = "levels:\n  L1: [a, b\n  x: }\n"
    with pytest.raises(yaml.YAMLError) as ref:
        yaml.safe_load(text)
    path = tmp_path / "bad.building.yaml"
    path.write_text(text, encoding="utf-8")
    with pytest.raises(InvalidInputError) as info:
        read_layout_file(path)
    print(info.value)
    assert str(getattr(ref.value, "problem", "")) in str(info.value)
    assert "line 3 column 4" in str(info.value)
