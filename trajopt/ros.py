"""ROS 2 exports of a verified :class:`~trajopt.export.Trajectory`: a ``JointTrajectory`` as YAML, and an MCAP bag.

Both carry the same points as the CSV (:meth:`Trajectory.resample`): one point per row, ``positions`` the route
coordinates ``a_s, b_s`` (m; what a cart's odometer measures, continuous through P and round the loop),
``velocities`` and ``accelerations`` their first two time derivatives (m/s, m/s²), ``time_from_start`` the row's
time as ``{sec, nanosec}`` (rounded to the nanosecond). Joint ``i`` of the message is robot A (``i = 0``) or B.

- :func:`ros2_yaml_text` / :func:`write_ros2_yaml`: a ``trajectory_msgs/msg/JointTrajectory`` written as YAML by
  hand (no YAML library needed), in the layout of ``ros2 topic echo``; it can be published with
  ``ros2 topic pub --once /joint_trajectory_controller/joint_trajectory trajectory_msgs/msg/JointTrajectory
  "$(cat trajectory.yaml)"``. Floats are written with 17 significant digits and always with a decimal point
  (``1.0e-05``), so that YAML 1.1 readers (PyYAML) read them as floats, bit for bit.
- :func:`write_mcap`: a rosbag2 bag (storage ``mcap``) written with the optional dependency ``rosbags``
  (``pip install 'lollipop-mpa[ros]'``). A rosbag2 bag is a directory: ``PATH/metadata.yaml`` and the
  self-contained MCAP file ``PATH/<name of PATH>.mcap`` (message definitions embedded), so ``ros2 bag play PATH``
  replays it and the ``.mcap`` file alone opens in MCAP tools. Topics: the whole ``JointTrajectory`` on ``topic``
  (default ``/joint_trajectory``) at ``stamp_ns``, and every row as a ``trajectory_msgs/msg/JointTrajectoryPoint``
  on ``point_topic`` (default ``/joint_trajectory_point``) stamped ``stamp_ns + time`` (ns).

All writes are atomic: the YAML through :func:`trajopt.export.atomic_write_text`; the bag is written into a
temporary directory beside ``PATH`` and moved into place with :func:`os.replace` (an existing bag at ``PATH`` is
replaced only once the new one is complete).
"""

from __future__ import annotations

import os
import re
import shutil
import tempfile
from collections.abc import Callable, Iterator, Sequence
from pathlib import Path
from typing import Any

import numpy as np
from numpy.typing import NDArray

from mpa.errors import InvalidInputError
from trajopt.export import Trajectory, atomic_write_text

__all__ = [
    "DEFAULT_JOINT_NAMES",
    "DEFAULT_POINT_TOPIC",
    "DEFAULT_TOPIC",
    "JointPoints",
    "check_joint_names",
    "check_topic",
    "joint_points",
    "ros2_yaml_text",
    "split_ns",
    "write_mcap",
    "write_ros2_yaml",
]

FloatArray = NDArray[np.float64]
#: Joint names of robot A and robot B.
DEFAULT_JOINT_NAMES = ("cart_a", "cart_b")
#: Topic of the whole ``JointTrajectory`` message in the bag.
DEFAULT_TOPIC = "/joint_trajectory"
#: Topic of the per-row ``JointTrajectoryPoint`` messages in the bag.
DEFAULT_POINT_TOPIC = "/joint_trajectory_point"
#: ROS 2 distribution whose message definitions are stored in the bag (the trajectory messages are identical in all).
ROS_DISTRO = "humble"

_NAME_RE = re.compile(r"^[A-Za-z_][A-Za-z0-9_]*$")
_TOPIC_RE = re.compile(r"^/?[A-Za-z_][A-Za-z0-9_]*(/[A-Za-z_][A-Za-z0-9_]*)*$")


class JointPoints:
    """The points of a trajectory message: ``t`` (N,) s, ``ns`` (N,) int nanoseconds, ``positions``,
    ``velocities``, ``accelerations`` (N, 2) in m, m/s, m/s² (column 0 = robot A)."""

    __slots__ = ("accelerations", "ns", "positions", "t", "velocities")

    def __init__(self, t: FloatArray, s: FloatArray, v: FloatArray, a: FloatArray) -> None:
        self.t = t
        self.ns = np.rint(np.asarray(t) * 1e9).astype(np.int64)
        self.positions = s
        self.velocities = v
        self.accelerations = a


