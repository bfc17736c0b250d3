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

import contextlib
import csv
import enum
import io
import json
import os
import shutil
import tempfile
from collections.abc import Callable, Iterable, Iterator
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
    "CSV_CHUNK_ROWS",
    "CSV_COLUMNS",
    "GRAPH_CSV_COLUMNS",
    "HEADING_COLUMNS",
    "XY_COLUMNS",
    "Content",
    "Source",
    "Streamed",
    "Trajectory",
    "atomic_write_bytes",
    "atomic_write_text",
    "check_output_path",
    "check_rate",
    "content_text",
    "csv_field",
    "csv_line",
    "directory_lock",
    "time_grid",
    "verified_rows",
    "write_directory",
    "write_output_file",
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
#: Memory one row takes at its peak (bytes): sampling and the gate (the CSV text is formatted and written in pieces
#: of :data:`CSV_CHUNK_ROWS` rows, :class:`Streamed`). Measured on the Y junction at 200 kHz (2 933 598 rows, 19
#: columns): peak resident memory 797 MB, 272 B per row with the interpreter; ``--format csv,ros2-yaml`` adds about
#: 400 B per row (20 kHz: 351 -> 470 MB for 294 286 rows), which 1 000 leaves room for.
ROW_BYTES = 1000
#: Default memory budget of a trajectory's rows (bytes): 4 GiB, about 4.3 million rows.
MEMORY_BUDGET = 4.0 * 2**30
#: Environment variable that overrides :data:`MEMORY_BUDGET` (bytes; suffix K, M or G).
BUDGET_ENV = "MPA_MEMORY_BUDGET"


#: Rows of one piece of :meth:`Trajectory.csv_chunks` (about 12 MB of text on a layout with coordinates).
CSV_CHUNK_ROWS = 65536


class Streamed:
    """A file's content made piece by piece while it is written, so the whole of it is never in memory.

    Parameters
    ----------
    chunks : callable
        ``chunks()`` yields the file's bytes in order (called once per write).
    """

    def __init__(self, chunks: Callable[[], Iterable[bytes]]) -> None:
        self.chunks = chunks

    def data(self) -> bytes:
        """The whole content (for callers that need it in memory)."""
        return b"".join(self.chunks())


#: A file's content: text (written as UTF-8), bytes, or :class:`Streamed` pieces.
Content = str | bytes | Streamed


def content_text(content: Content) -> str:
    """``content`` as text (UTF-8)."""
    if isinstance(content, str):
        return content
    return (content.data() if isinstance(content, Streamed) else content).decode("utf-8")


class Source(enum.Enum):
    """Where a verified trajectory comes from (a normal outcome, not an error)."""

    OPTIMIZED = "optimized"
    """The smoothed, re-timed, jerk-limited path."""
    PLAN = "plan"
    """The fallback: the plan's own polyline, every straight step rest to rest."""


def csv_field(value: str) -> str:
    """``value`` as one CSV field, quoted as RFC 4180 asks when it holds a comma, a quote or a line break.

    Written by :mod:`csv`'s writer (``QUOTE_MINIMAL`` with the RFC's ``\\r\\n`` as the line terminator, so a
    lone ``\\r`` is quoted too); :func:`csv.reader` reads back exactly ``value`` (the empty string as ``""``).
    """
    buf = io.StringIO()
    csv.writer(buf, lineterminator="\r\n", quoting=csv.QUOTE_MINIMAL).writerow([value])
    return buf.getvalue()[:-2]


def csv_line(cells: Iterable[Any]) -> str:
    """One CSV record: the cells as :func:`csv_field` (``str`` of each), comma-separated, ending in ``\\n``."""
    return ",".join(csv_field(str(c)) for c in cells) + "\n"


def check_rate(rate: Any, name: str = "rate") -> float:
    """Validate a setpoint rate (Hz): a positive finite number.

    Raises
    ------
    InvalidInputError
    """
    try:
        r = float(rate)
    except (TypeError, ValueError, OverflowError):
        raise InvalidInputError(f"{name} is {rate!r}, expected a positive finite number (Hz)") from None
    if not np.isfinite(r) or r <= 0:
        raise InvalidInputError(f"{name} is {r!r}, expected a positive finite number (Hz)")
    return r


