"""Re-planning every 0.1 s with the goal moved by up to 1 mm each time: does the class or the path jump?

For each query: generate, then repeatedly re-plan at t = 0.1 s of the current trajectory with the goal moved by a
uniform random vector of at most 1 mm per robot; compare the new motion's path with the rest of the previous one
(from 0.1 s): the homotopy class (``mpa.path_word``) and the largest distance between the two paths, both
parametrized by route travel (600 points, track graph distance, worst robot), relative to the goal's move.

The OMPL pipeline of the benchmark (RRTConnect, geodesic motions, simplified; ``bench.baselines.OmplPlanner``)
is run on the same sequence, re-seeded at every step as a long-running re-planner would be: at re-plan k it
solves (x_k, g_{k-1}) with seed k and (x_k, g_k) with seed k + 1, x_k the carts' rest point of our re-plan k, and
the two paths are compared the same way (class and largest distance, parametrized by route travel).

With ``--graph`` the same measurement runs on example layouts (``GRAPH_QUERIES``): the class is the sequence of
edges each cart visits, the distance the layout's graph distance; the goal moves by up to 1 mm along its edge.

Usage::

    python experiments/replan_stability.py [--replans 80] [--seed 0] [--no-ompl] [--graph]

Prints one line per query. Headless, no files written.
"""

from __future__ import annotations

import argparse
import sys
import time
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

from mpa import Lollipop
from mpa.geometry import densify_polyline
from mpa.homotopy import path_word
from trajopt import TrajectoryGenerator
from trajopt.testing import travel_curve

QUERIES = [((0.2, 0.5), (0.5, 0.2)), ((0.1, 0.6), (0.8, 0.3)), ((1.25, 1.75), (1.75, 1.25)), ((0.3, 1.2), (1.6, 0.4))]


def _by_travel(pts: np.ndarray, s: np.ndarray, n: int) -> np.ndarray:
    """Track positions ``pts`` (K, 2) with route coordinates ``s`` (K, 2) resampled at ``n`` equal steps of travel."""
    c = np.concatenate([[0.0], np.cumsum(np.max(np.abs(np.diff(s, axis=0)), axis=1))])
    u = np.linspace(0.0, c[-1], n)
    idx = np.clip(np.searchsorted(c, u, side="right") - 1, 0, len(c) - 1)
    return pts[idx]


def ompl_curve(track, result, n: int = 600) -> np.ndarray | None:  # type: ignore[no-untyped-def]
    """The OMPL path as ``n`` track positions equally spaced in route travel (None if unsolved)."""
    from bench.geometry import split_routes

    if not result.solved or result.simplified is None:
        return None
    pts, ss, offset = [], [], np.zeros(2)
    for seg in split_routes(result.simplified):
        dense = densify_polyline(seg.nodes, 1e-3)
        pts.append(np.stack([seg.routes[0].position(dense[:, 0]), seg.routes[1].position(dense[:, 1])], axis=1))
        ss.append(np.cumsum(np.vstack([offset[None, :], np.abs(np.diff(dense, axis=0))]), axis=0))
        offset = ss[-1][-1]
    if not pts:
        return None
    return _by_travel(np.vstack(pts), np.vstack(ss), n)


def compare_ompl(track, pairs, seed: int) -> str:  # type: ignore[no-untyped-def]
    """Class changes and path jumps of the OMPL pipeline re-seeded on the sequence ``pairs`` of (x_k, g_{k-1}, g_k)."""
    sys.path.insert(0, str(Path(__file__).resolve().parent))
    from bench.baselines import OmplPlanner

    planner = OmplPlanner(track, 0.05, budget=1.0, geodesic=True)
    changes = jumps = unsolved = 0
    ratios = []
    for k, (x, g0, g1) in enumerate(pairs):
        c0 = ompl_curve(track, planner.solve(x, g0, seed + 2 * k + 1))
        c1 = ompl_curve(track, planner.solve(x, g1, seed + 2 * k + 2))
        if c0 is None or c1 is None:
            unsolved += 1
            continue
        changes += path_word(track, c0) != path_word(track, c1)
        gap = max(track.distance(c0[:, 0], c1[:, 0]).max(), track.distance(c0[:, 1], c1[:, 1]).max())
        ratios.append(gap / max(np.abs(np.asarray(g1) - np.asarray(g0)).max(), 1e-12))
        jumps += ratios[-1] > 10
    if not ratios:
        return f"OMPL re-seeded: {len(pairs)} re-plans, none solved"
    return (
        f"OMPL re-seeded: {len(ratios)} re-plans ({unsolved} unsolved), class changes {changes}, path jumps > 10x "
        f"the goal move {jumps}, jump/move median {np.median(ratios):.2f} max {max(ratios):.2f}"
    )


#: Layout queries of ``--graph``: (layout file in examples/tracks, clearance, start, goal).
GRAPH_QUERIES = [
    ("y_junction.json", 0.5, ("left", "right"), ("right", "left")),
    ("passing_loop.json", 0.2, ("W", "E"), ("E", "W")),
    ("two_sidings.json", 0.05, ("north_end", "south_end"), ("south_end", "north_end")),
]


