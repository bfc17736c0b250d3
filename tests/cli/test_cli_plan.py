"""`mpa plan`: the JSON contract (docs/conventions.md, "Command line and files") and the error contract."""

from __future__ import annotations

import json
import subprocess
import sys

import numpy as np
import pytest

from mpa import make_track
from trajopt.cli import main

QUERIES = [
    ["--track", "lollipop", "--start", "0.1", "0.6", "--goal", "0.8", "0.3"],
    ["--track", "lollipop", "--stick", "0.3", "--loop", "2", "--start", "0.1", "1.0", "--goal", "1.5", "0.2"],
    ["--track", "circle", "--loop", "3", "--start", "0.3", "1.2", "--goal", "2.9", "0.1"],
    ["--track", "interval", "--stick", "2", "--start", "0.1", "1.2", "--goal", "0.9", "1.9"],
    ["--track", "lollipop", "--stick", "4", "--loop", "0.5", "--start", "0.0", "4.2", "--goal", "3.9", "0.1"],
]


@pytest.mark.parametrize("argv", QUERIES)
def test_plan_json_contract(argv, capsys) -> None:  # type: ignore[no-untyped-def]
    assert main(["plan", *argv, "--json"]) == 0
    out = json.loads(capsys.readouterr().out)
    assert isinstance(out["domain"], int) and isinstance(out["rule"], str)
    path = np.array(out["path"])
    assert path.ndim == 2 and path.shape[1] == 2 and len(path) >= 200
    i_start, i_goal = argv.index("--start"), argv.index("--goal")
    start = [float(argv[i_start + 1]), float(argv[i_start + 2])]
    goal = [float(argv[i_goal + 1]), float(argv[i_goal + 2])]
    assert np.allclose(path[0], start) and np.allclose(path[-1], goal)
    kw = {"stick": None, "loop": None}
    for k in kw:
        if f"--{k}" in argv:
            kw[k] = float(argv[argv.index(f"--{k}") + 1])
    track = make_track(argv[1], **kw)
    step = max(track.distance(path[:-1, 0], path[1:, 0]).max(), track.distance(path[:-1, 1], path[1:, 1]).max())
    assert step <= 0.01 * track.total_length + 1e-12


def test_plan_samples_option_and_text_output(capsys) -> None:  # type: ignore[no-untyped-def]
    assert main(["plan", *QUERIES[0], "--json", "--samples", "1000"]) == 0
    assert len(json.loads(capsys.readouterr().out)["path"]) == 1000
    assert main(["plan", *QUERIES[0]]) == 0
    text = capsys.readouterr().out
    assert "domain     1" in text and "+S1a" in text


@pytest.mark.parametrize(
    ("argv", "message"),
    [
        (["--track", "circle", "--start", "nan", "0.5", "--goal", "0.6", "0.2"], "is nan"),
        (["--track", "lollipop", "--start", "0.1", "0.1", "--goal", "0.6", "0.2"], "robots coincide"),
        (["--track", "lollipop", "--loop", "-1", "--start", "0.1", "0.6", "--goal", "0.6", "0.2"], "loop length is -1"),
        (["--track", "lollipop", "--start", "0.1", "5", "--goal", "0.6", "0.2"], "is 5.0, expected a track coordinate"),
        (["--track", "lollipop", "--start", "0.1", "0.7", "--goal", "0.6", "0.2", "--clearance", "0.5"], "clearance"),
        (["--track", "circle", "--stick", "1", "--start", "0.1", "0.6", "--goal", "0.6", "0.2"], "has no stick"),
        (["--track", "lollipop", "--start", "0.1"], "expected 2 arguments"),
        (["--track", "lollipop", "--start", "0.1", "0.6", "--goal", "0.8", "0.3", "--samples", "0"], "samples is 0"),
    ],
)
def test_plan_errors_exit_2_with_one_error_line(argv, message, capsys) -> None:  # type: ignore[no-untyped-def]
    with pytest.raises(SystemExit) if "expected 2 arguments" in message else _nullcontext() as exc:
        code = main(["plan", *argv])
    if exc is not None and getattr(exc, "value", None) is not None:
        code = exc.value.code
    err = capsys.readouterr().err
    assert code == 2
    lines = err.strip().splitlines()
    assert len(lines) == 1 and lines[0].startswith("error:") and message in lines[0], err


def test_plan_no_motion_exits_3_with_one_line(capsys) -> None:  # type: ignore[no-untyped-def]
    """Valid input without a collision-free motion: exit 3, one ``no motion:`` line (the reliability issue)."""
    code = main(["plan", "--track", "interval", "--start", "0.1", "0.5", "--goal", "0.6", "0.2"])
    err = capsys.readouterr().err
    assert code == 3
    lines = err.strip().splitlines()
    assert len(lines) == 1 and lines[0].startswith("no motion:") and "can never change order" in lines[0], err


class _nullcontext:
    def __enter__(self):  # type: ignore[no-untyped-def]
        return None

    def __exit__(self, *a):  # type: ignore[no-untyped-def]
        return False


def test_console_script_prints_no_traceback() -> None:
    r = subprocess.run(
        [
            sys.executable,
            "-m",
            "trajopt.cli",
            "plan",
            "--track",
            "interval",
            "--start",
            "0.1",
            "0.5",
            "--goal",
            "0.6",
            "0.2",
        ],
        capture_output=True,
        text=True,
        timeout=60,
    )
    assert r.returncode == 3  # no motion (exit 2 is bad input since the reliability issue)
    assert r.stderr.startswith("no motion:") and "Traceback" not in r.stderr and len(r.stderr.strip().splitlines()) == 1
