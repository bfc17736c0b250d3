"""Stage 5, export: the :class:`Trajectory` result and its CSV / JSON files (written atomically).

CSV (docs/conventions.md, "Command line and files"). Paper tracks: header
``time,a_track,a_s,a_v,a_a,a_j,b_track,b_s,b_v,b_a,b_j,a_edge,a_offset,a_dir,b_edge,b_offset,b_dir``
(:data:`CSV_COLUMNS`); one row every ``1/rate`` seconds from 0. ``*_track`` is the track coordinate, ``*_s`` the
route coordinate σ (signed distance travelled along the robot's own route, continuous through P and round the
loop), ``*_v/_a/_j`` its first three time derivatives. Graph tracks (layouts): header
``time,a_edge,a_offset,a_s,a_v,a_a,a_j,b_edge,b_offset,b_s,b_v,b_a,b_j,a_dir,b_dir`` (:data:`GRAPH_CSV_COLUMNS`)
and ``a_x,a_y,b_x,b_y`` when the layout has vertex coordinates (:data:`XY_COLUMNS`); ``*_s`` is the distance
travelled along the robot's route. On both, ``*_edge`` is the edge's name (the paper tracks' graph form:
``stick``, ``loop``), ``*_offset`` metres from the edge's ``from`` vertex, ``*_dir`` the direction of travel on
that edge (+1 along its orientation, -1 against, 0 at rest).

The motion lasts :attr:`Trajectory.motion_time`; the grid ends at the first multiple of
``1/rate`` at or after it, the robots holding the goal at rest for the rest of that last step, so the last row is
exactly at :attr:`Trajectory.makespan` (= ``ceil(motion_time·rate)/rate``) and at the goal, at rest.

Files are written to a temporary file in the target directory and moved into place with :func:`os.replace`:
a reader never sees a half-written file, and nothing is left behind on an error.
"""

from __future__ import annotations

import enum
import io
import json
import os
import tempfile
from collections.abc import Callable
from dataclasses import dataclass, field, replace
from pathlib import Path
from typing import Any

import numpy as np
from numpy.typing import NDArray

from mpa.errors import InvalidInputError
from mpa.plan import Plan
from mpa.planners.graph import GraphPlan
from trajopt.planview import plan_view
from trajopt.timing import Limits
from trajopt.verify import VerificationError, VerificationReport

__all__ = [
    "CSV_COLUMNS",
    "GRAPH_CSV_COLUMNS",
    "HEADING_COLUMNS",
    "XY_COLUMNS",
    "Source",
    "Trajectory",
    "atomic_write_bytes",
    "atomic_write_text",
    "check_rate",
    "time_grid",
    "verified_rows",
]

FloatArray = NDArray[np.float64]
#: The pinned CSV columns of the paper's tracks, in order.
CSV_COLUMNS = (
    "time",
    "a_track",
    "a_s",
    "a_v",
    "a_a",
    "a_j",
    "b_track",
    "b_s",
    "b_v",
    "b_a",
    "b_j",
    "a_edge",
    "a_offset",
    "a_dir",
    "b_edge",
    "b_offset",
    "b_dir",
)
#: The pinned CSV columns on a layout (:class:`mpa.GraphTrack`), in order.
GRAPH_CSV_COLUMNS = (
    "time",
    "a_edge",
    "a_offset",
    "a_s",
    "a_v",
    "a_a",
    "a_j",
    "b_edge",
    "b_offset",
    "b_s",
    "b_v",
    "b_a",
    "b_j",
    "a_dir",
    "b_dir",
)
#: Appended to :data:`GRAPH_CSV_COLUMNS` when the layout has vertex coordinates: points on the drawn edges (m).
XY_COLUMNS = ("a_x", "a_y", "b_x", "b_y")
#: Columns after :data:`XY_COLUMNS` when the motion was made with a footprint: each robot's heading (radians, the
#: direction of its piece of the drawing, :class:`mpa.footprint.Drawing`).
HEADING_COLUMNS = ("a_heading", "b_heading")
#: Largest number of rows a grid may have.
MAX_ROWS = 20_000_000


