"""The MCAP bag written a chunk at a time is, byte for byte, the bag of one ``rosbags`` message object per point.

The reference below is the per-point writer (a ``JointTrajectoryPoint`` object per row, ``serialize_cdr``, one
``Writer.write`` per message); :func:`trajopt.io.ros.write_mcap` encodes the CDR itself and writes the points' records
a chunk at a time, and must give the same file.
"""

from __future__ import annotations

import json
from pathlib import Path
from typing import Any

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from rosbags.rosbag2 import StoragePlugin, Writer
from rosbags.typesys import Stores, get_typestore

import trajopt.io.ros as ros
from mpa import GraphTrack, Lollipop
from trajopt import generate_trajectory
from trajopt.io.ros import JointPoints, joint_points, joint_trajectory_cdr, joint_trajectory_point_cdr, split_ns

ROOT = Path(__file__).resolve().parents[2]
TS = get_typestore(Stores.ROS2_HUMBLE)
T = TS.types
JT, JTP = T["trajectory_msgs/msg/JointTrajectory"], T["trajectory_msgs/msg/JointTrajectoryPoint"]


def _objects(pts: JointPoints, names: tuple[str, str], stamp: int, frame_id: str) -> tuple[Any, list[Any]]:
    Time, Duration, Header = (
        T[f"{x}"] for x in ("builtin_interfaces/msg/Time", "builtin_interfaces/msg/Duration", "std_msgs/msg/Header")
    )
    empty = np.zeros(0, dtype=np.float64)
    points = [
        JTP(
            positions=np.array(pts.positions[k], dtype=np.float64),
            velocities=np.array(pts.velocities[k], dtype=np.float64),
            accelerations=np.array(pts.accelerations[k], dtype=np.float64),
            effort=empty,
            time_from_start=Duration(*split_ns(int(pts.ns[k]))),
        )
        for k in range(len(pts.t))
    ]
    msg = JT(header=Header(stamp=Time(*split_ns(stamp)), frame_id=frame_id), joint_names=list(names), points=points)
    return msg, points


def _reference_bag(
    bag: Path, pts: JointPoints, names: tuple[str, str], stamp: int, frame_id: str, point_topic: str | None
) -> bytes:
    msg, points = _objects(pts, names, stamp, frame_id)
    writer = Writer(bag, version=9, storage_plugin=StoragePlugin.MCAP)
    writer.open()
    conn = writer.add_connection("/joint_trajectory", JT.__msgtype__, typestore=TS)
    writer.write(conn, stamp, TS.serialize_cdr(msg, JT.__msgtype__))
    if point_topic is not None:
        pconn = writer.add_connection(point_topic, JTP.__msgtype__, typestore=TS)
        for k, p in enumerate(points):
            writer.write(pconn, stamp + int(pts.ns[k]), TS.serialize_cdr(p, JTP.__msgtype__))
    writer.close()
    return (bag / f"{bag.name}.mcap").read_bytes() + (bag / "metadata.yaml").read_bytes()


def _new_bag(
    tmp: Path, traj: Any, rate: float | None, names: tuple[str, str], stamp: int, frame_id: str, point_topic: str | None
) -> bytes:
    tmp.mkdir()
    bag = tmp / "bag"
    ros.write_mcap(traj, bag, joint_names=names, stamp_ns=stamp, frame_id=frame_id, point_topic=point_topic, rate=rate)
    return (bag / "bag.mcap").read_bytes() + (bag / "metadata.yaml").read_bytes()


@pytest.fixture(scope="module")
def layout_motion() -> Any:
    track = GraphTrack.from_layout(json.loads((ROOT / "examples" / "tracks" / "y_junction.json").read_text()))
    return generate_trajectory(track, ((1, 1.5), (2, 2.0)), ((2, 2.5), (1, 1.0)))


CASES = [
    ("paper", None, ("cart_a", "cart_b"), 0, "", "/joint_trajectory_point"),
    ("paper", 37.0, ("a", "bb"), 1_700_000_000_123_456_789, "map", None),
    ("layout", 1000.0, ("left_cart", "r"), 5, "wörld/frame", "/points"),  # 11 771 rows of 119 bytes: two chunks
    ("layout", 3.0, ("abc", "defg"), 2**40, "xyz1", "/p"),
]


