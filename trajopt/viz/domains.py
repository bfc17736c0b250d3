"""Domain maps and pictures of a paper plan (``mpa domains --plot``, ``mpa plan --track ... --plot``).

A *domain map* answers the question a reader of the paper asks first: for a fixed goal, which domain of
continuity (conventions: Domains of continuity) does each start fall in — or, for a fixed start, each goal. The
configuration space (track coordinates of A and B, metres) is sampled on a ``samples × samples`` grid of cell
centres; every state at least the clearance apart is a query, answered all at once by :func:`mpa.plan_many`
(vectorised: about 40 000 queries in 3 s). States closer than the clearance are the collision band; a query
without a collision-free motion (the interval's other order, ``D >= c/2`` on a loop) is marked "no motion".
Within a domain the planner's output moves continuously with the start and goal; its borders are where it jumps.

:func:`plan_figure` draws a plan of the paper's algorithm for one query: the track with the robots at start and
goal, the configuration space with the skeleton, the collision band and the plan's path (its preliminary, main and
final steps), and the domain map for the query's goal with the start and the path on it.
"""

from __future__ import annotations

import textwrap
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from mpa._arrays import FloatArray
from mpa.batch import plan_many
from mpa.errors import InvalidInputError, NoMotionError
from mpa.planners import make_planner
from mpa.planners.base import DEFAULT_NEIGHBOURHOOD
from mpa.tracks import Track

if TYPE_CHECKING:  # pragma: no cover
    from matplotlib.axes import Axes
    from matplotlib.figure import Figure

    from mpa.plans import Plan

__all__ = [
    "DOMAIN_COLORS",
    "DomainGrid",
    "domain_grid",
    "domain_map_figure",
    "draw_domain_map",
    "plan_figure",
]

#: Colours of the domains 1, 2, 3 (colour-blind safe), of the collision band and of "no motion".
DOMAIN_COLORS = {1: "#4477aa", 2: "#ccbb44", 3: "#66ccee", 0: "#bbbbbb", -1: "#ffffff"}
#: Grid value of a state closer than the clearance (the collision band).
COLLISION = 0
#: Grid value of a query without a collision-free motion.
NO_MOTION = -1


@dataclass(frozen=True)
class DomainGrid:
    """The domain of every query of a grid (see the module docstring).

    Attributes
    ----------
    track : Track
    coords : ndarray, shape (n,)
        Cell centres along each axis (track coordinates, m).
    domain : ndarray of int, shape (n, n)
        ``domain[i, j]``: the query with robot B at ``coords[i]`` and A at ``coords[j]`` (as in the pictures:
        A horizontal, B vertical); 1, 2, 3, or :data:`COLLISION` (0), :data:`NO_MOTION` (-1).
    fixed : ndarray, shape (2,)
        The fixed state (track coordinates of A and B).
    varies : str
        ``"start"`` (the goal is fixed) or ``"goal"`` (the start is fixed).
    clearance : float
    """

    track: Track
    coords: FloatArray
    domain: NDArray[np.int64]
    fixed: FloatArray
    varies: str
    clearance: float

    def fractions(self) -> dict[int, float]:
        """Share of the valid queries (not in the collision band) in each domain and without motion."""
        valid = self.domain != COLLISION
        n = max(int(np.sum(valid)), 1)
        return {int(k): float(np.sum(self.domain == k)) / n for k in (1, 2, 3, NO_MOTION)}


def _domains(track: Track, starts: FloatArray, goals: FloatArray, clearance: float, nb: float) -> NDArray[np.int64]:
    """Domains of many queries; queries without motion are :data:`NO_MOTION` (halves split until singletons)."""
    if len(starts) == 0:
        return np.zeros(0, dtype=np.int64)
    try:
        return np.asarray(plan_many(track, starts, goals, clearance, nb).domain, dtype=np.int64)
    except NoMotionError:
        if len(starts) == 1:
            return np.array([NO_MOTION], dtype=np.int64)
    h = len(starts) // 2
    return np.concatenate(
        [_domains(track, starts[:h], goals[:h], clearance, nb), _domains(track, starts[h:], goals[h:], clearance, nb)]
    )