class Source(enum.Enum):
    """Where a verified trajectory comes from (a normal outcome, not an error)."""

    OPTIMIZED = "optimized"
    """The smoothed, re-timed, jerk-limited path."""
    PLAN = "plan"
    """The fallback: the plan's own polyline, every straight step rest to rest."""


def check_rate(rate: Any, name: str = "rate") -> float:
    """Validate a setpoint rate (Hz): a positive finite number.

    Raises
    ------
    InvalidInputError
    """
    try:
        r = float(rate)
    except (TypeError, ValueError):
        raise InvalidInputError(f"{name} is {rate!r}, expected a positive finite number (Hz)") from None
    if not np.isfinite(r) or r <= 0:
        raise InvalidInputError(f"{name} is {r!r}, expected a positive finite number (Hz)")
    return r


def time_grid(duration: float, rate: float) -> FloatArray:
    """``k / rate`` for ``k = 0 … ceil(duration·rate)`` (s). Shape (N,)."""
    n = int(np.ceil(duration * rate - 1e-9)) if duration > 0 else 0
    if n + 1 > MAX_ROWS:
        raise InvalidInputError(f"rate {rate:g} Hz gives {n + 1} rows for {duration:g} s, expected at most {MAX_ROWS}")
    return np.arange(n + 1) / rate


def atomic_write_text(path: str | os.PathLike[str], text: str) -> None:
    """Write ``text`` (UTF-8) to ``path`` atomically (see :func:`atomic_write_bytes`)."""
    atomic_write_bytes(path, text.encode("utf-8"))


def _umask() -> int:
    mask = os.umask(0o022)
    os.umask(mask)
    return mask


def _remove_stale_temporaries(p: Path) -> None:
    """Remove ``.NAME.PID.*.tmp`` files of ``p`` left by a process that no longer exists (e.g. ``kill -9``)."""
    parent = p.parent if str(p.parent) else Path(".")
    try:
        candidates = list(parent.glob(f".{glob_escape(p.name)}.*.tmp"))
    except OSError:
        return
    for tmp in candidates:
        parts = tmp.name[len(p.name) + 2 :].split(".")
        if not parts or not parts[0].isdigit():
            continue
        pid = int(parts[0])
        if pid == os.getpid():
            continue
        try:
            os.kill(pid, 0)
        except ProcessLookupError:
            tmp.unlink(missing_ok=True)
        except OSError:  # alive but not ours (PermissionError): keep it
            continue


def glob_escape(name: str) -> str:
    """``name`` with the glob metacharacters escaped."""
    import glob

    return glob.escape(name)


def atomic_write_bytes(path: str | os.PathLike[str], data: bytes) -> None:
    """Write ``data`` to ``path`` through a temporary file in the same directory and :func:`os.replace`.

    The file gets the usual permissions (``0o666`` less the umask); on any error the temporary file is removed.
    A reader never sees a partial file, even if the writer is killed (``kill -9``): then only the hidden
    temporary ``.NAME.PID.XXXX.tmp`` is left, and the next write of ``path`` removes it.
    """
    p = Path(path)
    _remove_stale_temporaries(p)
    fd, tmp = tempfile.mkstemp(
        dir=p.parent if str(p.parent) else ".", prefix=f".{p.name}.{os.getpid()}.", suffix=".tmp"
    )
    try:
        with os.fdopen(fd, "wb") as fh:
            fh.write(data)
            fh.flush()
            os.fsync(fh.fileno())
        os.chmod(tmp, 0o666 & ~_umask())
        os.replace(tmp, p)
    except BaseException:
        try:
            os.unlink(tmp)
        except OSError:
            pass
        raise