@pytest.mark.parametrize(("which", "rate", "names", "stamp", "frame_id", "point_topic"), CASES)
@pytest.mark.parametrize("batched", [True, False])
def test_the_streamed_bag_is_the_per_point_bag_byte_for_byte(
    which: str,
    rate: float | None,
    names: tuple[str, str],
    stamp: int,
    frame_id: str,
    point_topic: str | None,
    batched: bool,
    layout_motion: Any,
    tmp_path: Path,
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    traj = layout_motion if which == "layout" else generate_trajectory(Lollipop(1, 1), (0.2, 0.5), (0.5, 0.2))
    if not batched:  # any other storage: one writer.write per message
        monkeypatch.setattr(ros, "_batched", lambda storage: False)
    new = _new_bag(tmp_path / "new", traj, rate, names, stamp, frame_id, point_topic)
    (tmp_path / "old").mkdir()
    old = _reference_bag(tmp_path / "old" / "bag", joint_points(traj, rate), names, stamp, frame_id, point_topic)
    print(which, rate, len(old), len(new))
    assert new == old


ROW = st.floats(min_value=-1e6, max_value=1e6, allow_nan=False)
NAME = st.from_regex(r"[A-Za-z_][A-Za-z0-9_]{0,9}", fullmatch=True)


@settings(max_examples=40, deadline=None)
@given(
    st.lists(st.tuples(ROW, ROW, ROW, ROW, ROW, ROW), min_size=0, max_size=7),
    st.tuples(NAME, NAME),
    st.integers(min_value=0, max_value=ros.MAX_STAMP_NS - 1),
    st.text(max_size=9),
)
def test_the_messages_are_the_bytes_rosbags_serializes(
    rows: list[tuple[float, ...]], names: tuple[str, str], stamp: int, frame_id: str
) -> None:
    x = np.array(rows, dtype=np.float64).reshape(len(rows), 6)
    t = np.sort(np.abs(x[:, 0])) / 7.0
    pts = JointPoints(t, x[:, 0:2], x[:, 2:4], x[:, 4:6])
    msg, points = _objects(pts, names, stamp, frame_id)
    assert joint_trajectory_cdr(pts, names, stamp, frame_id) == TS.serialize_cdr(msg, JT.__msgtype__)
    data = joint_trajectory_point_cdr(pts)
    assert data.shape == (len(rows), 88)
    for k, p in enumerate(points):
        assert data[k].tobytes() == TS.serialize_cdr(p, JTP.__msgtype__)


@pytest.mark.parametrize("stamp", [ros.MAX_STAMP_NS, 2**62])
def test_a_stamp_past_the_int32_seconds_is_an_input_error(stamp: int, tmp_path: Path) -> None:
    """``builtin_interfaces/Time`` holds int32 seconds: rosbags raised ``struct.error`` (exit 4) for such a stamp."""
    traj = generate_trajectory(Lollipop(1, 1), (0.2, 0.5), (0.5, 0.2))
    with pytest.raises(ros.InvalidInputError, match="stamp_ns"):
        ros.write_mcap(traj, tmp_path / "bag", stamp_ns=stamp)
    with pytest.raises(ros.InvalidInputError, match="stamp_ns"):
        ros.ros2_yaml_text(traj, stamp_ns=stamp)
    assert not (tmp_path / "bag").exists()


def test_a_bag_path_whose_directory_is_missing_is_an_input_error_naming_it(tmp_path: Path) -> None:
    """``write_mcap`` into a missing directory raised a raw ``FileNotFoundError`` (exit 4); it is an input error
    naming the path and its directory, and nothing is created."""
    traj = generate_trajectory(Lollipop(1, 1), (0.2, 0.5), (0.5, 0.2))
    bag = tmp_path / "missing" / "deeper" / "bag"
    with pytest.raises(ros.InvalidInputError, match="does not exist") as info:
        ros.write_mcap(traj, bag)
    assert str(bag) in str(info.value) and str(bag.parent) in str(info.value)
    assert not (tmp_path / "missing").exists()
    assert list(tmp_path.iterdir()) == []


def test_a_bag_is_replaced_as_a_whole_and_kept_when_the_write_fails(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    """An existing bag is replaced by the new one (the same bytes as a bag written to a new path), with no
    temporary left beside it; a write that fails with an ``OSError`` is an input error and the old bag is
    untouched. Both with the one-step exchange and with the two renames where it is missing."""
    import trajopt.io.directory as directory

    short = generate_trajectory(Lollipop(1, 1), (0.2, 0.5), (0.5, 0.2))
    other = generate_trajectory(Lollipop(1, 1), (0.1, 0.6), (0.8, 0.3))
    (tmp_path / "fresh").mkdir()
    fresh = ros.write_mcap(other, tmp_path / "fresh" / "bag")
    for exchange in (True, False):
        d = tmp_path / f"exchange_{exchange}"
        d.mkdir()
        if not exchange:
            monkeypatch.setattr(directory, "_exchange", lambda a, b: False)
        bag = d / "bag"
        old = ros.write_mcap(short, bag).read_bytes()
        new = ros.write_mcap(other, bag)
        assert new.read_bytes() == fresh.read_bytes() != old
        assert sorted(p.name for p in d.iterdir()) == ["bag"]

        def fail(*args: Any) -> None:
            raise OSError(28, "No space left on device")

        with monkeypatch.context() as m:
            m.setattr(ros, "_write_bag", fail)
            with pytest.raises(ros.InvalidInputError, match="cannot write: No space left on device"):
                ros.write_mcap(short, bag)
        assert new.read_bytes() == fresh.read_bytes()
        assert sorted(p.name for p in d.iterdir()) == ["bag"]
