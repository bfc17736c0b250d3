"""The PVT default ``--pvt-interval auto``, exact row times in the files and positions in words to the mm."""

from __future__ import annotations

import csv
import json
import re
from decimal import Decimal
from pathlib import Path

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from mpa import Lollipop
from trajopt import generate_trajectory
from trajopt.cli import main
from trajopt.io.pvt import _series, check_pvt, largest_pvt_interval, pvt_knots, pvt_table, time_text

QUERY = ["--track", "lollipop", "--stick", "1.3", "--loop", "0.9", "--start", "0.35", "1.75", "--goal", "1.75", "0.35"]
EXAMPLES = Path(__file__).resolve().parents[2] / "examples" / "tracks"


@pytest.fixture(scope="module")
def ordinary():  # type: ignore[no-untyped-def]
    """The issue's ordinary query: exact samples fail PVT at 0.1 s, fitted row velocities pass."""
    return generate_trajectory(Lollipop(1.3, 0.9), (0.35, 1.75), (1.75, 0.35), clearance=0.05)


def test_auto_is_the_largest_round_interval_that_passes(ordinary) -> None:  # type: ignore[no-untyped-def]
    tab = pvt_table(ordinary, "auto")
    assert tab.interval <= 0.1 and tab.stretch == 1.0
    assert check_pvt(ordinary, tab.interval).ok
    assert tab.interval == 0.1 and tab.velocity_change > 0.0
    best = largest_pvt_interval(ordinary, 0.5)
    assert best is not None and check_pvt(ordinary, best).ok
    for x in [x for x in _series(0.5) if x > best]:  # every larger round interval fails
        assert not check_pvt(ordinary, x).ok, x
    with pytest.raises(ValueError, match=f"the largest interval that works is {best:g} s"):
        pvt_table(ordinary, 0.5)


def test_default_formats_write_everything(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    out = tmp_path / "run"
    rc = main(["trajectory", *QUERY, "--clearance", "0.05", "--format", "csv,ros2-yaml,pvt", "--out", str(out)])
    err = capsys.readouterr().err
    assert rc == 0, err
    summary = json.loads((out / "summary.json").read_text())
    pvt = summary["pvt"]
    assert pvt["auto"] is True and 0.001 <= pvt["interval"] <= 0.1
    with open(out / "pvt.csv") as f:
        rows = list(csv.reader(f))[1:]
    assert len(rows) == pvt["rows"]
    step = Decimal(repr(pvt["interval"]))
    for k, row in enumerate(rows[:-1]):  # every row but the last (the end of the motion) is an exact multiple
        assert Decimal(row[0]) == k * step, (k, row[0])
    assert float(rows[-1][0]) == pytest.approx(summary["motion_time"], abs=1e-12)
    # an explicit interval that fails is still refused, naming the largest that works; nothing written
    bad = tmp_path / "bad"
    rc = main(["trajectory", *QUERY, "--format", "pvt", "--pvt-interval", "0.5", "--out", str(bad)])
    err = capsys.readouterr().err
    assert rc == 2 and err.startswith("error: --pvt-interval 0.5 s") and err.count("\n") == 1
    assert "the largest interval that works is " in err
    assert not bad.exists()


@settings(max_examples=100, deadline=None)
@given(
    st.sampled_from(_series(1.0)),
    st.floats(0.01, 60.0, allow_nan=False),
)
def test_row_times_print_as_exact_multiples(interval: float, motion_time: float) -> None:
    t = pvt_knots(motion_time, interval)
    text = time_text(t)
    step = Decimal(repr(interval))
    for k, x in enumerate(text[:-1]):
        assert "e" not in x and Decimal(x) == k * step, (interval, k, x)
    assert float(text[-1]) == motion_time  # the last row reads back exactly
    assert np.array_equal(np.array([float(x) for x in text]), t)


def test_positions_in_words_are_millimetres(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    out = tmp_path / "spur"
    layout = str(EXAMPLES / "y_junction.json")
    argv = ["trajectory", "--graph", layout, "--start", "b_left:1.7001", "b_right:2.70000001"]
    argv += ["--goal", "b_right:2.5123456", "b_left:1.8"]
    rc = main([*argv, "--clearance", "0.5", "--out", str(out)])
    text, err = capsys.readouterr()
    assert rc == 0, err
    words = json.loads((out / "summary.json").read_text())["words"]
    for w in (words["A"], words["B"], text):
        assert not re.search(r":\d+\.\d{4,}", w), w


def test_auto_at_the_acceleration_limit_fits_the_row_velocities() -> None:
    """A layout motion at its acceleration limit: exact samples keep the limits at no interval; auto fits."""
    from mpa import GraphTrack
    from trajopt import TrajectoryGenerator

    traj = TrajectoryGenerator(GraphTrack.from_json(str(EXAMPLES / "y_junction.json")), clearance=0.5).generate(
        ("left", "right"), ("right", "left")
    )
    tab = pvt_table(traj, "auto", max_stretch=2.0)
    assert tab.interval == 0.1 and tab.stretch == 1.0 and tab.velocity_change > 0.0 and check_pvt(traj, 0.1).ok
