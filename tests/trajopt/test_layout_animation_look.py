"""The layout animation's look: legend size, border, labels apart, quiet unless stderr is a terminal."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
from PIL import Image

from mpa import GraphTrack
from trajopt import TrajectoryGenerator
from trajopt.viz.labels import separate_labels
from trajopt.viz.layout import layout_geometry
from trajopt.viz.layout_animation import LEGEND_SIZE, _static_figure, animate_layout

EXAMPLES = Path(__file__).resolve().parents[2] / "examples" / "tracks"
QUERIES = [
    ("y_junction.json", 0.5, ("left", "right"), ("right", "left")),
    ("two_sidings.json", 0.05, ("north_end", "south_end"), ("south_end", "north_end")),
    ("warehouse.json", 0.3, ("A1_X4", "dock6"), ("dock6", "A1_X4")),
]


@pytest.mark.parametrize(("layout", "clearance", "start", "goal"), QUERIES)
def test_frames_keep_off_the_border(tmp_path, layout, clearance, start, goal, capsys) -> None:  # type: ignore[no-untyped-def]
    track = GraphTrack.from_json(str(EXAMPLES / layout))
    traj = TrajectoryGenerator(track, clearance=clearance).generate(start, goal)
    p = traj.plan
    out = tmp_path / "a.gif"
    animate_layout(track, p.route_a, p.route_b, traj.t, traj.s, out, clearance=clearance, title="t", max_frames=4)
    assert capsys.readouterr().err == ""  # no progress bar when stderr is not a terminal
    with Image.open(out) as im:
        assert im.size[0] == 800  # the default width at the default dpi
        for k in range(im.n_frames):
            im.seek(k)
            a = np.asarray(im.convert("RGB")).astype(int)
            ink = (a < 245).any(axis=2)
            rows, cols = np.nonzero(ink.any(axis=1))[0], np.nonzero(ink.any(axis=0))[0]
            # nothing within 6 px of the border
            assert cols.min() >= 6 and cols.max() <= a.shape[1] - 7, (k, cols.min(), cols.max())
            assert rows.min() >= 6 and rows.max() <= a.shape[0] - 7, (k, rows.min(), rows.max())


def test_legend_text_is_at_least_10_px_and_labels_do_not_overlap() -> None:
    assert LEGEND_SIZE * 80.0 / 72.0 >= 10.0  # points at the default 80 dpi
    track = GraphTrack.from_json(str(EXAMPLES / "y_junction.json"))
    traj = TrajectoryGenerator(track, clearance=0.5).generate(("left", "right"), ("right", "left"))
    p = traj.plan
    fig = _static_figure(track, layout_geometry(track), p.route_a, p.route_b, "t", 1.0, None)
    fig.set_dpi(80.0)
    fig.canvas.draw()
    ax = fig.axes[0]
    legend = ax.get_legend()
    assert all(t.get_fontsize() * 80.0 / 72.0 >= 10.0 for t in legend.get_texts())
    separate_labels(ax)
    fig.canvas.draw()
    r = fig.canvas.get_renderer()  # type: ignore[attr-defined]
    boxes = [t.get_window_extent(r) for t in ax.texts if t.get_text()]
    for i, a in enumerate(boxes):
        for b in boxes[i + 1 :]:
            assert not a.overlaps(b), (a, b)


def test_separate_labels_moves_an_overlapping_annotation() -> None:
    from matplotlib.backends.backend_agg import FigureCanvasAgg
    from matplotlib.figure import Figure

    fig = Figure(figsize=(4, 3), dpi=80)
    FigureCanvasAgg(fig)
    ax = fig.subplots()
    ax.set_xlim(0, 10)
    ax.set_ylim(0, 10)
    ax.annotate("vertex", (5, 5), xytext=(0, 8), textcoords="offset points", zorder=6)
    low = ax.annotate("edge name", (5, 5), xytext=(0, 10), textcoords="offset points", zorder=2)
    fig.canvas.draw()
    assert separate_labels(ax)
    fig.canvas.draw()
    r = fig.canvas.get_renderer()  # type: ignore[attr-defined]
    a, b = (t.get_window_extent(r) for t in ax.texts)
    assert not a.overlaps(b) and tuple(low.xyann) != (0, 10)


def test_progress_bar_on_request(tmp_path, capsys) -> None:  # type: ignore[no-untyped-def]
    track = GraphTrack.from_json(str(EXAMPLES / "y_junction.json"))
    traj = TrajectoryGenerator(track, clearance=0.5).generate(("left", "right"), ("right", "left"))
    p = traj.plan
    out = tmp_path / "a.gif"
    animate_layout(track, p.route_a, p.route_b, traj.t, traj.s, out, max_frames=5, progress=True, dpi=30)
    err = capsys.readouterr().err
    assert "animate: [" in err and "5/5 frames" in err and err.endswith("\n")