def graph_curve(traj, t0: float, n: int = 600):  # type: ignore[no-untyped-def]
    """A layout trajectory's path from ``t0``: per cart the edges visited in order (the class) and ``n`` positions
    ``(edges, offsets)``, each shape (n, 2), equally spaced in route travel."""
    from trajopt.path.planview import plan_view

    t = np.append(np.arange(t0, traj.motion_time, 1 / 2000.0), traj.motion_time)
    s, v, _, _ = traj.sampler(t)
    c = np.concatenate([[0.0], np.cumsum(np.max(np.abs(np.diff(s, axis=0)), axis=1))])
    idx = np.clip(np.searchsorted(c, np.linspace(0.0, c[-1], n), side="right") - 1, 0, len(c) - 1)
    e, o = plan_view(traj.plan).positions(s[idx], v[idx])
    word = tuple(tuple(x for k, x in enumerate(e[:, r].tolist()) if k == 0 or e[k - 1, r] != x) for r in (0, 1))
    return word, e, o


def main_graph(replans: int, seed: int) -> int:
    """Re-planning on the layouts of :data:`GRAPH_QUERIES`, measured as on the paper's lollipop (the class: the
    edges each cart visits; the jump: the largest graph distance between the old and new paths)."""
    from mpa import GraphTrack

    root = Path(__file__).resolve().parents[1] / "examples" / "tracks"
    rng = np.random.default_rng(seed)
    for name, clearance, start, goal in GRAPH_QUERIES:
        track = GraphTrack.from_json(str(root / name))
        gen = TrajectoryGenerator(track, clearance=clearance)
        cur = gen.generate(start, goal)
        pos = [track.position(x) for x in goal]
        g = np.array([p[1] for p in pos])
        lengths = np.array([track.lengths[p[0]] for p in pos])
        changes = jumps = 0
        ratios: list[float] = []
        t0 = time.perf_counter()
        for _ in range(replans):
            if cur.motion_time <= 0.1:
                break
            target = np.clip(g + rng.uniform(-1e-3, 1e-3, 2), 0.0, lengths)  # the goal stays on its edge
            move = float(np.max(np.abs(target - g)))
            new = gen.replan(cur, 0.1, [(int(p[0]), float(x)) for p, x in zip(pos, target)])
            w0, e0, o0 = graph_curve(cur, 0.1)
            w1, e1, o1 = graph_curve(new, 0.0)
            changes += w0 != w1
            gap = max(float(np.max(track.geometry.distance(e0[:, r], o0[:, r], e1[:, r], o1[:, r]))) for r in (0, 1))
            ratios.append(gap / max(move, 1e-12))
            jumps += ratios[-1] > 10
            cur, g = new, target
        print(
            f"{name} {start} -> {goal} (D = {clearance:g} m): {len(ratios)} re-plans, class changes {changes}, "
            f"path jumps > 10x the goal move {jumps}, jump/move median {np.median(ratios):.2f} "
            f"max {max(ratios):.2f}, {(time.perf_counter() - t0) / len(ratios) * 1e3:.0f} ms per re-plan"
        )
    return 0


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--replans", type=int, default=80)
    ap.add_argument("--seed", type=int, default=0)
    ap.add_argument("--no-ompl", action="store_true", help="skip the OMPL pipeline re-seeded on the same sequence")
    ap.add_argument("--graph", action="store_true", help="re-plan on the example layouts instead of the lollipop")
    args = ap.parse_args(argv)
    if args.graph:
        return main_graph(args.replans, args.seed)
    track = Lollipop(1.0, 1.0)
    gen = TrajectoryGenerator(track, clearance=0.05)
    rng = np.random.default_rng(args.seed)
    for start, goal in QUERIES:
        cur, g = gen.generate(start, goal), np.array(goal, dtype=float)
        changes = jumps = 0
        ratios = []
        pairs = []
        t0 = time.perf_counter()
        for _ in range(args.replans):
            if cur.motion_time <= 0.1:
                break
            move = rng.uniform(-1e-3, 1e-3, 2)
            new = gen.replan(cur, 0.1, g + move)
            pairs.append((tuple(new.plan.start), tuple(g), tuple(g + move)))
            rem, nw = travel_curve(cur, 0.1), travel_curve(new, 0.0)
            changes += path_word(track, rem) != path_word(track, nw)
            gap = max(track.distance(rem[:, 0], nw[:, 0]).max(), track.distance(rem[:, 1], nw[:, 1]).max())
            ratios.append(gap / np.abs(move).max())
            jumps += ratios[-1] > 10
            cur, g = new, g + move
        print(
            f"{start} -> {goal}: {len(ratios)} re-plans, class changes {changes}, path jumps > 10x the goal move "
            f"{jumps}, jump/move median {np.median(ratios):.2f} max {max(ratios):.2f}, "
            f"{(time.perf_counter() - t0) / len(ratios) * 1e3:.0f} ms per re-plan (with the checks)"
        )
        if not args.no_ompl:
            print("    " + compare_ompl(track, pairs, args.seed))
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