def domain_grid(
    track: Track,
    *,
    goal: ArrayLike | None = None,
    start: ArrayLike | None = None,
    clearance: float = 0.0,
    neighbourhood: float = DEFAULT_NEIGHBOURHOOD,
    samples: int = 200,
) -> DomainGrid:
    """The domain of every start for a fixed ``goal`` (or of every goal for a fixed ``start``) on a grid.

    Parameters
    ----------
    track : Track
        One of the paper's tracks.
    goal, start : array_like, shape (2,)
        Exactly one of them: the fixed state (track coordinates of A and B, m).
    clearance : float
        D (m).
    neighbourhood : float
        The domains' neighbourhood ε as a fraction of half the loop.
    samples : int
        Grid cells per axis (>= 10); ``samples²`` queries.

    Raises
    ------
    InvalidInputError
        Not a paper track, both or neither of ``goal`` and ``start``, a fixed state off the track or closer than
        the clearance, ``samples`` not an integer >= 10.
    """
    if not isinstance(track, Track):
        raise InvalidInputError(f"track is {track!r}, expected one of the paper's tracks (interval, circle, lollipop)")
    if (goal is None) == (start is None):
        raise InvalidInputError("give exactly one of goal= (the map of starts) and start= (the map of goals)")
    if isinstance(samples, bool) or not isinstance(samples, (int, np.integer)) or samples < 10:
        raise InvalidInputError(f"samples is {samples!r}, expected an integer >= 10")
    varies = "start" if goal is not None else "goal"
    fixed_in: Any = goal if goal is not None else start
    name = "goal" if goal is not None else "start"
    fixed: FloatArray = np.asarray(track.validate(fixed_in, name), dtype=np.float64).reshape(2)
    make_planner(track, clearance, neighbourhood).plan(fixed, fixed)  # validates the fixed state (clearance too)
    from trajopt.viz.drawing import coordinate_extent

    n = int(samples)
    ext = coordinate_extent(track)
    coords = (np.arange(n) + 0.5) * ext / n
    aa, bb = np.meshgrid(coords, coords)  # [i, j]: B = coords[i], A = coords[j]
    states = np.column_stack([aa.ravel(), bb.ravel()])
    d = track.distance(states[:, 0], states[:, 1])
    valid = d >= clearance + 1e-12 * max(1.0, ext)
    dom = np.full(len(states), COLLISION, dtype=np.int64)
    other = np.broadcast_to(fixed, (int(np.sum(valid)), 2))
    qs = states[valid]
    dom[valid] = (
        _domains(track, qs, np.array(other), clearance, neighbourhood)
        if varies == "start"
        else _domains(track, np.array(other), qs, clearance, neighbourhood)
    )
    return DomainGrid(track, coords, dom.reshape(n, n), fixed, varies, float(clearance))


def draw_domain_map(ax: Axes, grid: DomainGrid, *, legend: bool = True, mark: bool = True) -> None:
    """Draw a :class:`DomainGrid` on ``ax``: one colour per domain (:data:`DOMAIN_COLORS`), the collision band
    grey, the fixed state as a star; axes in track coordinates (m)."""
    from matplotlib.colors import ListedColormap
    from matplotlib.patches import Patch

    keys = [NO_MOTION, COLLISION, 1, 2, 3]
    cmap = ListedColormap([DOMAIN_COLORS[k] for k in keys])
    idx = np.searchsorted(keys, grid.domain)
    ext = float(grid.coords[-1] + grid.coords[0])
    ax.imshow(
        idx,
        origin="lower",
        extent=(0.0, ext, 0.0, ext),
        cmap=cmap,
        vmin=-0.5,
        vmax=len(keys) - 0.5,
        interpolation="nearest",
        aspect="equal",
    )
    ax.set_xlim(0.0, ext)
    ax.set_ylim(0.0, ext)
    ax.set_xlabel("a: track coordinate of A (m)")
    ax.set_ylabel("b: track coordinate of B (m)")
    if mark:
        ax.plot(*grid.fixed, marker="*", ms=16, mfc="k", mec="white", mew=1.2, ls="none", zorder=6)
        ax.annotate(
            f"{'goal' if grid.varies == 'start' else 'start'}",
            (float(grid.fixed[0]), float(grid.fixed[1])),
            xytext=(8, 8),
            textcoords="offset points",
            fontsize=10,
            fontweight="bold",
            bbox={"fc": "white", "ec": "none", "alpha": 0.8, "pad": 1.0},
            zorder=7,
        )
    if legend:
        frac = grid.fractions()
        handles = [
            Patch(fc=DOMAIN_COLORS[k], ec="0.3", label=f"domain {k} ({100 * frac[k]:.0f} %)")
            for k in (1, 2, 3)
            if frac[k] > 0
        ]
        handles.append(Patch(fc=DOMAIN_COLORS[COLLISION], ec="0.3", label=f"closer than D = {grid.clearance:g} m"))
        if frac[NO_MOTION] > 0:
            handles.append(Patch(fc=DOMAIN_COLORS[NO_MOTION], ec="0.3", label="no motion"))
        ax.legend(handles=handles, loc="upper left", bbox_to_anchor=(1.02, 1.0), fontsize=10, frameon=False)


