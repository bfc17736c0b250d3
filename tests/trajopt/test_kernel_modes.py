"""The kernels' two modes (:mod:`trajopt._numba`): numba's compiled kernels, or their numpy twins with numba not
imported, as the ``mpa`` command runs them. Both must give the same gate reports and the same files, byte for byte.

Each mode is chosen once per process, so every check runs in fresh processes.
"""

from __future__ import annotations

import json
import os
import subprocess
import sys
from pathlib import Path
from typing import Any

import numpy as np
import pytest

from tests.trajopt.test_gate_kernels import _gate_cases, run_gate_cases

ROOT = Path(__file__).resolve().parents[2]
AIRPORT = ROOT / "tests" / "data" / "openrmf" / "airport_terminal.building.yaml"


def _env(mode: str | None) -> dict[str, str]:
    env = {k: v for k, v in os.environ.items() if k != "TRAJOPT_KERNELS"}
    if mode is not None:
        env["TRAJOPT_KERNELS"] = mode
    env["PYTHONPATH"] = os.pathsep.join([str(ROOT), os.environ.get("PYTHONPATH", "")])
    return env


def _python(script: str, *args: str, mode: str | None = None, timeout: float = 300.0) -> str:
    done = subprocess.run(
        [sys.executable, "-c", script, *args],
        cwd=ROOT,
        env=_env(mode),
        capture_output=True,
        text=True,
        timeout=timeout,
    )
    assert done.returncode == 0, done.stderr[-3000:]
    lines = done.stdout.strip().splitlines()
    return lines[-1] if lines else ""


# ------------------------------------------------------------------------------------------- the switch
_MODE_OF = r"""
import sys
from trajopt import _numba
from trajopt.cli.main import console_main
sys.argv = ["mpa", *sys.argv[1:]]
try:
    console_main()
except SystemExit:
    pass
import trajopt.verify.gate
print(_numba.kernel_mode(), "numba" in sys.modules)
"""


@pytest.mark.parametrize(
    ("argv", "mode", "expect"),
    [
        (["trajectory", "--help"], None, "numpy False"),
        (["plan", "--help"], None, "numpy False"),
        (["batch", "--help"], None, "numba True"),
        (["serve", "--help"], None, "numba True"),
        (["trajectory", "--help"], "numba", "numba True"),
        (["batch", "--help"], "numpy", "numpy False"),
    ],
)
def test_the_command_line_chooses_the_kernels_per_subcommand(argv: list[str], mode: str | None, expect: str) -> None:
    # the gate's module imported after the command: its kernels are what the process would run
    assert _python(_MODE_OF, *argv, mode=mode) == expect


def test_the_mode_is_fixed_once_a_kernel_module_is_imported() -> None:
    script = (
        "import sys\n"
        "from trajopt import _numba\n"
        "import trajopt.verify.kernels as k\n"
        "print(_numba.use_numpy_twins(), _numba.kernel_mode(), type(k.check_rows).__name__)\n"
    )
    assert _python(script, mode="numba") == "False numba CPUDispatcher"
    twins = _python(
        script.replace("import trajopt.verify.kernels", "_numba.use_numpy_twins()\nimport trajopt.verify.kernels")
    )
    assert twins == "True numpy function", twins


# ------------------------------------------------------------------------------------ the same results
_GATE = r"""
import json, sys
import numpy as np
import trajopt.verify.kernels as gk
from trajopt import _numba
from tests.trajopt.test_gate_kernels import run_gate_cases
assert _numba.kernel_mode() == "numpy" and gk.check_rows.__module__ == "trajopt.verify.kernels_numpy"
meta = json.loads(open(sys.argv[1]).read())
with np.load(sys.argv[2]) as z:
    arrays = {k: z[k] for k in z.files}

def subset(idx):
    new = {old: k for k, old in enumerate(idx)}
    out = {}
    for key, v in arrays.items():
        i, field = key.split("_", 1)
        if int(i) in new:
            out[f"{new[int(i)]}_{field}"] = v
    return [meta[i] for i in idx], out

graph = [i for i, m in enumerate(meta) if m["kind"] != "paper"]
paper = [i for i, m in enumerate(meta) if m["kind"] == "paper"]
reports = dict(zip(graph, run_gate_cases(*subset(graph))))
reports.update(zip(paper, run_gate_cases(*subset(paper))))
clean = "numba" not in sys.modules  # every kernel of the gate has a twin
open(sys.argv[3], "w").write(json.dumps({"clean": clean, "reports": [reports[i] for i in range(len(meta))]}))
"""


def test_gate_reports_are_the_same_with_the_numpy_twins(tmp_path: Path) -> None:
    pytest.importorskip("numba")
    metas, arrays, kinds, _ = _gate_cases()
    assert len(metas) >= 300
    (tmp_path / "cases.json").write_text(json.dumps(metas))
    np.savez(tmp_path / "cases.npz", **arrays)
    files = [str(tmp_path / x) for x in ("cases.json", "cases.npz", "reports.json")]
    _python(_GATE, *files, mode="numpy")
    got = json.loads((tmp_path / "reports.json").read_text())
    compiled = run_gate_cases(metas, arrays)
    assert got["clean"], "numba was imported by the gate in the numpy mode"
    assert sum(m["kind"] != "paper" for m in metas) >= 100
    for i, (kind, _) in enumerate(kinds):
        twin = got["reports"][i]
        assert twin == compiled[i], f"case {i} ({kind}, {metas[i]}): numpy {twin} != compiled {compiled[i]}"


