"""Bad input: typed errors from the API, exit status 2 with one ``error:`` line and no files from the CLI."""

from __future__ import annotations

import numpy as np
import pytest

from mpa import Circle, InvalidInputError, Lollipop, NoMotionError
from trajopt import Limits, TrajectoryGenerator, generate_trajectory
from trajopt.cli import main

L = Lollipop(1.0, 1.0)
QUERY = ["--track", "lollipop", "--start", "0.2", "0.5", "--goal", "0.5", "0.2"]


@pytest.mark.parametrize(
    ("kwargs", "match"),
    [
        ({"vmax": 0.0}, r"vmax is 0\.0, expected a positive finite number"),
        ({"vmax": -1.0}, r"vmax is -1\.0"),
        ({"amax": float("nan")}, r"amax is nan"),
        ({"jmax": float("inf")}, r"jmax is inf"),
        ({"vmax": (0.5, -0.1)}, r"vmax of robot B is -0\.1"),
        ({"rate": 0.0}, r"rate is 0\.0, expected a positive finite number \(Hz\)"),
        ({"rate": -5.0}, r"rate is -5\.0"),
        ({"rate": float("nan")}, r"rate is nan"),
        ({"clearance": -0.1}, r"clearance is -0\.1"),
    ],
)
def test_bad_limits_rate_clearance(kwargs, match) -> None:  # type: ignore[no-untyped-def]
    with pytest.raises(InvalidInputError, match=match):
        generate_trajectory(L, (0.2, 0.5), (0.5, 0.2), **kwargs)


def test_limits_type_checked() -> None:
    with pytest.raises(InvalidInputError, match="vmax is 'fast'"):
        Limits("fast", 1.0, 1.0)
    with pytest.raises(InvalidInputError, match="limits is"):
        TrajectoryGenerator(L, limits=(1, 2, 3))  # type: ignore[arg-type]


@pytest.mark.parametrize(
    ("start", "goal", "match"),
    [
        ((0.2, 0.22), (0.5, 0.2), r"start \(0\.2, 0\.22\) has the robots 0\.02 apart"),
        ((0.2, 0.5), (1.5, 1.52), r"goal .* apart, expected at least the clearance"),
        ((0.2, 0.5), (0.5, 7.0), r"goal of robot B is 7\.0"),
    ],
)
def test_states_closer_than_clearance(start, goal, match) -> None:  # type: ignore[no-untyped-def]
    with pytest.raises(InvalidInputError, match=match):
        generate_trajectory(L, start, goal, clearance=0.05)


def test_order_change_needs_clearance_below_half_loop() -> None:
    with pytest.raises(NoMotionError, match=r"clearance 0\.6 >= loop/2"):
        generate_trajectory(L, (0.0, 0.9), (0.9, 0.0), clearance=0.6)
    with pytest.raises(NoMotionError):
        generate_trajectory(L, (0.0, 0.5), (0.5, 0.0), clearance=0.5)


def test_same_order_with_large_clearance_is_fine() -> None:
    traj = generate_trajectory(L, (0.0, 0.9), (0.1, 1.0), clearance=0.6)
    assert traj.verification["ok"] and traj.min_separation >= 0.6


def test_circle_clearance_too_large_is_rejected() -> None:
    with pytest.raises(InvalidInputError):
        generate_trajectory(Circle(1.0), (0.0, 0.5), (0.25, 0.75), clearance=0.6)


BAD_CLI = [
    (["trajectory", *QUERY, "--rate", "0"], "rate is 0.0"),
    (["trajectory", *QUERY, "--rate", "-10"], "rate is -10.0"),
    (["trajectory", *QUERY, "--vmax", "0"], "vmax is 0.0"),
    (["trajectory", *QUERY, "--amax", "nan"], "amax is nan"),
    (["trajectory", *QUERY, "--jmax", "-1"], "jmax is -1.0"),
    (["trajectory", "--track", "lollipop", "--start", "0.2", "0.21", "--goal", "0.5", "0.2"], "start (0.2, 0.21)"),
    (
        ["trajectory", "--track", "circle", "--stick", "1", "--start", "0.1", "0.5", "--goal", "0.5", "0.1"],
        "circle track has no stick",
    ),
]


@pytest.mark.parametrize(("argv", "needle"), BAD_CLI, ids=[" ".join(a[1:4]) + a[-1] for a, _ in BAD_CLI])
def test_cli_errors_exit_2_one_line_no_files(argv, needle, tmp_path, capsys) -> None:  # type: ignore[no-untyped-def]
    out = tmp_path / "out"
    code = main([*argv, "--out", str(out)])
    err = capsys.readouterr().err
    assert code == 2
    lines = err.strip().splitlines()
    assert len(lines) == 1 and lines[0].startswith("error:"), err
    assert needle in lines[0]
    assert not out.exists()
    assert list(tmp_path.iterdir()) == []


NO_MOTION_CLI = [
    ["trajectory", "--track", "lollipop", "--start", "0", "0.9", "--goal", "0.9", "0", "--clearance", "0.6"],
    ["trajectory", "--track", "interval", "--start", "0.1", "0.5", "--goal", "0.5", "0.1"],
]


@pytest.mark.parametrize("argv", NO_MOTION_CLI, ids=["lollipop", "interval"])
def test_cli_no_motion_exit_3_one_line_no_files(argv, tmp_path, capsys) -> None:  # type: ignore[no-untyped-def]
    """Valid input without a collision-free motion: exit 3 and one ``no motion:`` line (the reliability issue)."""
    out = tmp_path / "out"
    code = main([*argv, "--out", str(out)])
    err = capsys.readouterr().err
    assert code == 3
    lines = err.strip().splitlines()
    assert len(lines) == 1 and lines[0].startswith("no motion:"), err
    assert "no collision-free motion exists" in lines[0]
    assert not out.exists()
    assert list(tmp_path.iterdir()) == []


def test_cli_out_is_a_file(tmp_path, capsys) -> None:  # type: ignore[no-untyped-def]
    f = tmp_path / "taken"
    f.write_text("keep")
    code = main(["trajectory", *QUERY, "--out", str(f)])
    assert code == 2 and capsys.readouterr().err.startswith("error:")
    assert f.read_text() == "keep"


def test_cli_write_failure_leaves_nothing(tmp_path, capsys, monkeypatch) -> None:  # type: ignore[no-untyped-def]
    import trajopt.cli.trajectory as ct

    calls = {"n": 0}

    def flaky(real):  # type: ignore[no-untyped-def]
        def write(path, content):  # type: ignore[no-untyped-def]
            calls["n"] += 1  # the second file of the run (text or bytes: setpoints.csv is written in pieces) fails
            if calls["n"] == 2:
                raise OSError(28, "No space left on device")
            real(path, content)

        return write

    monkeypatch.setattr(ct, "atomic_write_text", flaky(ct.atomic_write_text))
    monkeypatch.setattr(ct, "atomic_write_bytes", flaky(ct.atomic_write_bytes))
    out = tmp_path / "o"
    code = main(["trajectory", *QUERY, "--out", str(out)])
    assert code == 2 and capsys.readouterr().err.startswith("error:")
    assert not out.exists() and calls["n"] == 2


def test_invalid_input_is_value_error() -> None:
    with pytest.raises(ValueError):
        generate_trajectory(L, (0.2, 0.5), (0.5, 0.2), rate=np.inf)
