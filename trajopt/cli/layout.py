"""``mpa layout convert|show``: Open-RMF maps (and our layouts) converted to our JSON, or described and drawn.

- ``mpa layout convert FILE [--level L] [--nav-graph IDX] --out layout.json`` writes our JSON layout (vertex names
  and coordinates, edges with ``length``, ``oneway`` (true/false) and ``speed_limit`` (m/s, null: none)) of a building
  map, a navigation graph or a layout of ours, for users who want to edit it (:mod:`mpa.openrmf` states the
  conversion rules).
- ``mpa layout show FILE [--level L] [--nav-graph IDX] [--plot out.png] [--dpi N]`` prints the layout (vertices,
  edges, length, parts, one-way lanes, speed limits) and with ``--plot`` draws it with vertex names, one-way arrows
  and limits (:func:`trajopt.viz.layout_rules.layout_figure`).

Files are written atomically; on bad input exit 2 with one ``error:`` line and nothing written.
"""

from __future__ import annotations

import argparse
import json
from pathlib import Path
from typing import Any

from mpa.errors import InvalidInputError
from mpa.graph_track import GraphTrack
from mpa.openrmf import read_layout_file
from trajopt.cli.common import add_map_arguments, output_error

__all__ = ["layout_summary", "register"]

PLOT_SUFFIXES = (".png", ".pdf", ".svg")


def _read(args: argparse.Namespace) -> tuple[GraphTrack, dict[str, Any]]:
    layout, info = read_layout_file(args.file, args.level, args.nav_graph)
    return GraphTrack.from_layout(layout), info


def layout_summary(track: GraphTrack, info: dict[str, Any]) -> dict[str, Any]:
    """What ``mpa layout show`` prints: counts, length, parts, one-way edges and speed limits (JSON-friendly)."""
    names = track.edge_names
    parts = track.graph.components()
    out: dict[str, Any] = {
        "kind": info.get("kind", "layout"),
        "vertices": len({*track.tails.tolist(), *track.heads.tolist()}),
        "edges": track.n_edges,
        "total_length": track.total_length,
        "parts": len(parts),
        "oneway": [names[i] for i, ow in enumerate(track.oneway) if ow],
        "speed_limits": {names[i]: v for i, v in enumerate(track.speed_limits) if v is not None},
    }
    for key in ("level", "nav_graph", "coordinate_system", "lanes", "merged_lanes", "dropped_lanes"):
        if key in info:
            out[key] = info[key]
    if info.get("projection_error"):
        out["projection_error"] = info["projection_error"]
    return out


def _print_summary(s: dict[str, Any]) -> None:
    src = s["kind"]
    if src == "building":
        src = f"building map, level {s['level']}, nav graph {s['nav_graph']} ({s['coordinate_system']})"
    elif src == "nav_graph":
        src = f"navigation graph, level {s['level']}"
    print(f"source     {src}")
    if "lanes" in s:
        print(f"lanes      {s['lanes']} ({s['merged_lanes']} merged as repeats, {s['dropped_lanes']} of zero length)")
    print(f"layout     {s['vertices']} vertices, {s['edges']} edges, {s['total_length']:.6g} m")
    if s["parts"] > 1:
        print(f"parts      {s['parts']} (not connected: a query between two parts has no motion)")
    one = s["oneway"]
    print(f"one-way    {len(one)}" + (f": {', '.join(one[:12])}{' ...' if len(one) > 12 else ''}" if one else ""))
    lim = s["speed_limits"]
    text = ", ".join(f"{k} {v:g} m/s" for k, v in list(lim.items())[:12])
    print(f"limits     {len(lim)}" + (f": {text}{' ...' if len(lim) > 12 else ''}" if lim else ""))
    if s.get("projection_error"):
        print(f"projection local tangent plane, relative distance error below {s['projection_error']:.2g}")


