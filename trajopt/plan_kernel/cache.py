"""The compiled search's on-disk cache kept consistent across its modules.

numba's cache (``cache=True``) keys a kernel's machine code by its own source file's time stamp and size only, while
a kernel keeps the code of the kernels it calls from other modules compiled into its own. After one module of this
package changes (an edit, a checkout in an editable install) while its callers' modules do not, the callers would
load stale code: the search would run the previous version of the changed kernels. So the package's cache is keyed
as a whole: :func:`fresh_cache` keeps a stamp of the time stamps and sizes of every module the kernels are compiled
from (this package's, and the :mod:`mpa` modules whose constants they read) beside the cache, and removes the
package's cache files when the stamp differs, before any kernel is loaded (:mod:`trajopt.plan_kernel` calls it on
import). An install rewrites every file, so it renews every kernel's key anyway; this guards the working copies.
A cache directory that cannot be written is left as it is (numba then compiles in memory).
"""

from __future__ import annotations

import contextlib
import os
from collections.abc import Iterable
from pathlib import Path

__all__ = ["STAMP", "fresh_cache", "kernel_sources"]

#: The stamp's file name in the package's ``__pycache__``.
STAMP = "plan_kernel.sources"

#: The :mod:`mpa` modules whose constants the kernels read (numba compiles a global's value into the code).
_MPA_SOURCES = (
    "planners/search_common.py",
    "planners/graph/base.py",
    "planners/graph/bounds.py",
    "planners/corners.py",
)


def kernel_sources() -> list[Path]:
    """The source files the package's kernels are compiled from: its own modules, :mod:`trajopt._numba` and the
    :mod:`mpa` modules of ``_MPA_SOURCES``, in a fixed order."""
    here = Path(__file__).resolve().parent
    mpa_dir = here.parent.parent / "mpa"
    if not (mpa_dir / "__init__.py").exists():  # an install where mpa lies elsewhere
        import mpa

        mpa_dir = Path(mpa.__file__).resolve().parent
    own = sorted(here.glob("*.py"))
    return [*own, here.parent / "_numba.py", *(mpa_dir / s for s in _MPA_SOURCES)]


def _stamp(sources: Iterable[Path]) -> str:
    lines = []
    for p in sources:
        try:
            st = p.stat()
            lines.append(f"{p.name} {st.st_mtime_ns} {st.st_size}")
        except OSError:
            lines.append(f"{p.name} missing")
    return "\n".join(lines) + "\n"


def fresh_cache(cache_dir: Path, sources: Iterable[Path]) -> bool:
    """Remove numba's cache files (``*.nbi``, ``*.nbc``) from ``cache_dir`` unless its stamp (``STAMP``) matches the
    time stamps and sizes of ``sources``, and write the new stamp (a temporary file, then a rename).

    Parameters
    ----------
    cache_dir : Path
        The package's ``__pycache__`` directory (need not exist).
    sources : iterable of Path
        The files the kernels are compiled from (:func:`kernel_sources`).

    Returns
    -------
    bool
        Whether the stamp differed (files were removed, when there were any); False also when the directory cannot
        be read or written.
    """
    stamp = _stamp(sources)
    path = cache_dir / STAMP
    try:
        if path.read_text() == stamp:
            return False
    except OSError:
        pass
    try:
        cache_dir.mkdir(exist_ok=True)
        for f in cache_dir.iterdir():
            if f.suffix in (".nbi", ".nbc"):
                with contextlib.suppress(FileNotFoundError):  # another process removed it first
                    f.unlink()
        tmp = cache_dir / f".{STAMP}.{os.getpid()}"
        tmp.write_text(stamp)
        os.replace(tmp, path)
    except OSError:  # a read-only install: numba keeps its cache elsewhere or compiles in memory
        return False
    return True