def verified_rows(
    t: FloatArray,
    track: FloatArray,
    rows: tuple[FloatArray, FloatArray, FloatArray, FloatArray],
    report: VerificationReport,
) -> dict[str, Any]:
    """The :class:`Trajectory` fields that rows which passed the gate set.

    Parameters
    ----------
    t : ndarray, shape (N,)
        Times (s).
    track : ndarray, shape (N, 2)
        Track coordinates (m).
    rows : tuple of ndarray, each shape (N, 2)
        ``s, v, a, j`` (m, m/s, m/s², m/s³).
    report : VerificationReport
        The gate's report on these rows.

    Returns
    -------
    dict
        ``t, track, s, v, a, j``, ``makespan`` (the last row's time), ``min_separation`` and ``verification``.
    """
    s, v, a, j = rows
    return {
        "t": t,
        "track": track,
        "s": s,
        "v": v,
        "a": a,
        "j": j,
        "makespan": float(t[-1]),
        "min_separation": report.min_separation,
        "verification": report.to_dict(),
    }


def _json_default(obj: Any) -> Any:
    if isinstance(obj, np.generic):
        return obj.item()
    if isinstance(obj, np.ndarray):
        return obj.tolist()
    if isinstance(obj, enum.Enum):
        return obj.value
    raise TypeError(f"not JSON serializable: {type(obj).__name__}")