def run_convert(args: argparse.Namespace) -> int:
    """Handler of ``mpa layout convert``: write our JSON layout; returns 0."""
    out = Path(args.out)
    if out.suffix.lower() != ".json":
        raise InvalidInputError(f"--out is {args.out!r}, expected a file name ending in .json")
    if not (out.parent if str(out.parent) else Path(".")).is_dir():
        raise InvalidInputError(f"--out folder {str(out.parent)!r} does not exist, expected an existing folder")
    track, info = _read(args)
    data = track.to_dict()
    for edge in data["edges"]:  # every edge states its rules, also when it has none
        edge.setdefault("oneway", False)
        edge.setdefault("speed_limit", None)
    text = json.dumps(data, indent=1) + "\n"
    GraphTrack.from_layout(json.loads(text))  # what is written reads back
    from trajopt.export import atomic_write_text

    try:
        atomic_write_text(out, text)
    except OSError as exc:
        raise output_error("--out", out, exc) from None
    s = layout_summary(track, info)
    print(
        f"wrote      {out}: {s['vertices']} vertices, {s['edges']} edges ({len(s['oneway'])} one-way, "
        f"{len(s['speed_limits'])} with a speed limit), {s['total_length']:.6g} m"
    )
    return 0


def run_show(args: argparse.Namespace) -> int:
    """Handler of ``mpa layout show``: print the layout, draw it into ``--plot``; returns 0."""
    if args.plot is not None:
        out = Path(args.plot)
        if out.suffix.lower() not in PLOT_SUFFIXES:
            raise InvalidInputError(f"--plot is {args.plot!r}, expected a file name ending in one of {PLOT_SUFFIXES}")
        if not (out.parent if str(out.parent) else Path(".")).is_dir():
            raise InvalidInputError(f"--plot folder {str(out.parent)!r} does not exist, expected an existing folder")
        if not (args.dpi >= 10 and args.dpi < 10000):
            raise InvalidInputError(f"--dpi is {args.dpi!r}, expected a number in [10, 10000)")
    track, info = _read(args)
    s = layout_summary(track, info)
    if args.json:
        print(json.dumps(s))
    else:
        _print_summary(s)
    if args.plot is not None:
        from trajopt.viz.layout_rules import layout_figure
        from trajopt.viz.plotting import save_figure

        fig = layout_figure(track, name=Path(args.file).name)
        try:
            save_figure(fig, args.plot, args.dpi, facecolor="white")
        except OSError as exc:
            raise output_error("--plot", args.plot, exc) from None
        if not args.json:
            print(f"plot       {args.plot}")
    return 0


def register(subparsers: Any) -> argparse.ArgumentParser:
    """Add the ``layout`` subcommand (``convert``, ``show``) to an argparse subparsers object."""
    p = subparsers.add_parser(
        "layout",
        help="convert an Open-RMF map to a JSON layout, or describe and draw a layout",
        description="Open-RMF building maps (*.building.yaml), navigation graphs and our JSON layouts.",
    )
    sub = p.add_subparsers(dest="layout_command", required=True, parser_class=type(p))
    c = sub.add_parser("convert", help="write our JSON layout (names, coordinates, oneway, speed_limit)")
    c.add_argument("file", metavar="FILE", help="a building map, navigation graph or JSON layout")
    add_map_arguments(c)
    c.add_argument("--out", required=True, metavar="FILE", help="the JSON layout to write")
    c.set_defaults(func=run_convert)
    s = sub.add_parser("show", help="print a layout; --plot draws it with names, one-way arrows and limits")
    s.add_argument("file", metavar="FILE", help="a building map, navigation graph or JSON layout")
    add_map_arguments(s)
    s.add_argument("--plot", default=None, metavar="FILE", help="draw the layout (.png, .pdf or .svg)")
    s.add_argument("--dpi", type=float, default=110.0, help="resolution of --plot (default 110)")
    s.add_argument("--json", action="store_true", help="print one JSON object")
    s.set_defaults(func=run_show)
    return p
