"""``mpa plot PATH [--out FILE]``: a PNG of any setpoints file or output directory the project wrote.

``PATH`` is an output directory (its ``setpoints.csv``, else its ``pvt.csv``) or a setpoints file
(``setpoints.csv``, ``pvt.csv`` or any CSV with ``time`` and ``a_*``/``b_*`` columns). The track, clearance and
each cart's motion in words come from ``summary.json`` beside the file when there is one (a paper track, or a
graph layout). ``--out`` defaults to ``PATH/trajectory.png`` for a directory and to the file with the suffix
``.png`` for a file. Written atomically; errors: exit 2, one ``error:`` line, nothing written.
"""

from __future__ import annotations

import argparse
import json
from pathlib import Path
from typing import Any

from mpa.errors import InvalidInputError
from mpa.tracks import make_track
from trajopt.cli.common import output_error
from trajopt.export import atomic_write_bytes

__all__ = ["register"]


def _source(path: Path) -> tuple[Path, Path]:
    """The setpoints file of ``path`` and the default PNG."""
    if path.is_dir():
        for name in ("setpoints.csv", "pvt.csv"):
            if (path / name).is_file():
                return path / name, path / "trajectory.png"
        raise InvalidInputError(
            f"PATH {str(path)!r} holds no setpoints.csv or pvt.csv, expected an output directory of mpa or a file"
        )
    if path.is_file():
        return path, path.with_suffix(".png")
    if path.exists():
        raise InvalidInputError(
            f"PATH {str(path)!r} is neither a regular file nor a directory, expected a setpoints file or an output "
            "directory"
        )
    raise InvalidInputError(f"PATH {str(path)!r} does not exist, expected a setpoints file or an output directory")


def _mm(name: object) -> str:
    """A position name with its offset to the millimetre (``b_left:0.523367558163`` -> ``b_left:0.523``)."""
    text = str(name)
    edge, sep, off = text.rpartition(":")
    try:
        return f"{edge}:{round(float(off), 3):g}" if sep else text
    except ValueError:
        return text


def _context(csv_path: Path) -> dict[str, Any]:
    """Track, clearance, title and words from ``summary.json`` beside the file (empty if none or unreadable)."""
    p = csv_path.parent / "summary.json"
    try:
        s = json.loads(p.read_text(encoding="utf-8"))
    except (OSError, UnicodeDecodeError, ValueError, RecursionError):
        return {}
    if not isinstance(s, dict):
        return {}
    out: dict[str, Any] = {}
    tr = s.get("track")
    if isinstance(tr, dict):
        kind = tr.get("track")
        if kind in ("interval", "circle", "lollipop"):
            try:
                out["track"] = make_track(kind, tr.get("stick"), tr.get("loop"))
            except InvalidInputError:
                pass
        elif "edges" in tr:
            out["layout"] = tr
            if isinstance(s.get("routes"), dict):
                out["routes"] = s["routes"]
            if isinstance(s.get("limits"), dict):
                out["limits"] = s["limits"]
    if isinstance(s.get("clearance"), (int, float)):
        out["clearance"] = float(s["clearance"])
    if isinstance(s.get("words"), dict):
        out["words"] = {str(k): str(v) for k, v in s["words"].items()}
    parts = [csv_path.name]
    if "layout" in out and isinstance(s.get("start"), list) and isinstance(s.get("goal"), list):
        (a0, b0), (a1, b1) = (_mm(x) for x in s["start"][:2]), (_mm(x) for x in s["goal"][:2])
        parts.append(f"A {a0} → {a1}, B {b0} → {b1}")  # a layout has no domains
    elif "domain" in s and "word" in s:
        parts.append(f"domain {s['domain']}, class {' '.join(s['word']) or '(trivial)'}")
    if isinstance(s.get("makespan"), (int, float)):
        parts.append(f"makespan {s['makespan']:.2f} s")
    out["title"] = " · ".join(parts)
    return out


def _layout_run(rows: dict[str, Any], ctx: dict[str, Any]) -> Any:
    """The figure of a layout run (:func:`trajopt.viz.layout_run.layout_run_figure`) when the rows have route
    coordinates and ``summary.json`` the layout and routes; else None."""
    if "layout" not in ctx or "routes" not in ctx or "a_s" not in rows or "b_s" not in rows:
        return None
    import numpy as np

    from mpa.graph_track import GraphTrack
    from trajopt.viz.layout_run import layout_run_figure, routes_from_summary

    try:
        track = GraphTrack.from_layout(dict(ctx["layout"]))
        routes = routes_from_summary(track, ctx["routes"])
    except InvalidInputError:
        return None

    def pair(k: str) -> Any:
        return np.column_stack([rows[f"a_{k}"], rows[f"b_{k}"]]) if f"a_{k}" in rows and f"b_{k}" in rows else None

    lim = ctx.get("limits") or {}
    limits = {k: lim[k] for k in ("vmax", "amax") if isinstance(lim.get(k), list) and len(lim[k]) == 2}
    return layout_run_figure(
        track,
        routes,
        rows["time"],
        pair("s"),
        v=pair("v"),
        a=pair("a"),
        clearance=ctx.get("clearance"),
        limits=limits,
        title=ctx.get("title", ""),
        words=ctx.get("words"),
    )


def _cmd_plot(args: argparse.Namespace) -> int:
    src, default_png = _source(Path(args.path))
    out = Path(args.out) if args.out is not None else default_png
    if not str(args.out if args.out is not None else out).strip():
        raise InvalidInputError("--out is '', expected a PNG file path")
    if out.is_dir():
        raise InvalidInputError(f"--out is {str(out)!r}, which is a directory, expected a PNG file path")
    from trajopt.viz.plotting import figure_png
    from trajopt.viz.setpoints import plot_rows, read_rows

    rows = read_rows(src)
    ctx = _context(src)
    fig = _layout_run(rows, ctx)
    if fig is None:
        ctx.pop("routes", None)
        ctx.pop("limits", None)
        fig = plot_rows(rows, **ctx)
    png = figure_png(fig)
    try:
        atomic_write_bytes(out, png)
    except OSError as exc:
        raise output_error("--out", out, exc) from None
    print(out)
    return 0


def register(subparsers: Any) -> None:
    """Add ``plot`` to the ``mpa`` command (called by :func:`trajopt.cli.main.build_parser`)."""
    p = subparsers.add_parser("plot", help="draw a setpoints file or an output directory of mpa into a PNG")
    p.add_argument("path", metavar="PATH", help="setpoints.csv / pvt.csv, or an output directory")
    p.add_argument("--out", default=None, metavar="FILE", help="PNG to write (default: DIR/trajectory.png or FILE.png)")
    p.set_defaults(func=_cmd_plot)
