"""Issue 14 on the command line: ``mpa trajectory --format/--plot/--delay-tolerance``, ``mpa replan``, ``mpa plot``.

Every format is read back and compared with ``setpoints.csv``; every bad input exits 2 with one ``error:`` line
and writes nothing.
"""

from __future__ import annotations

import json
import re
import shutil
import sys
from pathlib import Path

import numpy as np
import pytest
import yaml
from rosbags.rosbag2 import Reader
from rosbags.typesys import Stores, get_typestore

from trajopt.cli import main
from trajopt.cli.replan import load_trajectory

ROOT = Path(__file__).resolve().parents[2]
QUERY = ["--track", "lollipop", "--start", "0.1", "0.6", "--goal", "0.8", "0.3"]
ALL = {"setpoints.csv", "trajectory.yaml", "trajectory.mcap", "pvt.csv", "trajectory.png", "summary.json"}
NS = 1e-9


def run(argv, capsys):  # type: ignore[no-untyped-def]
    code = main([str(a) for a in argv])
    cap = capsys.readouterr()
    return code, cap.out, cap.err


def one_line(err: str, prefix: str) -> str:
    lines = err.strip().splitlines()
    assert len(lines) == 1 and lines[0].startswith(prefix + ": "), err
    assert "Traceback" not in err
    return lines[0]


def read_csv(path: Path) -> dict[str, np.ndarray]:
    header = path.read_text().splitlines()[0].split(",")
    numeric = [i for i, h in enumerate(header) if not h.endswith("_edge")]  # edge names are not numbers
    data = np.loadtxt(path, delimiter=",", skiprows=1, ndmin=2, usecols=numeric)
    return {header[i]: data[:, k] for k, i in enumerate(numeric)}


def png_pixels(path: Path) -> np.ndarray:
    from PIL import Image

    with Image.open(path) as im:
        return np.asarray(im.convert("RGB"), dtype=float)


def assert_png_not_blank(path: Path) -> None:
    assert path.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    px = png_pixels(path)
    assert px.shape[0] > 300 and px.shape[1] > 300
    colours = np.unique(px.reshape(-1, 3), axis=0)
    assert len(colours) > 50  # lines, text, shading: not a blank canvas
    assert float(np.mean(px < 200)) > 0.01  # some dark ink


@pytest.fixture(scope="module")
def full(tmp_path_factory):  # type: ignore[no-untyped-def]
    """One run with every format and the plot."""
    out = tmp_path_factory.mktemp("full") / "run"
    argv = ["trajectory", *QUERY, "--format", "csv,ros2-yaml,mcap,pvt", "--plot", "--out", str(out)]
    code = main(argv)
    assert code == 0
    return out


# --------------------------------------------------------------------------------------------- trajectory
def test_all_formats_written(full) -> None:  # type: ignore[no-untyped-def]
    assert {p.name for p in full.iterdir()} == ALL
    js = json.loads((full / "summary.json").read_text())
    assert js["formats"] == ["csv", "ros2-yaml", "mcap", "pvt"]
    assert set(js["files"]) == ALL
    assert js["recipe"] == {"start": [0.1, 0.6], "goal": [0.8, 0.3], "delay_tolerance": None, "replans": []}
    assert js["words"]["A"] and js["words"]["B"] and js["margins"]["tracking_margin"] > 0
    rows = len(read_csv(full / "pvt.csv")["time"])
    # the default: auto
    assert js["pvt"] == {"interval": 0.1, "auto": True, "stretch": 1.0, "rows": rows, "velocity_change": 0.0}
    assert js["ros"] == {"joint_names": ["cart_a", "cart_b"], "topic": "/joint_trajectory"}


def test_ros2_yaml_equals_csv(full) -> None:  # type: ignore[no-untyped-def]
    rows = read_csv(full / "setpoints.csv")
    msg = yaml.safe_load((full / "trajectory.yaml").read_text())
    assert msg["joint_names"] == ["cart_a", "cart_b"]
    pts = msg["points"]
    assert len(pts) == len(rows["time"])
    t = np.array([p["time_from_start"]["sec"] + p["time_from_start"]["nanosec"] * 1e-9 for p in pts])
    np.testing.assert_allclose(t, rows["time"], atol=NS)
    for key, col in (("positions", "s"), ("velocities", "v"), ("accelerations", "a")):
        got = np.array([p[key] for p in pts])
        want = np.column_stack([rows[f"a_{col}"], rows[f"b_{col}"]])
        np.testing.assert_allclose(got, want, rtol=1e-11, atol=1e-12)


