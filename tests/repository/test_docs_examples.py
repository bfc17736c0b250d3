"""Every Python example in docs/*.md runs as written, in a scratch directory.

The README's examples: tests/repository/test_readme.py.
"""

from __future__ import annotations

import re
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]
DOCS = sorted((ROOT / "docs").glob("*.md"))


def _blocks(path: Path) -> list[str]:
    return re.findall(r"```python\n(.*?)```", path.read_text(encoding="utf-8"), flags=re.S)


@pytest.mark.parametrize("path", [p for p in DOCS if _blocks(p)], ids=lambda p: p.name)
def test_python_examples_run(path: Path, tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.chdir(tmp_path)
    (tmp_path / "examples").symlink_to(ROOT / "examples", target_is_directory=True)
    namespace: dict[str, object] = {"__name__": "__doc_example__"}  # one page reads top to bottom, as a reader does
    for i, code in enumerate(_blocks(path)):
        try:
            exec(compile(code, f"{path.name} (python block {i})", "exec"), namespace)
        except Exception as exc:  # pragma: no cover - the message is the point
            pytest.fail(f"{path.name}, python block {i} fails: {type(exc).__name__}: {exc}\n{code}")


def test_every_doc_with_code_is_checked() -> None:
    assert sum(bool(_blocks(p)) for p in DOCS) >= 2
