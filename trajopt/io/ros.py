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
import struct
from collections.abc import Iterator, Sequence
from pathlib import Path
from typing import Any

import numpy as np
from numpy.typing import NDArray

from mpa._arrays import FloatArray
from mpa._deprecation import deprecated_alias
from mpa.errors import InvalidInputError
from trajopt.export import Trajectory, atomic_write_text
from trajopt.io.directory import atomic_directory

__all__ = [
    "DEFAULT_JOINT_NAMES",
    "DEFAULT_POINT_TOPIC",
    "DEFAULT_TOPIC",
    "MAX_STAMP_NS",
    "JointPoints",
    "joint_points",
    "ros2_yaml_text",
    "split_ns",
    "validate_joint_names",
    "validate_topic",
    "write_mcap",
    "write_ros2_yaml",
]

#: Joint names of robot A and robot B.
DEFAULT_JOINT_NAMES = ("cart_a", "cart_b")
#: Topic of the whole ``JointTrajectory`` message in the bag.
DEFAULT_TOPIC = "/joint_trajectory"
#: Topic of the per-row ``JointTrajectoryPoint`` messages in the bag.
DEFAULT_POINT_TOPIC = "/joint_trajectory_point"
#: ROS 2 distribution whose message definitions are stored in the bag (the trajectory messages are identical in all).
ROS_DISTRO = "humble"

#: Stamps (ns) from this on do not fit the int32 ``sec`` of ``builtin_interfaces/msg/Time``.
MAX_STAMP_NS = 2**31 * 1_000_000_000

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


def validate_joint_names(joint_names: Any) -> tuple[str, str]:
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


#: Deprecated name of :func:`validate_joint_names` (warns).
check_joint_names = deprecated_alias(validate_joint_names, "check_joint_names")


def validate_topic(topic: Any, name: str = "topic") -> str:
    """Validate a ROS 2 topic name (``/a/b_c``: tokens of letters, digits and ``_``, not starting with a digit).

    Raises
    ------
    InvalidInputError
    """
    if not isinstance(topic, str) or not _TOPIC_RE.match(topic):
        raise InvalidInputError(f"{name} is {topic!r}, expected a ROS 2 topic name such as '/joint_trajectory'")
    return topic if topic.startswith("/") else "/" + topic


#: Deprecated name of :func:`validate_topic` (warns).
check_topic = deprecated_alias(validate_topic, "check_topic")


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
    names = validate_joint_names(joint_names)
    stamp = _validate_stamp(stamp_ns)
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