def test_mcap_read_back_equals_csv(full) -> None:  # type: ignore[no-untyped-def]
    rows = read_csv(full / "setpoints.csv")
    path = full / "trajectory.mcap"
    assert path.read_bytes()[:8] == b"\x89MCAP0\r\n"
    ts = get_typestore(Stores.ROS2_HUMBLE)
    msgs: dict[str, list] = {}
    with Reader(path) as reader:  # a bare MCAP file, schemas embedded
        for conn, stamp, raw in reader.messages():
            msgs.setdefault(conn.topic, []).append((stamp, ts.deserialize_cdr(raw, conn.msgtype)))
    assert set(msgs) == {"/joint_trajectory", "/joint_trajectory_point"}
    ((_, jt),) = msgs["/joint_trajectory"]
    assert list(jt.joint_names) == ["cart_a", "cart_b"]
    pts = msgs["/joint_trajectory_point"]
    assert len(jt.points) == len(pts) == len(rows["time"])
    stamps = np.array([s for s, _ in pts]) * 1e-9
    np.testing.assert_allclose(stamps, rows["time"], atol=NS)
    for key, col in (("positions", "s"), ("velocities", "v"), ("accelerations", "a")):
        want = np.column_stack([rows[f"a_{col}"], rows[f"b_{col}"]])
        for seq in ([getattr(p, key) for _, p in pts], [getattr(p, key) for p in jt.points]):
            np.testing.assert_allclose(np.array(seq), want, rtol=1e-11, atol=1e-12)


def test_pvt_rows(full) -> None:  # type: ignore[no-untyped-def]
    rows = read_csv(full / "setpoints.csv")
    pvt = read_csv(full / "pvt.csv")
    assert (full / "pvt.csv").read_text().splitlines()[0] == "time,a_s,a_v,b_s,b_v"
    js = json.loads((full / "summary.json").read_text())
    t = pvt["time"]
    np.testing.assert_allclose(np.diff(t[:-1]), 0.1, atol=1e-12)
    assert t[0] == 0.0 and t[-1] == pytest.approx(js["motion_time"], abs=1e-12)
    assert pvt["a_v"][-1] == 0.0 and pvt["b_v"][-1] == 0.0
    # rows at multiples of 0.1 s are rows of the 100 Hz CSV too: same positions and velocities
    for k, tk in enumerate(t[:-1]):
        i = round(float(tk) * 100)
        assert rows["time"][i] == pytest.approx(tk, abs=1e-12)
        for c in ("a_s", "a_v", "b_s", "b_v"):
            assert pvt[c][k] == pytest.approx(rows[c][i], rel=1e-10, abs=1e-11)


def test_plot_png_not_blank(full) -> None:  # type: ignore[no-untyped-def]
    assert_png_not_blank(full / "trajectory.png")


def test_printout_in_words(tmp_path, capsys) -> None:  # type: ignore[no-untyped-def]
    code, out, err = run(["trajectory", *QUERY, "--out", tmp_path / "o"], capsys)
    assert code == 0 and err == ""
    js = json.loads((tmp_path / "o" / "summary.json").read_text())
    assert f"A           {js['words']['A']}" in out and f"B           {js['words']['B']}" in out
    assert re.search(r"margins     tracking [0-9.e-]+ m, delay ", out)
    assert "domain      1, class" in out
    assert {p.name for p in (tmp_path / "o").iterdir()} == {"setpoints.csv", "summary.json"}


def test_joint_names_and_topic(tmp_path, capsys) -> None:  # type: ignore[no-untyped-def]
    out = tmp_path / "o"
    argv = ["trajectory", *QUERY, "--format", "ros2-yaml,mcap", "--joint-names", "left,right"]
    code, _, _ = run([*argv, "--topic", "/carts/plan", "--out", out], capsys)
    assert code == 0
    assert {p.name for p in out.iterdir()} == {"trajectory.yaml", "trajectory.mcap", "summary.json"}
    assert yaml.safe_load((out / "trajectory.yaml").read_text())["joint_names"] == ["left", "right"]
    with Reader(out / "trajectory.mcap") as reader:
        assert {c.topic for c in reader.connections} == {"/carts/plan", "/joint_trajectory_point"}


