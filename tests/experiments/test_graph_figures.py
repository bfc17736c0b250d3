"""Pictures of graph tracks and graph plans: drawable geometry, switches, the figure script, ``mpa plan --plot``."""

from __future__ import annotations

import itertools
import sys
from pathlib import Path

import matplotlib as mpl

mpl.use("Agg")

import numpy as np
import pytest
from matplotlib.figure import Figure
from PIL import Image

from mpa import GraphTrack, free_space, plan
from mpa.planners.graph import GraphPlan
from trajopt.cli import main
from trajopt.viz.layout import (
    draw_configuration_cells,
    draw_layout,
    graph_plan_figure,
    layout_geometry,
    route_switches,
)
from trajopt.viz.layout_animation import StreamingGifWriter, animate_layout, graph_plan_motion

ROOT = Path(__file__).resolve().parents[2]
EXAMPLES = ROOT / "examples" / "tracks"
Y = EXAMPLES / "y_junction.json"
sys.path.insert(0, str(ROOT / "experiments"))

#: A picture is "not blank" if at least this fraction of its pixels is not white and it has this many colours.
MIN_INK = 0.01
MIN_COLOURS = 8


def _ink(path: Path) -> tuple[float, int]:
    with Image.open(path) as im:
        arr = np.asarray(im.convert("RGB"), dtype=np.int16)
    return float(np.mean(np.any(arr < 245, axis=-1))), len(np.unique(arr.reshape(-1, 3), axis=0))


def _y_swap() -> GraphPlan:
    p = plan(GraphTrack.from_json(Y), ("left", "right"), ("right", "left"), clearance=0.5)
    assert isinstance(p, GraphPlan)
    return p


def test_geometry_follows_the_layout_coordinates() -> None:
    rng = np.random.default_rng(3)
    for name in ("y_junction", "passing_loop", "theta", "figure_eight", "two_sidings", "lollipop"):
        tr = GraphTrack.from_json(EXAMPLES / f"{name}.json")
        geo = layout_geometry(tr)
        assert not geo.automatic
        e = rng.integers(0, tr.n_edges, 50)
        o = rng.uniform(0, 1, 50) * tr.lengths[e]
        np.testing.assert_allclose(geo.embed(e, o, tr.lengths), tr.embed(e, o), atol=1e-12, err_msg=name)
        n = geo.normal(e, o, tr.lengths)
        np.testing.assert_allclose(np.hypot(n[:, 0], n[:, 1]), 1.0, err_msg=name)


def test_automatic_layout_is_deterministic_and_draws_loops_and_parallel_edges() -> None:
    layout = {"edges": [["a", "b", 2.0], ["b", "c", 1.0], ["c", "c", 3.0], ["a", "b", 2.5], ["a", "b", 3.0]]}
    tr = GraphTrack.from_layout(layout)
    g1, g2 = layout_geometry(tr), layout_geometry(GraphTrack.from_layout(layout))
    assert g1.automatic
    for p, q in zip(g1.polylines, g2.polylines):
        np.testing.assert_array_equal(p, q)
    for i in range(tr.n_edges):  # every polyline runs from its tail's point to its head's point
        np.testing.assert_allclose(g1.polylines[i][0], g1.vertices[tr.tails[i]], atol=1e-12)
        np.testing.assert_allclose(g1.polylines[i][-1], g1.vertices[tr.heads[i]], atol=1e-12)
    # the loop is a circle of circumference = its length, through its vertex
    loop = g1.polylines[2]
    drawn = float(np.sum(np.hypot(*np.diff(loop, axis=0).T)))
    assert drawn == pytest.approx(3.0, rel=0.01)
    # the three parallel edges a-b are drawn apart (their midpoints differ)
    mids = [g1.embed(i, tr.lengths[i] / 2, tr.lengths) for i in (0, 3, 4)]
    assert min(np.hypot(*(mids[i] - mids[j])) for i in range(3) for j in range(i + 1, 3)) > 0.1
    # graph distances are roughly kept: b-c drawn about 1 m, a-b about 2 m
    v = g1.vertices
    assert np.hypot(*(v[0] - v[1])) == pytest.approx(2.0, rel=0.25)
    assert np.hypot(*(v[1] - v[2])) == pytest.approx(1.0, rel=0.25)


