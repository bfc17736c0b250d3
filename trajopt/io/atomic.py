"""Atomic writes, once for the whole project: a file is written to a temporary file in its directory and moved into
place with :func:`os.replace`, so a reader never sees a half-written file and nothing is left behind on an error.

:func:`atomic_path` is the one primitive (a temporary path, then the rename); :func:`atomic_write_bytes`,
:func:`atomic_write_text` and :func:`atomic_write` write content through it, :class:`Streamed` content piece by
piece as it is made.
"""

from __future__ import annotations

import contextlib
import os
import tempfile
from collections.abc import Callable, Iterable, Iterator
from pathlib import Path


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


def atomic_write_text(path: str | os.PathLike[str], text: str) -> None:
    """Write ``text`` (UTF-8) to ``path`` atomically (see :func:`atomic_write_bytes`)."""
    atomic_write_bytes(path, text.encode("utf-8"))


def _umask() -> int:
    mask = os.umask(0o022)
    os.umask(mask)
    return mask


def _remove_stale_temporaries(p: Path) -> None:
    """Remove ``.NAME.PID.*.tmp`` files (with any suffix) of ``p`` left by a process that no longer exists
    (e.g. ``kill -9``)."""
    parent = p.parent if str(p.parent) else Path(".")
    try:
        candidates = list(parent.glob(f".{glob_escape(p.name)}.*.tmp*"))
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


@contextlib.contextmanager
def atomic_path(path: str | os.PathLike[str], suffix: str = "") -> Iterator[Path]:
    """A temporary path beside ``path`` to write to; moved onto ``path`` with :func:`os.replace` when the block ends.

    The one atomic write of the project: every file the library, the command line and the figures write goes
    through it. The temporary file ``.NAME.PID.XXXX.tmp`` + ``suffix`` (a writer that picks the format by the
    file's extension, e.g. an animation writer, gets it from ``suffix``) is made in the target's directory; after
    the block it gets the usual permissions (``0o666`` less the umask) and replaces ``path``. On any error it is
    removed and ``path`` is untouched. A reader never sees a partial file, even if the writer is killed
    (``kill -9``): then only the hidden temporary is left, and the next write of ``path`` removes it.

    Parameters
    ----------
    path : str or path-like
        The file to write.
    suffix : str
        Appended to the temporary file's name (e.g. ``".gif"``).

    Yields
    ------
    Path
        The temporary file to write (it exists, empty).
    """
    p = Path(path)
    _remove_stale_temporaries(p)
    fd, name = tempfile.mkstemp(
        dir=p.parent if str(p.parent) else ".", prefix=f".{p.name}.{os.getpid()}.", suffix=".tmp" + suffix
    )
    os.close(fd)
    tmp = Path(name)
    try:
        yield tmp
        os.chmod(tmp, 0o666 & ~_umask())
        os.replace(tmp, p)
    except BaseException:
        try:
            os.unlink(tmp)
        except OSError:
            pass
        raise


def atomic_write_bytes(path: str | os.PathLike[str], data: bytes | Streamed) -> None:
    """Write ``data`` to ``path`` atomically (:func:`atomic_path`), flushed to the disk before the rename.

    ``data`` may be :class:`Streamed`: its pieces are written as they are made.
    """
    with atomic_path(path) as tmp, open(tmp, "wb") as fh:
        if isinstance(data, Streamed):
            for piece in data.chunks():
                fh.write(piece)
        else:
            fh.write(data)
        fh.flush()
        os.fsync(fh.fileno())


def atomic_write(path: str | os.PathLike[str], content: Content) -> None:
    """Write ``content`` to ``path`` atomically: text as UTF-8, bytes or :class:`Streamed` pieces as they are."""
    if isinstance(content, str):
        atomic_write_text(path, content)
    else:
        atomic_write_bytes(path, content)


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
