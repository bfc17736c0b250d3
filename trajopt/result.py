"""The result of the pipeline: :class:`Trajectory` (verified setpoint rows and what made them), :class:`Source`,
and :func:`verified_rows` (the fields rows that passed the gate set).

The motion lasts :attr:`Trajectory.motion_time`; the grid ends at the first multiple of ``1/rate`` at or after
it, the robots holding the goal at rest for the rest of that last step, so the last row is exactly at
:attr:`Trajectory.makespan` (= ``ceil(motion_time·rate)/rate``) and at the goal, at rest. The files
(:mod:`trajopt.io`) are written by :meth:`Trajectory.to_csv` and :meth:`Trajectory.to_json`.
"""

from __future__ import annotations

import enum
import os
from collections.abc import Callable, Iterator
from dataclasses import dataclass, field, replace
from typing import Any

import numpy as np
from numpy.typing import NDArray

from mpa._arrays import FloatArray
from mpa.plans import MotionPlan
from trajopt.grid import time_grid, validate_rate
from trajopt.io.csvfile import CSV_COLUMNS, GRAPH_CSV_COLUMNS, HEADING_COLUMNS, XY_COLUMNS
from trajopt.path.planview import plan_view
from trajopt.timing import Limits
from trajopt.verify.gate import VerificationError, VerificationReport
from trajopt.verify.rows import Setpoints


