"""Animations of the paper's sample runs: both circle examples and the three lollipop domains.

For each query of :func:`figures.queries` (the same queries as the step-by-step figures) this writes one animation
with the raw plan and the jerk-limited trajectory of the same query on a shared clock (:mod:`trajopt.viz.animation`).

Usage::

    python experiments/animate.py --out animations/                  # five GIFs
    python experiments/animate.py --out animations/ --format mp4     # MP4 (pip install imageio-ffmpeg)
    python experiments/animate.py --out anim --dpi 40 --max-frames 4 --only circle_ex1

Headless (Agg).
"""

from __future__ import annotations

import argparse
import sys
import time
from collections.abc import Sequence
from pathlib import Path

import matplotlib

matplotlib.use("Agg")

sys.path.insert(0, str(Path(__file__).resolve().parent))

from figures import queries

from mpa.errors import MPAError
from trajopt.viz.animation import FORMATS, animate_query

__all__ = ["main"]


def main(argv: Sequence[str] | None = None) -> int:
    """Command-line entry point; returns the exit status."""
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--out", required=True, type=Path, help="output directory")
    ap.add_argument("--format", choices=sorted(FORMATS), default="gif", help="gif (default) or mp4")
    ap.add_argument("--fps", type=float, default=15.0, help="frames per second (default 15)")
    ap.add_argument("--dpi", type=float, default=70.0, help="resolution (default 70)")
    ap.add_argument("--max-frames", type=int, default=None, help="cap the frames of each animation")
    ap.add_argument("--raw-only", action="store_true", help="raw plans only (no trajectory optimisation)")
    ap.add_argument("--only", nargs="*", default=None, help="query names (default: all)")
    args = ap.parse_args(argv)
    names = list(queries()) if not args.only else args.only
    try:
        for name in names:
            if name not in queries():
                print(f"error: query is {name!r}, expected one of {sorted(queries())}", file=sys.stderr)
                return 2
            track, start, goal, _dom = queries()[name]
            t0 = time.perf_counter()
            path = animate_query(
                track,
                start,
                goal,
                args.out / f"{name}{FORMATS[args.format]}",  # type: ignore[arg-type]
                trajectory=not args.raw_only,
                fps=args.fps,
                dpi=args.dpi,
                max_frames=args.max_frames,
                fmt=args.format,
            )
            print(f"{path}  {time.perf_counter() - t0:.1f} s")
    except MPAError as exc:
        print(f"error: {exc}", file=sys.stderr)
        return 2
    return 0


if __name__ == "__main__":
    sys.exit(main())
