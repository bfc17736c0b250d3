"""The bodies drawn to scale: patch sizes in data units, centres and headings at the gate's poses."""

from __future__ import annotations

import math
from pathlib import Path
from typing import Any

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from matplotlib.figure import Figure
from matplotlib.patches import Circle, Polygon

import mpa
from mpa.footprint import Disc, Rectangle, drawing_of, parse_footprint
from mpa.graph_track import GraphTrack
from tests.helpers.cli import run_redirected as _cli
from trajopt.viz.bodies import body_patch, move_body

ROOT = Path(__file__).resolve().parents[2]
YARD = ROOT / "examples" / "tracks" / "rail_yard.json"


def _rect_size(poly: Polygon) -> tuple[float, float, float]:
    """(length, width, heading) of a drawn rectangle: its first side runs along the heading."""
    xy = np.asarray(poly.get_xy())[:4]
    along, across = xy[1] - xy[0], xy[2] - xy[1]
    return float(np.hypot(*along)), float(np.hypot(*across)), math.atan2(along[1], along[0])


def _angle_diff(a: float, b: float) -> float:
    """Difference of two headings of a symmetric body (mod pi)."""
    d = (a - b) % math.pi
    return min(d, math.pi - d)


@settings(max_examples=60, deadline=None)
@given(
    st.floats(0.05, 5.0),
    st.floats(0.05, 5.0),
    st.floats(-50, 50),
    st.floats(-50, 50),
    st.floats(-math.pi, math.pi),
)
def test_patches_have_the_bodies_size_in_data_units(length: float, width: float, x: float, y: float, h: float) -> None:
    fig = Figure()
    ax = fig.subplots()
    rect = body_patch(Rectangle(length, width), (x, y), h)
    ax.add_patch(rect)
    assert isinstance(rect, Polygon)
    lg, wd, hd = _rect_size(rect)
    assert lg == pytest.approx(length, rel=1e-9) and wd == pytest.approx(width, rel=1e-9)
    assert _angle_diff(hd, h) < 1e-9
    assert np.allclose(np.asarray(rect.get_xy())[:4].mean(axis=0), (x, y))
    disc = body_patch(Disc(length), (x, y), h)
    assert isinstance(disc, Circle)
    assert disc.get_radius() == pytest.approx(length) and np.allclose(disc.get_center(), (x, y))
    # moved: the same body elsewhere, turned
    move_body(rect, Rectangle(length, width), (y, x), h + 1.0)
    lg, wd, hd = _rect_size(rect)
    assert (lg, wd) == pytest.approx((length, width)) and _angle_diff(hd, h + 1.0) < 1e-9
    assert np.allclose(np.asarray(rect.get_xy())[:4].mean(axis=0), (y, x))
    move_body(disc, Disc(length), (y, x), 0.0)
    assert np.allclose(disc.get_center(), (y, x))


def _bodies(ax: Any) -> tuple[list[Circle], list[Polygon]]:
    circles = [p for p in ax.patches if isinstance(p, Circle)]
    rects = [p for p in ax.patches if isinstance(p, Polygon) and len(np.asarray(p.get_xy())) in (4, 5)]
    return circles, rects


def test_plan_figure_draws_the_bodies_at_start_and_goal_to_scale() -> None:
    from trajopt.viz.layout import graph_plan_figure

    track = GraphTrack.from_json(YARD)
    p = mpa.plan(track, ("W", "E"), ("E", "W"), 2.5, footprint="2.0x0.8,0.45")
    fig = graph_plan_figure(p, name="rail_yard", footprint="2.0x0.8,0.45")
    ax = fig.axes[0]
    circles, rects = _bodies(ax)
    assert len(circles) == 2 and len(rects) == 2  # B a disc, A a rectangle; at start and goal
    dr = drawing_of(track)
    for ends, k in ((p.start, 0), (p.goal, 1)):
        xy, hd = dr.pose([ends[0][0], ends[1][0]], [ends[0][1], ends[1][1]])
        lg, wd, h = _rect_size(rects[k])
        assert (lg, wd) == pytest.approx((2.0, 0.8)) and _angle_diff(h, hd[0]) < 1e-9
        assert np.allclose(np.asarray(rects[k].get_xy())[:4].mean(axis=0), xy[0])
        assert circles[k].get_radius() == pytest.approx(0.45) and np.allclose(circles[k].get_center(), xy[1])
    assert "bodies 2x0.8,0.45 m to scale" in ax.get_title()
    assert ax.get_aspect() == 1.0  # to scale: one metre is as long across as along


