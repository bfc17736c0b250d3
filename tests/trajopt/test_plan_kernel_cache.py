"""The compiled search's on-disk cache is emptied when a module its kernels are compiled from changes
(:mod:`trajopt.plan_kernel.cache`): numba keys each kernel by its own file only, and a caller keeps its callees'
code, so a changed module with unchanged callers would otherwise run stale code."""

from __future__ import annotations

import os
from pathlib import Path

from trajopt.plan_kernel import cache


def _cache_files(d: Path) -> set[str]:
    return {f.name for f in d.iterdir() if f.suffix in (".nbi", ".nbc")}


def test_a_changed_source_empties_the_cache_and_an_unchanged_one_keeps_it(tmp_path: Path) -> None:
    src = [tmp_path / "search.py", tmp_path / "expand.py"]
    for p in src:
        p.write_text("x = 1\n")
    pyc = tmp_path / "__pycache__"
    pyc.mkdir()
    kept = pyc / "search.cpython-311.pyc"
    kept.write_bytes(b"pyc")

    def fill() -> None:
        for name in ("run._run-278.py311.nbi", "run._run-278.py311.1.nbc", "expand._push-204.py311.nbi"):
            (pyc / name).write_bytes(b"code")

    fill()
    assert cache.fresh_cache(pyc, src)  # no stamp yet: the cache may predate it
    assert _cache_files(pyc) == set() and kept.exists()
    assert (pyc / cache.STAMP).exists()
    fill()
    assert not cache.fresh_cache(pyc, src)  # nothing changed: the cache is kept
    assert len(_cache_files(pyc)) == 3
    st = src[1].stat()
    os.utime(src[1], ns=(st.st_atime_ns, st.st_mtime_ns + 1_000_000))  # one module edited (time stamp)
    assert cache.fresh_cache(pyc, src)
    assert _cache_files(pyc) == set() and kept.exists()
    fill()
    assert not cache.fresh_cache(pyc, src)
    src[0].write_text("x = 22\n")  # a change of size
    os.utime(src[0], ns=(st.st_atime_ns, st.st_mtime_ns))
    assert cache.fresh_cache(pyc, src)
    assert _cache_files(pyc) == set()
    src[1].unlink()  # a module removed
    fill()
    assert cache.fresh_cache(pyc, src)
    assert _cache_files(pyc) == set()
    assert not list(pyc.glob(".*"))  # no temporary stamp left


def test_an_unwritable_cache_directory_is_left_alone(tmp_path: Path) -> None:
    src = tmp_path / "search.py"
    src.write_text("x = 1\n")
    not_a_dir = tmp_path / "__pycache__"
    not_a_dir.write_text("a file where the directory would be")
    assert not cache.fresh_cache(not_a_dir, [src])
    assert not_a_dir.read_text().startswith("a file")


def test_the_kernels_sources_are_the_package_and_the_mpa_modules_whose_constants_they_read() -> None:
    names = [(p.parent.name, p.name) for p in cache.kernel_sources()]
    for mod in ("arith.py", "bound.py", "corners.py", "expand.py", "run.py", "search.py"):
        assert ("plan_kernel", mod) in names
    assert ("trajopt", "_numba.py") in names
    assert ("planners", "search_common.py") in names and ("graph", "base.py") in names
    assert all(p.exists() for p in cache.kernel_sources())
    pyc = Path(cache.__file__).resolve().parent / "__pycache__"
    stamp = (pyc / cache.STAMP).read_text()  # written when the package was imported
    assert stamp == cache._stamp(cache.kernel_sources())
