"""Output files and directories: a path checked before anything is made, one file written atomically, and a run's
directory replaced as a whole (:func:`write_directory`, under :func:`directory_lock`), a directory another library
writes (a ROS 2 bag) put in place as a whole (:func:`atomic_directory`).
"""

from __future__ import annotations

import contextlib
import os
import shutil
import tempfile
from collections.abc import Callable, Iterator
from pathlib import Path
from typing import Any

from mpa._deprecation import deprecated_alias
from mpa.errors import InvalidInputError
from trajopt.io.atomic import (
    Content,
    _fsync_dir,
    _umask,
    atomic_write,
    glob_escape,
)

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


@contextlib.contextmanager
def atomic_directory(path: str | os.PathLike[str]) -> Iterator[Path]:
    """A path for a new directory that replaces the directory ``path`` as a whole when the block ends.

    The counterpart of :func:`~trajopt.io.atomic.atomic_path` for a directory another library fills (a ROS 2
    bag): the block makes the directory at the yielded path, inside a hidden temporary directory
    ``.NAME.XXXX.tmp`` beside ``path``; after the block it gets the usual permissions (``0o777`` less the umask)
    and is swapped with ``path`` in one ``renameat2(RENAME_EXCHANGE)`` (a plain :func:`os.replace` when ``path``
    does not exist; where the exchange is missing, ``path`` is renamed aside and put back if the second rename
    fails). The temporary directory, with the previous ``path``, is removed; on any error ``path`` is untouched.

    Parameters
    ----------
    path : str or path-like
        The directory to replace; its parent must exist.

    Yields
    ------
    Path
        Where the block makes the new directory (it does not exist yet).
    """
    target = Path(path)
    parent = target.parent if str(target.parent) else Path(".")
    tmp = Path(tempfile.mkdtemp(dir=parent, prefix=f".{target.name}.", suffix=".tmp"))
    try:
        new = tmp / target.name
        yield new
        os.chmod(new, 0o777 & ~_umask())
        if not target.exists():
            os.replace(new, target)
        elif not _exchange(new, target):
            old = tmp / ".old"
            os.replace(target, old)
            try:
                os.replace(new, target)
            except BaseException:
                os.replace(old, target)
                raise
    finally:
        shutil.rmtree(tmp, ignore_errors=True)


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

    writer = write or atomic_write
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


def validate_output_path(path: Any, what: str = "path") -> Path:
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


#: Deprecated name of :func:`validate_output_path` (warns).
check_output_path = deprecated_alias(validate_output_path, "check_output_path")


def write_output_file(path: Path, content: Content, what: str = "path") -> None:
    """Write one file atomically (:func:`atomic_write_text`/:func:`atomic_write_bytes`).

    Raises
    ------
    InvalidInputError
        The file cannot be written: ``{what} {path!r}: cannot write: reason`` (no ``[Errno ..]``).
    """
    try:
        atomic_write(path, content)
    except OSError as exc:
        reason = exc.strerror or type(exc).__name__
        raise InvalidInputError(f"{what} {str(path)!r}: cannot write: {reason}") from None