def test_plan_without_footprint_draws_no_bodies() -> None:
    from trajopt.viz.layout import graph_plan_figure

    track = GraphTrack.from_json(YARD)
    fig = graph_plan_figure(mpa.plan(track, ("W", "E"), ("E", "W"), 2.5))
    circles, rects = _bodies(fig.axes[0])
    assert circles == [] and rects == []


def test_run_figure_and_mpa_plot_draw_the_bodies_at_the_csv_poses(tmp_path: Path) -> None:
    from trajopt.cli.plot import _context, _layout_run
    from trajopt.viz.setpoints import read_rows

    argv = ["trajectory", "--graph", str(YARD), "--start", "west:1", "east:5", "--goal", "west:4", "spur:3"]
    argv += ["--clearance", "1", "--rate", "20", "--footprint", "2.0x0.8", "--plot", "--out", str(tmp_path)]
    rc, _, err = _cli(argv)
    assert rc == 0, err
    assert (tmp_path / "trajectory.png").stat().st_size > 0
    rows = read_rows(tmp_path / "setpoints.csv")
    ctx = _context(tmp_path / "setpoints.csv")
    assert ctx["footprint"] == parse_footprint("2.0x0.8")
    fig = _layout_run(rows, ctx)
    _, rects = _bodies(fig.axes[0])
    assert len(rects) == 2 * 6  # both carts at the start, four snapshots and the goal
    centres = np.array([np.asarray(r.get_xy())[:4].mean(axis=0) for r in rects])
    sizes = np.array([_rect_size(r)[:2] for r in rects])
    assert np.allclose(sizes, [2.0, 0.8])
    n = len(rows["time"])
    for who in "ab":
        at = np.column_stack([rows[f"{who}_x"], rows[f"{who}_y"]])
        for c in centres[(0 if who == "a" else 1) :: 2]:
            k = int(np.argmin(np.hypot(*(at - c).T)))
            assert np.hypot(*(at[k] - c)) < 1e-9, (who, c)
    assert np.allclose(centres[0], [rows["a_x"][0], rows["a_y"][0]])
    assert np.allclose(centres[-1], [rows["b_x"][n - 1], rows["b_y"][n - 1]])
    # the figure of the run itself (mpa trajectory --plot) draws the same bodies
    assert rc == 0 and (tmp_path / "trajectory.png").exists()


def test_layout_animation_places_the_bodies_at_the_gates_poses(tmp_path: Path, monkeypatch: Any) -> None:
    import trajopt.viz.bodies as bodies

    seen: list[tuple[Any, np.ndarray, float]] = []
    real = bodies.move_body

    def spy(patch: Any, fp: Any, xy: Any, heading: float) -> None:
        seen.append((fp, np.asarray(xy, dtype=float), heading))
        real(patch, fp, xy, heading)

    monkeypatch.setattr(bodies, "move_body", spy)
    track = GraphTrack.from_json(YARD)
    p = mpa.plan(track, ("W", "E"), ("E", "W"), 2.5, footprint="1.5x0.6,0.4")
    from trajopt.viz.layout_animation import animate_graph_plan

    out = animate_graph_plan(p, tmp_path / "a.gif", footprint="1.5x0.6,0.4", max_frames=12, progress=False)
    assert out.stat().st_size > 0
    assert len(seen) == 2 * 12
    dr = drawing_of(track)
    routes = (p.route_a, p.route_b)
    # each frame: A's rectangle then B's disc, at a pose of the drawing on the robot's route
    for i, (fp, xy, h) in enumerate(seen):
        k = i % 2
        assert fp == (Rectangle(1.5, 0.6) if k == 0 else Disc(0.4))
        s = np.linspace(routes[k].breaks[0], routes[k].breaks[-1], 4001)
        e, o = routes[k].positions(s)
        pts, _ = dr.pose(e, o)
        j = int(np.argmin(np.hypot(*(pts - xy).T)))
        assert np.hypot(*(pts[j] - xy)) < 0.02
        assert min(_angle_diff(h, float(x)) for x in dr.piece_heading) < 1e-9  # turned along a piece of track
    first_a, last_a = seen[0][1], seen[-2][1]
    assert np.allclose(first_a, dr.pose(*p.start[0])[0], atol=1e-9)
    assert np.allclose(last_a, dr.pose(*p.goal[0])[0], atol=1e-9)
