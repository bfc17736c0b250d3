"""The repository itself: no merge-conflict markers left in any tracked text file."""

from __future__ import annotations

import re
import subprocess
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
MARKER = re.compile(r"^(<{7}|>{7})( |$)|^={7}$", re.M)


def test_no_conflict_markers_in_tracked_text_files() -> None:
    files = subprocess.run(["git", "ls-files"], cwd=ROOT, capture_output=True, text=True, check=False).stdout.split()
    if not files:  # not a git checkout: check the usual text files
        files = [str(p.relative_to(ROOT)) for p in ROOT.rglob("*") if p.suffix in {".py", ".md", ".toml", ".json"}]
    bad = []
    for name in files:
        p = ROOT / name
        if p.suffix not in {".py", ".md", ".toml", ".json", ".txt", ".yaml", ".yml", ".cfg", ""} or not p.is_file():
            continue
        try:
            text = p.read_text(encoding="utf-8")
        except (UnicodeDecodeError, OSError):
            continue
        bad += [f"{name}:{text.count(chr(10), 0, m.start()) + 1}" for m in MARKER.finditer(text)]
    assert not bad, bad


def test_no_module_of_the_packages_above_700_lines() -> None:
    """One job per module: no module of ``mpa`` or ``trajopt`` is longer than 700 lines (docs/architecture.md)."""
    root = Path(__file__).resolve().parents[2]
    long = {
        str(p.relative_to(root)): n
        for package in ("mpa", "trajopt")
        for p in sorted((root / package).rglob("*.py"))
        if (n := len(p.read_text(encoding="utf-8").splitlines())) > 700
    }
    assert not long, long