def _title(grid: DomainGrid) -> str:
    from trajopt.viz.drawing import track_title

    what = "start" if grid.varies == "start" else "goal"
    other = "goal" if grid.varies == "start" else "start"
    a, b = grid.fixed
    n = len(grid.coords)
    return (
        f"{track_title(grid.track)}, D = {grid.clearance:g} m\nthe domain of every {what} for the {other} "
        f"({a:g}, {b:g})  [{n}×{n} samples]"
    )


def domain_map_figure(grid: DomainGrid) -> Figure:
    """A figure of one domain map with its title and legend."""
    from matplotlib.figure import Figure

    fig = Figure(figsize=(8.6, 6.2), layout="constrained")
    ax = fig.add_subplot(1, 1, 1)
    draw_domain_map(ax, grid)
    ax.set_title(_title(grid), fontsize=10)
    return fig


def plan_figure(p: Plan, *, samples: int = 160, neighbourhood: float = DEFAULT_NEIGHBOURHOOD) -> Figure:
    """A plan of the paper's algorithm: track, configuration space with the path, and the domain map of its goal.

    Parameters
    ----------
    p : Plan
    samples : int
        Grid cells per axis of the domain map (>= 10).
    neighbourhood : float
        The ε the plan was made with (fraction of half the loop), for the domain map.
    """
    from matplotlib.figure import Figure

    from trajopt.viz.drawing import STEP_COLORS, StepStyle, draw_flat_path, draw_plan_step, draw_state, track_title

    track = p.track
    fig = Figure(figsize=(16.0, 5.6), layout="constrained")
    ax_t, ax_c, ax_d = fig.subplots(1, 3, width_ratios=[1.0, 1.0, 1.25])
    draw_plan_step((ax_t, ax_c), p, StepStyle(step=None))
    u = np.linspace(0.0, 1.0, max(1500, p.samples_needed(0.002)))
    for st in p.steps:  # the plan's path over the faint whole, step by step in the step's colour
        if st.u_end > st.u_start:
            seg = p.path(u[(u >= st.u_start) & (u <= st.u_end)])
            if len(seg) > 1:
                draw_flat_path(ax_c, track, seg, color=STEP_COLORS.get(st.name, "k"), lw=2.2, arrows=(0.5,))
    ax_t.set_title("the track: robots at the start (filled) and goal (empty)", fontsize=10)
    ax_c.set_title(f"configuration space: the skeleton and the plan's path (domain {p.domain})", fontsize=10)
    grid = domain_grid(track, goal=p.goal, clearance=p.clearance, neighbourhood=neighbourhood, samples=samples)
    draw_domain_map(ax_d, grid)
    draw_flat_path(ax_d, track, p.path(u), color="k", lw=1.6, arrows=(0.5,), alpha=0.9)
    draw_state(ax_d, p.start, "start", color="k", size=8, offset=(8, -14))
    ax_d.set_title(f"domains of every start for this goal: the query is in domain {p.domain}", fontsize=10)
    word = " ".join(p.word) if p.word else "(trivial)"
    head = (
        f"{track_title(track)}, D = {p.clearance:g} m: ({p.start[0]:g}, {p.start[1]:g}) → "
        f"({p.goal[0]:g}, {p.goal[1]:g}) · domain {p.domain} · class {word}"
    )
    fig.suptitle(head + "\n" + "\n".join(textwrap.wrap(p.rule, 150)), fontsize=11)
    return fig