@dataclass(frozen=True)
class Trajectory:
    """A verified, jerk-limited trajectory of both robots, sampled at the controller rate.

    Arrays hold one row per setpoint; column 0 is robot A, column 1 robot B. Units: s, m, m/s, m/s², m/s³.

    Attributes
    ----------
    t : ndarray, shape (N,)
        Times ``k / rate`` (s).
    track : ndarray, shape (N, 2)
        Track coordinates (m) on a paper track; on a layout the offsets on the current edges (see :attr:`edges`).
    s : ndarray, shape (N, 2)
        Route coordinates σ (m): signed distance along each robot's route, continuous through P (on a layout the
        distance travelled along the route).
    v, a, j : ndarray, shape (N, 2)
        First, second and third time derivatives of ``s`` (m/s, m/s², m/s³).
    limits : Limits
    clearance : float
        Required separation D (m).
    rate : float
        Row rate (Hz).
    makespan : float
        Time of the last row (s): ``motion_time`` rounded up to a multiple of ``1/rate``.
    motion_time : float
        End of the motion (s); afterwards the robots hold the goal at rest.
    min_separation : float
        Smallest graph distance between the robots over the rows (m).
    domain : int
        The plan's domain of continuity (0 on a layout).
    word : tuple of str
        Reduced skeleton word (homotopy class), equal to the plan's (on a layout: the plan's cell word).
    source : Source
        ``OPTIMIZED`` or ``PLAN`` (the fallback).
    fallback : bool
        ``source is Source.PLAN``.
    fallback_reason : str
        Why the optimized trajectory was not used ("" if it was).
    solver_stats : dict
        IPOPT iterations and status, node counts, toppra duration, pieces and blends.
    timings : dict
        Wall time of every stage (s).
    verification : dict
        The gate's report (:meth:`trajopt.verify.VerificationReport.to_dict`).
    plan : Plan or GraphPlan
        The plan the trajectory follows.
    sampler : callable
        ``sampler(t) -> (s, v, a, j)``: the continuous motion at any times (for analysis; exports go through
        :meth:`at_rate`, which verifies).
    retimer : callable or None
        ``retimer(rate) -> Trajectory``: the plan re-timed for another rate by the generator that made this
        trajectory (used by :meth:`at_rate` when the resampled rows fail the gate).
    footprint : Footprints or None
        The robots' bodies in the plane (:mod:`mpa.footprint`), when the motion was made with them.
    plane : dict or None
        The gate's check in the plane (:meth:`trajopt.planar_gate.PlaneReport.to_dict`), with a footprint.
    """

    t: FloatArray
    track: FloatArray
    s: FloatArray
    v: FloatArray
    a: FloatArray
    j: FloatArray
    limits: Limits
    clearance: float
    rate: float
    makespan: float
    motion_time: float
    min_separation: float
    domain: int
    word: tuple[str, ...]
    source: Source
    fallback_reason: str
    solver_stats: dict[str, Any]
    timings: dict[str, Any]
    verification: dict[str, Any]
    plan: Plan | GraphPlan
    sampler: Callable[[FloatArray], tuple[FloatArray, FloatArray, FloatArray, FloatArray]] = field(
        repr=False, compare=False
    )
    retimer: Callable[[float], Trajectory] | None = field(default=None, repr=False, compare=False)
    footprint: Any = None
    plane: dict[str, Any] | None = None

    @property
    def fallback(self) -> bool:
        """Whether the plan itself (re-timed) was returned instead of the optimized trajectory."""
        return self.source is Source.PLAN

    def at_rate(self, rate: float) -> Trajectory:
        """This trajectory with its setpoints at another rate, verified at that rate.

        The same continuous motion is sampled every ``1/rate`` seconds and passed through the gate
        (:func:`trajopt.verify.verify_setpoints`) at that rate. If the gate rejects it (at a low rate the
        robots may come closer between rows than the rows show), the plan is re-timed for that rate by the
        generator (optimised with the separation margin the rate needs, else the re-timed plan), verified again;
        ``solver_stats["retimed_for_rate"]`` then holds the reason. No rows the gate rejects are ever returned.

        Raises
        ------
        InvalidInputError
            ``rate`` not a positive finite number, too many rows, or too low for this motion (the message names
            the lowest usable rate).
        PlanningError
            No verified setpoints at that rate could be made (never expected).
        """
        r = check_rate(rate)
        if r == self.rate:
            return self
        t = time_grid(self.motion_time, r)
        s, v, a, j = self.sampler(t)
        view = plan_view(self.plan)
        tr = view.track_coordinates(s)
        rep = view.verify(t, s, v, a, j, limits=self.limits, clearance=self.clearance, rate=r, track_pos=tr)
        plane = self.plane
        if rep.ok and self.footprint is not None:
            from trajopt.planar_gate import verify_plane

            e, o = view.positions(s, v)
            prep = verify_plane(view.graph, self.footprint, e, o, v, amax=self.limits.a, rate=r)
            plane = prep.to_dict()
            if not prep.ok:
                rep = replace(rep, ok=False, failures=rep.failures + prep.failures)
        if rep.ok:
            return replace(self, rate=r, plane=plane, **verified_rows(t, tr, (s, v, a, j), rep))
        if self.retimer is None:
            raise VerificationError(rep)
        new = self.retimer(r)
        new.solver_stats["retimed_for_rate"] = f"resampled at {r:g} Hz: {'; '.join(rep.failures)}"
        return new

    def resample(self, rate: float | None = None) -> tuple[FloatArray, ...]:
        """``t, track, s, v, a, j`` at another rate, verified at that rate (see :meth:`at_rate`).

        Raises
        ------
        InvalidInputError
            ``rate`` not a positive finite number, or too low for this motion.
        """
        if rate is None:
            return self.t, self.track, self.s, self.v, self.a, self.j
        tr = self.at_rate(rate)
        return tr.t, tr.track, tr.s, tr.v, tr.a, tr.j

    # ------------------------------------------------------------------------------- graph positions
    @property
    def is_graph(self) -> bool:
        """Whether the trajectory is on a layout (:class:`mpa.GraphTrack`, a :class:`GraphPlan`)."""
        return isinstance(self.plan, GraphPlan)

    def _positions(self) -> tuple[NDArray[np.int64], FloatArray, NDArray[np.int64]]:
        cached = self.__dict__.get("_pos")
        if cached is None:
            view = plan_view(self.plan)
            e, o = view.positions(self.s, self.v)
            cached = (e, o, view.directions(self.s, self.v))
            object.__setattr__(self, "_pos", cached)
        return cached

    @property
    def edges(self) -> NDArray[np.int64]:
        """Edge index of each robot at every row (on the paper tracks: of the graph form). Shape (N, 2)."""
        return self._positions()[0]

    @property
    def offsets(self) -> FloatArray:
        """Offset of each robot from its edge's ``from`` vertex at every row (m). Shape (N, 2)."""
        return self._positions()[1]

    @property
    def directions(self) -> NDArray[np.int64]:
        """Direction of travel on the current edge (+1 along it, -1 against, 0 at rest). Shape (N, 2)."""
        return self._positions()[2]

    @property
    def edge_names(self) -> tuple[str, ...]:
        """Names of the track's edges (the paper tracks' graph form: ``stick``, ``loop``)."""
        return plan_view(self.plan).graph.edge_names

    @property
    def columns(self) -> tuple[str, ...]:
        """The CSV columns of this trajectory (:data:`CSV_COLUMNS`, or on a layout :data:`GRAPH_CSV_COLUMNS` and,
        with coordinates, :data:`XY_COLUMNS`)."""
        if not self.is_graph:
            return CSV_COLUMNS
        if plan_view(self.plan).graph.has_coordinates:
            return GRAPH_CSV_COLUMNS + XY_COLUMNS + (HEADING_COLUMNS if self.footprint is not None else ())
        return GRAPH_CSV_COLUMNS

    def xy(self) -> FloatArray:
        """Planar points of both robots on the drawn layout (m), shape (N, 2, 2): ``[:, robot, (x, y)]``.

        Raises
        ------
        InvalidInputError
            The layout has no vertex coordinates.
        """
        g = plan_view(self.plan).graph
        e, o, _ = self._positions()
        return np.stack([g.embed(e[:, 0], o[:, 0]), g.embed(e[:, 1], o[:, 1])], axis=1)

    def headings(self) -> FloatArray:
        """Heading of each robot's piece of the drawing at every row (radians, the edge's tangent direction,
        :class:`mpa.footprint.Drawing`), shape (N, 2)."""
        from mpa.footprint import drawing_of

        d = drawing_of(plan_view(self.plan).graph)
        e, o, _ = self._positions()
        return np.stack([d.pose(e[:, 0], o[:, 0])[1], d.pose(e[:, 1], o[:, 1])[1]], axis=1)

    def csv_text(self, rate: float | None = None) -> str:
        """The CSV file's content (see the module docstring), verified at ``rate`` (see :meth:`at_rate`)."""
        tr = self if rate is None else self.at_rate(rate)
        return tr._csv()

    def _csv(self) -> str:
        names = np.asarray(self.edge_names, dtype=object)
        e, o, d = self._positions()
        col: dict[str, Any] = {"time": self.t}
        for r, x in enumerate("ab"):
            col.update(
                {
                    f"{x}_track": self.track[:, r],
                    f"{x}_s": self.s[:, r],
                    f"{x}_v": self.v[:, r],
                    f"{x}_a": self.a[:, r],
                    f"{x}_j": self.j[:, r],
                    f"{x}_edge": names[e[:, r]],
                    f"{x}_offset": o[:, r],
                    f"{x}_dir": d[:, r],
                }
            )
        columns = self.columns
        if "b_y" in columns:
            p = self.xy()
            col.update({"a_x": p[:, 0, 0], "a_y": p[:, 0, 1], "b_x": p[:, 1, 0], "b_y": p[:, 1, 1]})
        if "b_heading" in columns:
            h = self.headings()
            col.update({"a_heading": h[:, 0], "b_heading": h[:, 1]})
        text = []
        for name in columns:
            x = col[name]
            if x.dtype == object:
                text.append(x.astype(str))
            elif np.issubdtype(x.dtype, np.integer):
                text.append(x.astype(str))
            else:
                text.append(np.char.mod("%.12g", x))
        buf = io.StringIO()
        buf.write(",".join(columns) + "\n")
        if len(self.t):
            rows = text[0].astype(object)
            for x in text[1:]:
                rows = rows + "," + x.astype(object)
            buf.write("\n".join(rows.tolist()) + "\n")
        return buf.getvalue()

    def to_csv(self, path: str | os.PathLike[str], rate: float | None = None) -> None:
        """Write the setpoints as CSV (atomically); ``rate`` (Hz) defaults to the trajectory's own.

        At another rate the rows are verified at that rate first (see :meth:`at_rate`); nothing is written
        if that fails.
        """
        text = self.csv_text(rate)
        atomic_write_text(path, text)

    def margins(self) -> Any:
        """Tracking margin and delay tolerance (:func:`trajopt.margins.margins`; computed once)."""
        cached = self.__dict__.get("_margins")
        if cached is None:
            from trajopt.margins import margins

            cached = margins(self)
            object.__setattr__(self, "_margins", cached)
        return cached

    def words(self) -> dict[str, str]:
        """The motion in plain words per cart (:func:`trajopt.words.describe`)."""
        from trajopt.words import describe

        return describe(self)

    def summary(self) -> dict[str, Any]:
        """JSON-ready summary (everything but the arrays).

        ``routes`` gives each robot's route (``"a"``, ``"b"``): the edges in the order travelled, each with ``dir``
        (+1 along the edge, -1 against), the ``entry`` offset and the route coordinates ``from_s``/``to_s`` where
        the robot is on it (what a controller needs to set the switches). On a layout ``start`` and ``goal`` are
        position names (``EDGE:OFFSET`` or a vertex) and ``track`` is the layout.
        """
        view = plan_view(self.plan)
        plan = self.plan
        if isinstance(plan, GraphPlan):
            g = view.graph
            track: Any = g.to_dict()
            start: Any = [g.position_name(*p) for p in plan.start]
            goal: Any = [g.position_name(*p) for p in plan.goal]
            units = {"time": "s", "offset": "m", "s": "m", "v": "m/s", "a": "m/s^2", "j": "m/s^3"}
        else:
            track, start, goal = plan.track.to_dict(), plan.start.tolist(), plan.goal.tolist()
            units = {"time": "s", "track": "m", "offset": "m", "s": "m", "v": "m/s", "a": "m/s^2", "j": "m/s^3"}
        if "b_y" in self.columns:
            units["x"] = units["y"] = "m"
        extra: dict[str, Any] = {}
        if self.footprint is not None:
            units["heading"] = "rad"
            plane = dict(self.plane or {})
            gap = float(plane.get("min_gap_plane", float("nan")))
            from mpa.footprint import drawing_of

            scale = float(np.max(np.hypot(*drawing_of(plan_view(plan).graph).piece_dir.T)))
            extra = {
                "footprint": self.footprint.to_dict(),
                "min_gap_plane": gap,
                # each cart may lag or lead its setpoint by this much along its track (both at once) while the
                # bodies stay apart in the plane (translation; turning at corners not included)
                "tracking_margin_plane": max(0.0, gap) / (2.0 * scale),
                "plane": plane,
            }
        return extra | {
            "makespan": self.makespan,
            "motion_time": self.motion_time,
            "min_separation": self.min_separation,
            "domain": self.domain,
            "fallback": self.fallback,
            "fallback_reason": self.fallback_reason,
            "source": self.source.value,
            "word": list(self.word),
            "track": track,
            "start": start,
            "goal": goal,
            "clearance": self.clearance,
            "limits": self.limits.to_dict(),
            "rate": self.rate,
            "rows": len(self.t),
            "columns": list(self.columns),
            "units": units,
            "routes": self.routes(),
            "peak": {
                "v": np.max(np.abs(self.v), axis=0).tolist(),
                "a": np.max(np.abs(self.a), axis=0).tolist(),
                "j": np.max(np.abs(self.j), axis=0).tolist(),
            },
            "solver": self.solver_stats,
            "timings": self.timings,
            "verification": self.verification,
            "margins": self.margins().to_dict(),
            "words": self.words(),
        }

    def routes(self) -> dict[str, list[dict[str, object]]]:
        """Each robot's route over the travelled range (``{"a": [...], "b": [...]}``, see :meth:`summary`)."""
        return plan_view(self.plan).route_lists(self.s)

    def to_json(self, path: str | os.PathLike[str]) -> None:
        """Write :meth:`summary` as JSON (atomically)."""
        atomic_write_text(path, json.dumps(self.summary(), indent=2, default=_json_default) + "\n")
