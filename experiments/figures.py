"""Reproduce every figure of Boughrira & Colman, "A Motion Planning Algorithm in a lollipop graph", from the library.

The paper's figures are missing from its source; this script redraws all 53 of them (one PNG per caption, numbered
in paper order) from :mod:`mpa`'s own objects: track embeddings, distances, the skeleton graph, the retraction H
and the planners' plans. Nothing is placed by hand where the library can compute it, so the pictures double as a
visual check of the implementation (several figures print a numeric check in their footer).

Usage::

    python experiments/figures.py --out figures/            # all figures and figures/index.md
    python experiments/figures.py --out figs --dpi 40 --only fig30 fig31

Headless (Agg).
"""

from __future__ import annotations

import argparse
import re
import sys
import time
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from pathlib import Path

import matplotlib

matplotlib.use("Agg")

import numpy as np
from matplotlib.figure import Figure
from mpl_toolkits.mplot3d import Axes3D  # noqa: F401  (registers the 3-D projection)

from mpa import Circle, Interval, Lollipop, NoMotionError, plan, retract, skeleton_of
from mpa.plans import Plan
from mpa.skeleton import LollipopSkeleton, SkeletonPoint
from trajopt.viz import drawing as dr
from trajopt.viz.plotting import save_figure

__all__ = ["FIGURES", "FigureSpec", "main", "queries"]

LOLLIPOP = Lollipop(1.0, 1.0)
CIRCLE = Circle(1.0)
INTERVAL = Interval(1.0)


@dataclass(frozen=True)
class FigureSpec:
    """One figure of the paper: number (paper order), file slug, the paper's caption, the function drawing it, and
    what the redrawn figure shows."""

    number: int
    slug: str
    caption: str
    make: Callable[[], Figure]
    shows: str = ""

    @property
    def filename(self) -> str:
        """``figNN_slug.png``."""
        return f"fig{self.number:02d}_{self.slug}.png"


# ---------------------------------------------------------------------------------------------------
# the queries of the sample runs (asserted to land in the intended domain)
def queries() -> dict[str, tuple[object, tuple[float, float], tuple[float, float], int]]:
    """The sample queries: name to (track, start, goal, expected domain).

    The circle examples and the lollipop domain runs start and end off the skeleton so that the preliminary and
    final steps are not empty; each retracts onto the canonical situation of its domain
    (docs/conventions.md, "Domains of continuity").
    """
    return {
        "circle_ex1": (CIRCLE, (0.3, 0.6), (0.6, 0.85), 2),
        "circle_ex2": (CIRCLE, (0.3, 0.6), (0.25, 0.1), 1),
        "lollipop_V1": (LOLLIPOP, (0.1, 0.4), (1.02, 0.7), 1),
        "lollipop_V2": (LOLLIPOP, (1.3, 1.7), (1.7, 1.3), 2),
        "lollipop_V3": (LOLLIPOP, (0.8, 1.2), (1.45, 1.85), 3),
    }


def query_plan(name: str) -> Plan:
    """The plan of a sample query; raises if it does not land in the intended domain."""
    track, s, g, dom = queries()[name]
    p = plan(track, s, g)  # type: ignore[arg-type]
    if p.domain != dom:
        raise AssertionError(f"query {name} {s} -> {g} is in domain {p.domain}, expected {dom}")
    return p


def _footer(fig: Figure, text: str) -> None:
    """A note under the figure (constrained layout keeps room for it)."""
    width = int(fig.get_figwidth() * 17)
    fig.supxlabel(
        "\n".join(_wrap(line, width) for line in text.split("\n")), fontsize=7.5, color="0.35", x=0.01, ha="left"
    )


# ---------------------------------------------------------------------------------------------------
# §2 preliminaries
def _curve_a(theta: np.ndarray) -> np.ndarray:
    return np.pi / 6 + np.abs(np.sin(theta + np.pi / 6) ** 5)


def _curve_b(theta: np.ndarray) -> np.ndarray:
    return 3 * np.cos(theta)


def fig_subspaces() -> Figure:
    fig, axes = dr.new_figure(2, width=4.0, height=4.0)
    th = np.linspace(0, 2 * np.pi, 1000)
    r = _curve_a(th)
    axes[0, 0].plot(r * np.cos(th), r * np.sin(th), color=dr.ROBOT_COLORS["A"], lw=2.5)
    axes[0, 0].set_title(r"$A:\ r = \pi/6 + |\sin(\theta+\pi/6)^5|,\ \theta\in[0,2\pi]$", fontsize=10)
    th2 = np.linspace(0, np.pi, 1000)
    r2 = _curve_b(th2)
    axes[0, 1].plot(r2 * np.cos(th2), r2 * np.sin(th2), color=dr.ROBOT_COLORS["B"], lw=2.5)
    axes[0, 1].set_title(r"$B:\ r = 3\cos\theta,\ \theta\in[0,\pi]$", fontsize=10)
    for ax in axes[0]:
        ax.set_aspect("equal")
        ax.axhline(0, color="0.8", lw=0.8, zorder=0)
        ax.axvline(0, color="0.8", lw=0.8, zorder=0)
        ax.grid(alpha=0.3)
    return fig


def _surface(ax: object, xyz: np.ndarray, colour_by: np.ndarray, cmap: str = "viridis", alpha: float = 0.9) -> None:
    colors = matplotlib.colormaps[cmap]((colour_by - colour_by.min()) / max(np.ptp(colour_by), 1e-12))
    ax.plot_surface(
        xyz[..., 0],
        xyz[..., 1],
        xyz[..., 2],
        facecolors=colors,
        rstride=1,
        cstride=1,  # type: ignore[attr-defined]
        linewidth=0.15,
        edgecolor=(0, 0, 0, 0.15),
        antialiased=True,
        shade=False,
        alpha=alpha,
    )


def _equal_3d(ax: object, xyz: np.ndarray, zoom: float = 1.0) -> None:
    pts = xyz.reshape(-1, 3)
    lo, hi = np.nanmin(pts, axis=0), np.nanmax(pts, axis=0)
    for setter, a, b in zip((ax.set_xlim, ax.set_ylim, ax.set_zlim), lo, hi):  # type: ignore[attr-defined]
        setter(a, b)
    ax.set_box_aspect(hi - lo, zoom=zoom)  # type: ignore[attr-defined]
    ax.set_axis_off()  # type: ignore[attr-defined]


def fig_product_space() -> Figure:
    fig = Figure(figsize=(5.5, 4.5), layout="constrained")
    ax = fig.add_subplot(projection="3d")
    th = np.linspace(0, 2 * np.pi, 121)
    ph = np.linspace(0, np.pi, 61)
    T, PH = np.meshgrid(th, ph, indexing="ij")
    ra = _curve_a(T)
    rb = _curve_b(PH)
    bx, by = rb * np.cos(PH), rb * np.sin(PH)  # B: circle of diameter 3 through 0, centre (1.5, 0)
    s = 0.3  # B scaled into the normal plane of A (radial direction and z): tube radius 0.45 < min r_A = π/6
    radial = ra + s * (bx - 1.5)
    xyz = np.stack([radial * np.cos(T), radial * np.sin(T), s * by], axis=-1)
    _surface(ax, xyz, T, "twilight")
    core = np.stack([_curve_a(th) * np.cos(th), _curve_a(th) * np.sin(th), 0 * th], axis=-1)
    ax.plot(*core.T, color="k", lw=0.8, ls=":")
    _equal_3d(ax, xyz)
    ax.view_init(elev=35, azim=-60)
    _footer(fig, "each point a ∈ A (colour) carries a copy of B in the plane spanned by the radial direction and z")
    return fig


def _torus(n: int = 97, m: int = 49, R: float = 2.0, r: float = 0.8) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    u = np.linspace(0, 2 * np.pi, n)
    v = np.linspace(0, 2 * np.pi, m)
    U, V = np.meshgrid(u, v, indexing="ij")
    xyz = np.stack([(R + r * np.cos(V)) * np.cos(U), (R + r * np.cos(V)) * np.sin(U), r * np.sin(V)], axis=-1)
    return xyz, U, V


