"""Pictures of layout runs: ``mpa trajectory --graph ... --plot`` and ``mpa plot DIR`` of a layout run."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest

from mpa import GraphTrack
from trajopt import TrajectoryGenerator
from trajopt.cli import main
from trajopt.viz.layout_run import layout_run_figure, routes_from_summary, trajectory_figure

EXAMPLES = Path(__file__).resolve().parents[2] / "examples" / "tracks"
Y = str(EXAMPLES / "y_junction.json")
PNG = b"\x89PNG\r\n\x1a\n"


@pytest.fixture(scope="module")
def swap():  # type: ignore[no-untyped-def]
    return TrajectoryGenerator(GraphTrack.from_json(Y), clearance=0.5).generate(("left", "right"), ("right", "left"))


def _texts(fig) -> list[str]:  # type: ignore[no-untyped-def]
    return [t.get_text() for t in fig.findobj(match=lambda a: hasattr(a, "get_text"))]


def test_layout_figure_shows_routes_carts_and_profiles(swap) -> None:  # type: ignore[no-untyped-def]
    fig = trajectory_figure(swap, "y_junction")
    texts = " ".join(_texts(fig))
    assert "domain" not in texts  # a layout has no domains
    assert "route A" in texts and "route B" in texts and "A start" in texts and "B goal" in texts
    assert "speed (m/s)" in texts and "acceleration (m/s²)" in texts and "distance A–B (m)" in texts
    legend = [t.get_text() for t in fig.axes[0].get_legend().get_texts()]
    times = [float(x.split("= ")[1].split(" s")[0]) for x in legend if x.startswith("t = ")]
    assert len(times) == 4 and 0 < times[0] < times[-1] < swap.makespan  # the carts at four times inside the motion
    # the distance panel is the exact graph distance of the rows, never below the clearance
    ax_d = fig.axes[-1]
    d = ax_d.lines[0].get_ydata()
    assert len(d) == len(swap.t) and float(np.min(d)) >= 0.5 - 1e-9
    np.testing.assert_allclose(float(np.min(d)), swap.min_separation, atol=1e-9)


def test_routes_from_summary_round_trip(swap) -> None:  # type: ignore[no-untyped-def]
    s = swap.summary()
    track = GraphTrack.from_layout(s["track"])
    ra, rb = routes_from_summary(track, s["routes"])
    for mine, route in ((ra, swap.plan.route_a), (rb, swap.plan.route_b)):
        e0, o0 = mine.positions(swap.s[:, 0 if route is swap.plan.route_a else 1])
        e1, o1 = route.positions(swap.s[:, 0 if route is swap.plan.route_a else 1])
        d = track.geometry.distance(e0, o0, e1, o1)
        assert float(np.max(d)) <= 1e-9
    with pytest.raises(ValueError, match="route of robot A"):
        routes_from_summary(track, {"b": s["routes"]["b"]})
    with pytest.raises(ValueError, match="expected"):
        layout_run_figure(track, (ra, rb), [0.0, 1.0], [[0.0, 0.0]])


def test_cli_plot_of_a_layout_run(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    out = tmp_path / "run"
    q = ["trajectory", "--graph", Y, "--start", "left", "right", "--goal", "right", "left", "--clearance", "0.5"]
    assert main([*q, "--plot", "--format", "csv,pvt", "--pvt-stretch", "2", "--out", str(out)]) == 0, (
        capsys.readouterr().err
    )
    png = (out / "trajectory.png").read_bytes()
    assert png.startswith(PNG) and len(png) > 20_000
    assert "trajectory.png" in json.loads((out / "summary.json").read_text())["files"]
    capsys.readouterr()
    # mpa plot DIR draws the same kind of picture from the files
    other = tmp_path / "again.png"
    assert main(["plot", str(out), "--out", str(other)]) == 0
    assert other.read_bytes().startswith(PNG)
    from trajopt.cli.plot import _context, _layout_run
    from trajopt.viz.setpoints import read_rows

    rows = read_rows(out / "setpoints.csv")
    ctx = _context(out / "setpoints.csv")
    assert "domain" not in ctx["title"] and "A left → right, B right → left" in ctx["title"]
    fig = _layout_run(rows, ctx)
    assert fig is not None and "route A" in " ".join(_texts(fig))
    # from pvt.csv (no accelerations): speed and distance only
    fig = _layout_run(read_rows(out / "pvt.csv"), _context(out / "pvt.csv"))
    texts = " ".join(_texts(fig))
    assert "speed (m/s)" in texts and "acceleration" not in texts