def test_single_vertex_layout_without_coordinates() -> None:
    tr = GraphTrack.from_layout({"edges": [["O", "O", 2.0], ["O", "O", 4.0]]})
    geo = layout_geometry(tr)
    assert geo.automatic
    ends = [p[0] for p in geo.polylines] + [p[-1] for p in geo.polylines]
    np.testing.assert_allclose(ends, 0.0, atol=1e-12)
    centres = [p.mean(axis=0) for p in geo.polylines]
    assert np.hypot(*(centres[0] - centres[1])) > 0.5  # the two loops do not lie on top of each other
    fig = Figure()
    draw_layout(fig.subplots(), tr)


def test_switches_of_the_y_junction_swap() -> None:
    p = _y_swap()
    tr = p.track
    names = tr.edge_names
    visits_short = 0
    for robot, route, first, last in (("A", p.route_a, "b_left", "b_right"), ("B", p.route_b, "b_right", "b_left")):
        sw = route_switches(tr, route, robot)
        # every switch is at J and the switches chain the robot's edges from its start edge to its goal edge
        assert all(tr.graph.vertices[s.vertex] == "J" and s.robot == robot for s in sw)
        chain = [names[sw[0].from_edge]] + [names[s.to_edge] for s in sw]
        assert chain[0] == first and chain[-1] == last, chain
        assert all(a.to_edge == b.from_edge for a, b in itertools.pairwise(sw))
        assert [s.r for s in sw] == sorted(s.r for s in sw)
        visits_short += "b_short" in chain
    assert visits_short == 1  # to swap, exactly one robot steps into the short branch
    # the text of a switch, as the legend shows it
    a = route_switches(tr, p.route_a, "A")
    assert a[0].text(tr) == f"A: switch at J: b_left → {names[a[0].to_edge]}"


def test_plan_figure_has_legend_entries_and_cells() -> None:
    p = _y_swap()
    fig = graph_plan_figure(p, name="y_junction")
    ax_top = fig.axes[0]
    labels = [t.get_text() for t in ax_top.get_legend().get_texts()]
    assert (
        any(x.startswith("A: switch at J: b_left → ") for x in labels) and "route A" in labels and "route B" in labels
    )
    texts = [t.get_text() for t in ax_top.texts]
    for lab in ("A start", "A goal", "B start", "B goal", "J", "b_short"):
        assert lab in texts
    assert "D = 0.5 m" in ax_top.get_title() and "makespan" in ax_top.get_title()
    fig2 = Figure()
    drawn = draw_configuration_cells(fig2.subplots(), free_space(p.track, 0.5), p)
    assert {(e, f) for e, f, _ in drawn} == {(e, f) for e, f, _ in p.segment_cells}


def test_figure_script_writes_non_blank_pictures(tmp_path: Path) -> None:
    import figures_graphs

    argv = ["--out", str(tmp_path), "--dpi", "40", "--gif-frames", "4", "--gif-dpi", "30"]
    assert figures_graphs.main(argv) == 0
    layouts = sorted((tmp_path / "layouts").glob("*.png"))
    graphs = sorted((tmp_path / "graphs").glob("*.png"))
    assert {p.stem for p in layouts} >= {p.stem for p in EXAMPLES.glob("*.json")} | {"theta_no_coordinates"}
    assert len(graphs) == len(figures_graphs.QUERIES)
    for path in layouts + graphs:
        ink, colours = _ink(path)
        assert ink >= MIN_INK and colours >= MIN_COLOURS, (path.name, ink, colours)
    assert len(_frames(tmp_path / "graphs" / "y_junction_swap.gif")) == 4
    assert not list(tmp_path.rglob(".*tmp*"))