def _torus_point(a: np.ndarray, b: np.ndarray, c: float = 1.0, R: float = 2.0, r: float = 0.8) -> np.ndarray:
    u, v = 2 * np.pi * np.asarray(a) / c, 2 * np.pi * np.asarray(b) / c
    return np.stack([(R + r * np.cos(v)) * np.cos(u), (R + r * np.cos(v)) * np.sin(u), r * np.sin(v)], axis=-1)


def fig_torus() -> Figure:
    fig = Figure(figsize=(5.5, 4.2), layout="constrained")
    ax = fig.add_subplot(projection="3d")
    xyz, _, V = _torus()
    ax.computed_zorder = False
    _surface(ax, xyz, V, "Blues", alpha=0.6)
    t = np.linspace(0, 1, 200)
    ax.plot(
        *_torus_point(t, 0 * t + 0.25).T, color=dr.ROBOT_COLORS["A"], lw=2.5, label="$S^1\\times\\{b\\}$", zorder=10
    )
    ax.plot(
        *_torus_point(0 * t + 0.9, t).T, color=dr.ROBOT_COLORS["B"], lw=2.5, label="$\\{a\\}\\times S^1$", zorder=10
    )
    _equal_3d(ax, xyz)
    ax.view_init(elev=40, azim=-60)
    ax.legend(loc="upper right", fontsize=9)
    return fig


# ---------------------------------------------------------------------------------------------------
# §3 one robot on the circle, on the interval
def _shortest_offset(a: float, b: np.ndarray | float, c: float) -> np.ndarray:
    """Signed shortest travel from a to b on a circle of circumference c (ties go ccw)."""
    return np.mod(np.asarray(b) - a + 0.5 * c, c) - 0.5 * c


def _one_robot_run(ax: object, track: Circle, a: float, b: float, delta: float, title: str) -> None:
    dr.draw_track(ax, track, ccw_arrow=False)  # type: ignore[arg-type]
    path = a + np.linspace(0, delta, 200)
    dr.draw_motion(ax, track, np.mod(path, track.loop), "A", lane=0.25, spread=0.0)  # type: ignore[arg-type]
    dr.draw_robot(ax, track, a, "A", label="a")  # type: ignore[arg-type]
    dr.draw_robot(ax, track, float(np.mod(b, track.loop)), "A", final=True, label="b")  # type: ignore[arg-type]
    ax.set_title(title, fontsize=10)  # type: ignore[attr-defined]


def fig_discontinuity_shortest() -> Figure:
    c = CIRCLE.loop
    a = 0.05
    fig, axes = dr.new_figure(3, width=3.6, height=3.6)
    eps = 0.03
    for ax, b in zip(axes[0, :2], (a + 0.5 * c - eps, a + 0.5 * c + eps)):
        delta = float(_shortest_offset(a, b, c))
        sign = "−" if b < a + 0.5 else "+"
        _one_robot_run(ax, CIRCLE, a, b, delta, f"b = antipode {sign} {eps:g}: travel {delta:+.2f}")
    ax = axes[0, 2]
    bs = np.linspace(0, c, 1001)
    off = _shortest_offset(a, bs, c)
    jump = np.flatnonzero(np.abs(np.diff(off)) > 0.5 * c)
    off[jump + 1] = np.nan
    ax.plot(bs, off, color=dr.ROBOT_COLORS["A"], lw=2)
    ax.axvline(a + 0.5 * c, color=dr.COLLISION_COLOR, ls="--", lw=1)
    ax.set_xlabel("final position b")
    ax.set_ylabel("signed travel of the robot (ccw > 0)")
    ax.set_title("the instruction jumps at the antipode of a", fontsize=10)
    ax.set_box_aspect(1)
    return fig


def fig_discontinuity_ccw() -> Figure:
    c = CIRCLE.loop
    a = 0.05
    fig, axes = dr.new_figure(3, width=3.6, height=3.6)
    eps = 0.03
    for ax, b in zip(axes[0, :2], (a - eps, a + eps)):
        delta = float(np.mod(b - a, c))
        _one_robot_run(ax, CIRCLE, a, b, delta, f"b = a {'−' if b < a else '+'} {eps:g}: travel {delta:+.2f}")
    ax = axes[0, 2]
    bs = np.linspace(0, c, 1001, endpoint=False)
    off = np.mod(bs - a, c)
    jump = np.flatnonzero(np.abs(np.diff(off)) > 0.5 * c)
    off[jump + 1] = np.nan
    ax.plot(bs, off, color=dr.ROBOT_COLORS["A"], lw=2)
    ax.axvline(a, color=dr.COLLISION_COLOR, ls="--", lw=1)
    ax.set_xlabel("final position b")
    ax.set_ylabel("ccw travel of the robot")
    ax.set_title("the instruction jumps at b = a", fontsize=10)
    ax.set_box_aspect(1)
    return fig


def fig_one_robot_interval() -> Figure:
    fig, axes = dr.new_figure(1, width=5.0, height=2.4)
    ax = axes[0, 0]
    dr.draw_track(ax, INTERVAL)
    a, b = 0.2, 0.75
    dr.draw_motion(ax, INTERVAL, np.linspace(a, b, 100), "A", lane=0.5, spread=0.0)
    dr.draw_robot(ax, INTERVAL, a, "A", label="a")
    dr.draw_robot(ax, INTERVAL, b, "A", final=True, label="b")
    ax.set_title('"go in straight line towards the final position": continuous on $I\\times I$', fontsize=10)
    ax.set_ylim(-0.25, 0.3)
    return fig


def fig_two_instructions_circle() -> Figure:
    c = CIRCLE.loop
    fig, axes = dr.new_figure(3, width=3.7, height=3.7)
    a = 0.1
    b1 = 0.35
    _one_robot_run(axes[0, 0], CIRCLE, a, b1, float(_shortest_offset(a, b1, c)), "not antipodal: shortest path")
    b2 = a + 0.5 * c
    _one_robot_run(axes[0, 1], CIRCLE, a, b2, 0.5 * c, "antipodal: counterclockwise")
    ax = axes[0, 2]
    g = np.linspace(0, c, 301)
    A, B = np.meshgrid(g, g)
    d = CIRCLE.distance(A, B)
    ax.contourf(g, g, (np.abs(d - 0.5 * c) < 0.04).astype(float), levels=[0.5, 1.5], colors=["#ffd9b3"])
    ax.contourf(g, g, (d >= 0.5 * c - 0.04).astype(float), levels=[-0.5, 0.5], colors=["#d6e9ff"], alpha=0.6)
    ax.plot([0, c], [0, c], color=dr.COLLISION_COLOR, lw=1.5)
    for sh in (0.5 * c, -0.5 * c):
        ax.plot([max(0, -sh), min(c, c - sh)], [max(0, sh), min(c, c + sh)], color="#ff7f0e", lw=1.5)
    ax.text(0.72, 0.45, "U (not antipodal):\nshortest path", ha="center", fontsize=8, color="#1f4e79")
    ax.text(0.22, 0.88, "near antipodal,\nin V (a ≠ b): ccw", ha="center", fontsize=8, color="#b35900")
    ax.text(0.62, 0.75, "Δ ∉ V", ha="center", fontsize=8, color=dr.COLLISION_COLOR, rotation=45)
    ax.set_xlabel("initial position a")
    ax.set_ylabel("final position b")
    ax.set_title("domains of continuity in $S^1\\times S^1$", fontsize=10)
    ax.set_aspect("equal")
    return fig


# ---------------------------------------------------------------------------------------------------
# §5.1 two robots on an interval
def _phys_and_flat(*, width: float = 4.2) -> tuple[Figure, object, object]:
    fig, axes = dr.new_figure(2, width=width, height=4.0)
    return fig, axes[0, 0], axes[0, 1]


