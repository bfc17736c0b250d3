"""``mpa trajectory`` and ``mpa demo`` end to end, and the benchmark script at a small size."""

from __future__ import annotations

import csv
import json
import os
import subprocess
import sys
from pathlib import Path

import numpy as np

from trajopt.cli import main

ROOT = Path(__file__).resolve().parents[2]


def test_cli_trajectory_writes_files(tmp_path, capsys) -> None:  # type: ignore[no-untyped-def]
    out = tmp_path / "run"
    code = main(
        [
            "trajectory",
            "--track",
            "lollipop",
            "--stick",
            "1.2",
            "--loop",
            "0.9",
            "--start",
            "0.1",
            "0.6",
            "--goal",
            "0.8",
            "0.3",
            "--clearance",
            "0.1",
            "--vmax",
            "0.4",
            "--amax",
            "0.9",
            "--jmax",
            "4",
            "--rate",
            "50",
            "--out",
            str(out),
        ]
    )
    assert code == 0
    assert "makespan" in capsys.readouterr().out
    assert sorted(p.name for p in out.iterdir()) == ["setpoints.csv", "summary.json"]
    js = json.loads((out / "summary.json").read_text())
    assert {"makespan", "min_separation", "domain", "fallback"} <= set(js)
    assert js["rate"] == 50 and js["clearance"] == 0.1 and js["limits"]["jmax"] == [4.0, 4.0]
    with open(out / "setpoints.csv", newline="") as fh:
        rows = list(csv.reader(fh))
    data = np.array([r[:11] for r in rows[1:]], dtype=float)
    np.testing.assert_allclose(np.diff(data[:, 0]), 0.02, atol=1e-9)
    assert data[-1, 0] == js["makespan"]
    assert np.abs(data[:, [3, 8]]).max() <= 0.4 * (1 + 1e-6)


def test_cli_defaults(tmp_path) -> None:  # type: ignore[no-untyped-def]
    out = tmp_path / "d"
    assert (
        main(["trajectory", "--track", "circle", "--start", "0.3", "0.6", "--goal", "0.25", "0.1", "--out", str(out)])
        == 0
    )
    js = json.loads((out / "summary.json").read_text())
    assert js["clearance"] == 0.05 and js["rate"] == 100.0
    assert js["limits"] == {"vmax": [0.5, 0.5], "amax": [1.0, 1.0], "jmax": [5.0, 5.0]}


def test_demo_subprocess(tmp_path) -> None:  # type: ignore[no-untyped-def]
    out = tmp_path / "demo"
    env = dict(os.environ, MPLBACKEND="Agg")
    proc = subprocess.run(
        [
            sys.executable,
            "-c",
            "import sys; from trajopt.cli import main; sys.exit(main(sys.argv[1:]))",
            "demo",
            "--out",
            str(out),
        ],
        capture_output=True,
        text=True,
        timeout=120,
        cwd=tmp_path,
        env=env,
    )
    assert proc.returncode == 0, proc.stderr
    names = sorted(p.name for p in out.iterdir())
    assert names == ["plan.json", "setpoints.csv", "summary.json", "trajectory.png"]
    assert (out / "trajectory.png").read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    js = json.loads((out / "summary.json").read_text())
    assert js["verification"]["ok"] and js["domain"] in (1, 2, 3)
    assert "makespan" in proc.stdout


def test_demo_default_out_dir(tmp_path, monkeypatch, capsys) -> None:  # type: ignore[no-untyped-def]
    monkeypatch.chdir(tmp_path)
    assert main(["demo"]) == 0
    assert (tmp_path / "mpa-demo" / "setpoints.csv").exists()


def test_bench_smoke(tmp_path) -> None:  # type: ignore[no-untyped-def]
    sys.path.insert(0, str(ROOT / "experiments"))
    try:
        import bench_trajectory
    finally:
        sys.path.pop(0)
    out = tmp_path / "b.json"
    assert bench_trajectory.main(["--n", "6", "--seed", "3", "--json", str(out)]) == 0
    res = json.loads(out.read_text())
    assert res["table"]["queries"] == 6
