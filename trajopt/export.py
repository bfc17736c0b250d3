"""Stage 5, export: the :class:`Trajectory` result and its CSV / JSON files (written atomically).

CSV (docs/conventions.md, "Command line and files"): header
``time,a_track,a_s,a_v,a_a,a_j,b_track,b_s,b_v,b_a,b_j``; one row every ``1/rate``
seconds from 0. ``*_track`` is the track coordinate, ``*_s`` the route coordinate σ (signed distance travelled
along the robot's own route, continuous through P and round the loop), ``*_v/_a/_j`` its first three time
derivatives. The motion lasts :attr:`Trajectory.motion_time`; the grid ends at the first multiple of
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
from trajopt.timing import Limits
from trajopt.verify import VerificationError, verify_setpoints

__all__ = ["CSV_COLUMNS", "Source", "Trajectory", "atomic_write_bytes", "atomic_write_text", "check_rate", "time_grid"]

FloatArray = NDArray[np.float64]
#: The pinned CSV columns, in order.
CSV_COLUMNS = ("time", "a_track", "a_s", "a_v", "a_a", "a_j", "b_track", "b_s", "b_v", "b_a", "b_j")
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
        Track coordinates (m).
    s : ndarray, shape (N, 2)
        Route coordinates σ (m): signed distance along each robot's route, continuous through P.
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
        The plan's domain of continuity.
    word : tuple of str
        Reduced skeleton word (homotopy class), equal to the plan's.
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
    plan : Plan
        The topological plan the trajectory follows.
    sampler : callable
        ``sampler(t) -> (s, v, a, j)``: the continuous motion at any times (for analysis; exports go through
        :meth:`at_rate`, which verifies).
    retimer : callable or None
        ``retimer(rate) -> Trajectory``: the plan re-timed for another rate by the generator that made this
        trajectory (used by :meth:`at_rate` when the resampled rows fail the gate).
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
    plan: Plan
    sampler: Callable[[FloatArray], tuple[FloatArray, FloatArray, FloatArray, FloatArray]] = field(
        repr=False, compare=False
    )
    retimer: Callable[[float], Trajectory] | None = field(default=None, repr=False, compare=False)

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
        routes = self.plan.routes
        tr = np.stack([routes[0].position(s[:, 0]), routes[1].position(s[:, 1])], axis=1)
        plan = self.plan
        rep = verify_setpoints(
            plan.track,
            routes,
            t,
            tr,
            s,
            v,
            a,
            j,
            limits=self.limits,
            clearance=self.clearance,
            start=plan.start,
            goal=plan.goal,
            word=plan.word,
            rate=r,
        )
        if rep.ok:
            return replace(
                self,
                t=t,
                track=tr,
                s=s,
                v=v,
                a=a,
                j=j,
                rate=r,
                makespan=float(t[-1]),
                min_separation=rep.min_separation,
                verification=rep.to_dict(),
            )
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

    def csv_text(self, rate: float | None = None) -> str:
        """The CSV file's content (see the module docstring), verified at ``rate`` (see :meth:`at_rate`)."""
        t, tr, s, v, a, j = self.resample(rate)
        cols = [t, tr[:, 0], s[:, 0], v[:, 0], a[:, 0], j[:, 0], tr[:, 1], s[:, 1], v[:, 1], a[:, 1], j[:, 1]]
        buf = io.StringIO()
        buf.write(",".join(CSV_COLUMNS) + "\n")
        np.savetxt(buf, np.column_stack(cols), delimiter=",", fmt="%.12g")
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
        """JSON-ready summary (everything but the arrays)."""
        return {
            "makespan": self.makespan,
            "motion_time": self.motion_time,
            "min_separation": self.min_separation,
            "domain": self.domain,
            "fallback": self.fallback,
            "fallback_reason": self.fallback_reason,
            "source": self.source.value,
            "word": list(self.word),
            "track": self.plan.track.to_dict(),
            "start": self.plan.start.tolist(),
            "goal": self.plan.goal.tolist(),
            "clearance": self.clearance,
            "limits": self.limits.to_dict(),
            "rate": self.rate,
            "rows": len(self.t),
            "columns": list(CSV_COLUMNS),
            "units": {"time": "s", "track": "m", "s": "m", "v": "m/s", "a": "m/s^2", "j": "m/s^3"},
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

    def to_json(self, path: str | os.PathLike[str]) -> None:
        """Write :meth:`summary` as JSON (atomically)."""
        atomic_write_text(path, json.dumps(self.summary(), indent=2, default=_json_default) + "\n")