def fig_interval_spaces() -> Figure:
    fig, ax_p, ax_f = _phys_and_flat()
    s = (0.25, 0.7)
    dr.draw_track(ax_p, INTERVAL)  # type: ignore[arg-type]
    dr.draw_robots(ax_p, INTERVAL, s)  # type: ignore[arg-type]
    ax_p.set_ylim(-0.3, 0.3)  # type: ignore[attr-defined]
    ax_p.set_title("physical space $I$", fontsize=10)  # type: ignore[attr-defined]
    dr.draw_flat_cspace(ax_f, INTERVAL)  # type: ignore[arg-type]
    dr.draw_state(ax_f, s, "(A, B)")  # type: ignore[arg-type]
    ax_f.set_title("configuration space $I\\times I-\\Delta$", fontsize=10)  # type: ignore[attr-defined]
    return fig


def fig_interval_same() -> Figure:
    fig, ax_p, ax_f = _phys_and_flat()
    s, g = (0.15, 0.5), (0.45, 0.9)
    p = plan(INTERVAL, s, g)
    dr.draw_track(ax_p, INTERVAL)  # type: ignore[arg-type]
    path = p.sample(300)
    dr.draw_motion(ax_p, INTERVAL, path[:, 0], "A", spread=0)  # type: ignore[arg-type]
    dr.draw_motion(ax_p, INTERVAL, path[:, 1], "B", spread=0)  # type: ignore[arg-type]
    dr.draw_robots(ax_p, INTERVAL, s)  # type: ignore[arg-type]
    dr.draw_robots(ax_p, INTERVAL, g, final=True, labels=("", ""))  # type: ignore[arg-type]
    ax_p.set_ylim(-0.3, 0.3)  # type: ignore[attr-defined]
    dr.draw_flat_cspace(ax_f, INTERVAL, components=True)  # type: ignore[arg-type]
    dr.draw_flat_path(ax_f, INTERVAL, path, color=dr.STEP_COLORS["main"])  # type: ignore[arg-type]
    dr.draw_state(ax_f, s, "$x_i$")  # type: ignore[arg-type]
    dr.draw_state(ax_f, g, "$x_f$", filled=False)  # type: ignore[arg-type]
    ax_f.set_title(f"same component: plan found (domain {p.domain})", fontsize=10)  # type: ignore[attr-defined]
    return fig


def fig_interval_different() -> Figure:
    fig, ax_p, ax_f = _phys_and_flat()
    s, g = (0.2, 0.6), (0.8, 0.35)
    try:
        plan(INTERVAL, s, g)
        msg = "unexpected: a plan was found"
    except NoMotionError as exc:
        msg = str(exc)
    dr.draw_track(ax_p, INTERVAL)  # type: ignore[arg-type]
    dr.draw_robots(ax_p, INTERVAL, s, labels=("$A_i$", "$B_i$"))  # type: ignore[arg-type]
    dr.draw_robots(ax_p, INTERVAL, g, final=True, labels=("$A_f$", "$B_f$"))  # type: ignore[arg-type]
    ax_p.set_ylim(-0.3, 0.3)  # type: ignore[attr-defined]
    ax_p.set_title("the robots cannot swap on $I$", fontsize=10)  # type: ignore[attr-defined]
    dr.draw_flat_cspace(ax_f, INTERVAL, components=True)  # type: ignore[arg-type]
    dr.draw_state(ax_f, s, "$x_i$")  # type: ignore[arg-type]
    dr.draw_state(ax_f, g, "$x_f$", filled=False)  # type: ignore[arg-type]
    ax_f.set_title("different components: no path", fontsize=10)  # type: ignore[attr-defined]
    _footer(fig, "mpa.plan: " + _wrap(msg, 120))
    return fig


def _wrap(text: str, width: int) -> str:
    words, lines, cur = text.split(), [], ""
    for w in words:
        if len(cur) + len(w) + 1 > width:
            lines.append(cur)
            cur = w
        else:
            cur = f"{cur} {w}".strip()
    lines.append(cur)
    return "\n".join(lines)


# ---------------------------------------------------------------------------------------------------
# §5.2 two robots on a circle
def fig_circle_spaces() -> Figure:
    fig = Figure(figsize=(12.5, 4.0), layout="constrained")
    ax_p = fig.add_subplot(1, 3, 1)
    ax_t = fig.add_subplot(1, 3, 2, projection="3d")
    ax_f = fig.add_subplot(1, 3, 3)
    s, g = (0.1, 0.35), (0.55, 0.8)
    dr.draw_track(ax_p, CIRCLE)
    dr.draw_robots(ax_p, CIRCLE, s, labels=("$A_i$", "$B_i$"))
    dr.draw_robots(ax_p, CIRCLE, g, final=True, labels=("$A_f$", "$B_f$"))
    ax_p.set_title("physical space $S^1$", fontsize=10)
    xyz, _, V = _torus()
    ax_t.computed_zorder = False
    _surface(ax_t, xyz, V, "Blues", alpha=0.45)
    t = np.linspace(0, 1, 300)
    ax_t.plot(*_torus_point(t, t).T, color=dr.COLLISION_COLOR, lw=2.0, label="diagonal Δ", zorder=10)
    for st, m in ((s, "o"), (g, "s")):
        ax_t.plot(*_torus_point(np.array([st[0]]), np.array([st[1]])).T, m, color="k", ms=6, zorder=11)
    _equal_3d(ax_t, xyz)
    ax_t.view_init(elev=40, azim=-60)
    ax_t.legend(loc="upper right", fontsize=8)
    ax_t.set_title("$T-\\Delta$", fontsize=10)
    dr.draw_flat_cspace(ax_f, CIRCLE)
    dr.draw_state(ax_f, s, "$x_i$")
    dr.draw_state(ax_f, g, "$x_f$", filled=False)
    ax_f.set_title("flat torus (opposite sides identified)", fontsize=10)
    return fig


def fig_antipodal_circle() -> Figure:
    fig, ax_p, ax_f = _phys_and_flat()
    sk = skeleton_of(CIRCLE)
    dr.draw_flat_cspace(ax_f, CIRCLE, level_h=True)  # type: ignore[arg-type]
    samples = dr.draw_skeleton(ax_f, sk)  # type: ignore[arg-type]
    ax_f.set_title("antipodal circle $\\mathcal{A}$ in the flat torus", fontsize=10)  # type: ignore[attr-defined]
    # a short ccw run along the antipodal circle, in both pictures
    from mpa.skeleton import CircleSkeleton

    assert isinstance(sk, CircleSkeleton)
    phis = np.linspace(0.1, 0.3, 60)
    run = np.array([sk.state(sk.point_of_phi(float(f))) for f in phis])
    dr.draw_track(ax_p, CIRCLE)  # type: ignore[arg-type]
    dr.draw_motion(ax_p, CIRCLE, run[:, 0], "A", spread=0)  # type: ignore[arg-type]
    dr.draw_motion(ax_p, CIRCLE, run[:, 1], "B", spread=0)  # type: ignore[arg-type]
    dr.draw_robots(ax_p, CIRCLE, run[0])  # type: ignore[arg-type]
    ax_p.set_title("ccw on $\\mathcal{A}$: both robots move ccw, antipodal", fontsize=10)  # type: ignore[attr-defined]
    err = max(float(np.max(np.abs(CIRCLE.distance(s[:, 0], s[:, 1]) - CIRCLE.half))) for s in samples.values())
    _footer(
        fig,
        f"skeleton sampled from mpa.CircleSkeleton.state; max |d − c/2| on it = {err:.1e} "
        "(dotted: level set d = c/2 from Circle.distance)",
    )
    return fig


def fig_circle_antipodal_states() -> Figure:
    p = query_plan("circle_ex1")
    fig, axes = dr.new_figure(2, width=4.4, height=4.2)
    dr.draw_plan_step(axes[0], p, dr.StepStyle(step=None))
    axes[0, 1].set_title("$x_i' = H_1(x_i)$, $x_f' = H_1(x_f)$: horizontal traces", fontsize=10)
    return fig


