"""Running a script of ``experiments/`` in a fresh interpreter from the repository's root, and the PNG it writes."""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
#: The eight bytes every PNG file starts with.
PNG_SIGNATURE = b"\x89PNG\r\n\x1a\n"


def run_script(*args: str, timeout: float = 300.0) -> subprocess.CompletedProcess[str]:
    """``python ARGS`` run from the repository's root, its output captured as text (never raises on exit status).

    Parameters
    ----------
    *args : str
        The script's path relative to the root, then its arguments.
    timeout : float
        Seconds before the run is killed (``subprocess.TimeoutExpired``).
    """
    return subprocess.run(
        [sys.executable, *args], cwd=ROOT, capture_output=True, text=True, timeout=timeout, check=False
    )


def is_png(path: Path, min_bytes: int = 5000) -> bool:
    """Whether ``path`` holds a PNG file of at least ``min_bytes`` bytes."""
    return path.read_bytes()[:8] == PNG_SIGNATURE and path.stat().st_size > min_bytes
