"""Start-up: ``mpa --help`` imports no numpy or subcommand module; the lazy ``mpa`` package keeps its names."""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

import pytest

from trajopt.cli.main import SUBCOMMANDS, build_parser

ROOT = Path(__file__).resolve().parents[2]


def _run(code: str, *argv: str, **env: str) -> str:
    """``python -c code argv...`` from the repository root with only ``PYTHONPATH`` and ``env`` set; its stdout."""
    out = subprocess.run(
        [sys.executable, "-c", code, *argv],
        capture_output=True,
        text=True,
        check=True,
        cwd=ROOT,
        env={"PYTHONPATH": str(ROOT), **env},
    )
    return out.stdout.strip()


def test_lazy_help_lists_the_same_subcommands_as_the_full_parser() -> None:
    assert build_parser(None, full=False).format_help() == build_parser().format_help()
    full = build_parser()
    sub = next(a for a in full._actions if a.dest == "command")
    helps = {a.dest: a.help for a in sub._choices_actions}  # type: ignore[attr-defined]
    assert helps == {name: text for name, (_m, text) in SUBCOMMANDS.items()}


@pytest.mark.parametrize("command", list(SUBCOMMANDS))
def test_lazy_parser_of_a_subcommand_is_the_full_one(command: str) -> None:
    lazy = next(a for a in build_parser(command, full=False)._actions if a.dest == "command")
    full = next(a for a in build_parser()._actions if a.dest == "command")
    assert lazy.choices[command].format_help() == full.choices[command].format_help()  # type: ignore[index]


def test_help_and_version_import_no_numpy() -> None:
    code = (
        "import contextlib, io, sys\n"
        "from trajopt.cli.main import main\n"
        "for argv in (['--help'], ['--version']):\n"
        "    with contextlib.redirect_stdout(io.StringIO()), contextlib.suppress(SystemExit):\n"
        "        main(argv)\n"
        "print(sorted(m for m in ('numpy', 'mpa.planners', 'trajopt.cli.plan', 'casadi', 'matplotlib')"
        " if m in sys.modules))"
    )
    assert _run(code) == "[]"


def test_the_version_is_read_only_by_version() -> None:
    code = (
        "import contextlib, io, sys\n"
        "from trajopt.cli.main import main\n"
        "with contextlib.redirect_stdout(io.StringIO()), contextlib.suppress(SystemExit):\n"
        "    main(['--help'])\n"
        "assert 'mpa._version' not in sys.modules and 'email' not in sys.modules, 'read by --help'\n"
        "buf = io.StringIO()\n"
        "with contextlib.redirect_stdout(buf), contextlib.suppress(SystemExit):\n"
        "    main(['--version'])\n"
        "import mpa\n"
        "from importlib import metadata\n"
        "assert buf.getvalue() == f'mpa (lollipop-mpa) {mpa.__version__}\\n', buf.getvalue()\n"
        "assert mpa.__version__ == metadata.version('lollipop-mpa')\n"
        "print('ok')\n"
    )
    assert _run(code) == "ok"


def test_lazy_package_names() -> None:
    code = (
        "import mpa, sys, types\n"
        "assert 'numpy' not in sys.modules\n"
        "import mpa.plans as pm\n"  # the module of the result type: no name clash with the function mpa.plan
        "assert isinstance(pm, types.ModuleType) and pm.Plan is mpa.Plan\n"
        "assert callable(mpa.plan) and not isinstance(mpa.plan, types.ModuleType), mpa.plan\n"
        "from mpa import Lollipop, plan\n"
        "assert plan(Lollipop(1.0, 1.0), (0.1, 0.6), (0.8, 0.3)).domain == 1\n"
        "assert all(hasattr(mpa, n) for n in mpa.__all__) and set(mpa.__all__) <= set(dir(mpa))\n"
        "assert mpa.tracks.Lollipop is Lollipop\n"
        "try:\n"
        "    mpa.no_such_name\n"
        "except AttributeError:\n"
        "    print('ok')\n"
    )
    assert _run(code) == "ok"


def test_monkeypatching_mpa_plan(monkeypatch: pytest.MonkeyPatch) -> None:
    import mpa

    original = mpa.plan
    monkeypatch.setattr(mpa, "plan", len)
    assert mpa.plan is len
    monkeypatch.undo()
    assert mpa.plan is original