def fig_circle_steps_in_x() -> Figure:
    p = query_plan("circle_ex2")
    fig, axes = dr.new_figure(1, width=5.0, height=4.6)
    ax = axes[0, 0]
    dr.draw_flat_cspace(ax, CIRCLE)
    dr.draw_skeleton(ax, p.skeleton)
    for st in p.steps:
        if st.u_end > st.u_start:
            seg = p.path(np.linspace(st.u_start, st.u_end, 400))
            dr.draw_flat_path(ax, CIRCLE, seg, color=dr.STEP_COLORS[st.name], lw=2.6, arrows=(0.5, 1.0))
            ax.plot([], [], color=dr.STEP_COLORS[st.name], lw=2.6, label=f"{st.name} step")
    dr.draw_state(ax, p.start, "$x_i$")
    dr.draw_state(ax, p.skeleton_start, "$x_i'$", color=dr.STEP_COLORS["preliminary"])
    dr.draw_state(ax, p.skeleton_goal, "$x_f'$", color=dr.STEP_COLORS["final"], filled=False)
    dr.draw_state(ax, p.goal, "$x_f$", filled=False)
    ax.legend(loc="center right", fontsize=8)
    ax.set_title(f"the three steps in X (domain {p.domain})", fontsize=10)
    return fig


def fig_swapped_physical() -> Figure:
    fig, axes = dr.new_figure(2, width=3.8, height=3.8)
    s = (0.1, 0.3)
    g = (s[1], s[0])
    dr.draw_track(axes[0, 0], CIRCLE)
    dr.draw_robots(axes[0, 0], CIRCLE, s, labels=("$A_i$", "$B_i$"))
    axes[0, 0].set_title("initial positions", fontsize=10)
    dr.draw_track(axes[0, 1], CIRCLE)
    dr.draw_robots(axes[0, 1], CIRCLE, g, final=True, labels=("$A_f$", "$B_f$"))
    axes[0, 1].set_title("final positions: $A_f = B_i$, $B_f = A_i$", fontsize=10)
    return fig


def fig_swapped_config() -> Figure:
    fig, axes = dr.new_figure(2, width=4.2, height=4.2)
    sk = skeleton_of(CIRCLE)
    s = np.array([0.35, 0.15])
    for ax in axes[0]:
        dr.draw_flat_cspace(ax, CIRCLE)
    dr.draw_state(axes[0, 0], s, "$x_i$")
    dr.draw_state(axes[0, 0], s[::-1], "$x_f$", filled=False)
    axes[0, 0].plot(*np.array([s, s[::-1]]).T, color="0.5", ls=":", lw=1)
    axes[0, 0].set_title("swapped states: symmetric about Δ", fontsize=10)
    dr.draw_skeleton(axes[0, 1], sk)
    xi = np.array([0.3, 0.8])
    dr.draw_state(axes[0, 1], xi, "$x_i$")
    dr.draw_state(axes[0, 1], xi[::-1], "$x_f$", filled=False)
    axes[0, 1].set_title("on $\\mathcal{A}$: swapped = antipodal on $\\mathcal{A}$", fontsize=10)
    return fig


def _run_figure(name: str, step: str | None, title: str) -> Callable[[], Figure]:
    def make() -> Figure:
        p = query_plan(name)
        wide = isinstance(p.track, Lollipop)
        fig = Figure(figsize=(11.0 if wide else 8.8, 4.4), layout="constrained")
        axes = fig.subplots(1, 2, squeeze=False, width_ratios=[1.5, 1] if wide else [1, 1])
        dr.draw_plan_step(axes[0], p, dr.StepStyle(step=step))
        axes[0, 0].set_title(title, fontsize=10)
        what = "query" if step is None else f"{step} step"
        axes[0, 1].set_title(f"{what} in the configuration space (domain {p.domain})", fontsize=10)
        desc = next(s.description for s in p.steps if s.name == step) if step else p.rule
        _footer(fig, f"start ({p.start[0]:g}, {p.start[1]:g}) → goal ({p.goal[0]:g}, {p.goal[1]:g}); {what}: {desc}")
        return fig

    return make


# ---------------------------------------------------------------------------------------------------
# §6 the lollipop
def fig_generalized_lollipop() -> Figure:
    n, g = 9, 5
    fig, axes = dr.new_figure(1, width=6.0, height=3.0)
    ax = axes[0, 0]
    path_x = np.arange(n - g) * 1.0
    R = 1.0
    cx = path_x[-1] + 1.0 + R
    ang = np.pi + np.arange(g) * 2 * np.pi / g
    cyc = np.stack([cx + R * np.cos(ang), R * np.sin(ang)], axis=-1)
    ax.plot(np.append(path_x, cyc[0, 0]), np.zeros(n - g + 1), color=dr.TRACK_COLOR, lw=2)
    ax.plot(*np.vstack([cyc, cyc[:1]]).T, color=dr.TRACK_COLOR, lw=2)
    ax.plot(path_x, 0 * path_x, "o", color="k", ms=7)
    ax.plot(*cyc.T, "o", color="k", ms=7)
    for i, x in enumerate(path_x):
        ax.annotate(
            str(i + 1) if i < min(3, n - g - 1) else "", (x, 0), xytext=(0, 8), textcoords="offset points", ha="center"
        )
    ax.annotate("$n-g$", (path_x[-1], 0), xytext=(0, 8), textcoords="offset points", ha="center")
    for i, p in enumerate(cyc):
        ax.annotate(
            str(i + 1) if i < 3 else ("$g$" if i == g - 1 else ""),
            p,
            xytext=(10, 0),
            textcoords="offset points",
            va="center",
        )
    ax.set_aspect("equal")
    ax.axis("off")
    ax.set_title(f"$C_{{n,g}}$ with n = {n}, g = {g}: a path of n − g vertices, a g-cycle appended", fontsize=10)
    _footer(fig, "as a metric graph every C(n,g) is a lollipop track: stick ℓ = n − g edges, loop c = g edges")
    return fig


def fig_lollipop_graph() -> Figure:
    fig, axes = dr.new_figure(1, width=5.0, height=3.0)
    ax = axes[0, 0]
    dr.draw_track(ax, LOLLIPOP, labels=False, ccw_arrow=True)
    gr = LOLLIPOP.as_graph()
    for v, p in (("F", 0.0), ("P", LOLLIPOP.stick)):
        xy = LOLLIPOP.embed(p)
        ax.annotate(f"{gr.vertices.index(v) + 1}", xy, xytext=(-6, 8), textcoords="offset points", fontsize=12)
    ax.set_title(
        "$L = C_{2,1}$: vertices 1 (free end) and 2 (pole P); edges "
        + ", ".join(f"{e.name} ({e.length:g})" for e in gr.edges),
        fontsize=9,
    )
    return fig


def _lollipop_tube(a: np.ndarray, b: np.ndarray, track: Lollipop = LOLLIPOP) -> np.ndarray:
    """A 3-D picture of L × L: A's track as a core curve, a copy of B's track in a plane across it at every point.

    Core: the loop a circle of radius 1, the stick radial from P (outwards). Frame across the core: the horizontal
    direction ``m`` (radial turned by 45°, continuous at P) and z. Fibre: B's loop an ellipse, B's stick upwards.
    """
    ell, c = track.stick, track.loop
    k = 2 * np.pi / c  # loop coordinate to radians; stick drawn at half its metric length
    beta = np.pi / 4
    th_a = np.clip(a - ell, 0, None) * k
    core_loop = np.stack([np.cos(th_a), np.sin(th_a)], axis=-1)
    x_a = np.clip(ell - a, 0, None) * 0.5 * k / (2 * np.pi) * 2.0
    core = np.where((a < ell)[..., None], np.stack([1 + x_a, 0 * x_a], axis=-1), core_loop)
    alpha = np.where(a < ell, 0.0, th_a)
    m = np.stack([np.cos(alpha + beta), np.sin(alpha + beta)], axis=-1)
    th_b = np.clip(b - ell, 0, None) * k
    fx = np.where(b < ell, 0.0, 0.3 * np.sin(th_b))
    fz = np.where(b < ell, 0.3 + np.clip(ell - b, 0, None) * 0.7, 0.3 * np.cos(th_b))
    xy = core + fx[..., None] * m
    return np.concatenate([xy, fz[..., None]], axis=-1)