class Source(enum.Enum):
    """Where a verified trajectory comes from (a normal outcome, not an error)."""

    OPTIMIZED = "optimized"
    """The smoothed, re-timed, jerk-limited path."""
    PLAN = "plan"
    """The fallback: the plan's own polyline, every straight step rest to rest."""


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
        The limits asked for (m/s, m/s², m/s³ per robot).
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
        Corridor QP statistics (segments, iterations, QP time and status), pieces and blends.
    timings : dict
        Wall time of every stage (s).
    verification : dict
        The gate's report (:meth:`trajopt.verify.gate.VerificationReport.to_dict`).
    plan : MotionPlan
        The plan the rows execute (:class:`mpa.Plan` on a paper track, :class:`mpa.GraphPlan` on a layout).
    sampler : callable
        ``sampler(t) -> (s, v, a, j)``: the continuous motion at any times (for analysis; exports go through
        :meth:`at_rate`, which verifies).
    retimer : callable or None
        ``retimer(rate) -> Trajectory``: the plan re-timed for another rate by the generator that made this
        trajectory (used by :meth:`at_rate` when the resampled rows fail the gate).
    footprint : Footprints or None
        The robots' bodies in the plane (:mod:`mpa.footprint`), when the motion was made with them.
    plane : dict or None
        The gate's check in the plane (:meth:`trajopt.verify.planar.PlaneReport.to_dict`), with a footprint.
    limits_used : Limits
        The limits the motion was timed with, per robot, each at most the one in :attr:`limits` (the generator
        chooses them, :attr:`trajopt.generator.TrajectoryGenerator.motion_limits`; default :attr:`limits`). The
        rows keep them, and the gate bounds the motion between rows with them: a controller that executes the
        setpoints within these limits stays inside the verified envelope.
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
    plan: MotionPlan
    sampler: Callable[[FloatArray], tuple[FloatArray, FloatArray, FloatArray, FloatArray]] = field(
        repr=False, compare=False
    )
    retimer: Callable[[float], Trajectory] | None = field(default=None, repr=False, compare=False)
    footprint: Any = None
    plane: dict[str, Any] | None = None
    limits_used: Limits = None  # type: ignore[assignment]  # default: limits (set in __post_init__)

    def __post_init__(self) -> None:
        if self.limits_used is None:
            object.__setattr__(self, "limits_used", self.limits)

    @property
    def fallback(self) -> bool:
        """Whether the plan itself (re-timed) was returned instead of the optimized trajectory."""
        return self.source is Source.PLAN

    def at_rate(self, rate: float) -> Trajectory:
        """This trajectory with its setpoints at another rate, verified at that rate.

        The same continuous motion is sampled every ``1/rate`` seconds and passed through the gate
        (:func:`trajopt.verify.gate.verify_setpoints`) at that rate. If the gate rejects it (at a low rate the
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
        r = validate_rate(rate)
        if r == self.rate:
            return self
        t = time_grid(self.motion_time, r)
        s, v, a, j = self.sampler(t)
        view = plan_view(self.plan)
        tr = view.track_coordinates(s)
        rep = view.verify(
            Setpoints(t, s, v, a, j, track=tr),
            limits=self.limits,
            clearance=self.clearance,
            rate=r,
            limits_used=self.limits_used,
        )
        plane = self.plane
        if rep.ok and self.footprint is not None:
            from trajopt.verify.planar import verify_plane

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

    def rows(self) -> Setpoints:
        """The verified rows (``t, s, v, a, j``, ``track`` on a paper track) as one
        :class:`~trajopt.verify.rows.Setpoints`."""
        return Setpoints(self.t, self.s, self.v, self.a, self.j, track=None if self.is_graph else self.track)

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
        """Whether the trajectory is on a layout rather than in a paper track's coordinates (a plan other than the
        paper's :class:`mpa.Plan`; :attr:`trajopt.path.planview.PlanView.is_graph`)."""
        return plan_view(self.plan).is_graph

    def _positions(self) -> tuple[NDArray[np.int64], FloatArray, NDArray[np.int64]]:
        cached = self.__dict__.get("_pos")
        if cached is None:
            view = plan_view(self.plan)
            e, o = view.positions(self.s, self.v)
            cached = (e, o, view.directions(self.s, self.v))
            object.__setattr__(self, "_pos", cached)
        return cached

    def cache_positions(self, edges: NDArray[np.int64], offsets: FloatArray, directions: NDArray[np.int64]) -> None:
        """Keep the rows' positions, computed with the rows (:meth:`trajopt.path.planview.PlanView.graph_rows`),
        for :attr:`edges`, :attr:`offsets` and :attr:`directions` (each shape (N, 2)), instead of searching the
        routes again."""
        object.__setattr__(self, "_pos", (edges, offsets, directions))

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
        """The CSV file's content (:mod:`trajopt.io.csvfile`), verified at ``rate`` (see :meth:`at_rate`)."""
        return b"".join(self.csv_chunks(rate)).decode("utf-8")

    def csv_chunks(self, rate: float | None = None) -> Iterator[bytes]:
        """The CSV file's content (UTF-8) in pieces of at most :data:`CSV_CHUNK_ROWS` rows, the header first.

        The rows are verified at ``rate`` (see :meth:`at_rate`) before the first piece; each piece is formatted
        when it is asked for, so writing them one by one keeps the text of only one piece in memory. Numbers are
        ``"%.12g"``, the edge names RFC 4180 fields, ``*_dir`` integers (:func:`trajopt.io.csvfile.csv_chunks`).
        """
        from trajopt.io.csvfile import csv_chunks

        return csv_chunks(self if rate is None else self.at_rate(rate))

    def to_csv(self, path: str | os.PathLike[str], rate: float | None = None) -> None:
        """Write the setpoints as CSV (atomically); ``rate`` (Hz) defaults to the trajectory's own.

        At another rate the rows are verified at that rate first (see :meth:`at_rate`); nothing is written
        if that fails.

        Raises
        ------
        InvalidInputError
            ``path`` is not a file path (empty, a directory, not a string or path), the file cannot be written
            (the message names the path and the reason), or ``rate`` is invalid or too low.
        """
        from trajopt.io.csvfile import write_csv

        write_csv(self, path, rate)

    def margins(self) -> Any:
        """Tracking margin and delay tolerance (:func:`trajopt.analysis.margins.margins`; computed once)."""
        cached = self.__dict__.get("_margins")
        if cached is None:
            from trajopt.analysis.margins import margins

            cached = margins(self)
            object.__setattr__(self, "_margins", cached)
        return cached

    def description(self) -> dict[str, str]:
        """The motion in plain words per cart, ``{"A": ..., "B": ...}`` (:func:`trajopt.analysis.words.describe`;
        computed
        once). Not to be confused with :attr:`word`, the homotopy class."""
        cached = self.__dict__.get("_words")
        if cached is None:
            from trajopt.analysis.words import describe

            cached = describe(self)
            object.__setattr__(self, "_words", cached)
        return dict(cached)

    def words(self) -> dict[str, str]:
        """Deprecated name of :meth:`description` (the prose, not the homotopy class :attr:`word`)."""
        import warnings

        warnings.warn("Trajectory.words() is deprecated: use Trajectory.description()", DeprecationWarning, 2)
        return self.description()

    def summary(self, *, margins: bool = False) -> dict[str, Any]:
        """JSON-ready summary (everything but the arrays): :func:`trajopt.io.summary.summary`.

        ``margins=True`` adds ``"margins"`` (:meth:`margins`, which takes 0.4-2 s the first time).
        """
        from trajopt.io.summary import summary

        return summary(self, margins=margins)

    def routes(self) -> dict[str, list[dict[str, object]]]:
        """Each robot's route over the travelled range (``{"a": [...], "b": [...]}``, see :meth:`summary`)."""
        return plan_view(self.plan).route_lists(self.s)

    def to_json(self, path: str | os.PathLike[str], *, margins: bool = True) -> None:
        """Write :meth:`summary` as JSON (atomically); ``margins`` as in :meth:`summary` (the file has them unless
        ``margins=False``).

        Raises
        ------
        InvalidInputError
            ``path`` is not a file path, or the file cannot be written (the message names the path and the reason).
        """
        from trajopt.io.summary import write_json

        write_json(self, path, margins=margins)
