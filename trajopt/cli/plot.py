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
    if isinstance(s.get("clearance"), (int, float)):
        out["clearance"] = float(s["clearance"])
    if isinstance(s.get("words"), dict):
        out["words"] = {str(k): str(v) for k, v in s["words"].items()}
    parts = [csv_path.name]
    if "domain" in s and "word" in s:
        parts.append(f"domain {s['domain']}, class {' '.join(s['word']) or '(trivial)'}")
    if isinstance(s.get("makespan"), (int, float)):
        parts.append(f"makespan {s['makespan']:.2f} s")
    out["title"] = " · ".join(parts)
    return out


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
    png = figure_png(plot_rows(rows, **ctx))
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