# --------------------------------------------------------------------------------------------- bad input
@pytest.mark.parametrize(
    ("extra", "match"),
    [
        (["--format", "csv,foo"], "--format has 'foo'"),
        (["--format", ""], "--format is ''"),
        (["--format", "pvt", "--pvt-interval", "0"], "--pvt-interval is 0.0 s"),
        (["--format", "pvt", "--pvt-interval", "0.5"], "the largest interval that works is 0.2 s"),
        (["--format", "pvt", "--pvt-stretch", "0.5"], "--pvt-stretch"),
        (["--format", "ros2-yaml", "--joint-names", "a"], "joint names"),
        (["--format", "mcap", "--topic", "no spaces"], "--topic"),
        (["--delay-tolerance", "-1"], "delay tolerance"),
    ],
)
def test_bad_output_options(tmp_path, capsys, extra, match) -> None:  # type: ignore[no-untyped-def]
    out = tmp_path / "o"
    code, stdout, err = run(["trajectory", *QUERY, *extra, "--out", out], capsys)
    assert code == 2 and stdout == ""
    assert match in one_line(err, "error")
    assert not out.exists()


def test_pvt_failure_leaves_existing_directory_alone(tmp_path, capsys) -> None:  # type: ignore[no-untyped-def]
    out = tmp_path / "o"
    out.mkdir()
    (out / "old.txt").write_text("keep")
    code, _, err = run(["trajectory", *QUERY, "--format", "csv,pvt", "--pvt-interval", "0.5", "--out", out], capsys)
    assert code == 2 and "largest interval that works is 0.2 s" in one_line(err, "error")
    assert [p.name for p in out.iterdir()] == ["old.txt"]


def test_mcap_without_rosbags(tmp_path, capsys, monkeypatch) -> None:  # type: ignore[no-untyped-def]
    for name in [m for m in sys.modules if m == "rosbags" or m.startswith("rosbags.")]:
        monkeypatch.delitem(sys.modules, name)
    monkeypatch.setitem(sys.modules, "rosbags", None)  # import rosbags -> ImportError
    out = tmp_path / "o"
    code, _, err = run(["trajectory", *QUERY, "--format", "csv,mcap", "--out", out], capsys)
    assert code == 2
    line = one_line(err, "error")
    assert "rosbags" in line and "pip install 'lollipop-mpa[ros]'" in line
    assert not out.exists()


# --------------------------------------------------------------------------------------------- delay tolerance
def test_delay_tolerance_option(tmp_path, capsys) -> None:  # type: ignore[no-untyped-def]
    out = tmp_path / "o"
    q = ["--track", "lollipop", "--start", "0.3", "1.2", "--goal", "1.6", "0.4"]
    code, stdout, _ = run(["trajectory", *q, "--delay-tolerance", "0.05", "--out", out], capsys)
    assert code == 0
    js = json.loads((out / "summary.json").read_text())
    assert js["margins"]["delay_tolerance"] >= 0.05
    assert js["solver"]["delay_tolerance"]["effective_clearance"] > js["clearance"] == 0.05
    assert js["recipe"]["delay_tolerance"] == 0.05
    assert "tolerance   asked 0.05 s" in stdout
    # the recipe rebuilds the tolerant motion (checked against setpoints.csv), so it can be re-planned
    code, _, err = run(
        ["replan", "--from", out, "--at", "1.0", "--goal", "1.5", "0.4", "--out", tmp_path / "r"], capsys
    )
    assert code == 0, err
    js2 = json.loads((tmp_path / "r" / "summary.json").read_text())
    assert js2["recipe"]["delay_tolerance"] == 0.05 and js2["recipe"]["replans"] == [{"at": 1.0, "goal": [1.5, 0.4]}]


def test_delay_tolerance_none_found_exit_3(tmp_path, capsys) -> None:  # type: ignore[no-untyped-def]
    out = tmp_path / "o"
    q = ["--track", "interval", "--start", "0.0", "0.06", "--goal", "0.5", "0.56"]
    code, stdout, err = run(["trajectory", *q, "--delay-tolerance", "5", "--out", out], capsys)
    assert code == 3 and stdout == ""
    line = one_line(err, "no motion")
    assert re.search(r"best found tolerates [0-9.e-]+ s", line)
    assert not out.exists()


