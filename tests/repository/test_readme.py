"""The README's quick start and Python example stay true."""

from __future__ import annotations

import re
from pathlib import Path

README = Path(__file__).resolve().parents[2] / "README.md"


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


def test_ci_runs_the_quality_gates_before_the_tests() -> None:
    lines = [ln.strip() for ln in (README.parent / ".ci" / "run").read_text().splitlines()]
    gates = ["ruff check .", "ruff format --check .", "mypy mpa trajopt"]
    for gate in gates:
        assert gate in lines, f".ci/run does not run {gate!r}"
    assert max(lines.index(g) for g in gates) < lines.index("python -m pytest -q")
    text = README.read_text()
    assert all(f"`{g}`" in text for g in gates), "the README does not name every gate of .ci/run"
