"""The command line keeps its word (reliability issue, item 5), and ruckig's internals we rely on (item 7)."""

from __future__ import annotations

import contextlib
import io
import json
import os
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

import mpa
from mpa import defaults
from trajopt.cli import build_parser, main

ROOT = Path(__file__).resolve().parents[2]
QUERY = ["--track", "lollipop", "--start", "0.2", "0.5", "--goal", "0.5", "0.2"]


def run(argv: list[str]) -> tuple[int, str, str]:
    out, err = io.StringIO(), io.StringIO()
    with contextlib.redirect_stdout(out), contextlib.redirect_stderr(err):
        try:
            code = main(argv)
        except SystemExit as exc:  # argparse: --help, --version, usage errors
            code = int(exc.code or 0)
    return code, out.getvalue(), err.getvalue()


def _one_error_line(err: str, prefix: str = "error:") -> str:
    lines = err.strip().splitlines()
    assert len(lines) == 1 and lines[0].startswith(prefix) and "Traceback" not in err, err
    return lines[0]


@pytest.mark.parametrize("cmd", ["trajectory", "animate", "demo"])
def test_unwritable_out_fails_before_any_work(cmd, monkeypatch) -> None:  # type: ignore[no-untyped-def]
    import trajopt.generator as gm

    def no_work(*a, **k):  # type: ignore[no-untyped-def]
        raise AssertionError("the trajectory was computed before the output was checked")

    monkeypatch.setattr(gm.TrajectoryGenerator, "generate", no_work)
    argv = [cmd, *([] if cmd == "demo" else QUERY), "--out", "/proc/x"]
    code, _out, err = run(argv)
    assert code == 2
    line = _one_error_line(err)
    assert line.startswith("error: --out: cannot write '/proc/x': "), line


@pytest.mark.parametrize("cmd", ["trajectory", "animate", "demo"])
def test_empty_out_is_an_error(cmd, tmp_path, monkeypatch) -> None:  # type: ignore[no-untyped-def]
    monkeypatch.chdir(tmp_path)
    code, _out, err = run([cmd, *([] if cmd == "demo" else QUERY), "--out", ""])
    assert code == 2
    assert "--out is '', expected a directory path" in _one_error_line(err)
    assert list(tmp_path.iterdir()) == []


def test_os_error_names_the_option(tmp_path) -> None:  # type: ignore[no-untyped-def]
    ro = tmp_path / "ro"
    ro.mkdir()
    (ro / "file").write_text("x")
    code, _out, err = run(["trajectory", *QUERY, "--out", str(ro / "file" / "sub")])
    assert code == 2
    line = _one_error_line(err)
    assert line.startswith("error: --out: cannot write ") and "Not a directory" in line and "[Errno" not in line


def test_write_error_after_work_names_the_option(tmp_path, monkeypatch) -> None:  # type: ignore[no-untyped-def]
    import trajopt.cli.trajectory as ct

    def full(path, text):  # type: ignore[no-untyped-def]
        raise OSError(28, "No space left on device")

    monkeypatch.setattr(ct, "atomic_write_text", full)
    monkeypatch.setattr(ct, "atomic_write_bytes", full)  # setpoints.csv is written piece by piece, as bytes
    code, _out, err = run(["trajectory", *QUERY, "--out", str(tmp_path / "o")])
    assert code == 2
    assert (
        _one_error_line(err)
        == f"error: --out: cannot write {str(tmp_path / 'o' / 'setpoints.csv')!r}: No space left on device"
    )
    assert not (tmp_path / "o").exists()


def test_one_default_clearance_everywhere() -> None:
    parser = build_parser()
    sub = next(a for a in parser._actions if a.dest == "command").choices  # type: ignore[attr-defined]
    for name in ("plan", "trajectory", "animate"):
        ns = sub[name].parse_args(QUERY + (["--out", "x"] if name != "plan" else []))
        assert ns.clearance == defaults.CLEARANCE == 0.05, name
    for name in ("trajectory", "animate"):
        ns = sub[name].parse_args([*QUERY, "--out", "x"])
        assert (ns.vmax, ns.amax, ns.jmax, ns.rate) == (defaults.VMAX, defaults.AMAX, defaults.JMAX, defaults.RATE)
    from trajopt import TrajectoryGenerator
    from trajopt.cli.trajectory import DEMO_JOB

    assert DEMO_JOB["clearance"] == defaults.CLEARANCE
    gen = TrajectoryGenerator(mpa.Lollipop())
    assert gen.clearance == defaults.CLEARANCE and gen.rate == defaults.RATE


def test_plan_uses_the_default_clearance() -> None:
    code, out, _err = run(["plan", "--track", "lollipop", "--start", "0.2", "0.23", "--goal", "0.5", "0.2"])
    assert code == 2  # 0.03 apart: below the default clearance 0.05 (it used to be 0 for `plan` only)
    code, out, _err = run(["plan", *QUERY, "--json"])
    assert code == 0 and json.loads(out)["clearance"] == defaults.CLEARANCE


@pytest.mark.parametrize("n", [2, 5, 150, 199, 200, 1000])
def test_samples_any_n_at_least_2(n: int) -> None:
    code, out, _err = run(["plan", *QUERY, "--json", "--samples", str(n)])
    assert code == 0
    d = json.loads(out)
    assert d["samples"] == len(d["path"]) >= max(n, 200)
    if n >= 200:
        assert d["samples"] >= n


@pytest.mark.parametrize("n", ["1", "0", "-3"])
def test_samples_below_2_is_an_error(n: str) -> None:
    code, _out, err = run(["plan", *QUERY, "--json", "--samples", n])
    assert code == 2 and f"--samples is {n}, expected an integer >= 2" in _one_error_line(err)


