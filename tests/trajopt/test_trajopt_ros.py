"""ROS 2 exports: the JointTrajectory YAML parses and equals the CSV rows; the MCAP bag reads back with rosbags."""

from __future__ import annotations

import csv
import os

import numpy as np
import pytest
import yaml
from rosbags.rosbag2 import Reader
from rosbags.typesys import Stores, get_typestore

from mpa import Circle, InvalidInputError, Lollipop
from trajopt import generate_trajectory
from trajopt.io.ros import ros2_yaml_text, split_ns, write_mcap, write_ros2_yaml

NS = 1e-9  # one nanosecond (s)


@pytest.fixture(scope="module")
def traj():  # type: ignore[no-untyped-def]
    return generate_trajectory(Lollipop(1.0, 1.0), (0.2, 0.5), (0.5, 0.2), vmax=0.4, amax=0.8, jmax=3.0, rate=50.0)


def csv_rows(traj, tmp_path, rate=None):  # type: ignore[no-untyped-def]
    path = tmp_path / "sp.csv"
    traj.to_csv(path, rate=rate)
    with open(path, newline="") as fh:
        rows = list(csv.reader(fh))
    data = np.array([r[:11] for r in rows[1:]], dtype=float)
    h = rows[0]
    return (
        data[:, 0],
        data[:, [h.index("a_s"), h.index("b_s")]],
        data[:, [h.index("a_v"), h.index("b_v")]],
        data[:, [h.index("a_a"), h.index("b_a")]],
    )


def test_split_ns() -> None:
    assert split_ns(0) == (0, 0)
    assert split_ns(1_999_999_999) == (1, 999_999_999)
    assert split_ns(3_000_000_000) == (3, 0)


@pytest.mark.parametrize("rate", [None, 20.0])
def test_yaml_parses_and_equals_csv(traj, tmp_path, rate) -> None:  # type: ignore[no-untyped-def]
    path = tmp_path / "trajectory.yaml"
    write_ros2_yaml(traj, path, rate=rate)
    assert sorted(os.listdir(tmp_path)) == ["trajectory.yaml"]
    msg = yaml.safe_load(path.read_text())
    assert msg["joint_names"] == ["cart_a", "cart_b"]
    assert msg["header"] == {"stamp": {"sec": 0, "nanosec": 0}, "frame_id": ""}
    t, s, v, a = csv_rows(traj, tmp_path, rate)
    pts = msg["points"]
    assert len(pts) == len(t)
    for k, p in enumerate(pts):
        assert set(p) == {"positions", "velocities", "accelerations", "effort", "time_from_start"}
        assert all(isinstance(x, float) for x in p["positions"] + p["velocities"] + p["accelerations"]), k
        tf = p["time_from_start"]
        assert 0 <= tf["nanosec"] < 1_000_000_000
        assert abs(tf["sec"] + tf["nanosec"] * 1e-9 - t[k]) <= NS, k
        np.testing.assert_allclose(p["positions"], s[k], rtol=1e-11, atol=1e-12, err_msg=f"row {k}")
        np.testing.assert_allclose(p["velocities"], v[k], rtol=1e-11, atol=1e-12, err_msg=f"row {k}")
        np.testing.assert_allclose(p["accelerations"], a[k], rtol=1e-11, atol=1e-12, err_msg=f"row {k}")
    # exact: YAML floats are the arrays' own bits
    if rate is None:
        got = np.array([p["positions"] for p in pts])
        assert np.array_equal(got, traj.s)
    # first point at the start, last at rest
    assert pts[0]["positions"] == [0.0, 0.0]
    assert pts[-1]["velocities"] == [0.0, 0.0] or np.max(np.abs(pts[-1]["velocities"])) <= 1e-9


def test_yaml_options() -> None:
    tr = generate_trajectory(Circle(1.0), (0.1, 0.6), (0.3, 0.8), rate=20.0)
    text = ros2_yaml_text(tr, joint_names=["left", "right"], header=False)
    msg = yaml.safe_load(text)
    assert "header" not in msg and msg["joint_names"] == ["left", "right"]
    msg = yaml.safe_load(ros2_yaml_text(tr, frame_id="it's", stamp_ns=5_000_000_001))
    assert msg["header"] == {"stamp": {"sec": 5, "nanosec": 1}, "frame_id": "it's"}
    assert yaml.safe_load("x: " + __import__("trajopt.io.ros", fromlist=["_f"])._f(1e-5))["x"] == 1e-5


@pytest.mark.parametrize(
    ("kwargs", "match"),
    [
        ({"joint_names": ["a"]}, "expected two names"),
        ({"joint_names": ["a", "a"]}, "distinct"),
        ({"joint_names": ["a", "1b"]}, "not a ROS name"),
        ({"stamp_ns": -1}, "stamp_ns"),
        ({"rate": 0}, "rate"),
    ],
)
def test_yaml_bad_input(traj, tmp_path, kwargs, match) -> None:  # type: ignore[no-untyped-def]
    with pytest.raises(InvalidInputError, match=match):
        write_ros2_yaml(traj, tmp_path / "t.yaml", **kwargs)
    assert list(tmp_path.iterdir()) == []