# --------------------------------------------------------------------------------------------- replan
def test_replan_splice_is_continuous(full, tmp_path, capsys) -> None:  # type: ignore[no-untyped-def]
    out = tmp_path / "r"
    argv = ["replan", "--from", full, "--at", "1.0", "--goal", "0.7", "0.35", "--out", out]
    code, stdout, err = run([*argv, "--format", "csv,ros2-yaml,mcap,pvt", "--plot"], capsys)
    assert code == 0, err
    assert {p.name for p in out.iterdir()} == ALL
    assert stdout.startswith("replan      at 1 s of")
    old, new = read_csv(full / "setpoints.csv"), read_csv(out / "setpoints.csv")
    js = json.loads((out / "summary.json").read_text())
    orient = js["solver"]["replan"]["orientation"]
    i = 100  # the row at 1.0 s
    assert old["time"][i] == pytest.approx(1.0, abs=1e-12) and new["time"][0] == 0.0
    for r, c in enumerate("ab"):
        assert new[f"{c}_track"][0] == pytest.approx(old[f"{c}_track"][i], abs=1e-11)
        assert new[f"{c}_s"][0] == 0.0
        for q in ("v", "a"):
            assert new[f"{c}_{q}"][0] == pytest.approx(orient[r] * old[f"{c}_{q}"][i], abs=1e-9)
    assert js["recipe"]["replans"] == [{"at": 1.0, "goal": [0.7, 0.35]}]
    assert js["goal"] == [0.7, 0.35]
    # the re-plan's other files are read back too
    assert len(yaml.safe_load((out / "trajectory.yaml").read_text())["points"]) == len(new["time"])
    assert read_csv(out / "pvt.csv")["a_v"][0] == pytest.approx(new["a_v"][0], abs=1e-11)  # moving first row
    assert_png_not_blank(out / "trajectory.png")

    # between rows: the state of the motion rebuilt from --from, exactly (continuity to 1e-9 in p, v, a)
    out2 = tmp_path / "r2"
    code, _, err = run(["replan", "--from", full, "--at", "1.005", "--goal", "0.7", "0.35", "--out", out2], capsys)
    assert code == 0, err
    _, traj, _ = load_trajectory(full)
    s, v, a, _ = traj.sampler(np.array([1.005]))
    _, new2, _ = load_trajectory(out2)
    o2 = new2.solver_stats["replan"]["orientation"]
    for r in (0, 1):
        assert abs(new2.s[0, r]) <= 1e-9
        assert abs(new2.track[0, r] - traj.plan.routes[r].position(s[0, r])) <= 1e-9
        assert abs(new2.v[0, r] - o2[r] * v[0, r]) <= 1e-9 and abs(new2.a[0, r] - o2[r] * a[0, r]) <= 1e-9

    # and again from the re-plan (the recipe chains)
    out3 = tmp_path / "r3"
    code, _, err = run(["replan", "--from", out, "--at", "0.5", "--goal", "0.72", "0.35", "--out", out3], capsys)
    assert code == 0, err
    js3 = json.loads((out3 / "summary.json").read_text())
    assert [r["at"] for r in js3["recipe"]["replans"]] == [1.0, 0.5]
    new3 = read_csv(out3 / "setpoints.csv")
    assert new3["a_track"][0] == pytest.approx(new["a_track"][50], abs=1e-11)


@pytest.mark.parametrize(
    ("at", "goal", "match"),
    [
        ("-0.1", ("0.7", "0.35"), "--at is -0.1 s, expected a time in"),
        ("99", ("0.7", "0.35"), "--at is 99.0 s, expected a time in"),
        ("nan", ("0.7", "0.35"), "--at is"),
        ("1.0", ("0.7", "5"), "goal of robot B is 5.0"),
        ("1.0", ("0.7", "0.71"), "goal (0.7, 0.71) has the robots"),
        ("1.0", ("0.7", "x"), "--goal has 'x'"),
    ],
)
def test_replan_bad_input(full, tmp_path, capsys, at, goal, match) -> None:  # type: ignore[no-untyped-def]
    out = tmp_path / "r"
    code, stdout, err = run(["replan", "--from", full, "--at", at, "--goal", *goal, "--out", out], capsys)
    assert code == 2 and stdout == ""
    assert match in one_line(err, "error")
    assert not out.exists()