def test_bare_mpa_prints_usage_and_exits_2() -> None:
    code, out, err = run([])
    assert code == 2 and out == ""
    from trajopt.cli.main import SUBCOMMANDS

    assert err.startswith("usage: mpa") and "{" + ",".join(SUBCOMMANDS) + "}" in err  # every subcommand listed
    env = {**os.environ, "PYTHONPATH": str(ROOT)}
    cp = subprocess.run([sys.executable, "-m", "trajopt.cli"], capture_output=True, text=True, env=env)
    assert cp.returncode == 2 and cp.stderr.startswith("usage: mpa") and "Traceback" not in cp.stderr


def test_version() -> None:
    assert isinstance(mpa.__version__, str) and mpa.__version__[0].isdigit()
    code, out, _err = run(["--version"])
    assert code == 0 and out.strip() == f"mpa (lollipop-mpa) {mpa.__version__}"
    text = (ROOT / "pyproject.toml").read_text()
    assert f'version = "{mpa.__version__}"' in text


def test_ctrl_c_exits_130_with_one_line(monkeypatch) -> None:  # type: ignore[no-untyped-def]
    import trajopt.generator as gm

    def interrupted(*a, **k):  # type: ignore[no-untyped-def]
        raise KeyboardInterrupt

    monkeypatch.setattr(gm.TrajectoryGenerator, "generate", interrupted)
    code, _out, err = run(["trajectory", *QUERY, "--out", "x-never-written"])
    assert code == 130 and err.strip() == "interrupted"
    assert not Path("x-never-written").exists()


def test_ctrl_c_subprocess(tmp_path) -> None:  # type: ignore[no-untyped-def]
    """A real SIGINT to a running `mpa`: exit 130, one line, no traceback, no output directory."""
    import signal
    import time

    env = {**os.environ, "PYTHONPATH": str(ROOT)}
    code = (
        "import time, sys\n"
        "import trajopt.generator as gm\n"
        "def slow(*a, **k):\n"
        "    print('working', flush=True); time.sleep(60)\n"
        "gm.TrajectoryGenerator.generate = slow\n"
        "from trajopt.cli import main\n"
        f"sys.exit(main(['trajectory', *{QUERY!r}, '--out', {str(tmp_path / 'o')!r}]))\n"
    )
    proc = subprocess.Popen(
        [sys.executable, "-c", code], env=env, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True
    )
    assert proc.stdout is not None and proc.stdout.readline().strip() == "working"
    time.sleep(0.1)
    proc.send_signal(signal.SIGINT)
    _out, err = proc.communicate(timeout=60)
    assert proc.returncode == 130 and err.strip() == "interrupted", err
    assert not (tmp_path / "o").exists()


def test_internal_error_exits_4_one_line(monkeypatch) -> None:  # type: ignore[no-untyped-def]
    import trajopt.generator as gm

    def bug(*a, **k):  # type: ignore[no-untyped-def]
        raise ZeroDivisionError("float division by zero")

    monkeypatch.setattr(gm.TrajectoryGenerator, "generate", bug)
    code, _out, err = run(["trajectory", *QUERY, "--out", "x-never-written"])
    assert code == 4
    assert _one_error_line(err, "internal error:") == "internal error: ZeroDivisionError: float division by zero"


# --- ruckig: the internals the jerk-limited scaling reads ----------------------------------------------------
def test_ruckig_profiles_assumption() -> None:
    """``Trajectory.profiles[0][0]`` has 7 phases ``t, p, v, a, j`` and ``brake``/``accel`` with ``duration``,
    and integrating them reproduces ruckig's public ``at_time``: what :func:`trajopt.timing.jerk_limited_scaling`
    relies on (pyproject bounds ruckig to ``>=0.12,<0.20``)."""
    from importlib import metadata

    from ruckig import InputParameter, Result, Ruckig, Trajectory

    major, minor = (int(x) for x in metadata.version("ruckig").split(".")[:2])
    assert (0, 12) <= (major, minor) < (0, 20)
    otg, inp, traj = Ruckig(1), InputParameter(1), Trajectory(1)
    inp.current_position, inp.current_velocity, inp.current_acceleration = [0.1], [0.2], [0.0]
    inp.target_position, inp.target_velocity, inp.target_acceleration = [1.3], [0.1], [0.0]
    inp.max_velocity, inp.max_acceleration, inp.max_jerk = [0.5], [1.0], [5.0]
    assert otg.calculate(inp, traj) in (Result.Working, Result.Finished)
    prof = traj.profiles[0][0]
    assert prof.brake.duration == 0 and prof.accel.duration == 0
    t, p, v, a, j = (np.asarray(x, dtype=float) for x in (prof.t, prof.p, prof.v, prof.a, prof.j))
    assert t.shape == (7,) and p.shape[0] >= 7 and j.shape == (7,)
    assert abs(float(np.sum(t)) - traj.duration) < 1e-9
    t0 = np.concatenate([[0.0], np.cumsum(t)[:-1]])
    for tq in np.linspace(0.0, traj.duration, 23):
        i = int(np.clip(np.searchsorted(t0, tq, side="right") - 1, 0, 6))
        tau = tq - t0[i]
        pos = p[i] + v[i] * tau + a[i] * tau**2 / 2 + j[i] * tau**3 / 6
        vel = v[i] + a[i] * tau + j[i] * tau**2 / 2
        acc = a[i] + j[i] * tau
        rp, rv, ra = traj.at_time(float(tq))
        assert abs(pos - rp[0]) < 1e-9 and abs(vel - rv[0]) < 1e-9 and abs(acc - ra[0]) < 1e-9