def read_bag(path):  # type: ignore[no-untyped-def]
    ts = get_typestore(Stores.ROS2_HUMBLE)
    out: dict[str, list] = {}
    meta = yaml.safe_load((path / "metadata.yaml").read_text())["rosbag2_bagfile_information"]
    assert meta["storage_identifier"] == "mcap"
    with Reader(path) as reader:
        for conn, stamp, raw in reader.messages():
            out.setdefault(conn.topic, []).append((conn.msgtype, stamp, ts.deserialize_cdr(raw, conn.msgtype)))
    return out


def test_mcap_round_trip(traj, tmp_path) -> None:  # type: ignore[no-untyped-def]
    bag = tmp_path / "trajectory"
    mcap = write_mcap(traj, bag, stamp_ns=1_700_000_000_000_000_000)
    assert mcap == bag / "trajectory.mcap" and mcap.is_file()
    assert mcap.read_bytes()[:8] == b"\x89MCAP0\r\n"
    assert sorted(os.listdir(tmp_path)) == ["trajectory"]
    assert sorted(os.listdir(bag)) == ["metadata.yaml", "trajectory.mcap"]
    t, s, v, a = csv_rows(traj, tmp_path)
    msgs = read_bag(bag)
    assert set(msgs) == {"/joint_trajectory", "/joint_trajectory_point"}
    ((typ, stamp, jt),) = msgs["/joint_trajectory"]
    assert typ == "trajectory_msgs/msg/JointTrajectory" and stamp == 1_700_000_000_000_000_000
    assert list(jt.joint_names) == ["cart_a", "cart_b"]
    assert (jt.header.stamp.sec, jt.header.stamp.nanosec) == (1_700_000_000, 0)
    assert len(jt.points) == len(t)
    pts = msgs["/joint_trajectory_point"]
    assert len(pts) == len(t)
    for k, ((typ, stamp, p), q) in enumerate(zip(pts, jt.points)):
        assert typ == "trajectory_msgs/msg/JointTrajectoryPoint"
        assert abs((stamp - 1_700_000_000_000_000_000) * 1e-9 - t[k]) <= NS, k
        for m in (p, q):
            assert abs(m.time_from_start.sec + m.time_from_start.nanosec * 1e-9 - t[k]) <= NS, k
            np.testing.assert_allclose(m.positions, s[k], rtol=1e-11, atol=1e-12, err_msg=f"row {k}")
            np.testing.assert_allclose(m.velocities, v[k], rtol=1e-11, atol=1e-12, err_msg=f"row {k}")
            np.testing.assert_allclose(m.accelerations, a[k], rtol=1e-11, atol=1e-12, err_msg=f"row {k}")
            assert len(m.effort) == 0
    # exact: the doubles themselves
    assert np.array_equal(np.array([p.positions for _, _, p in pts]), traj.s)
    assert np.array_equal(np.array([p.velocities for _, _, p in pts]), traj.v)


def test_mcap_options_and_overwrite(traj, tmp_path) -> None:  # type: ignore[no-untyped-def]
    bag = tmp_path / "b"
    write_mcap(traj, bag, rate=10.0)
    write_mcap(traj, bag, joint_names=("x", "y"), topic="/carts/traj", point_topic=None)  # replaces the bag
    assert sorted(os.listdir(tmp_path)) == ["b"]
    msgs = read_bag(bag)
    assert set(msgs) == {"/carts/traj"}
    ((_, _, jt),) = msgs["/carts/traj"]
    assert list(jt.joint_names) == ["x", "y"] and len(jt.points) == len(traj.t)


@pytest.mark.parametrize(
    ("kwargs", "match"),
    [
        ({"topic": "no spaces"}, "topic"),
        ({"topic": "/a//b"}, "topic"),
        ({"point_topic": "/joint_trajectory"}, "other than"),
        ({"joint_names": ("a", "b", "c")}, "expected two names"),
    ],
)
def test_mcap_bad_input(traj, tmp_path, kwargs, match) -> None:  # type: ignore[no-untyped-def]
    with pytest.raises(InvalidInputError, match=match):
        write_mcap(traj, tmp_path / "bag", **kwargs)
    assert list(tmp_path.iterdir()) == []


def test_mcap_refuses_to_replace_a_non_bag(traj, tmp_path) -> None:  # type: ignore[no-untyped-def]
    (tmp_path / "f").write_text("keep")
    with pytest.raises(InvalidInputError, match="not a rosbag2 bag"):
        write_mcap(traj, tmp_path / "f")
    assert (tmp_path / "f").read_text() == "keep" and sorted(os.listdir(tmp_path)) == ["f"]