def test_cli_plan_plot(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    out = tmp_path / "y.png"
    argv = ["plan", "--graph", str(Y), "--start", "left", "right", "--goal", "right", "left", "--clearance", "0.5"]
    assert main([*argv, "--plot", str(out), "--dpi", "40"]) == 0
    assert f"plot       {out}" in capsys.readouterr().out
    ink, colours = _ink(out)
    assert ink >= MIN_INK and colours >= MIN_COLOURS
    # failures write nothing and say why in one line
    for extra, message in (
        (["--plot", str(tmp_path / "missing" / "y.png")], "does not exist"),
        (["--plot", str(tmp_path / "y.txt")], "expected a file name ending"),
        (["--plot", str(tmp_path / "z.png"), "--dpi", "nan"], "--dpi is nan"),
    ):
        assert main([*argv, *extra]) == 2
        err = capsys.readouterr().err
        assert err.startswith("error: ") and message in err and err.count("\n") == 1
    paper = ["plan", "--track", "lollipop", "--start", "0.2", "1.5", "--goal", "1.5", "0.2", "--clearance", "0.1"]
    assert main([*paper, "--plot", str(tmp_path / "paper.png"), "--dpi", "40"]) == 0  # a paper plan is drawn too
    assert (tmp_path / "paper.png").read_bytes().startswith(b"\x89PNG")
    assert main([*paper, "--planner", "graph", "--plot", str(tmp_path / "p.png"), "--dpi", "40"]) == 0
    no_motion = [*argv[:-1], "1.5", "--plot", str(tmp_path / "none.png")]
    assert main(no_motion) != 0
    assert sorted(p.name for p in tmp_path.iterdir()) == ["p.png", "paper.png", "y.png"]


def _frames(path: Path) -> list[np.ndarray]:
    out = []
    with Image.open(path) as im:
        for k in range(im.n_frames):
            im.seek(k)
            out.append(np.asarray(im.convert("RGB")))
    return out


def test_animation_of_a_plan_moves_both_robots(tmp_path: Path) -> None:
    p = _y_swap()
    t, s = graph_plan_motion(p, samples=50)
    assert t[0] == 0.0 and t[-1] == pytest.approx(p.makespan)
    np.testing.assert_allclose(s[0], 0.0)
    np.testing.assert_allclose(s[-1], [p.route_a.length, p.route_b.length])
    out = tmp_path / "y.gif"
    assert animate_layout(p.track, p.route_a, p.route_b, t, s, out, clearance=0.5, dpi=30, max_frames=6) == out
    frames = _frames(out)
    assert len(frames) == 6
    assert all(f.shape == frames[0].shape for f in frames)
    diffs = [int(np.sum(np.any(a != b, axis=-1))) for a, b in itertools.pairwise(frames)]
    assert min(diffs) > 0  # the robots and the clock move in every frame
    # the robots' colours are there, at different places in the first and last frame
    blue = np.array([0x1F, 0x77, 0xB4])
    where = [
        np.argwhere(np.all(np.abs(f.astype(int) - blue) < 40, axis=-1)).mean(axis=0) for f in (frames[0], frames[-1])
    ]
    assert np.hypot(*(where[0] - where[1])) > 5
    assert sorted(x.name for x in tmp_path.iterdir()) == ["y.gif"]


def test_animation_rejects_bad_input_and_writes_nothing(tmp_path: Path) -> None:
    p = _y_swap()
    t, s = graph_plan_motion(p, samples=20)
    out = tmp_path / "bad.gif"
    cases = [
        ((t, s[:, :1]), {}, "s has shape"),
        ((t[::-1], s[::-1]), {}, "t decreases"),
        ((t, np.where(s > 1, np.nan, s)), {}, "not finite"),
        ((t, s), {"fps": 0}, "fps is 0"),
        ((t, s), {"max_frames": 1}, "max_frames is 1"),
        ((t, s), {"fmt": "avi"}, "format is 'avi'"),
    ]
    from mpa import InvalidInputError

    for (tt, ss), kw, message in cases:
        with pytest.raises(InvalidInputError, match=message):
            animate_layout(p.track, p.route_a, p.route_b, tt, ss, out, **kw)
    from trajopt.viz.animation import ffmpeg_executable

    if ffmpeg_executable() is None:
        with pytest.raises(InvalidInputError, match="ffmpeg"):
            animate_layout(p.track, p.route_a, p.route_b, t, s, tmp_path / "x.mp4")
    assert not list(tmp_path.iterdir())


def test_gif_frames_are_streamed_to_the_file(tmp_path: Path) -> None:
    fig = Figure(figsize=(2, 1.5))
    ax = fig.subplots()
    (line,) = ax.plot([0, 1], [0, 0])
    writer = StreamingGifWriter(fps=5)
    sizes = []
    with writer.saving(fig, str(tmp_path / "s.gif"), 40):
        for k in range(5):
            line.set_ydata([0, k])
            writer.grab_frame()
            sizes.append(writer._fp.tell())
    assert all(b > a for a, b in itertools.pairwise(sizes))  # every frame went to the file when it was grabbed
    assert not any(isinstance(v, list) and len(v) >= 5 for v in vars(writer).values())  # no list of frames is kept
    assert len(_frames(tmp_path / "s.gif")) == 5
