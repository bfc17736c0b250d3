"""The page of ``mpa serve`` in headless Chromium: a screenshot for docs/gallery.md and the plan latency.

Starts ``mpa serve --port 0 --no-browser``, drags robot A's start along the paper's lollipop (every answer timed in
the page, from the request to the parsed answer), runs a trajectory, pauses its animation half-way and saves the
page. Prints the median and 90th percentile of the plan latency seen by the page.

    python experiments/web_screenshot.py --out docs/img/web_explorer.png
"""

from __future__ import annotations

import argparse
import os
import shutil
import signal
import statistics
import subprocess
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--out", default="docs/img/web_explorer.png", help="PNG of the page")
    ap.add_argument("--drags", type=int, default=6, help="drags of A's start along the track (each ~20 plans)")
    ap.add_argument("--chromium", default=os.environ.get("MPA_CHROMIUM") or shutil.which("chromium"))
    args = ap.parse_args(argv)
    from playwright.sync_api import sync_playwright

    env = {**os.environ, "PYTHONPATH": str(ROOT)}
    cmd = [sys.executable, "-m", "trajopt.cli", "serve", "--port", "0", "--no-browser"]
    with subprocess.Popen(cmd, stdout=subprocess.PIPE, text=True, env=env, cwd=ROOT) as proc:
        try:
            assert proc.stdout is not None
            url = proc.stdout.readline().split()[2]
            with sync_playwright() as p:
                browser = p.chromium.launch(executable_path=args.chromium, headless=True)
                page = browser.new_page(viewport={"width": 1240, "height": 1020})
                page.goto(url)
                page.wait_for_function("window.mpa && window.mpa.ready && window.mpa.plan !== null")
                settle = "!window.mpa.inflight && !window.mpa.pending"
                page.wait_for_function(settle)
                n0 = page.evaluate("window.mpa.latencies.length")
                for k in range(args.drags):
                    target = (0.05, 0.45)[k % 2]
                    x0, y0 = page.evaluate("window.mpa.markerScreen('a_start')")
                    x1, y1 = page.evaluate(f"window.mpa.screenOf({target})")
                    page.mouse.move(x0, y0)
                    page.mouse.down()
                    page.mouse.move(x1, y1, steps=20)
                    page.mouse.up()
                    page.wait_for_function(settle)
                lat = page.evaluate("window.mpa.latencies")[n0:]
                # the pictured query: A's start on the stick, B's on the loop (domain 3), goal (0.5, 0.2)
                x0, y0 = page.evaluate("window.mpa.markerScreen('b_start')")
                x1, y1 = page.evaluate("window.mpa.screenOf(1.62)")
                page.mouse.move(x0, y0)
                page.mouse.down()
                page.mouse.move(x1, y1, steps=10)
                page.mouse.up()
                page.wait_for_function(settle)
                page.click("#trajectory-btn")
                page.wait_for_function("window.mpa.traj !== null")
                page.wait_for_function("!window.mpa.playing")
                mid = page.evaluate("window.mpa.traj.t[window.mpa.traj.t.length - 1] / 2")
                page.fill("#time", str(mid))
                page.dispatch_event("#time", "input")
                page.wait_for_timeout(300)
                page.screenshot(path=args.out, full_page=True)
                browser.close()
        finally:
            proc.send_signal(signal.SIGINT)
            proc.wait(timeout=20)
    lat.sort()
    p90 = lat[int(0.9 * (len(lat) - 1))]
    print(f"plan latency in the page: median {statistics.median(lat):.1f} ms, p90 {p90:.1f} ms over {len(lat)} plans")
    print(f"wrote {args.out}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