def _validate_stamp(stamp_ns: Any) -> int:
    try:
        v = int(stamp_ns)
    except (TypeError, ValueError, OverflowError):
        raise InvalidInputError(f"stamp_ns is {stamp_ns!r}, expected a non-negative integer (ns)") from None
    if v != stamp_ns or v < 0:
        raise InvalidInputError(f"stamp_ns is {stamp_ns!r}, expected a non-negative integer (ns)")
    if v >= MAX_STAMP_NS:
        raise InvalidInputError(
            f"stamp_ns is {v}, expected below {MAX_STAMP_NS} (2**31 s: the int32 seconds of builtin_interfaces/Time)"
        )
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
        Bad names, stamp or rate; ``rosbags`` not installed; ``path`` exists and is not a rosbag2 bag, its directory
        does not exist, or the bag cannot be written there (``bag path PATH: cannot write: reason``); ``path`` is
        then unchanged.
    """
    names = validate_joint_names(joint_names)
    topic, point_topic = _validate_topics(topic, point_topic)
    stamp = _validate_stamp(stamp_ns)
    pts = joint_points(trajectory, rate)
    target = _validate_bag_path(path)
    ts = _typestore()
    try:
        with atomic_directory(target) as bag:
            _write_bag(bag, ts, topic, point_topic, pts, names, stamp, frame_id)
    except OSError as exc:
        reason = exc.strerror or type(exc).__name__
        raise InvalidInputError(f"bag path {str(target)!r}: cannot write: {reason}") from None
    return target / f"{target.name}.mcap"


def _validate_topics(topic: str, point_topic: str | None) -> tuple[str, str | None]:
    """The trajectory's topic and the points' topic (or None), checked, and distinct."""
    topic = validate_topic(topic)
    if point_topic is not None:
        point_topic = validate_topic(point_topic, "point topic")
        if point_topic == topic:
            raise InvalidInputError(f"point topic is {point_topic!r}, expected a topic other than {topic!r}")
    return topic, point_topic


def _write_bag(
    bag: Path,
    ts: Any,
    topic: str,
    point_topic: str | None,
    pts: JointPoints,
    names: tuple[str, str],
    stamp: int,
    frame_id: str,
) -> None:
    """Write a rosbag2 bag (MCAP storage) at ``bag``: the ``JointTrajectory`` message on ``topic`` at ``stamp`` (ns)
    and, unless ``point_topic`` is None, each row's ``JointTrajectoryPoint`` at ``stamp`` + its time (ns).

    The messages are CDR-encoded here (:func:`joint_trajectory_cdr`, :func:`joint_trajectory_point_cdr`: the
    bytes ``rosbags`` writes) and the points are written a chunk at a time (:func:`_write_points`)."""
    from rosbags.rosbag2 import StoragePlugin, Writer

    T = ts.types
    jt = T["trajectory_msgs/msg/JointTrajectory"].__msgtype__
    jtp = T["trajectory_msgs/msg/JointTrajectoryPoint"].__msgtype__
    writer = Writer(bag, version=9, storage_plugin=StoragePlugin.MCAP)
    writer.open()
    try:
        conn = writer.add_connection(topic, jt, typestore=ts)
        writer.write(conn, stamp, joint_trajectory_cdr(pts, names, stamp, frame_id))
        if point_topic is not None:
            pconn = writer.add_connection(point_topic, jtp, typestore=ts)
            _write_points(writer, pconn, pts, stamp)
    finally:
        writer.close()


#: Rows encoded and written at once by :func:`_write_points`.
_ROWS_PER_PIECE = 8192
#: CDR little-endian encapsulation header.
_CDR_HEADER = b"\x00\x01\x00\x00"
#: MCAP message record before the data: opcode, record length, channel id, sequence, log time, publish time.
_RECORD_HEAD = 1 + 8 + 2 + 4 + 8 + 8


def _point_dtype(offset: int) -> np.dtype[Any]:
    """The CDR layout of one ``JointTrajectoryPoint`` with two joints starting ``offset`` bytes into the payload
    (``offset`` a multiple of 4): three ``float64[2]`` sequences (count, padding to 8, values), an empty
    ``effort``, ``time_from_start``; padding bytes are zero in arrays made with :func:`numpy.zeros`."""
    fields: list[tuple[str, Any, int]] = []
    rel = 0
    for name in ("positions", "velocities", "accelerations"):
        fields.append((f"n_{name}", "<u4", rel))
        rel += 4
        rel += (-(offset + rel)) % 8
        fields.append((name, ("<f8", (2,)), rel))
        rel += 16
    for name, fmt in (("n_effort", "<u4"), ("sec", "<i4"), ("nanosec", "<u4")):
        fields.append((name, fmt, rel))
        rel += 4
    names, formats, offsets = zip(*fields, strict=True)
    return np.dtype({"names": list(names), "formats": list(formats), "offsets": list(offsets), "itemsize": rel})


def _fill_points(out: NDArray[Any], pts: JointPoints, lo: int, hi: int) -> None:
    """Fill the :func:`_point_dtype` array ``out`` (``hi - lo`` rows) with rows ``lo:hi`` of ``pts``."""
    ns = pts.ns[lo:hi]
    for name in ("positions", "velocities", "accelerations"):
        out[f"n_{name}"] = 2
        out[name] = np.asarray(getattr(pts, name), dtype=np.float64)[lo:hi]
    out["sec"] = ns // 1_000_000_000
    out["nanosec"] = ns % 1_000_000_000


def joint_trajectory_point_cdr(pts: JointPoints, lo: int = 0, hi: int | None = None) -> NDArray[np.uint8]:
    """CDR messages (``trajectory_msgs/msg/JointTrajectoryPoint``, little-endian) of rows ``lo:hi``.

    Parameters
    ----------
    pts : JointPoints
        The rows (N of them).
    lo, hi : int
        The rows encoded (default all).

    Returns
    -------
    ndarray of uint8, shape (hi - lo, 88)
        Row ``k`` is the message of row ``lo + k``: the bytes ``rosbags`` ``serialize_cdr`` gives for that point.
    """
    hi = len(pts.t) if hi is None else hi
    dt = np.dtype({"names": ["cdr", "point"], "formats": ["V4", _point_dtype(0)], "offsets": [0, 4]})
    out = np.zeros(hi - lo, dtype=dt)
    out["cdr"] = np.void(_CDR_HEADER)
    _fill_points(out["point"], pts, lo, hi)
    return out.view(np.uint8).reshape(hi - lo, dt.itemsize)


def _cdr_string(out: list[bytes], pos: int, text: str) -> int:
    """Append a CDR string (aligned count including the NUL, bytes, NUL) to ``out``; the payload position after."""
    data = text.encode() + b"\x00"
    pad = (-pos) % 4
    out.append(b"\x00" * pad + struct.pack("<I", len(data)) + data)
    return pos + pad + 4 + len(data)


def joint_trajectory_cdr(pts: JointPoints, names: tuple[str, str], stamp: int, frame_id: str) -> bytes:
    """The CDR message (``trajectory_msgs/msg/JointTrajectory``, little-endian) of all rows.

    Parameters
    ----------
    pts : JointPoints
        The rows.
    names : (str, str)
        Joint names of robot A and robot B.
    stamp : int
        Header stamp (ns since the epoch).
    frame_id : str

    Returns
    -------
    bytes
        The bytes ``rosbags`` ``serialize_cdr`` gives for the same message (80 bytes a row and a header).
    """
    out = [_CDR_HEADER, struct.pack("<iI", *split_ns(stamp))]
    pos = _cdr_string(out, 8, frame_id)
    pad = (-pos) % 4
    out.append(b"\x00" * pad + struct.pack("<I", len(names)))
    pos += pad + 4
    for joint in names:
        pos = _cdr_string(out, pos, joint)
    pad = (-pos) % 4
    out.append(b"\x00" * pad + struct.pack("<I", len(pts.t)))
    pos += pad + 4
    n, lo = len(pts.t), 0
    if n and pos % 8 == 0:  # a point starting 8-aligned takes 84 bytes, so the next ones start 4 past 8
        first = np.zeros(1, dtype=_point_dtype(0))
        _fill_points(first, pts, 0, 1)
        out.append(first.tobytes())
        lo = 1
    rest = _point_dtype(4)  # 80 bytes: every further point starts 4 past a multiple of 8
    for a in range(lo, n, _ROWS_PER_PIECE):
        piece = np.zeros(min(a + _ROWS_PER_PIECE, n) - a, dtype=rest)
        _fill_points(piece, pts, a, a + len(piece))
        out.append(piece.tobytes())
    return b"".join(out)


def _write_points(writer: Any, conn: Any, pts: JointPoints, stamp: int) -> None:
    """Write each row's ``JointTrajectoryPoint`` on ``conn`` at ``stamp`` + its time (ns), a chunk at a time.

    With ``rosbags``' MCAP storage (uncompressed) the message records of up to a chunk (1 MiB) are built at once
    and written into the storage's pending chunk, which is closed where ``McapWriter.write`` closes it (after the
    record that takes it past 2²⁰ bytes): the file is the one per-message writes give. Any other storage gets
    one ``writer.write`` per message.
    """
    storage = writer.storage
    batched = _batched(storage) and all(hasattr(writer, x) for x in ("counts", "min_timestamp", "max_timestamp"))
    n = len(pts.t)
    for lo in range(0, n, _ROWS_PER_PIECE):
        hi = min(lo + _ROWS_PER_PIECE, n)
        data = joint_trajectory_point_cdr(pts, lo, hi)
        stamps = stamp + pts.ns[lo:hi].astype(np.uint64)
        if not batched:
            for t, d in zip(stamps.tolist(), data, strict=True):
                writer.write(conn, t, d.tobytes())
            continue
        k = 0
        while k < len(data):
            k = _write_records(storage, conn.id, stamps, data, k)
        writer.counts[conn.id] += len(data)
        writer.min_timestamp = min(int(stamps.min()), writer.min_timestamp)
        writer.max_timestamp = max(int(stamps.max()), writer.max_timestamp)


def _batched(storage: Any) -> bool:
    """Whether ``storage`` is ``rosbags``' uncompressed MCAP storage, whose pending chunk :func:`_write_records`
    fills."""
    chunk = getattr(storage, "chunk", None)
    return (
        type(storage).__name__ == "McapWriter"
        and getattr(storage, "compression", None) == ""
        and all(hasattr(chunk, x) for x in ("bio", "msgs", "message_start_time", "message_end_time"))
        and all(hasattr(storage, x) for x in ("close_chunk", "channel_stats", "message_start_time"))
    )


def _write_records(storage: Any, cid: int, stamps: NDArray[np.uint64], data: NDArray[np.uint8], k: int) -> int:
    """Write messages ``k:`` into ``storage``'s pending chunk (rosbags ``McapWriter``) up to the one that fills it,
    then close the chunk; the index of the next message to write."""
    chunk = storage.chunk
    start = chunk.bio.tell()
    size = _RECORD_HEAD + data.shape[1]
    count = min(len(data) - k, max(0, (2**20 - start) // size) + 1)  # the record that passes 2**20 closes it
    records = np.zeros((count, size), dtype=np.uint8)
    records[:, 0] = 0x05
    records[:, 1:9] = np.array([size - 9], dtype="<u8").view(np.uint8)
    records[:, 9:11] = np.array([cid], dtype="<u2").view(np.uint8)
    t = stamps[k : k + count].astype("<u8")
    records[:, 15:23] = records[:, 23:31] = t.view(np.uint8).reshape(count, 8)
    records[:, _RECORD_HEAD:] = data[k : k + count]
    offsets = start + size * np.arange(count)
    chunk.msgs[cid].extend(zip(t.tolist(), offsets.tolist(), strict=True))
    chunk.bio.write(records.tobytes())
    lo, hi = int(t.min()), int(t.max())
    storage.message_start_time = min(lo, storage.message_start_time)
    storage.message_end_time = max(hi, storage.message_end_time)
    storage.channel_stats[cid] += count
    chunk.message_start_time = min(lo, chunk.message_start_time)
    chunk.message_end_time = max(hi, chunk.message_end_time)
    if chunk.bio.tell() > 2**20:
        storage.close_chunk()
    return k + count


def _validate_bag_path(path: str | os.PathLike[str]) -> Path:
    """The bag directory: a new path or an existing rosbag2 bag (to be replaced)."""
    target = Path(path)
    parent = target.parent if str(target.parent) else Path(".")
    if not parent.is_dir():
        raise InvalidInputError(
            f"bag path {str(target)!r}: its directory {str(parent)!r} does not exist, expected an existing directory"
        )
    if target.exists() and not (target.is_dir() and (target / "metadata.yaml").is_file()):
        raise InvalidInputError(f"bag path {str(target)!r} exists and is not a rosbag2 bag, expected a new path")
    if not target.name or target.name in (".", ".."):
        raise InvalidInputError(f"bag path is {str(target)!r}, expected a directory name")
    return target
