"""The README's quick start and Python example stay true."""

from __future__ import annotations

import re
from pathlib import Path

README = Path(__file__).resolve().parents[1] / "README.md"


def test_python_example_runs(tmp_path, monkeypatch) -> None:  # type: ignore[no-untyped-def]
    blocks = re.findall(r"```python\n(.*?)```", README.read_text(), flags=re.S)
    assert blocks, "README has no python example"
    monkeypatch.chdir(tmp_path)
    for code in blocks:
        exec(compile(code, "README.md", "exec"), {})
    assert (tmp_path / "setpoints.csv").stat().st_size > 1000


def test_quick_start_lines_and_ci_agree() -> None:
    text = README.read_text()
    quick = re.search(r"## Quick start\n\n```bash\n(.*?)```", text, flags=re.S)
    assert quick is not None
    lines = [ln for ln in quick.group(1).splitlines() if ln.strip()]
    assert lines == ["pip install -e . && mpa demo", 'pip install -e ".[test]" && python -m pytest -q']
    ci = (README.parent / ".ci" / "run").read_text()
    assert 'pip install --quiet -e ".[test]"' in ci and "python -m pytest -q" in ci
