"""The installed version of ``lollipop-mpa`` (:data:`mpa.__version__`).

From the package metadata (:func:`importlib.metadata.version`); in a source checkout that is not installed,
from the ``version`` line of its ``pyproject.toml``.
"""

from __future__ import annotations

import re
from importlib import metadata
from pathlib import Path

__all__ = ["__version__"]


def _version() -> str:
    try:
        return metadata.version("lollipop-mpa")
    except metadata.PackageNotFoundError:
        pass
    try:
        text = (Path(__file__).resolve().parents[1] / "pyproject.toml").read_text(encoding="utf-8")
    except OSError:
        return "0+unknown"
    m = re.search(r'(?m)^version\s*=\s*"([^"]+)"', text)
    return m.group(1) if m else "0+unknown"


#: The project's version string (e.g. ``"0.1.0"``).
__version__ = _version()
