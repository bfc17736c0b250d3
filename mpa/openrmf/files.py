"""Reading Open-RMF YAML files safely.

libyaml's C loader on a large stack where the nesting is bounded, PyYAML's Python loader otherwise; every
failure is one :class:`~mpa.errors.InvalidInputError`.
"""

from __future__ import annotations

import threading
from pathlib import Path

from mpa.errors import InvalidInputError

#: Nesting bound (levels) up to which YAML is parsed by libyaml's C loader (PyYAML's ``CSafeLoader``, about 6x
#: faster: the airport terminal's map 1.5 -> 0.26 s CPU) on a thread with :data:`C_LOADER_STACK` bytes of stack; the C
#: loader recurses on the C stack, which a deeper text would overflow (a crash, not an error), so deeper texts go to
#: the Python loader, whose recursion limit gives an error.
C_LOADER_DEPTH = 20_000


C_LOADER_STACK = 64 << 20


def _nesting_bound(text: str) -> int:
    """An upper bound of the nesting depth of a YAML text: every flow collection opens with ``[`` or ``{``, every
    compact block entry needs a ``-`` or ``?``, and the other block levels need one more column of indentation each
    (a mapping and the sequence it holds may share one), so at most twice the longest line."""
    longest = max((len(line) for line in text.splitlines()), default=0)
    return sum(text.count(c) for c in "[{-?") + 2 * longest + 2


def _safe_load(text: str) -> object:
    """``yaml.safe_load``, with libyaml's C loader when it is installed and the text's nesting is bounded (a text
    the C loader refuses is read again by PyYAML's loader, so that the error names what PyYAML names)."""
    import yaml

    loader = getattr(yaml, "CSafeLoader", None)
    if loader is None or _nesting_bound(text) > C_LOADER_DEPTH:
        return yaml.safe_load(text)
    out: list[object] = []
    err: list[BaseException] = []

    def run() -> None:
        try:
            out.append(yaml.load(text, Loader=loader))  # the safe loader, in C
        except BaseException as exc:  # re-raised in the caller's thread
            err.append(exc)

    old = threading.stack_size(C_LOADER_STACK)
    try:
        worker = threading.Thread(target=run, name="yaml-c-loader", daemon=True)
        worker.start()
    finally:
        threading.stack_size(old)
    worker.join()
    if err:
        if isinstance(err[0], yaml.YAMLError):  # PyYAML's own message and mark for a text that is not valid
            return yaml.safe_load(text)
        raise err[0]
    return out[0]


def _load_yaml(text: str, what: str) -> object:
    import yaml

    try:
        return _safe_load(text)
    except RecursionError:
        raise InvalidInputError(f"{what} is nested too deeply, expected at most a few hundred levels") from None
    except yaml.YAMLError as exc:
        mark = getattr(exc, "problem_mark", None)
        where = f" at line {mark.line + 1} column {mark.column + 1}" if mark is not None else ""
        raise InvalidInputError(f"{what} is not valid YAML or JSON ({getattr(exc, 'problem', exc)}{where})") from None


def read_yaml_file(path: str | Path, what: str) -> object:
    """The decoded content of a UTF-8 YAML (or JSON) file; ``what`` names the file in the error messages.

    Raises
    ------
    InvalidInputError
        The file is missing, unreadable, or neither YAML nor JSON.
    """
    return _load_yaml(_read_text(path, what, "a UTF-8 YAML file"), f"{what} file {str(path)!r}")


def _read_text(path: str | Path, what: str, expected: str) -> str:
    """The text of a UTF-8 file; InvalidInputError naming it (``what`` file) when missing or unreadable."""
    p = Path(path)
    try:
        return p.read_text(encoding="utf-8")
    except FileNotFoundError:
        raise InvalidInputError(f"{what} file {str(p)!r} does not exist, expected {expected}") from None
    except (OSError, UnicodeDecodeError) as exc:
        raise InvalidInputError(f"{what} file {str(p)!r} cannot be read ({exc}), expected {expected}") from None