def joint_points(trajectory: Trajectory, rate: float | None = None) -> JointPoints:
    """The rows of ``trajectory`` (at ``rate`` Hz, default its own) as message points."""
    t, _tr, s, v, a, _j = trajectory.resample(rate)
    return JointPoints(t, s, v, a)


def split_ns(ns: int) -> tuple[int, int]:
    """``builtin_interfaces/Duration`` fields ``(sec, nanosec)`` of a non-negative time in nanoseconds."""
    sec, nsec = divmod(int(ns), 1_000_000_000)
    return sec, nsec


def check_joint_names(joint_names: Any) -> tuple[str, str]:
    """Validate the joint names: two distinct ROS names (letters, digits, ``_``; not starting with a digit).

    Raises
    ------
    InvalidInputError
    """
    if isinstance(joint_names, str):
        joint_names = [x.strip() for x in joint_names.split(",")]
    try:
        names = tuple(str(x) for x in joint_names)
    except TypeError:
        raise InvalidInputError(f"joint names are {joint_names!r}, expected two names (robot A, robot B)") from None
    if len(names) != 2:
        raise InvalidInputError(f"joint names are {list(names)!r}, expected two names (robot A, robot B)")
    for x in names:
        if not _NAME_RE.match(x):
            raise InvalidInputError(
                f"joint name {x!r} is not a ROS name, expected letters, digits and '_', not starting with a digit"
            )
    if names[0] == names[1]:
        raise InvalidInputError(f"joint names are both {names[0]!r}, expected two distinct names")
    return names[0], names[1]


def check_topic(topic: Any, name: str = "topic") -> str:
    """Validate a ROS 2 topic name (``/a/b_c``: tokens of letters, digits and ``_``, not starting with a digit).

    Raises
    ------
    InvalidInputError
    """
    if not isinstance(topic, str) or not _TOPIC_RE.match(topic):
        raise InvalidInputError(f"{name} is {topic!r}, expected a ROS 2 topic name such as '/joint_trajectory'")
    return topic if topic.startswith("/") else "/" + topic


def _f(x: float) -> str:
    """A float as YAML 1.1 reads it back exactly: 17 significant digits, always a '.' before any exponent."""
    r = repr(float(x))
    if "e" in r:
        mant, exp = r.split("e")
        if "." not in mant:
            mant += ".0"
        if exp[0] not in "+-":
            exp = "+" + exp
        return f"{mant}e{exp}"
    if "." not in r and r not in ("inf", "-inf", "nan"):
        r += ".0"
    return r


def _quote(s: str) -> str:
    return "'" + s.replace("'", "''") + "'"


def ros2_yaml_text(
    trajectory: Trajectory,
    *,
    joint_names: Sequence[str] = DEFAULT_JOINT_NAMES,
    header: bool = True,
    frame_id: str = "",
    stamp_ns: int = 0,
    rate: float | None = None,
) -> str:
    """The ``trajectory_msgs/msg/JointTrajectory`` of ``trajectory`` as YAML text.

    Parameters
    ----------
    trajectory : Trajectory
        A verified trajectory.
    joint_names : sequence of str
        Names of robot A's and robot B's joints.
    header : bool
        Write the ``header`` (``stamp`` ``stamp_ns``, ``frame_id``); a zero stamp means "start on receipt".
    frame_id : str
    stamp_ns : int
        Header stamp (ns since the epoch), >= 0.
    rate : float, optional
        Row rate (Hz); default the trajectory's own.

    Returns
    -------
    str

    Raises
    ------
    InvalidInputError
        Bad joint names, stamp or rate.
    """
    names = check_joint_names(joint_names)
    stamp = _check_stamp(stamp_ns)
    pts = joint_points(trajectory, rate)
    out: list[str] = []
    if header:
        sec, nsec = split_ns(stamp)
        out += ["header:", "  stamp:", f"    sec: {sec}", f"    nanosec: {nsec}", f"  frame_id: {_quote(frame_id)}"]
    out += ["joint_names:", *(f"- {n}" for n in names), "points:"]
    return "\n".join(out) + "\n" + "".join(_points_yaml(pts))