def fig_lollipop_cspace() -> Figure:
    fig = Figure(figsize=(11.0, 4.8), layout="constrained")
    ax3 = fig.add_subplot(1, 2, 1, projection="3d")
    ax_f = fig.add_subplot(1, 2, 2)
    tr = LOLLIPOP
    ell, c = tr.stick, tr.loop
    pieces = {
        "stick × stick": (np.linspace(0, ell, 25), np.linspace(0, ell, 25), "#c7e9c0"),
        "stick × loop": (np.linspace(0, ell, 25), np.linspace(ell, ell + c, 73), "#fdd0a2"),
        "loop × stick": (np.linspace(ell, ell + c, 73), np.linspace(0, ell, 25), "#c6dbef"),
        "loop × loop": (np.linspace(ell, ell + c, 73), np.linspace(ell, ell + c, 73), "#dadaeb"),
    }
    allxyz = []
    for name, (ga, gb, col) in pieces.items():
        A, B = np.meshgrid(ga, gb, indexing="ij")
        xyz = _lollipop_tube(A, B)
        allxyz.append(xyz.reshape(-1, 3))
        ax3.plot_surface(
            *np.moveaxis(xyz, -1, 0),
            color=col,
            alpha=0.7,
            linewidth=0.1,
            edgecolor=(0, 0, 0, 0.12),
            shade=True,
            rstride=2,
            cstride=2,
        )
        ax3.plot([], [], color=col, lw=6, label=name)
    t = np.linspace(0, ell + c, 600)
    diag = _lollipop_tube(t, t)
    ax3.plot(*diag.T, color=dr.COLLISION_COLOR, lw=2.0, label="diagonal Δ (removed)")
    sk = skeleton_of(tr)
    for e, st in dr.sample_skeleton(sk, 120).items():
        xyz = _lollipop_tube(st[:, 0], st[:, 1])
        ax3.plot(*xyz.T, color=dr.BLOCK_COLORS[dr.block_of_edge(sk, e)], lw=2.0)
    ax3.plot([], [], color="k", lw=2, label="skeleton S (colours as right)")
    _equal_3d(ax3, np.vstack(allxyz), zoom=1.35)
    ax3.view_init(elev=38, azim=-70)
    # the legend goes below the 3-D axes: inside them the surface is drawn over it
    fig.legend(*ax3.get_legend_handles_labels(), loc="outside lower left", fontsize=8, ncols=3, frameon=False)
    ax3.set_title("$X = L\\times L-\\Delta$", fontsize=10)
    dr.draw_flat_cspace(ax_f, tr, quadrant_labels=True)
    dr.draw_skeleton(ax_f, sk)
    ax_f.set_title("flat representation", fontsize=10)
    return fig


