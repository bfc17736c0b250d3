"""Figures of the example graph layouts and of plans of the complete graph planner on them (headless).

Writes ``<out>/layouts/<name>.png`` for every layout in ``examples/tracks/`` (plus ``theta_no_coordinates``, the
theta layout with its coordinates removed, drawn by the automatic layout), and ``<out>/graphs/<name>_<query>.png``
for one plan on each small layout: the layout, both routes, start and goal, the switches used, and the configuration
cells the plan crosses with their exact free polygons; and ``<out>/graphs/y_junction_swap.gif``, the robots moving
along that plan at 1 m/s.

Usage::

    python experiments/figures_graphs.py [--out docs/img] [--dpi 110] [--only y_junction ...]
"""

from __future__ import annotations

import argparse
import json
import sys
from pathlib import Path

import matplotlib as mpl

mpl.use("Agg")

from matplotlib.figure import Figure

from mpa.graph_track import GraphTrack
from mpa.planners.factory import plan
from trajopt.viz.layout import draw_layout, graph_plan_figure, layout_geometry
from trajopt.viz.layout_animation import animate_graph_plan
from trajopt.viz.plotting import save_figure

ROOT = Path(__file__).resolve().parents[1]
TRACKS = ROOT / "examples" / "tracks"

#: One plan per small layout: (layout, file suffix, start (A, B), goal (A, B), clearance D in metres, objective).
QUERIES: list[tuple[str, str, tuple[str, str], tuple[str, str], float, str]] = [
    ("y_junction", "swap", ("left", "right"), ("right", "left"), 0.5, "fastest"),
    ("passing_loop", "swap", ("W", "E"), ("E", "W"), 1.0, "fastest"),
    ("two_sidings", "swap", ("north_end", "south_end"), ("south_end", "north_end"), 1.0, "fastest"),
    ("theta", "swap", ("upper:1", "lower:1"), ("lower:1", "upper:1"), 0.5, "fastest"),
    ("figure_eight", "swap", ("left:3", "right:3"), ("right:3", "left:3"), 1.0, "fastest"),
    ("lollipop", "swap", ("F", "loop:0.5"), ("loop:0.5", "F"), 0.2, "fastest"),
    ("circle", "swap", ("P", "loop:0.5"), ("loop:0.5", "P"), 0.2, "fastest"),
]


def _save(fig: Figure, path: Path, dpi: float) -> None:
    save_figure(fig, path, dpi, facecolor="white")


def layouts() -> dict[str, GraphTrack]:
    """Every example layout by name, plus ``theta_no_coordinates``."""
    out = {p.stem: GraphTrack.from_json(p) for p in sorted(TRACKS.glob("*.json"))}
    data = json.loads((TRACKS / "theta.json").read_text(encoding="utf-8"))
    data.pop("vertices")
    for e in data["edges"]:
        e.pop("points", None)
    out["theta_no_coordinates"] = GraphTrack.from_layout(data)
    return out


def _count(n: int, one: str, many: str) -> str:
    return f"{n} {one if n == 1 else many}"


def draw_layout_figure(name: str, track: GraphTrack) -> Figure:
    """One layout: edges, direction arrows, vertex and edge names, title with its size."""
    geo = layout_geometry(track)
    xs = [p[:, 0] for p in geo.polylines]
    ys = [p[:, 1] for p in geo.polylines]
    w = max(float(max(x.max() for x in xs) - min(x.min() for x in xs)), 1e-9)
    h = max(float(max(y.max() for y in ys) - min(y.min() for y in ys)), 1e-9)
    width = 7.5 if track.n_edges > 30 else 6.0
    height = min(max(width * h / w + 1.0, 2.6), 9.0)
    fig = Figure(figsize=(width, height), layout="constrained")
    ax = fig.subplots()
    draw_layout(ax, track, geometry=geo)
    how = "automatic layout (no coordinates)" if geo.automatic else "from the layout's coordinates"
    _, b1 = track.graph.betti()
    ax.set_title(
        f"{name}: {_count(track.graph.n_vertices, 'vertex', 'vertices')}, {_count(track.n_edges, 'edge', 'edges')}, "
        f"{track.total_length:.4g} m, {_count(b1, 'independent cycle', 'independent cycles')}\n{how}",
        fontsize=9,
    )
    return fig


def main(argv: list[str] | None = None) -> int:
    """Draw the layouts and the plans; print one line per file written."""
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--out", type=Path, default=ROOT / "docs" / "img", help="output folder (default docs/img)")
    ap.add_argument("--dpi", type=float, default=100.0, help="resolution (default 100)")
    ap.add_argument("--only", nargs="*", default=None, help="only these layouts")
    ap.add_argument("--gif-frames", type=int, default=26, help="frames of the animation of the Y junction swap")
    ap.add_argument("--gif-dpi", type=float, default=80.0, help="resolution of that animation (default 80)")
    args = ap.parse_args(argv)
    written: list[Path] = []
    for name, track in layouts().items():
        if args.only and name not in args.only:
            continue
        path = args.out / "layouts" / f"{name}.png"
        _save(draw_layout_figure(name, track), path, args.dpi)
        written.append(path)
    tracks = layouts()
    for name, suffix, start, goal, clearance, objective in QUERIES:
        if args.only and name not in args.only:
            continue
        gp = plan(tracks[name], start, goal, clearance, planner="graph", objective=objective)
        path = args.out / "graphs" / f"{name}_{suffix}.png"
        _save(graph_plan_figure(gp, name=name), path, args.dpi)  # type: ignore[arg-type]
        written.append(path)
        if name == "y_junction" and args.gif_frames > 0:
            gif = args.out / "graphs" / f"{name}_{suffix}.gif"
            animate_graph_plan(gp, gif, name=name, fps=10, dpi=args.gif_dpi, max_frames=args.gif_frames)  # type: ignore[arg-type]
            written.append(gif)
    for path in written:
        print(path)
    return 0


if __name__ == "__main__":
    sys.exit(main())