def memory_budget() -> float:
    """The memory (bytes) a trajectory's rows may take: ``$MPA_MEMORY_BUDGET`` (bytes; suffix K, M or G allowed),
    else :data:`MEMORY_BUDGET` (4 GiB)."""
    text = os.environ.get(BUDGET_ENV, "").strip().upper()
    if not text:
        return MEMORY_BUDGET
    scale = {"K": 2.0**10, "M": 2.0**20, "G": 2.0**30}.get(text[-1:], 1.0)
    try:
        value = float(text[:-1] if scale != 1.0 else text) * scale
    except ValueError:
        raise InvalidInputError(f"${BUDGET_ENV} is {text!r}, expected a number of bytes (suffix K, M or G)") from None
    if not np.isfinite(value) or value <= 0:
        raise InvalidInputError(f"${BUDGET_ENV} is {text!r}, expected a positive number of bytes")
    return value


def time_grid(duration: float, rate: float) -> FloatArray:
    """``k / rate`` for ``k = 0 … ceil(duration·rate)`` (s). Shape (N,).

    Checked before any row is made: the rows' memory, estimated as :data:`ROW_BYTES` per row (the peak of
    sampling, the gate and the export, measured), must fit :func:`memory_budget`, and there are at most
    :data:`MAX_ROWS` rows.

    Raises
    ------
    InvalidInputError
        Too many rows for the budget: the message names ``--rate`` and the largest rate that fits.
    """
    with np.errstate(over="ignore"):
        steps = float(np.ceil(duration * rate - 1e-9)) if duration > 0 else 0.0
    budget = memory_budget()
    fit = int(min(MAX_ROWS, budget // ROW_BYTES))
    if not steps + 1 <= fit:  # also an infinite count
        n = steps
        best = (fit - 1) / duration
        digits = 10 ** np.floor(np.log10(best)) / 10 if best > 0 else 1.0
        best = float(np.floor(best / digits) * digits)
        raise InvalidInputError(
            f"rate (--rate) {rate:g} Hz gives {n + 1:.0f} rows for the {duration:.6g} s motion, about "
            f"{(n + 1) * ROW_BYTES / 2**30:.3g} GiB, above the memory budget of {budget / 2**30:.3g} GiB "
            f"({fit} rows; ${BUDGET_ENV} sets it); the largest rate that fits is {best:g} Hz"
        )
    return np.arange(int(steps) + 1) / rate


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


def atomic_write_bytes(path: str | os.PathLike[str], data: bytes | Streamed) -> None:
    """Write ``data`` to ``path`` through a temporary file in the same directory and :func:`os.replace`.

    ``data`` may be :class:`Streamed`: its pieces are written as they are made.

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
            if isinstance(data, Streamed):
                for piece in data.chunks():
                    fh.write(piece)
            else:
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


#: Files of a run that :func:`write_directory` owns: a new run replaces them all, and those of formats not asked for
#: are not carried over from an older run. Any other file in the directory is kept.
RUN_FILES = frozenset(
    {"setpoints.csv", "summary.json", "trajectory.yaml", "trajectory.mcap", "pvt.csv", "trajectory.png", "plan.json"}
)
#: Environment variable of the test hook of :func:`write_directory`: seconds to pause after each stage.
PAUSE_ENV = "MPA_TEST_PAUSE_BETWEEN_FILES"
_RENAME_EXCHANGE = 2  # renameat2 flag (Linux >= 3.15)
_AT_FDCWD = -100


def _exchange(a: Path, b: Path) -> bool:
    """Swap the directory entries ``a`` and ``b`` in one step (``renameat2(RENAME_EXCHANGE)``).

    Returns False where the system or the file system cannot (then the caller renames twice).
    """
    import ctypes
    import ctypes.util
    import errno as _errno

    try:
        libc = ctypes.CDLL(ctypes.util.find_library("c") or None, use_errno=True)
        fn = libc.renameat2
    except (OSError, AttributeError):
        return False
    fn.argtypes = [ctypes.c_int, ctypes.c_char_p, ctypes.c_int, ctypes.c_char_p, ctypes.c_uint]
    fn.restype = ctypes.c_int
    if fn(_AT_FDCWD, os.fsencode(a), _AT_FDCWD, os.fsencode(b), _RENAME_EXCHANGE) == 0:
        return True
    err = ctypes.get_errno()
    if err in (_errno.EINVAL, _errno.ENOSYS, _errno.EOPNOTSUPP):
        return False
    raise OSError(err, os.strerror(err), str(b))


def _hidden_stem(name: str) -> str:
    """The start of the hidden sibling names of directory ``name`` (short enough for any file system)."""
    import hashlib

    if len(name.encode("utf-8")) <= 100:
        return f".{name}"
    return f".mpa-{hashlib.sha1(name.encode('utf-8')).hexdigest()[:16]}"


def _pid_alive(pid: int) -> bool:
    if pid == os.getpid():
        return True
    try:
        os.kill(pid, 0)
    except ProcessLookupError:
        return False
    except OSError:  # alive, another user's
        return True
    return True


def _recover_siblings(d: Path) -> None:
    """Clean up after writers of ``d`` that died (``kill -9``, power loss) in :func:`write_directory`.

    A dead writer's new set (``.NAME.mpa-new.PID.*``) is removed. If it died between the two renames of the
    fallback without ``renameat2`` (``d`` missing, the previous set in ``.NAME.mpa-old.PID.*``), the previous set
    is put back first.
    """
    stem = _hidden_stem(d.name)
    try:
        siblings = sorted(d.parent.glob(f"{glob_escape(stem)}.mpa-*.*.*"))
    except OSError:
        return
    for sib in siblings:
        kind, _, rest = sib.name[len(stem) + 5 :].partition(".")
        pid_text = rest.split(".", 1)[0]
        if kind not in ("new", "old") or not pid_text.isdigit() or _pid_alive(int(pid_text)):
            continue
        if kind == "old" and not d.exists():
            try:
                os.rename(sib, d)
                continue
            except OSError:
                pass
        shutil.rmtree(sib, ignore_errors=True)


def _pause(stage: str) -> None:
    """Test hook: with ``$MPA_TEST_PAUSE_BETWEEN_FILES`` set, say ``stage`` on stderr and pause.

    The value is ``SECONDS`` (pause after every stage) or ``SECONDS@STAGE`` (only at that stage, e.g.
    ``30@commit``). Stages: ``wrote NAME`` after each file, ``commit`` before the swap, ``committed`` after it.
    """
    value = os.environ.get(PAUSE_ENV)
    if value:
        import sys
        import time

        seconds, _, only = value.partition("@")
        print(f"mpa-test-stage: {stage}", file=sys.stderr, flush=True)
        if not only or only == stage:
            time.sleep(float(seconds))


def _fsync_dir(path: Path) -> None:
    try:
        fd = os.open(path, os.O_RDONLY)
    except OSError:
        return
    try:
        os.fsync(fd)
    except OSError:
        pass
    finally:
        os.close(fd)


def write_directory(
    out: str | os.PathLike[str],
    files: dict[str, Content],
    *,
    write: Callable[[Path, Content], None] | None = None,
    option: str = "--out",
) -> list[Path]:
    """Replace the run files of directory ``out`` by ``files`` (name -> content) as a whole, in one step.

    Every file is written into a hidden temporary directory beside ``out`` (``.NAME.mpa-new.PID.XXXX``), with
    the other files of ``out`` (those not in :data:`RUN_FILES`) linked in; then that directory and ``out`` are
    swapped by one ``renameat2(RENAME_EXCHANGE)`` (a plain :func:`os.rename` when ``out`` does not exist yet), the
    commit point, and the previous set is removed. After any interruption (``kill -9``, ``SIGTERM``, Ctrl-C, a
    full disk) ``out`` holds exactly one run's complete set: this one or the previous one, untouched; files of
    formats an older run wrote and this one does not are gone. A directory that cannot be swapped (the working
    directory or one holding it, a mount point, or one with subdirectories that are not a run's) is written in
    place instead: each file atomically, ``summary.json`` last, stale run files removed, under the lock. Where
    ``renameat2`` is missing, ``out`` is renamed
    aside first and the next write of ``out`` puts it back if the writer died in between. A dead writer's
    temporary directory is removed by the next write. Writers of directories in one parent hold an exclusive
    ``flock`` of the parent (:func:`directory_lock`).

    Parameters
    ----------
    out : path
        The output directory (created with its parents if missing).
    files : dict
        File name -> content (``str`` written as UTF-8, ``bytes`` as is, :class:`Streamed` piece by piece).
    write : callable, optional
        ``write(path, content)`` writes one file (default: :func:`atomic_write_text` / :func:`atomic_write_bytes`).
    option : str
        Name of the option in error messages.

    Returns
    -------
    list of Path
        The files written, ``out / name``.

    Raises
    ------
    InvalidInputError
        ``out`` is empty or exists and is not a directory, or a file could not be written
        (``--out: cannot write PATH: reason``); ``out`` is then unchanged.
    """
    if not str(out).strip():
        raise InvalidInputError(f"{option} is {str(out)!r}, expected a directory path")
    d = Path(os.path.realpath(out))
    try:
        exists, is_dir = d.exists(), d.is_dir()
    except OSError as exc:  # e.g. a name too long for the file system
        raise InvalidInputError(f"{option}: cannot write {str(out)!r}: {exc.strerror or type(exc).__name__}") from None
    if exists and not is_dir:
        raise InvalidInputError(f"{option} is {str(out)!r}, which exists and is not a directory")

    def default_write(path: Path, content: Content) -> None:
        if isinstance(content, str):
            atomic_write_text(path, content)
        else:
            atomic_write_bytes(path, content)

    writer = write or default_write
    target = Path(out)
    try:
        if d.is_dir() and _in_place(d):
            return _write_in_place(d, Path(out), files, writer, option)
        d.parent.mkdir(parents=True, exist_ok=True)
        with directory_lock(d):
            _recover_siblings(d)
            stem = _hidden_stem(d.name)
            tmp = Path(tempfile.mkdtemp(dir=d.parent, prefix=f"{stem}.mpa-new.{os.getpid()}."))
            try:
                for name, content in files.items():
                    target = Path(out) / name
                    writer(tmp / name, content)
                    _pause(f"wrote {name}")
                target = Path(out)
                if d.is_dir():
                    for entry in os.scandir(d):
                        if entry.name in RUN_FILES or entry.name in files:
                            continue
                        if entry.is_dir(follow_symlinks=False):
                            shutil.copytree(entry.path, tmp / entry.name, symlinks=True, copy_function=_link_or_copy)
                        else:
                            _link_or_copy(entry.path, str(tmp / entry.name))
                    os.chmod(tmp, os.stat(d).st_mode & 0o7777)
                else:
                    os.chmod(tmp, 0o777 & ~_umask())
                _fsync_dir(tmp)
                _pause("commit")
                if not d.exists():
                    os.rename(tmp, d)
                elif not _exchange(tmp, d):
                    old = Path(tempfile.mkdtemp(dir=d.parent, prefix=f"{stem}.mpa-old.{os.getpid()}."))
                    os.rmdir(old)
                    os.rename(d, old)
                    os.rename(tmp, d)
                    tmp = old
                _fsync_dir(d.parent)
                _pause("committed")
            finally:
                shutil.rmtree(tmp, ignore_errors=True)
    except InvalidInputError:
        raise
    except OSError as exc:
        reason = exc.strerror or type(exc).__name__
        raise InvalidInputError(f"{option}: cannot write {str(target)!r}: {reason}") from None
    return [Path(out) / name for name in files]


def _in_place(d: Path) -> bool:
    """Whether directory ``d`` must be written in place rather than swapped: it is (or holds) the working
    directory, a mount point, or it holds subdirectories that are not a run's (they would have to be copied)."""
    try:
        cwd = Path(os.getcwd()).resolve()
    except OSError:
        cwd = None
    if cwd is not None and (cwd == d or d in cwd.parents):
        return True
    if os.path.ismount(d):
        return True
    with os.scandir(d) as it:
        return any(e.is_dir(follow_symlinks=False) and e.name not in RUN_FILES for e in it)


def _write_in_place(
    d: Path,
    shown: Path,
    files: dict[str, Content],
    writer: Callable[[Path, Content], None],
    option: str,
) -> list[Path]:
    """The fallback of :func:`write_directory` for a directory it cannot swap (see :func:`_in_place`): each file
    replaced atomically, ``summary.json`` last, then the run files of formats not asked for removed; all under
    :func:`directory_lock`. A reader that takes the lock sees one run's set."""
    order = [n for n in files if n != "summary.json"] + [n for n in files if n == "summary.json"]
    target = shown
    try:
        with directory_lock(d):
            for name in order:
                target = shown / name
                writer(d / name, files[name])
                _pause(f"wrote {name}")
            for name in RUN_FILES - set(files):
                (d / name).unlink(missing_ok=True)
    except OSError as exc:
        reason = exc.strerror or type(exc).__name__
        raise InvalidInputError(f"{option}: cannot write {str(target)!r}: {reason}") from None
    return [shown / name for name in files]


def _link_or_copy(src: str, dst: str) -> str:
    try:
        os.link(src, dst, follow_symlinks=False)
    except OSError:
        shutil.copy2(src, dst, follow_symlinks=False)
    return dst


@contextlib.contextmanager
def directory_lock(directory: str | os.PathLike[str]) -> Iterator[None]:
    """Hold an exclusive lock on the run files of ``directory``: a ``flock`` of its parent directory.

    :func:`write_directory` holds it while it writes and swaps, so two processes writing one directory never mix
    their files, and a reader that takes it sees one run's files. Without ``fcntl`` (Windows) it does nothing.
    """
    try:
        import fcntl
    except ImportError:  # pragma: no cover - not POSIX
        yield
        return
    parent = Path(os.path.realpath(directory)).parent
    fd = os.open(parent, os.O_RDONLY)
    try:
        fcntl.flock(fd, fcntl.LOCK_EX)
        yield
    finally:
        os.close(fd)  # releases the lock


def check_output_path(path: Any, what: str = "path") -> Path:
    """Check an output file's path before any work: a non-empty ``str`` or path-like that is not a directory.

    Raises
    ------
    InvalidInputError
        The message names ``what``, the value and what was expected.
    """
    if isinstance(path, bytes) or not isinstance(path, (str, os.PathLike)):
        raise InvalidInputError(f"{what} is {path!r}, expected a file path (str or os.PathLike)")
    text = os.fspath(path)
    if not isinstance(text, str) or not text.strip():
        raise InvalidInputError(f"{what} is {text!r}, expected a file path")
    if "\x00" in text:
        raise InvalidInputError(f"{what} is {text!r}, expected a file path without a NUL character")
    p = Path(text)
    try:
        is_dir = p.is_dir()
    except OSError as exc:  # e.g. a name too long for the file system
        raise InvalidInputError(f"{what} {text!r}: cannot write: {exc.strerror or type(exc).__name__}") from None
    if is_dir or text.endswith(os.sep):
        raise InvalidInputError(f"{what} is {text!r}, which is a directory, expected a file path")
    return p


def write_output_file(path: Path, content: Content, what: str = "path") -> None:
    """Write one file atomically (:func:`atomic_write_text`/:func:`atomic_write_bytes`).

    Raises
    ------
    InvalidInputError
        The file cannot be written: ``{what} {path!r}: cannot write: reason`` (no ``[Errno ..]``).
    """
    try:
        if isinstance(content, str):
            atomic_write_text(path, content)
        else:
            atomic_write_bytes(path, content)
    except OSError as exc:
        reason = exc.strerror or type(exc).__name__
        raise InvalidInputError(f"{what} {str(path)!r}: cannot write: {reason}") from None


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
        Corridor QP statistics (segments, iterations, QP time and status), pieces and blends.
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
        return b"".join(self.csv_chunks(rate)).decode("utf-8")

    def csv_chunks(self, rate: float | None = None) -> Iterator[bytes]:
        """The CSV file's content (UTF-8) in pieces of at most :data:`CSV_CHUNK_ROWS` rows, the header first.

        The rows are verified at ``rate`` (see :meth:`at_rate`) before the first piece; each piece is formatted
        when it is asked for, so writing them one by one keeps the text of only one piece in memory. Numbers are
        ``"%.12g"``, the edge names RFC 4180 fields (:func:`csv_field`), ``*_dir`` integers
        (:mod:`trajopt.csv_kernels`).
        """
        tr = self if rate is None else self.at_rate(rate)
        return tr._csv_chunks()

    def _csv_chunks(self) -> Iterator[bytes]:
        from trajopt.csv_kernels import csv_rows, format_g12, text_column

        columns = self.columns
        names = [csv_field(n) for n in self.edge_names]
        e, o, d = self._positions()
        col: dict[str, tuple[str, Any]] = {"time": ("f", self.t)}
        for r, x in enumerate("ab"):
            col.update(
                {
                    f"{x}_track": ("f", self.track[:, r]),
                    f"{x}_s": ("f", self.s[:, r]),
                    f"{x}_v": ("f", self.v[:, r]),
                    f"{x}_a": ("f", self.a[:, r]),
                    f"{x}_j": ("f", self.j[:, r]),
                    f"{x}_edge": ("name", e[:, r]),
                    f"{x}_offset": ("f", o[:, r]),
                    f"{x}_dir": ("int", d[:, r]),
                }
            )
        if "b_y" in columns:
            p = self.xy()
            col.update({"a_x": ("f", p[:, 0, 0]), "a_y": ("f", p[:, 0, 1]), "b_x": ("f", p[:, 1, 0])})
            col["b_y"] = ("f", p[:, 1, 1])
        if "b_heading" in columns:
            h = self.headings()
            col.update({"a_heading": ("f", h[:, 0]), "b_heading": ("f", h[:, 1])})
        yield csv_line(columns).encode("utf-8")
        for i in range(0, len(self.t), CSV_CHUNK_ROWS):
            cells = []
            for name in columns:
                kind, x = col[name]
                x = x[i : i + CSV_CHUNK_ROWS]
                if kind == "f":
                    cells.append(format_g12(x))
                elif kind == "name":
                    cells.append(text_column(names, x))
                else:
                    values, index = np.unique(x, return_inverse=True)
                    cells.append(text_column([str(int(v)) for v in values], index.reshape(-1)))
            yield csv_rows(cells)

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
        target = check_output_path(path)
        chunks = self.csv_chunks(rate)  # verified at the rate before anything is written
        write_output_file(target, Streamed(lambda: chunks))

    def margins(self) -> Any:
        """Tracking margin and delay tolerance (:func:`trajopt.margins.margins`; computed once)."""
        cached = self.__dict__.get("_margins")
        if cached is None:
            from trajopt.margins import margins

            cached = margins(self)
            object.__setattr__(self, "_margins", cached)
        return cached

    def words(self) -> dict[str, str]:
        """The motion in plain words per cart (:func:`trajopt.words.describe`; computed once)."""
        cached = self.__dict__.get("_words")
        if cached is None:
            from trajopt.words import describe

            cached = describe(self)
            object.__setattr__(self, "_words", cached)
        return dict(cached)

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
        """Write :meth:`summary` as JSON (atomically).

        Raises
        ------
        InvalidInputError
            ``path`` is not a file path, or the file cannot be written (the message names the path and the reason).
        """
        target = check_output_path(path)
        write_output_file(target, json.dumps(self.summary(), indent=2, default=_json_default) + "\n")