#: One point of :func:`ros2_yaml_text`: positions, velocities, accelerations (two each, :func:`_f`), sec, nanosec.
_POINT = (
    "- positions: [%s, %s]\n  velocities: [%s, %s]\n  accelerations: [%s, %s]\n  effort: []\n"
    "  time_from_start:\n    sec: %d\n    nanosec: %d\n"
)
#: Points formatted at once by :func:`_points_yaml`.
_POINTS_PER_PIECE = 20000


def _floats_yaml(x: FloatArray) -> list[str]:
    """:func:`_f` of every value: ``repr`` (mapped in C), fixed where it has an exponent or is not finite."""
    v = np.asarray(x, dtype=float).ravel()
    out = list(map(repr, v.tolist()))
    ax = np.abs(v)
    for i in np.flatnonzero(~((ax == 0.0) | ((ax >= 1e-4) & (ax < 1e16)))).tolist():
        out[i] = _f(float(v[i]))  # repr has an exponent (or is inf/nan) here
    return out


def _points_yaml(pts: JointPoints) -> Iterator[str]:
    """The ``points`` of :func:`ros2_yaml_text`, in pieces of :data:`_POINTS_PER_PIECE` points (one ``%`` each)."""
    for i in range(0, len(pts.t), _POINTS_PER_PIECE):
        sl = slice(i, i + _POINTS_PER_PIECE)
        cols = [
            _floats_yaml(np.asarray(x)[sl, r])
            for x in (pts.positions, pts.velocities, pts.accelerations)
            for r in (0, 1)
        ]
        sec, nsec = np.divmod(pts.ns[sl], 1_000_000_000)
        cells = [*cols, sec.tolist(), nsec.tolist()]
        yield (_POINT * len(cells[-1])) % tuple(v for row in zip(*cells, strict=True) for v in row)


def write_ros2_yaml(trajectory: Trajectory, path: str | os.PathLike[str], **kwargs: Any) -> None:
    """Write :func:`ros2_yaml_text` to ``path`` atomically (same keyword arguments)."""
    text = ros2_yaml_text(trajectory, **kwargs)
    atomic_write_text(path, text)


def _check_stamp(stamp_ns: Any) -> int:
    try:
        v = int(stamp_ns)
    except (TypeError, ValueError, OverflowError):
        raise InvalidInputError(f"stamp_ns is {stamp_ns!r}, expected a non-negative integer (ns)") from None
    if v != stamp_ns or v < 0:
        raise InvalidInputError(f"stamp_ns is {stamp_ns!r}, expected a non-negative integer (ns)")
    return v


def _typestore() -> Any:
    try:
        from rosbags.typesys import Stores, get_typestore
    except ImportError:
        raise InvalidInputError(
            "format mcap needs the optional dependency rosbags, expected it installed (pip install 'lollipop-mpa[ros]')"
        ) from None
    return get_typestore(Stores.ROS2_HUMBLE)


def write_mcap(
    trajectory: Trajectory,
    path: str | os.PathLike[str],
    *,
    joint_names: Sequence[str] = DEFAULT_JOINT_NAMES,
    topic: str = DEFAULT_TOPIC,
    point_topic: str | None = DEFAULT_POINT_TOPIC,
    frame_id: str = "",
    stamp_ns: int = 0,
    rate: float | None = None,
) -> Path:
    """Write ``trajectory`` as a rosbag2 bag with MCAP storage (a directory; see the module docstring).

    Parameters
    ----------
    trajectory : Trajectory
    path : path-like
        The bag directory; it holds ``metadata.yaml`` and ``<name>.mcap``. An existing bag there is replaced.
    joint_names : sequence of str
    topic : str
        Topic of the ``JointTrajectory`` message (stamped ``stamp_ns``).
    point_topic : str or None
        Topic of the per-row ``JointTrajectoryPoint`` messages (stamped ``stamp_ns`` + row time); None omits them.
    frame_id : str
    stamp_ns : int
        Bag time of the trajectory's start (ns since the epoch).
    rate : float, optional
        Row rate (Hz); default the trajectory's own.

    Returns
    -------
    Path
        The MCAP file inside the bag.

    Raises
    ------
    InvalidInputError
        Bad names, stamp or rate; ``rosbags`` not installed; ``path`` exists and is not a rosbag2 bag.
    """
    names = check_joint_names(joint_names)
    topic, point_topic = _check_topics(topic, point_topic)
    stamp = _check_stamp(stamp_ns)
    pts = joint_points(trajectory, rate)
    target = _check_bag_path(path)
    ts = _typestore()
    msg, points = _joint_trajectory_messages(ts, pts, names, stamp, frame_id)
    point_stamps = [stamp + int(pts.ns[k]) for k in range(len(points))]
    _write_directory_atomically(
        target, lambda bag: _write_bag(bag, ts, (topic, stamp, msg), point_topic, point_stamps, points)
    )
    return target / f"{target.name}.mcap"