def test_replan_from_without_trajectory(full, tmp_path, capsys) -> None:  # type: ignore[no-untyped-def]
    empty = tmp_path / "empty"
    empty.mkdir()
    only_summary = tmp_path / "only_summary"
    only_summary.mkdir()
    shutil.copy(full / "summary.json", only_summary)
    edited = tmp_path / "edited"
    shutil.copytree(full, edited)
    text = (edited / "setpoints.csv").read_text().splitlines()
    cells = text[50].split(",")
    cells[2] = str(float(cells[2]) + 1e-6)
    text[50] = ",".join(cells)
    (edited / "setpoints.csv").write_text("\n".join(text) + "\n")
    cases = [
        (tmp_path / "missing", "expected a directory written by mpa trajectory"),
        (empty, "holds no trajectory (no summary.json)"),
        (only_summary, "holds no setpoints.csv"),
        (edited, "differs from the motion rebuilt from summary.json (row 49, column a_s"),
    ]
    for src, match in cases:
        out = tmp_path / "r"
        code, _, err = run(["replan", "--from", src, "--at", "1.0", "--goal", "0.7", "0.35", "--out", out], capsys)
        assert code == 2, src
        assert match in one_line(err, "error"), err
        assert not out.exists()


# --------------------------------------------------------------------------------------------- plot
def test_plot_directory_and_files(full, tmp_path, capsys) -> None:  # type: ignore[no-untyped-def]
    d = tmp_path / "d"
    d.mkdir()
    for name in ("setpoints.csv", "summary.json", "pvt.csv"):
        shutil.copy(full / name, d)
    code, out, _ = run(["plot", d], capsys)
    assert code == 0 and out.strip() == str(d / "trajectory.png")
    assert_png_not_blank(d / "trajectory.png")
    code, out, _ = run(["plot", d / "pvt.csv"], capsys)
    assert code == 0 and out.strip() == str(d / "pvt.png")
    assert_png_not_blank(d / "pvt.png")
    bare = tmp_path / "bare"
    bare.mkdir()
    shutil.copy(full / "setpoints.csv", bare / "mine.csv")  # no summary.json beside it: no track panel
    code, _, _ = run(["plot", bare / "mine.csv", "--out", tmp_path / "x.png"], capsys)
    assert code == 0
    assert_png_not_blank(tmp_path / "x.png")


def test_plot_bad_input(full, tmp_path, capsys) -> None:  # type: ignore[no-untyped-def]
    empty = tmp_path / "empty"
    empty.mkdir()
    cases = [
        ([tmp_path / "nope.csv"], "does not exist"),
        ([empty], "holds no setpoints.csv or pvt.csv"),
        ([full / "summary.json", "--out", tmp_path / "s.png"], "expected a setpoints file"),
        ([full, "--out", empty], "is a directory"),
    ]
    for argv, match in cases:
        code, _, err = run(["plot", *argv], capsys)
        assert code == 2
        assert match in one_line(err, "error"), err
    assert list(empty.iterdir()) == [] and not (tmp_path / "s.png").exists()


def test_plot_graph_layout(tmp_path) -> None:  # type: ignore[no-untyped-def]
    from mpa.graph_track import GraphTrack
    from trajopt.viz.plotting import figure_png
    from trajopt.viz.setpoints import plot_rows

    layout = GraphTrack.from_json(ROOT / "examples" / "tracks" / "y_junction.json").to_dict()
    t = np.linspace(0.0, 1.0, 11)
    rows = {"time": t, "a_s": t, "b_s": 1 - t, "a_v": np.ones(11), "b_v": -np.ones(11)}
    (tmp_path / "g.png").write_bytes(figure_png(plot_rows(rows, layout=layout, title="graph")))
    assert_png_not_blank(tmp_path / "g.png")


# --------------------------------------------------------------------------------------------- README
def test_readme_ros_lines_are_true(tmp_path, monkeypatch) -> None:  # type: ignore[no-untyped-def]
    text = (ROOT / "README.md").read_text()
    block = re.search(r"### ROS 2\n\n```python\n(.*?)```", text, flags=re.S)
    assert block is not None
    code = block.group(1)
    assert 'write_ros2_yaml(traj, "trajectory.yaml")' in code and 'write_mcap(traj, "trajectory")' in code
    monkeypatch.chdir(tmp_path)
    exec(compile(code, "README.md", "exec"), {})
    msg = yaml.safe_load((tmp_path / "trajectory.yaml").read_text())
    assert msg["joint_names"] == ["cart_a", "cart_b"] and len(msg["points"]) > 100
    assert sorted(p.name for p in (tmp_path / "trajectory").iterdir()) == ["metadata.yaml", "trajectory.mcap"]
    with Reader(tmp_path / "trajectory") as reader:
        assert reader.message_count == len(msg["points"]) + 1