#: What ``main`` leaves in the environment, and whether numpy's OpenBLAS started with one thread.
_BLAS_PROBE = (
    "import contextlib, io, os, sys\n"
    "from trajopt.cli.main import BLAS_THREAD_VARIABLES, main\n"
    "with contextlib.redirect_stdout(io.StringIO()), contextlib.suppress(SystemExit):\n"
    "    main(['plan', '--track', 'lollipop', '--stick', '1', '--loop', '1', '--start', '0.2', '0.5',"
    " '--goal', '0.5', '0.2'])\n"
    "print([os.environ.get(k) for k in BLAS_THREAD_VARIABLES], 'numpy' in sys.modules)\n"
)


def test_the_command_line_runs_blas_on_one_thread() -> None:
    assert _run(_BLAS_PROBE) == "['1', '1', '1'] True"


def test_a_thread_count_given_in_the_environment_is_kept() -> None:
    assert _run(_BLAS_PROBE, OMP_NUM_THREADS="2") == "[None, None, '2'] True"
    assert _run(_BLAS_PROBE, OPENBLAS_NUM_THREADS="3") == "['3', None, None] True"


def test_a_process_with_numpy_loaded_keeps_its_environment() -> None:
    code = "import numpy\n" + _BLAS_PROBE
    assert _run(code) == "[None, None, None] True"


#: Runs ``main(argv)`` (``argv`` from ``sys.argv[1:]``) and prints which of the heavy libraries it imported.
_IMPORTS_PROBE = (
    "import contextlib, io, sys\n"
    "from trajopt.cli.main import main\n"
    "with contextlib.redirect_stdout(io.StringIO()):\n"
    "    status = main(sys.argv[1:])\n"
    "heavy = ('numba', 'toppra', 'casadi', 'matplotlib', 'scipy.optimize', 'scipy.sparse')\n"
    "print(status, sorted(m for m in heavy if m in sys.modules))\n"
)
_OFFICE = ["--graph", "tests/data/openrmf/office.building.yaml", "--level", "L1", "--clearance", "0.3"]
_OFFICE_QUERY = ["--start", "lane0:0.648778078072", "lane29:2.23700606941"]
_OFFICE_QUERY += ["--goal", "lane3:0.680007503632", "lane23:1.92555051153"]


def _imports(argv: list[str], tmp_path: Path) -> str:
    return _run(_IMPORTS_PROBE, *argv, MPA_CACHE_DIR=str(tmp_path / "cache"))


def test_plan_on_a_building_map_imports_no_numba_nor_the_optimisers(tmp_path: Path) -> None:
    assert _imports(["plan", *_OFFICE, *_OFFICE_QUERY], tmp_path) == "0 []"


def test_trajectory_on_a_building_map_imports_numba_only(tmp_path: Path) -> None:
    # main() in a process of its own keeps numba's compiled kernels (trajopt._numba); the paper's corridor QP
    # (CasADi), toppra and the drawings are not needed
    argv = ["trajectory", *_OFFICE, *_OFFICE_QUERY, "--out", str(tmp_path / "run")]
    assert _imports(argv, tmp_path) == "0 ['numba']"
    assert sorted(p.name for p in (tmp_path / "run").iterdir()) == ["setpoints.csv", "summary.json"]


def test_the_mpa_command_on_a_building_map_imports_none_of_them(tmp_path: Path) -> None:
    # the console script runs the gate's kernels as numpy twins: not even numba
    argv = ["trajectory", *_OFFICE, *_OFFICE_QUERY, "--out", str(tmp_path / "run")]
    probe = _IMPORTS_PROBE.replace("import main\n", "import console_main\n").replace(
        "status = main(sys.argv[1:])", "sys.argv[0] = 'mpa'; status = console_main()"
    )
    assert probe != _IMPORTS_PROBE
    assert _run(probe, *argv, MPA_CACHE_DIR=str(tmp_path / "cache")) == "0 []"
    assert sorted(p.name for p in (tmp_path / "run").iterdir()) == ["setpoints.csv", "summary.json"]