def _check_topics(topic: str, point_topic: str | None) -> tuple[str, str | None]:
    """The trajectory's topic and the points' topic (or None), checked, and distinct."""
    topic = check_topic(topic)
    if point_topic is not None:
        point_topic = check_topic(point_topic, "point topic")
        if point_topic == topic:
            raise InvalidInputError(f"point topic is {point_topic!r}, expected a topic other than {topic!r}")
    return topic, point_topic


def _write_bag(
    bag: Path,
    ts: Any,
    trajectory_message: tuple[str, int, Any],
    point_topic: str | None,
    point_stamps: Sequence[int],
    points: Sequence[Any],
) -> None:
    """Write a rosbag2 bag (MCAP storage) at ``bag``: the ``JointTrajectory`` message ``(topic, stamp, message)`` and,
    unless ``point_topic`` is None, each ``JointTrajectoryPoint`` at its stamp (ns)."""
    from rosbags.rosbag2 import StoragePlugin, Writer

    topic, stamp, msg = trajectory_message
    T = ts.types
    jt = T["trajectory_msgs/msg/JointTrajectory"].__msgtype__
    jtp = T["trajectory_msgs/msg/JointTrajectoryPoint"].__msgtype__
    writer = Writer(bag, version=9, storage_plugin=StoragePlugin.MCAP)
    writer.open()
    try:
        conn = writer.add_connection(topic, jt, typestore=ts)
        writer.write(conn, stamp, ts.serialize_cdr(msg, jt))
        if point_topic is not None:
            pconn = writer.add_connection(point_topic, jtp, typestore=ts)
            for k, p in enumerate(points):
                writer.write(pconn, point_stamps[k], ts.serialize_cdr(p, jtp))
    finally:
        writer.close()


def _check_bag_path(path: str | os.PathLike[str]) -> Path:
    """The bag directory: a new path or an existing rosbag2 bag (to be replaced)."""
    target = Path(path)
    if target.exists() and not (target.is_dir() and (target / "metadata.yaml").is_file()):
        raise InvalidInputError(f"bag path {str(target)!r} exists and is not a rosbag2 bag, expected a new path")
    if not target.name or target.name in (".", ".."):
        raise InvalidInputError(f"bag path is {str(target)!r}, expected a directory name")
    return target


def _joint_trajectory_messages(
    ts: Any, pts: JointPoints, names: tuple[str, str], stamp: int, frame_id: str
) -> tuple[Any, list[Any]]:
    """The ``JointTrajectory`` message stamped ``stamp`` (ns) and its ``JointTrajectoryPoint`` messages (rosbags
    types of the typestore ``ts``)."""
    T = ts.types
    Time, Duration, Header = (
        T["builtin_interfaces/msg/Time"],
        T["builtin_interfaces/msg/Duration"],
        T["std_msgs/msg/Header"],
    )
    JT, JTP = T["trajectory_msgs/msg/JointTrajectory"], T["trajectory_msgs/msg/JointTrajectoryPoint"]
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


def _write_directory_atomically(target: Path, write: Callable[[Path], None]) -> None:
    """``write(d)`` fills a new directory ``d`` in a temporary directory beside ``target``, which then replaces
    ``target`` (restored if the replacement fails); nothing is left behind on failure."""
    parent = target.parent if str(target.parent) else Path(".")
    tmp = Path(tempfile.mkdtemp(dir=parent, prefix=f".{target.name}.", suffix=".tmp"))
    try:
        bag = tmp / target.name
        write(bag)
        os.chmod(bag, 0o777 & ~_umask())
        if target.exists():
            old = tmp / ".old"
            os.replace(target, old)
            try:
                os.replace(bag, target)
            except BaseException:
                os.replace(old, target)
                raise
        else:
            os.replace(bag, target)
    finally:
        shutil.rmtree(tmp, ignore_errors=True)


def _umask() -> int:
    mask = os.umask(0o022)
    os.umask(mask)
    return mask
