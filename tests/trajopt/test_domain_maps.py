"""Domain maps (``mpa domains``) and pictures of a paper plan (``mpa plan --track ... --plot``)."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest

from mpa import Circle, InvalidInputError, Lollipop, plan
from tests.helpers.cli import run_main as _run
from trajopt.viz.domains import COLLISION, NO_MOTION, domain_grid, domain_map_figure, plan_figure

PNG = b"\x89PNG\r\n\x1a\n"


@pytest.mark.parametrize(
    ("track", "kw"),
    [
        (Lollipop(1.3, 0.9), {"goal": (1.75, 0.35)}),
        (Lollipop(1.0, 1.0), {"start": (1.25, 1.75)}),
        (Circle(1.0), {"start": (0.3, 0.6)}),
    ],
)
def test_every_cell_is_the_domain_of_its_query(track, kw) -> None:  # type: ignore[no-untyped-def]
    grid = domain_grid(track, clearance=0.05, samples=60, **kw)
    assert grid.domain.shape == (60, 60)
    rng = np.random.default_rng(24)
    valid = np.argwhere(grid.domain != COLLISION)
    for i, j in valid[rng.choice(len(valid), 40, replace=False)]:
        q = (float(grid.coords[j]), float(grid.coords[i]))  # A horizontal (j), B vertical (i)
        start, goal = (q, kw["goal"]) if "goal" in kw else (kw["start"], q)
        assert plan(track, start, goal, clearance=0.05).domain == grid.domain[i, j], (i, j, start, goal)
    # the collision band is the states closer than the clearance (states at D to rounding may go either way)
    aa, bb = np.meshgrid(grid.coords, grid.coords)
    d = track.distance(aa, bb)
    assert np.all(grid.domain[d < 0.05 - 1e-9] == COLLISION) and np.all(grid.domain[d > 0.05 + 1e-9] != COLLISION)
    frac = grid.fractions()
    assert sum(frac.values()) == pytest.approx(1.0)


def test_interval_maps_the_other_order_as_no_motion() -> None:
    from mpa import Interval

    grid = domain_grid(Interval(1.0), goal=(0.2, 0.6), clearance=0.05, samples=40)
    aa, bb = np.meshgrid(grid.coords, grid.coords)
    valid = grid.domain != COLLISION
    np.testing.assert_array_equal(grid.domain[valid] == NO_MOTION, (aa > bb)[valid])  # A behind B only
    assert set(np.unique(grid.domain[valid]).tolist()) == {NO_MOTION, 1}


def test_bad_input() -> None:
    L = Lollipop(1.0, 1.0)
    with pytest.raises(InvalidInputError, match="exactly one"):
        domain_grid(L, goal=(0.1, 0.6), start=(0.6, 0.1))
    with pytest.raises(InvalidInputError, match="samples"):
        domain_grid(L, goal=(0.1, 0.6), samples=3)
    with pytest.raises(InvalidInputError, match="clearance"):
        domain_grid(L, goal=(0.1, 0.12), clearance=0.05)


def test_figures_draw_the_map_and_the_plan() -> None:
    L = Lollipop(1.3, 0.9)
    fig = domain_map_figure(domain_grid(L, goal=(1.75, 0.35), clearance=0.05, samples=40))
    texts = [t.get_text() for t in fig.axes[0].get_legend().get_texts()]
    assert any(t.startswith("domain 1") for t in texts) and any("closer than D" in t for t in texts)
    p = plan(L, (0.35, 1.75), (1.75, 0.35), clearance=0.05)
    fig = plan_figure(p, samples=40)
    assert len(fig.axes) == 3 and f"domain {p.domain}" in fig.axes[2].get_title()


def test_cli_domains_and_plan_plot(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    png = tmp_path / "map.png"
    q = ["domains", "--track", "lollipop", "--stick", "1.3", "--loop", "0.9"]
    rc, out, err = _run([*q, "--goal", "1.75", "0.35", "--samples", "50", "--plot", str(png)], capsys)
    assert rc == 0, err
    assert png.read_bytes().startswith(PNG) and "domain 1" in out and f"plot       {png}" in out
    rc, out, err = _run([*q, "--start", "0.35", "1.75", "--samples", "30", "--json"], capsys)
    assert rc == 0, err
    js = json.loads(out)
    assert js["varies"] == "goal" and sum(js["fractions"].values()) == pytest.approx(1.0)
    for bad, match in (
        ([], "exactly one of --goal"),
        (["--goal", "1", "0.2", "--start", "0.2", "1"], "exactly one of --goal"),
        (["--goal", "1", "0.2", "--samples", "5"], "--samples is 5"),
        (["--goal", "1", "x"], "--goal has 'x'"),
        (["--goal", "1", "0.2", "--plot", str(tmp_path / "m.txt")], "--plot"),
    ):
        rc, _, err = _run([*q, *bad], capsys)
        assert rc == 2 and match in err and err.count("\n") == 1, (bad, err)
    plan_png = tmp_path / "plan.png"
    p = ["plan", "--track", "lollipop", "--stick", "1.3", "--loop", "0.9", "--start", "0.35", "1.75"]
    rc, out, err = _run([*p, "--goal", "1.75", "0.35", "--plot", str(plan_png)], capsys)
    assert rc == 0, err
    assert plan_png.read_bytes().startswith(PNG) and "domain     1" in out