def _trajectory(out: Path, mode: str, args: list[str]) -> dict[str, Any]:
    """``mpa trajectory ARGS --out OUT`` in a fresh process of the kernels' ``mode``: its files' bytes."""
    script = (
        "import sys\n"
        "from trajopt.cli.main import console_main\n"
        "sys.argv = ['mpa', *sys.argv[1:]]\n"
        "rc = console_main()\n"
        "print(rc, 'numba' in sys.modules)\n"
    )
    line = _python(script, "trajectory", *args, "--out", str(out), mode=mode)
    files = {p.name: p.read_bytes() for p in sorted(out.iterdir())}
    summary = json.loads(files.pop("summary.json"))
    summary.pop("timings", None)  # compute times
    summary["solver"].pop("jerk_time", None)
    return {"status": line, "files": files, "summary": summary}


@pytest.mark.parametrize(
    "args",
    [
        ["--graph", "examples/tracks/passing_loop.json", "--start", "W", "E", "--goal", "E", "W", "--clearance", "0.5"],
        ["--graph", "examples/tracks/warehouse.json", "--start", "A1_X1", "A1_X4", "--goal", "A1_X4", "A1_X1"],
        [
            "--graph", "examples/tracks/passing_loop.json", "--start", "W", "E", "--goal", "E", "W", "--clearance",
            "0.5", "--footprint", "0.3", "--format", "csv,ros2-yaml,mcap,pvt",
        ],
        [
            "--graph", str(AIRPORT), "--level", "L1", "--nav-graph", "2", "--start", "lane70:3.102", "lane143:8.848",
            "--goal", "lane87:1.237", "lane100:0.997", "--clearance", "0.6",
        ],
    ],
    ids=["passing loop", "warehouse", "footprint, every format", "airport 438 s"],
)  # fmt: skip
def test_graph_trajectory_files_are_the_same_without_numba(tmp_path: Path, args: list[str]) -> None:
    pytest.importorskip("numba")
    twins = _trajectory(tmp_path / "numpy", "numpy", args)
    compiled = _trajectory(tmp_path / "numba", "numba", args)
    assert twins["status"] == "0 False", twins["status"]  # numba never imported
    assert compiled["status"] == "0 True", compiled["status"]
    assert twins["files"].keys() == compiled["files"].keys()
    for name, data in compiled["files"].items():
        assert twins["files"][name] == data, f"{name} differs between the modes"
    assert twins["summary"] == compiled["summary"]


@pytest.mark.parametrize(
    "args",
    [
        ["--track", "lollipop", "--start", "0.1", "0.6", "--goal", "0.6", "0.1"],
        ["--track", "lollipop", "--stick", "0.3", "--loop", "1.2", "--start", "0.05", "1.0", "--goal", "1.2", "0.1"],
        ["--track", "circle", "--start", "0.1", "0.6", "--goal", "0.6", "0.1", "--format", "csv,ros2-yaml,mcap,pvt"],
        ["--track", "interval", "--start", "0.1", "0.6", "--goal", "0.3", "0.9"],
    ],
    ids=["lollipop swap", "lollipop 0.3/1.2", "circle, every format", "interval"],
)
def test_paper_trajectory_files_are_the_same_without_numba(tmp_path: Path, args: list[str]) -> None:
    pytest.importorskip("numba")
    twins = _trajectory(tmp_path / "numpy", "numpy", args)
    compiled = _trajectory(tmp_path / "numba", "numba", args)
    assert twins["status"] == "0 False", twins["status"]  # the paper's kernels have twins too: numba never imported
    assert compiled["status"] == "0 True", compiled["status"]
    assert twins["files"].keys() == compiled["files"].keys()
    for name, data in compiled["files"].items():
        assert twins["files"][name] == data, f"{name} differs between the modes"
    assert twins["summary"] == compiled["summary"]


_DEFERRED = r"""
import sys, types
from trajopt import _numba
assert _numba.use_numpy_twins()
mod = types.ModuleType("deferred_probe")
sys.modules["deferred_probe"] = mod
exec(
    "from trajopt._numba import njit\n"
    "@njit\n"
    "def inner(x):\n"
    "    return 2.0 * x\n"
    "@njit\n"
    "def outer(x):\n"
    "    return inner(x) + 1.0\n",
    mod.__dict__,
)
before = ("numba" in sys.modules, type(mod.outer).__name__)
value = mod.outer(3.0)
print(before, value, "numba" in sys.modules, type(mod.inner).__name__, type(mod.outer).__name__)
"""


def test_a_kernel_without_a_twin_is_compiled_on_its_first_call() -> None:
    pytest.importorskip("numba")
    # the kernel and its callee, found by numba in the module's globals, are rebound to numba's dispatchers
    out = _python(_DEFERRED)
    assert out == "(False, 'Deferred') 7.0 True CPUDispatcher CPUDispatcher", out
