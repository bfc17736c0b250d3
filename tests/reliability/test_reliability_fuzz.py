"""Arbitrary input to the public API and to the command line: only typed errors, one line, no traceback.

Hypothesis feeds numbers (NaN, ±inf, huge, tiny, negative), strings, None, wrong shapes and types to
:func:`mpa.plan`, :func:`mpa.make_planner`, the track constructors, :class:`trajopt.Limits`,
:class:`trajopt.TrajectoryGenerator`, :func:`trajopt.generate_trajectory` and :meth:`Trajectory.at_rate`, and
asserts that nothing but an :class:`mpa.MPAError` escapes; and the same kind of values as command-line arguments
to ``main(argv)`` (in process, plus a few subprocess runs), asserting exit 0, 2 or 3 with one stderr line.
"""

from __future__ import annotations

import contextlib
import io
import os
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

import mpa
from mpa import Circle, Interval, Lollipop, MPAError
from trajopt import Limits, TrajectoryGenerator, generate_trajectory
from trajopt.cli import main

ROOT = Path(__file__).resolve().parents[2]

NUMS = st.one_of(
    st.floats(allow_nan=True, allow_infinity=True),
    st.floats(-3.0, 3.0),
    st.sampled_from([0.0, -0.0, 1e-300, -1e-300, 1e300, 5e-324, 0.05, 0.5, 1.0, 2.0]),
    st.integers(-(10**20), 10**20),
)
JUNK = st.one_of(
    st.none(),
    st.booleans(),
    st.text(max_size=5),
    st.just(b"1.0"),
    st.just(object()),
    st.just([]),
    st.just({"a": 1}),
    st.lists(NUMS, max_size=4),
    st.lists(st.lists(NUMS, max_size=3), max_size=3),
    st.just(np.zeros((2, 2))),
    st.just(np.array(["a", "b"])),
    st.just(complex(1, 1)),
)
ANY = st.one_of(NUMS, JUNK)
PAIR = st.one_of(st.tuples(ANY, ANY), st.tuples(NUMS, NUMS), st.tuples(st.floats(0, 2), st.floats(0, 2)), ANY)
TRACK = st.one_of(
    st.builds(Lollipop, st.floats(0.2, 2.0), st.floats(0.5, 2.0)),
    st.builds(Circle, st.floats(0.5, 2.0)),
    st.builds(Interval, st.floats(0.3, 2.0)),
    JUNK,
)


def _only_mpa_errors(fn, *args, **kwargs):  # type: ignore[no-untyped-def]
    try:
        return fn(*args, **kwargs)
    except MPAError as exc:
        assert str(exc) and "\n" not in str(exc), repr(exc)
        return None


FAST = settings(max_examples=150, deadline=None, derandomize=True, suppress_health_check=list(HealthCheck))


@FAST
@given(ANY, ANY)
def test_tracks_typed_errors(a, b) -> None:  # type: ignore[no-untyped-def]
    _only_mpa_errors(Lollipop, a, b)
    _only_mpa_errors(Circle, a)
    _only_mpa_errors(Interval, a)
    _only_mpa_errors(mpa.make_track, a, b, None)


@FAST
@given(TRACK, PAIR, PAIR, ANY, ANY)
def test_plan_typed_errors(track, start, goal, clearance, nb) -> None:  # type: ignore[no-untyped-def]
    _only_mpa_errors(mpa.plan, track, start, goal)
    _only_mpa_errors(mpa.plan, track, start, goal, clearance)
    _only_mpa_errors(mpa.make_planner, track, clearance, nb)


def test_examples_found_by_hypothesis() -> None:
    for nb in ("", None, "x", [0.1]):
        with pytest.raises(mpa.InvalidInputError, match="neighbourhood is"):
            mpa.plan(Lollipop(1.0, 1.0), (0.2, 0.5), (0.5, 0.2), 0.0, nb)
    with pytest.raises(mpa.InvalidInputError, match="stick length is array"):
        Lollipop(np.zeros((2, 2)), 1.0)


def test_examples_from_the_issue() -> None:
    with pytest.raises(mpa.InvalidInputError, match=r"start is \('a', 0\.5\), expected two track coordinates"):
        mpa.plan(Lollipop(1.0, 1.0), ("a", 0.5), (0.5, 0.2))
    with pytest.raises(mpa.InvalidInputError, match=r"track is Circle.*expected an Interval"):
        mpa.IntervalSkeleton(Circle())


@FAST
@given(ANY, ANY, ANY)
def test_limits_typed_errors(v, a, j) -> None:  # type: ignore[no-untyped-def]
    _only_mpa_errors(Limits, v, a, j)