def fig_physical_states() -> Figure:
    tr = LOLLIPOP
    states = [(0.2, 0.55), (0.7, 1.3), (1.35, 1.8), (1.6, 0.4)]
    names = ["1", "2", "3", "4"]
    fig = Figure(figsize=(12.0, 4.6), layout="constrained")
    gs = fig.add_gridspec(2, 4, width_ratios=[1, 1, 1.9, 0.01])
    ax_f = fig.add_subplot(gs[:, 2])
    dr.draw_flat_cspace(ax_f, tr, quadrant_labels=True)
    for i, (st, nm) in enumerate(zip(states, names)):
        ax = fig.add_subplot(gs[i // 2, i % 2])
        dr.draw_track(ax, tr, labels=False, ccw_arrow=False)
        dr.draw_robots(ax, tr, st)
        ax.set_title(f"position {nm}: A = {st[0]:g}, B = {st[1]:g}", fontsize=9)
        dr.draw_state(ax_f, st, nm)
    ax_f.set_title("their states in the flat configuration space", fontsize=10)
    return fig


def fig_two_positions_skeleton() -> Figure:
    tr = LOLLIPOP
    sk = skeleton_of(tr)
    pts = [SkeletonPoint("I1", 0.2), SkeletonPoint("S2a", 0.3)]
    fig = Figure(figsize=(11.0, 4.6), layout="constrained")
    gs = fig.add_gridspec(2, 2, width_ratios=[1, 1.5])
    ax_f = fig.add_subplot(gs[:, 1])
    dr.draw_flat_cspace(ax_f, tr, level_h=True)
    dr.draw_skeleton(ax_f, sk)
    for i, pt in enumerate(pts):
        st = sk.state(pt)  # type: ignore[attr-defined]
        ax = fig.add_subplot(gs[i, 0])
        dr.draw_track(ax, tr, labels=False)
        d = dr.draw_track_geodesic(ax, tr, float(st[0]), float(st[1]))
        dr.draw_robots(ax, tr, st)
        ax.set_title(f"({st[0]:.2f}, {st[1]:.2f}) on edge {pt.edge}: d(A, B) = {d:.3f}", fontsize=9)
        dr.draw_state(ax_f, st, f"{i + 1}")
    ax_f.set_title("skeleton S = {d = h} (dotted: the level set from Lollipop.distance)", fontsize=9)
    return fig


def fig_homotopy_traces() -> Figure:
    tr = LOLLIPOP
    fig, axes = dr.new_figure(1, width=7.0, height=7.0)
    ax = axes[0, 0]
    dr.draw_flat_cspace(ax, tr)
    starts, ends = dr.draw_traces(ax, tr, n=16, steps=41)
    dr.draw_skeleton(ax, skeleton_of(tr), lw=2.4, alpha=0.85)
    ax.plot(ends[:, 0], ends[:, 1], "o", ms=2.5, color="k", zorder=6)
    err = float(np.max(np.abs(tr.distance(ends[:, 0], ends[:, 1]) - tr.half)))
    # the skeleton is fixed pointwise
    sk_pts = np.vstack(list(dr.sample_skeleton(skeleton_of(tr), 60).values()))
    fix = float(np.max(np.abs(retract(tr, sk_pts) - sk_pts)))
    ax.set_title("traces t ↦ H(x, t) of mpa.retract from a grid of states", fontsize=10)
    _footer(fig, f"{len(starts)} traces; max |d(H(x,1)) − h| = {err:.1e}; max |H(s,1) − s| on the skeleton = {fix:.1e}")
    return fig


def fig_skeleton_flat() -> Figure:
    tr = LOLLIPOP
    sk = skeleton_of(tr)
    fig, axes = dr.new_figure(1, width=6.5, height=6.5)
    ax = axes[0, 0]
    dr.draw_flat_cspace(ax, tr, level_h=True)
    samples = dr.draw_skeleton(ax, sk, lw=3.2)
    err = max(float(np.max(np.abs(tr.distance(s[:, 0], s[:, 1]) - tr.half))) for s in samples.values())
    b0, b1 = sk.betti
    ax.set_title("the skeleton S: $I_1$, $S_1$, $S_2$, $S_3$, $I_2$ with ccw orientations", fontsize=10)
    _footer(
        fig,
        f"edges of LollipopSkeleton.graph sampled via state(SkeletonPoint(edge, t)); max |d − h| = {err:.1e}; "
        f"graph Betti numbers b0 = {b0}, b1 = {b1}",
    )
    return fig


def fig_wedge() -> Figure:
    sk = skeleton_of(LOLLIPOP)
    assert isinstance(sk, LollipopSkeleton)
    tree = ["I1", "I2", "S1a", "S2a", "S3b"]  # the intervals and the lower half of each circle
    fig, axes = dr.new_figure(2, width=5.2, height=3.0)
    dr.draw_chain(axes[0, 0], sk, dim_edges=tree, vertex_names=False)
    axes[0, 0].set_title("contract the intervals and the lower arcs (dashed)", fontsize=10)
    ax = axes[0, 1]
    loops = [e for e in sk.graph.edges if e.name not in tree]
    for i, e in enumerate(loops):
        ang0 = np.pi / 2 + i * 2 * np.pi / len(loops)
        th = np.linspace(-np.pi / 6, np.pi / 6, 200)  # one petal of the rose r = cos 3θ, traversed ccw
        r = np.cos(3 * th)
        xy = np.stack([r * np.cos(th + ang0), r * np.sin(th + ang0)], axis=-1)
        col = dr.BLOCK_COLORS[dr.block_of_edge(sk, e.name)]
        ax.plot(*xy.T, color=col, lw=3)
        dr.arrow_along(ax, xy, frac=0.5, color=col, size=15)
        ax.text(
            1.2 * np.cos(ang0),
            1.2 * np.sin(ang0),
            f"${e.name[0]}_{e.name[1]}$",
            color=col,
            ha="center",
            va="center",
            fontsize=13,
        )
    ax.plot(0, 0, "o", color="k", ms=6)
    ax.set_aspect("equal")
    ax.axis("off")
    ax.set_ylim(-1.4, 1.45)  # room for the petal labels below the title
    _, b1 = sk.betti
    ax.set_title(f"wedge of {len(loops)} circles (b1 of S = {b1})", fontsize=10)
    return fig


def fig_distances() -> Figure:
    tr = LOLLIPOP
    cases = [(0.2, 0.7), (0.6, 1.3), (0.6, 1.8), (1.15, 1.8), (1.3, 1.45)]
    fig, axes = dr.new_figure(len(cases), width=2.9, height=2.6)
    for ax, (a, b) in zip(axes[0], cases):
        dr.draw_track(ax, tr, labels=False, ccw_arrow=False)
        d = dr.draw_track_geodesic(ax, tr, a, b)
        dr.draw_robots(ax, tr, (a, b))
        ax.set_title(f"A = {a:g}, B = {b:g}: d = {d:.2f}", fontsize=9)
    _footer(fig, "green: the shortest path, found as {r : d(A, r) + d(r, B) = d(A, B)} with Lollipop.distance")
    return fig


def fig_generalized_antipodal() -> Figure:
    tr = LOLLIPOP
    sk = skeleton_of(tr)
    pts = [
        SkeletonPoint("I1", 0.25),
        SkeletonPoint("S1a", 0.2),
        SkeletonPoint("S2a", 0.15),
        SkeletonPoint("S3b", 0.35),
        SkeletonPoint("I2", 0.1),
    ]
    fig, axes = dr.new_figure(len(pts), width=2.9, height=2.6)
    for ax, pt in zip(axes[0], pts):
        st = sk.state(pt)  # type: ignore[attr-defined]
        dr.draw_track(ax, tr, labels=False, ccw_arrow=False)
        d = dr.draw_track_geodesic(ax, tr, float(st[0]), float(st[1]))
        dr.draw_robots(ax, tr, st)
        blk = dr.block_of_edge(sk, pt.edge)
        ax.set_title(f"in ${blk[0]}_{blk[1]}$: d(A, B) = {d:.3f} = h", fontsize=9, color=dr.BLOCK_COLORS[blk])
    return fig


def fig_chain() -> Figure:
    sk = skeleton_of(LOLLIPOP)
    assert isinstance(sk, LollipopSkeleton)
    fig, axes = dr.new_figure(1, width=9.0, height=2.8)
    dr.draw_chain(axes[0, 0], sk)
    axes[0, 0].set_title(
        "the skeleton graph (LollipopSkeleton.graph): arrows = ccw orientation of each circle", fontsize=10
    )
    return fig


def fig_ccw_directions() -> Figure:
    tr = LOLLIPOP
    sk = skeleton_of(tr)
    assert isinstance(sk, LollipopSkeleton)
    fig = Figure(figsize=(11.0, 8.0), layout="constrained")
    gs = fig.add_gridspec(4, 2, height_ratios=[1.0, 1, 1, 1], width_ratios=[1.15, 1])
    ax_c = fig.add_subplot(gs[0, :])
    dr.draw_chain(ax_c, sk, vertex_names=False)
    ax_f = fig.add_subplot(gs[1:, 0])
    dr.draw_flat_cspace(ax_f, tr)
    dr.draw_skeleton(ax_f, sk)
    ax_f.set_title("ccw arrows in the flat space", fontsize=10)
    for j in (1, 2, 3):
        ax = fig.add_subplot(gs[j, 1])
        phis = np.linspace(0.05, 0.45, 60) * tr.loop
        run = np.array([sk.state(sk.circle_point(j, float(f))) for f in phis])
        dr.draw_track(ax, tr, labels=False, ccw_arrow=False)
        dr.draw_motion(ax, tr, run[:, 0], "A", spread=0)
        dr.draw_motion(ax, tr, run[:, 1], "B", spread=0)
        dr.draw_robots(ax, tr, run[0])
        ax.set_title(
            f"ccw in $S_{j}$: φ from {phis[0]:.2f} to {phis[-1]:.2f}", fontsize=10, color=dr.BLOCK_COLORS[f"S{j}"]
        )
    return fig


def _swapped_pairs(sk: LollipopSkeleton) -> list[tuple[int, np.ndarray, np.ndarray]]:
    """A pair of generalized swapped states in each circle: antipodal points of S_j (φ and φ + h)."""
    h = sk.half
    out = []
    for j, phi in ((1, 0.3 * h), (2, 0.5 * h), (3, 0.4 * h)):
        out.append((j, sk.state(sk.circle_point(j, phi)), sk.state(sk.circle_point(j, phi + h))))
    return out


def fig_swapped_generalized_config() -> Figure:
    tr = LOLLIPOP
    sk = skeleton_of(tr)
    assert isinstance(sk, LollipopSkeleton)
    fig, axes = dr.new_figure(1, width=6.5, height=6.5)
    ax = axes[0, 0]
    dr.draw_flat_cspace(ax, tr)
    dr.draw_skeleton(ax, sk, alpha=0.6)
    lines = []
    for j, xi, xf in _swapped_pairs(sk):
        col = dr.BLOCK_COLORS[f"S{j}"]
        dr.draw_state(ax, xi, f"$x_i$ ($S_{j}$)", color=col)
        dr.draw_state(ax, xf, f"$x_f$ ($S_{j}$)", color=col, filled=False)
        p = plan(tr, xi, xf)
        dr.draw_flat_path(ax, tr, p.sample(600), color=col, lw=1.2, ls="--", arrows=(0.5,))
        lines.append(f"S{j}: ({xi[0]:.3g}, {xi[1]:.3g}) → ({xf[0]:.3g}, {xf[1]:.3g}) domain {p.domain}")
    ax.set_title("generalized swapped states: antipodal in $S_j$ (dashed: the planned ccw run)", fontsize=10)
    _footer(fig, "; ".join(lines))
    return fig


def fig_swapped_generalized_physical() -> Figure:
    tr = LOLLIPOP
    sk = skeleton_of(tr)
    assert isinstance(sk, LollipopSkeleton)
    fig, axes = dr.new_figure(3, width=3.6, height=3.0)
    for ax, (j, xi, xf) in zip(axes[0], _swapped_pairs(sk)):
        dr.draw_track(ax, tr, labels=False)
        dr.draw_robots(ax, tr, xi, labels=("$A_i$", "$B_i$"))
        dr.draw_robots(ax, tr, xf, final=True, labels=("$A_f$", "$B_f$"))
        ax.set_title(f"in $S_{j}$", fontsize=11, color=dr.BLOCK_COLORS[f"S{j}"])
    return fig


def fig_extended_interval() -> Figure:
    fig, axes = dr.new_figure(1, width=4.5, height=2.8)
    ax = axes[0, 0]
    dr.draw_track(ax, LOLLIPOP, highlight=(0.0, LOLLIPOP.stick))
    ax.set_title("extended interval $\\tilde I = I\\cup\\{P\\}$ (green)", fontsize=10)
    return fig


def _prelim_case(ax_p: object, ax_f: object, tr: Lollipop, state: tuple[float, float]) -> None:
    ts = np.linspace(0, 1, 200)
    trace = retract(tr, np.repeat([state], len(ts), axis=0), ts)
    dr.draw_track(ax_p, tr, labels=False)  # type: ignore[arg-type]
    dr.draw_motion(ax_p, tr, trace[:, 0], "A", spread=0)  # type: ignore[arg-type]
    dr.draw_motion(ax_p, tr, trace[:, 1], "B", spread=0)  # type: ignore[arg-type]
    dr.draw_robots(ax_p, tr, trace[-1], final=True, labels=("", ""))  # type: ignore[arg-type]
    dr.draw_robots(ax_p, tr, state)  # type: ignore[arg-type]  (on top: a robot that waits shows filled)
    d0, d1 = float(tr.distance(*state)), float(tr.distance(*trace[-1]))
    ax_p.set_title(f"({state[0]:g}, {state[1]:g}): d = {d0:.2f} → {d1:.2f}", fontsize=9)  # type: ignore[attr-defined]
    dr.draw_flat_path(ax_f, tr, trace, color=dr.STEP_COLORS["preliminary"], lw=2.2, arrows=(1.0,))  # type: ignore[arg-type]
    dr.draw_state(ax_f, state, None, size=5)  # type: ignore[arg-type]


def fig_prelim_more() -> Figure:
    tr = LOLLIPOP
    cases = [(0.05, 0.85), (0.2, 1.5)]
    fig = Figure(figsize=(12.0, 3.8), layout="constrained")
    axes = fig.subplots(1, 3, squeeze=False, width_ratios=[1.5, 1.5, 1])
    for ax in axes[0, 2:]:
        dr.draw_flat_cspace(ax, tr, axis_labels=False)
        dr.draw_skeleton(ax, skeleton_of(tr), labels=False, alpha=0.6)
    for ax, st in zip(axes[0, :2], cases):
        _prelim_case(ax, axes[0, 2], tr, st)
    fig.suptitle(
        "d > h: the robot nearer the free end moves towards the other, which waits (traces of mpa.retract)", fontsize=10
    )
    return fig


def fig_prelim_less() -> Figure:
    tr = LOLLIPOP
    cases = [(0.1, 0.4), (0.85, 1.1), (1.3, 1.6)]
    fig = Figure(figsize=(15.0, 3.8), layout="constrained")
    axes = fig.subplots(1, 4, squeeze=False, width_ratios=[1.5, 1.5, 1.5, 1])
    dr.draw_flat_cspace(axes[0, 3], tr, axis_labels=False)
    dr.draw_skeleton(axes[0, 3], skeleton_of(tr), labels=False, alpha=0.6)
    for ax, st in zip(axes[0, :3], cases):
        _prelim_case(ax, axes[0, 3], tr, st)
    fig.suptitle(
        "d < h: both robots move apart (staying on the loop if on it) until d = h (traces of mpa.retract)", fontsize=10
    )
    return fig


# ---------------------------------------------------------------------------------------------------
#: What each redrawn figure shows (the sample runs are described by their step).
SHOWS = {
    "subspaces_A_B": "the polar curves A and B of the paper's Example",
    "product_space_AxB": "A × B as a 3-D surface: a copy of B across A at every point",
    "torus": "the torus S¹ × S¹ with a longitude and a meridian",
    "discontinuity_shortest_path": "one robot on S¹, 'shortest path': final positions either side of the antipode"
    " give opposite runs; travel vs final position jumps",
    "discontinuity_counterclockwise": "one robot on S¹, 'counterclockwise': the travel jumps from ~c to ~0 at b = a",
    "one_robot_on_I": "one robot on I moving straight to its goal",
    "two_instructions_S1": "the two instructions for one robot on S¹ and their domains of continuity in S¹ × S¹",
    "interval_physical_and_configuration": "two robots on I and their state in I × I − Δ",
    "interval_same_component": "a query in one component of C²(I) and the planned straight path",
    "interval_different_components": "a query across the components: the planner's NoMotionError message",
    "circle_physical_and_flat_torus": "two robots on S¹, the torus minus its diagonal, the flat torus",
    "antipodal_circle": "the antipodal circle (skeleton of the circle) with its ccw orientation, and a ccw run on"
    " the track",
    "circle_initial_final_antipodal_states": "x_i, x_f and their retractions x_i', x_f' by horizontal traces of H",
    "circle_steps_in_X": "preliminary, main and final step of a circle plan in the flat torus",
    "circle_swapped_physical": "swapped positions on the circle",
    "circle_swapped_configuration": "swapped states: symmetric about Δ; on the antipodal circle, antipodal points",
    "generalized_lollipop_Cng": "the generalized lollipop graph C(n,g)",
    "lollipop_graph": "the lollipop L = C(2,1) from Lollipop.embed / as_graph",
    "lollipop_configuration_space": "L × L − Δ in 3-D (torus, tube, wall, flat piece) and flat, with the skeleton",
    "lollipop_physical_positions_states": "four physical positions and their states in the flat space",
    "two_positions_in_skeleton": "two generalized antipodal positions and their points on the skeleton",
    "homotopy_traces": "traces of H from mpa.retract over a grid of states, ending on the skeleton",
    "skeleton_flat": "the skeleton I1, S1, S2, S3, I2 in the flat space with ccw arrows and the level set d = h",
    "wedge_of_three_circles": "contracting a spanning tree of the skeleton graph leaves a wedge of b₁ = 3 circles",
    "distance_between_robots": "graph distances between robots with the shortest path highlighted",
    "generalized_antipodal_positions": "a generalized antipodal position (d = h) in each block of the skeleton",
    "skeleton_chain": "the skeleton graph as the chain of three circles and two intervals, ccw arrows",
    "ccw_directions": "the ccw orientation of each S_j: chain, flat space, and the robots' motions on the track",
    "generalized_swapped_configuration": "generalized swapped states in each S_j and the planned ccw runs (domain 2)",
    "generalized_swapped_physical": "generalized swapped states in each S_j on the track",
    "extended_interval": "the extended interval Ĩ = I ∪ {P}",
    "preliminary_distance_more_than_half": "preliminary step for d > h: the robot nearer the free end moves, the"
    " other waits",
    "preliminary_distance_less_than_half": "preliminary step for d < h: both robots move apart (stick, stick-loop,"
    " loop)",
}


#: One figure: file slug, the paper's caption, the function drawing it.
_Entry = tuple[str, str, Callable[[], Figure]]


def _one_robot_figures() -> list[_Entry]:
    """§2-§4: product spaces, the torus, one robot on the circle and on the interval."""
    return [
        ("subspaces_A_B", "Subspaces $A$ and $B$", fig_subspaces),
        ("product_space_AxB", "Product space $A \\times B$", fig_product_space),
        ("torus", "Torus $T = S^1 \\times S^1$", fig_torus),
        ("discontinuity_shortest_path", "Discontinuity at the antipodal pairs", fig_discontinuity_shortest),
        ("discontinuity_counterclockwise", "Discontinuity at configuration $(a,a)$", fig_discontinuity_ccw),
        ("one_robot_on_I", "One robot moving on I", fig_one_robot_interval),
        ("two_instructions_S1", "Two Instructions for one robot moving on $S^1$", fig_two_instructions_circle),
    ]


def _interval_and_circle_figures() -> list[_Entry]:
    """§5: two robots on the interval and on the circle (spaces, antipodal circle, swapped states)."""
    return [
        (
            "interval_physical_and_configuration",
            "Physical and configuration spaces for two robots in $I$",
            fig_interval_spaces,
        ),
        ("interval_same_component", "Initial and final states are in the same connected component.", fig_interval_same),
        (
            "interval_different_components",
            "Initial and final states are in different connected components.",
            fig_interval_different,
        ),
        (
            "circle_physical_and_flat_torus",
            "Physical and configuration spaces for two robots on $S^1$",
            fig_circle_spaces,
        ),
        (
            "antipodal_circle",
            "The antipodal circle $\\mathcal{A}$ and its counterclockwise orientation",
            fig_antipodal_circle,
        ),
        ("circle_initial_final_antipodal_states", "Initial and final antipodal states", fig_circle_antipodal_states),
        ("circle_steps_in_X", "The steps of the MPA in $X$", fig_circle_steps_in_x),
        ("circle_swapped_physical", "Swapped states in the physical space", fig_swapped_physical),
        ("circle_swapped_configuration", "Swapped states in the configuration space", fig_swapped_config),
    ]


def _circle_run_figures() -> list[_Entry]:
    """§5.3: the two sample runs on the circle, step by step."""
    return [
        ("circle_ex1_setup", "Initial setup", _run_figure("circle_ex1", None, "initial (filled) and final (empty)")),
        ("circle_ex1_preliminary", "Preliminary step", _run_figure("circle_ex1", "preliminary", "preliminary step")),
        (
            "circle_ex1_main",
            'Main step: "Move following the shortest path"',
            _run_figure("circle_ex1", "main", "main step: shortest path"),
        ),
        ("circle_ex1_final", "Final step", _run_figure("circle_ex1", "final", "final step")),
        ("circle_ex2_setup", "Initial setup", _run_figure("circle_ex2", None, "initial (filled) and final (empty)")),
        ("circle_ex2_preliminary", "Preliminary step", _run_figure("circle_ex2", "preliminary", "preliminary step")),
        (
            "circle_ex2_main",
            'Main step: "Move both robots in counterclockwise direction"',
            _run_figure("circle_ex2", "main", "main step: both robots ccw"),
        ),
        ("circle_ex2_final", "Final step", _run_figure("circle_ex2", "final", "final step")),
    ]


def _lollipop_figures() -> list[_Entry]:
    """§6.1-§6.3: the lollipop, its configuration space, the skeleton, the definitions of the algorithm."""
    return [
        ("generalized_lollipop_Cng", "Generalized lollipop graph $C_{n,g}$", fig_generalized_lollipop),
        ("lollipop_graph", "Lollipop graph $L=C_{2,1}$", fig_lollipop_graph),
        ("lollipop_configuration_space", "Configuration space $X$ and its flat representation", fig_lollipop_cspace),
        (
            "lollipop_physical_positions_states",
            "Physical positions and their state in configuration space",
            fig_physical_states,
        ),
        ("two_positions_in_skeleton", "Two positions in the skeleton $S$", fig_two_positions_skeleton),
        ("homotopy_traces", "Traces of the homotopy deformation $H$", fig_homotopy_traces),
        ("skeleton_flat", "The skeleton $S$", fig_skeleton_flat),
        ("wedge_of_three_circles", "Wedge of three circles", fig_wedge),
        ("distance_between_robots", "Distance between two robots", fig_distances),
        ("generalized_antipodal_positions", "Generalized antipodal positions", fig_generalized_antipodal),
        ("skeleton_chain", "The skeleton $S$", fig_chain),
        ("ccw_directions", "Counterclockwise directions in each circle $Sj \\subset S$", fig_ccw_directions),
        (
            "generalized_swapped_configuration",
            "Generalized swapped states in the configuration space",
            fig_swapped_generalized_config,
        ),
        (
            "generalized_swapped_physical",
            "Generalized swapped states in the physical space",
            fig_swapped_generalized_physical,
        ),
        ("extended_interval", "Extended interval $\\tilde I$", fig_extended_interval),
        ("preliminary_distance_more_than_half", "Distance greater than half unit.", fig_prelim_more),
        ("preliminary_distance_less_than_half", "Distance shorter than half unit.", fig_prelim_less),
    ]


def _lollipop_run_figures() -> list[_Entry]:
    """§6.4: the sample runs in the three domains V1, V2, V3, step by step."""
    specs: list[_Entry] = []
    for dom, (cap_q, cap_rest) in zip(
        (1, 2, 3),
        (
            ("Initial and final states in $V_1$", "$V_1$"),
            ("Initial and final positions in  $V_2$", "$V_2$"),
            ("Initial and final states in $V_3$", "$V_3$"),
        ),
    ):
        name = f"lollipop_V{dom}"
        specs += [
            (f"V{dom}_initial_final", cap_q, _run_figure(name, None, "initial (filled) and final (empty)")),
            (
                f"V{dom}_preliminary",
                f"Preliminary step in {cap_rest}",
                _run_figure(name, "preliminary", "preliminary step"),
            ),
            (f"V{dom}_main", f"Main step in {cap_rest}", _run_figure(name, "main", "main step")),
            (f"V{dom}_final", f"Final step in {cap_rest}", _run_figure(name, "final", "final step")),
        ]
    return specs


def _figures() -> list[FigureSpec]:
    """Every figure of the paper, numbered in paper order."""
    specs = (
        _one_robot_figures()
        + _interval_and_circle_figures()
        + _circle_run_figures()
        + _lollipop_figures()
        + _lollipop_run_figures()
    )
    return [
        FigureSpec(i + 1, slug, cap, make, SHOWS[slug] if slug in SHOWS else _run_shows(slug))
        for i, (slug, cap, make) in enumerate(specs)
    ]


def _run_shows(slug: str) -> str:
    name, step = slug.rsplit("_", 1) if not slug.endswith("initial_final") else (slug[:-14], "query")
    q = {
        "circle_ex1": "circle example 1 (B not antipodal, domain 2)",
        "circle_ex2": "circle example 2 (B antipodal, domain 1)",
        "V1": "lollipop domain 1 (generalized vertex position)",
        "V2": "lollipop domain 2 (generalized swapped)",
        "V3": "lollipop domain 3",
    }[name]
    what = {
        "setup": "initial and final positions and states",
        "query": "initial and final positions and states",
        "preliminary": "preliminary step",
        "main": "main step",
        "final": "final step",
    }[step]
    return f"{q}: {what}, on the track and in the flat space"


FIGURES = _figures()


def write_index(out: Path, specs: Sequence[FigureSpec]) -> Path:
    """Write ``out/index.md``: the caption of the paper of every figure drawn, with its file."""
    lines = [
        "# Figures of Boughrira & Colman, redrawn from the library",
        "",
        "Generated by `python experiments/figures.py`. Numbering follows the paper's figure order.",
        "",
        "| # | caption in the paper | file | what the figure shows |",
        "|---|---|---|---|",
    ]
    for s in specs:
        cap = s.caption.replace("|", "\\|")
        lines.append(f"| {s.number} | {cap} | [{s.filename}]({s.filename}) | {s.shows} |")
    path = out / "index.md"
    path.write_text("\n".join(lines) + "\n", encoding="utf-8")
    return path


def main(argv: Sequence[str] | None = None) -> int:
    """Command-line entry point; returns the exit status."""
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--out", required=True, type=Path, help="output directory")
    ap.add_argument("--dpi", type=float, default=110.0, help="resolution of the PNGs (default 110)")
    ap.add_argument("--only", nargs="*", default=None, help="regular expressions: draw only matching file names")
    ap.add_argument("--no-index", action="store_true", help="do not write index.md")
    args = ap.parse_args(argv)
    if args.dpi <= 0:
        print(f"error: dpi is {args.dpi}, expected > 0", file=sys.stderr)
        return 2
    args.out.mkdir(parents=True, exist_ok=True)
    specs = FIGURES
    if args.only:
        pats = [re.compile(p) for p in args.only]
        specs = [s for s in specs if any(p.search(s.filename) for p in pats)]
    timings: dict[str, float] = {}
    for s in specs:
        t0 = time.perf_counter()
        fig = s.make()
        save_figure(fig, args.out / s.filename, args.dpi, facecolor="white")
        timings[s.filename] = time.perf_counter() - t0
        print(f"{s.filename}  {timings[s.filename]:.2f} s")
    if not args.no_index:
        write_index(args.out, specs)
    return 0


if __name__ == "__main__":
    sys.exit(main())
