"""An on-disk cache of converted Open-RMF maps: the layout of a building map or navigation graph, read once.

Converting a map costs its YAML parse and the conversion (the airport terminal's 177 kB map: about 0.24 s CPU);
the cached layout is read back in about 2 ms. The cache is an optimisation only and is never trusted:

- an entry's name and its first line hold the key: the SHA-256 of the file's text, the level and navigation graph
  asked for, :data:`CACHE_FORMAT`, the source code of the converter (:mod:`mpa.openrmf`) and where PyYAML is
  installed (path, size and time of its ``__init__``), so an edited map, a different level, a changed converter or
  a reinstalled PyYAML never finds an old entry;
- the first line also holds the SHA-256 of the rest of the entry; an entry whose key or digest does not match,
  that does not parse, or whose content is not a layout and its description, is ignored and written anew;
- entries are written to a temporary file in the cache directory and renamed into place (a reader sees a whole
  entry or none); a cache directory that cannot be created or written leaves the map converted in memory.

The directory is ``$MPA_CACHE_DIR`` when set (``off`` or the empty string turn the cache off), otherwise
``$XDG_CACHE_HOME/lollipop-mpa/layouts`` (``~/.cache/lollipop-mpa/layouts``; no cache without a home directory
or where the converter's source files cannot be read). Maps that fail to convert are never
cached (their error is raised every time); our JSON layouts are not cached (reading them is as fast as the cache).
"""

from __future__ import annotations

import hashlib
import json
import os
import tempfile
from collections.abc import Callable
from pathlib import Path
from typing import Any

__all__ = ["CACHED_KINDS", "CACHE_ENV", "CACHE_FORMAT", "cache_dir", "cached_layout", "entry_key"]

#: The environment variable naming the cache directory (``off`` or empty: no cache).
CACHE_ENV = "MPA_CACHE_DIR"
#: The entries' format; part of every key.
CACHE_FORMAT = "mpa-layout-cache 1"

#: The kinds of file (``info["kind"]`` of :func:`mpa.openrmf.read_layout_file`) whose conversion is cached.
CACHED_KINDS = ("building", "nav_graph")

_SOURCE_DIGEST: list[str] = []

Converted = tuple[dict[str, Any], dict[str, Any]]


def cache_dir() -> Path | None:
    """The cache directory (``$MPA_CACHE_DIR``, else the user's cache directory), or None when it is turned off."""
    env = os.environ.get(CACHE_ENV)
    if env is not None:
        return None if env.strip() in ("", "off") else Path(env).expanduser()
    base = os.environ.get("XDG_CACHE_HOME")
    if not base:
        try:
            base = str(Path.home() / ".cache")
        except (RuntimeError, KeyError):  # no home directory to be found: no cache
            return None
    return Path(base) / "lollipop-mpa" / "layouts"


def _source_digest() -> str:
    """SHA-256 of the converter's source files (:mod:`mpa.openrmf`) and of where PyYAML is installed (its
    ``__init__``'s path, size and modification time: a reinstalled PyYAML gives new keys without importing it)."""
    if not _SOURCE_DIGEST:
        import importlib.util

        h = hashlib.sha256()
        here = Path(__file__).resolve().parent
        for p in sorted(here.glob("*.py")):
            h.update(p.name.encode())
            h.update(p.read_bytes())
        spec = importlib.util.find_spec("yaml")
        if spec is not None and spec.origin:
            st = os.stat(spec.origin)
            h.update(f"{spec.origin}\0{st.st_size}\0{st.st_mtime_ns}".encode())
        _SOURCE_DIGEST.append(h.hexdigest())
    return _SOURCE_DIGEST[0]


def entry_key(text: str, level: str | None, nav_graph: int | None) -> str:
    """The key of a map's entry: SHA-256 (hex) of the format, the converter's source, the options and the text."""
    h = hashlib.sha256()
    for part in (CACHE_FORMAT, _source_digest(), repr(level), repr(nav_graph)):
        h.update(part.encode())
        h.update(b"\0")
    h.update(text.encode("utf-8", "surrogatepass"))
    return h.hexdigest()


def _read_entry(path: Path, key: str) -> Converted | None:
    """The entry at ``path`` if it is whole and belongs to ``key``; None for a missing, stale or damaged one."""
    try:
        data = path.read_bytes()
    except OSError:
        return None
    head, sep, body = data.partition(b"\n")
    if not sep:
        return None
    try:
        header = json.loads(head)
        if not isinstance(header, dict) or header.get("format") != CACHE_FORMAT or header.get("key") != key:
            return None
        if header.get("sha256") != hashlib.sha256(body).hexdigest():
            return None
        content = json.loads(body)
    except (ValueError, RecursionError):
        return None
    if not (isinstance(content, list) and len(content) == 2):
        return None
    layout, info = content
    if not (isinstance(layout, dict) and isinstance(info, dict) and isinstance(layout.get("edges"), list)):
        return None
    return layout, info


def _write_entry(directory: Path, path: Path, key: str, converted: Converted) -> None:
    """Write an entry whole (temporary file, then rename); any failure leaves the cache as it was."""
    body = json.dumps(list(converted), separators=(",", ":")).encode()
    header = json.dumps({"format": CACHE_FORMAT, "key": key, "sha256": hashlib.sha256(body).hexdigest()}).encode()
    tmp = None
    try:
        directory.mkdir(parents=True, exist_ok=True, mode=0o700)
        fd, tmp = tempfile.mkstemp(dir=directory, prefix=".entry-", suffix=".tmp")
        with os.fdopen(fd, "wb") as f:
            f.write(header + b"\n" + body)
        os.replace(tmp, path)
        tmp = None
    except OSError:
        pass
    finally:
        if tmp is not None:
            try:
                os.unlink(tmp)
            except OSError:
                pass


def cached_layout(text: str, level: str | None, nav_graph: int | None, convert: Callable[[], Converted]) -> Converted:
    """The converted map of ``text`` from the cache, or ``convert()`` stored there.

    Parameters
    ----------
    text : str
        The map file's text (the key is computed from it, not from the file's name or time).
    level, nav_graph
        The options the map is converted with (part of the key).
    convert : callable
        Converts the map: returns ``(layout, info)``; its errors propagate and nothing is stored. Only Open-RMF
        maps (``info["kind"]`` ``"building"`` or ``"nav_graph"``) are stored; our JSON layouts are returned as
        ``convert`` gives them.

    Returns
    -------
    layout, info : dict
        For Open-RMF maps JSON-shaped dicts (lists, not tuples), identical whether they come from the cache or
        from ``convert``.
    """
    directory = cache_dir()
    if directory is None:
        return convert()
    try:
        key = entry_key(text, level, nav_graph)
    except OSError:  # the converter's source cannot be read (e.g. a zipped install): no key, no cache
        return convert()
    path = directory / f"{key}.json"
    hit = _read_entry(path, key)
    if hit is not None:
        return hit
    converted = convert()
    if converted[1].get("kind") not in CACHED_KINDS:
        return converted
    layout, info = json.loads(json.dumps(list(converted)))  # the form an entry reads back as
    _write_entry(directory, path, key, (layout, info))
    return layout, info