@settings(max_examples=60, deadline=None, derandomize=True, suppress_health_check=list(HealthCheck))
@given(TRACK, PAIR, PAIR, ANY, ANY, ANY, ANY, ANY)
def test_generate_typed_errors(track, start, goal, clearance, v, a, j, rate) -> None:  # type: ignore[no-untyped-def]
    kw = {"clearance": clearance, "vmax": v, "amax": a, "jmax": j, "rate": rate}
    _only_mpa_errors(generate_trajectory, track, start, goal, **kw)
    gen = _only_mpa_errors(TrajectoryGenerator, track, clearance=clearance, rate=rate)
    if gen is not None:
        _only_mpa_errors(gen.generate, start, goal)


_TRAJ = []


@settings(max_examples=40, deadline=None, derandomize=True, suppress_health_check=list(HealthCheck))
@given(ANY)
def test_at_rate_typed_errors(rate) -> None:  # type: ignore[no-untyped-def]
    if not _TRAJ:
        _TRAJ.append(generate_trajectory(Lollipop(1.0, 1.0), (0.2, 0.5), (0.5, 0.2)))
    t = _only_mpa_errors(_TRAJ[0].at_rate, rate)
    if t is not None:
        assert t.verification["ok"]


# --- command line ----------------------------------------------------------------------------------
TEXT = st.one_of(
    st.text(alphabet=st.characters(blacklist_categories=("Cs",), blacklist_characters="\x00"), max_size=8),
    NUMS.map(repr),
    st.sampled_from(["nan", "inf", "-inf", "1e308", "1e-308", "-1", "0", "0.5", "", "--", "-h"]),
)
OPTS = [
    "--track",
    "--stick",
    "--loop",
    "--start",
    "--goal",
    "--clearance",
    "--vmax",
    "--amax",
    "--jmax",
    "--rate",
    "--samples",
    "--neighbourhood",
    "--json",
]


def run_main(argv: list[str]) -> tuple[int, str, str]:
    """``main(argv)`` in process; argparse's usage errors raise SystemExit(2), as from the console script."""
    out, err = io.StringIO(), io.StringIO()
    with contextlib.redirect_stdout(out), contextlib.redirect_stderr(err):
        try:
            code = main(argv)
        except SystemExit as exc:
            code = exc.code if isinstance(exc.code, int) else 2
    return code, out.getvalue(), err.getvalue()


def _check_cli(argv: list[str], tmp: Path) -> None:
    code, _out, err = run_main(argv)
    assert code in (0, 2, 3), (argv, code, err)
    assert "Traceback" not in err, (argv, err)
    if code != 0:
        lines = err.strip().splitlines()
        if argv:  # a bare `mpa` prints the usage instead
            assert len(lines) == 1, (argv, err)
            assert lines[0].startswith(("error:", "no motion:")), (argv, err)


@settings(max_examples=150, deadline=None, derandomize=True, suppress_health_check=list(HealthCheck))
@given(
    st.sampled_from(["plan", "trajectory"]),
    st.sampled_from(["lollipop", "circle", "interval"]),
    st.lists(st.tuples(st.sampled_from(OPTS), st.lists(TEXT, max_size=2)), max_size=4),
    st.tuples(TEXT, TEXT, TEXT, TEXT),
)
def test_cli_arbitrary_arguments(tmp_path_factory, cmd, track, extra, coords) -> None:  # type: ignore[no-untyped-def]
    tmp = tmp_path_factory.mktemp("cli")
    argv = [cmd, "--track", track, "--start", coords[0], coords[1], "--goal", coords[2], coords[3]]
    for opt, vals in extra:
        argv += [opt, *vals]
    if cmd == "trajectory":
        argv += ["--out", str(tmp / "run")]
    _check_cli(argv, tmp)
    if cmd == "trajectory" and not (tmp / "run").exists():
        assert not any(tmp.iterdir()), "a failed run left files"


@pytest.mark.parametrize(
    "argv",
    [
        ["plan", "--track", "lollipop", "--start", "nan", "0.5", "--goal", "0.5", "0.2"],
        ["trajectory", "--track", "circle", "--start", "0.1", "0.6", "--goal", "0.6", "0.1", "--vmax", "inf"],
        ["trajectory", "--track", "interval", "--start", "0.1", "0.6", "--goal", "0.6", "0.1", "--clearance", "0"],
        ["plan", "--track", "lollipop", "--stick", "-1", "--start", "0.1", "0.6", "--goal", "0.6", "0.1"],
    ],
)
def test_cli_subprocess_one_line(argv: list[str], tmp_path: Path) -> None:
    if argv[0] == "trajectory":
        argv = [*argv, "--out", str(tmp_path / "run")]
    env = {**os.environ, "PYTHONPATH": str(ROOT)}
    cp = subprocess.run([sys.executable, "-m", "trajopt.cli", *argv], capture_output=True, text=True, env=env)
    assert cp.returncode in (2, 3), cp
    lines = cp.stderr.strip().splitlines()
    assert len(lines) == 1 and lines[0].startswith(("error:", "no motion:")), cp.stderr
    assert not (tmp_path / "run").exists()
