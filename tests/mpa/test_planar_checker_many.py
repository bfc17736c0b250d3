"""The independent checker (``tests/helpers/planar_checker.py``: its own geometry, no code of ``mpa.footprint``,
``mpa.planar`` or ``trajopt.verify.planar``) on thousands of seeded plans and on trajectories at and between rows, over
the example layouts drawn in metres and random sidings, with discs and rectangles."""

from __future__ import annotations

from pathlib import Path
from typing import Any

import numpy as np
import pytest

import mpa
from mpa import Disc, GraphTrack, InvalidInputError, NoMotionError, Rectangle
from tests.helpers.planar_checker import depth_many, overlap_depth
from tests.mpa.test_footprints import DEPTH_TOL, drawn_of, fp_tuple, passing_loop, random_layout

EXAMPLES = Path(__file__).resolve().parents[2] / "examples" / "tracks"
DRAWN_EXAMPLES = ("passing_loop.json", "rail_yard.json", "two_sidings.json", "y_junction.json", "warehouse.json")
FOOTPRINTS: tuple[Disc | Rectangle, ...] = (Disc(0.25), Disc(0.45), Rectangle(1.2, 0.5), Rectangle(2.0, 0.8))


def _tracks(seed: int) -> list[GraphTrack]:
    rng = np.random.default_rng(seed)
    out = [GraphTrack.from_json(EXAMPLES / name) for name in DRAWN_EXAMPLES]
    return out + [GraphTrack.from_layout(random_layout(rng)) for _ in range(3)]


def test_vectorised_depth_equals_the_one_at_a_time_check() -> None:
    rng = np.random.default_rng(0)
    for tr in _tracks(0)[:4] + _tracks(0)[-2:]:
        dr = drawn_of(tr)
        n = 150
        ea, eb = rng.integers(0, tr.n_edges, n), rng.integers(0, tr.n_edges, n)
        oa, ob = rng.uniform(0, 1, n) * tr.lengths[ea], rng.uniform(0, 1, n) * tr.lengths[eb]
        oa[:10] = 0.0  # vertices: every orientation there
        for fa, fb in ((FOOTPRINTS[0], FOOTPRINTS[3]), (FOOTPRINTS[3], FOOTPRINTS[2]), (FOOTPRINTS[1],) * 2):
            a, b = fp_tuple(fa), fp_tuple(fb)
            many = depth_many(dr, a, b, ea, oa, eb, ob)
            one = [
                overlap_depth(dr, a, (int(x), float(y)), b, (int(z), float(w))) for x, y, z, w in zip(ea, oa, eb, ob)
            ]
            assert np.allclose(many, one, atol=1e-9), (tr.edge_names, fa, fb)


Query = tuple[int, Disc | Rectangle, float, list[tuple[int, float]]]
WAREHOUSE = DRAWN_EXAMPLES.index("warehouse.json")


def _queries(n: int, seed: int, layouts: list[int], fps: list[int], clearances: list[float]) -> list[Query]:
    """``n`` seeded queries (layout index, footprint, clearance, the four ends) drawn from the given layouts,
    footprints and clearances, grouped by (layout, footprint, clearance) so that the planner builds each free space
    once while its cache holds it. The warehouse (77 edges, about 40 s per free space on a loaded 2-core machine)
    is asked with one footprint and clearance only."""
    rng = np.random.default_rng(seed)
    tracks = _tracks(seed)
    out = []
    for _ in range(n):
        k = layouts[int(rng.integers(len(layouts)))]
        tr = tracks[k]
        f = fps[int(rng.integers(len(fps)))]
        clearance = float(rng.choice(clearances))
        if k == WAREHOUSE:
            f, clearance = fps[-1], clearances[-1]
        ends = []
        for _ in range(4):
            e = int(rng.integers(tr.n_edges))
            ends.append((e, float(rng.uniform(0.0, tr.lengths[e]))))
        out.append((k, f, clearance, ends))
    out.sort(key=lambda q: (q[0], q[1], q[2]))
    return [(k, FOOTPRINTS[f], c, ends) for k, f, c, ends in out]


def _plans(
    n: int,
    seed: int,
    layouts: list[int],
    fps: list[int],
    clearances: list[float],
    refusals: tuple[list[GraphTrack], list[Any]] | None = None,
) -> tuple[int, int]:
    """``n`` seeded queries; each plan sampled at 400 parameters and on both sides of every waypoint, checked by the
    vectorised independent checker along the motion (a robot on a vertex at the orientations of the edges it
    arrives on and leaves by). With ``refusals`` (the tracks and their drawings): a query refused as bad input must
    have the bodies overlapping (checker) or the robots closer than D along the track at its start or goal."""
    tracks, drawn = refusals if refusals is not None else (_tracks(seed), None)
    if drawn is None:
        drawn = [drawn_of(tr) for tr in tracks]
    planned = refused = 0
    u = np.linspace(0.0, 1.0, 400)
    for k, fp, clearance, ends in _queries(n, seed, layouts, fps, clearances):
        tr, dr = tracks[k], drawn[k]
        try:
            p = mpa.plan(tr, (ends[0], ends[1]), (ends[2], ends[3]), clearance=clearance, footprint=fp)
        except NoMotionError:
            refused += 1
            continue
        except InvalidInputError:
            refused += 1
            if refusals is not None:
                f = fp_tuple(fp)
                worst = max(
                    max(overlap_depth(dr, f, a, f, b), clearance - tr.geometry.distance_scalar(*a, *b))
                    for a, b in ((ends[0], ends[1]), (ends[2], ends[3]))
                )
                assert worst > -1e-6, (tr.to_dict(), ends, fp, clearance, worst)
            continue
        planned += 1
        # just before and after every waypoint (a corner of the plan), and the waypoint itself
        times = p._times
        eps = 1e-9
        wp = times / times[-1] if times[-1] > 0 else np.zeros(1)
        uu = np.clip(np.union1d(u, np.concatenate([wp - eps, wp, wp + eps])), 0.0, 1.0)
        (ea, oa), (eb, ob) = p.positions(uu)
        depth = depth_many(dr, fp_tuple(fp), fp_tuple(fp), ea, oa, eb, ob, along=True)
        i = int(np.argmax(depth))
        assert depth[i] <= DEPTH_TOL, (tr.to_dict(), ends, fp, clearance, float(depth[i]), i)
    return planned, refused


# the drawn passing loop, rail yard and Y junction and the three random sidings: small layouts, few free spaces
CI_LAYOUTS = [0, 1, 3, len(DRAWN_EXAMPLES), len(DRAWN_EXAMPLES) + 1, len(DRAWN_EXAMPLES) + 2]


def test_thousands_of_queries_few_free_spaces_independent_check() -> None:
    """2 400 seeded queries on 12 free spaces (6 layouts, a disc and a rectangle, D = 0.5 m): every plan checked
    along the motion by the independent checker, and every query refused for bodies overlapping at start or goal
    confirmed by it (the checker's overlap there, or the robots closer than D along the track)."""
    n, seed = 2400, 31
    tracks = _tracks(seed)
    drawn = [drawn_of(tr) for tr in tracks]
    counts = _plans(n, seed, CI_LAYOUTS, [1, 3], [0.5], refusals=(tracks, drawn))
    planned, refused = counts
    assert planned + refused == n and planned >= 900, counts


@pytest.mark.slow
def test_thousands_of_plans_never_overlap_independent_check() -> None:
    planned, refused = _plans(1000, 21, list(range(len(_tracks(0)))), [0, 1, 2, 3], [0.0, 0.5, 2.5])
    assert planned >= 200, (planned, refused)


@pytest.mark.slow  # about 30 s, nearly all of it planning (the checker itself takes about 3 s)
def test_hundreds_of_plans_never_overlap_independent_check() -> None:
    # the drawn passing loop, rail yard and Y junction and three random sidings; a disc and the large rectangle
    layouts = [0, 1, 3, len(DRAWN_EXAMPLES), len(DRAWN_EXAMPLES) + 1, len(DRAWN_EXAMPLES) + 2]
    planned, refused = _plans(200, 5, layouts, [1, 3], [0.0, 0.5])
    assert planned >= 40, (planned, refused)


def _trajectories(n: int, seed: int) -> int:
    from trajopt import generate_trajectory

    rng = np.random.default_rng(seed)
    tracks = _tracks(seed)[:2] + _tracks(seed)[-3:]  # the warehouse's long runs only in the plan check
    done = 0
    for _ in range(n):
        tr = tracks[int(rng.integers(len(tracks)))]
        fp = FOOTPRINTS[int(rng.integers(len(FOOTPRINTS)))]
        ends = []
        for _ in range(4):
            e = int(rng.integers(tr.n_edges))
            ends.append((e, float(rng.uniform(0.0, tr.lengths[e]))))
        try:
            traj = generate_trajectory(tr, (ends[0], ends[1]), (ends[2], ends[3]), clearance=0.5, footprint=fp)
        except (InvalidInputError, NoMotionError):
            continue
        done += 1
        plan: Any = traj.plan
        # the rows and 4 instants between consecutive rows, from the continuous motion
        t = np.union1d(traj.t, (traj.t[:-1, None] + np.linspace(0.2, 0.8, 4)[None, :] / traj.rate).ravel())
        s, _, _, _ = traj.sampler(np.minimum(t, traj.motion_time))
        ea, oa = plan.route_a.positions(s[:, 0])
        eb, ob = plan.route_b.positions(s[:, 1])
        # consecutive instants of one motion: a robot on a vertex takes the headings it arrives and leaves with
        depth = depth_many(drawn_of(tr), fp_tuple(fp), fp_tuple(fp), ea, oa, eb, ob, along=True)
        assert float(depth.max()) <= DEPTH_TOL, (tr.to_dict(), ends, fp, float(depth.max()))
    return done


def test_trajectories_never_overlap_at_and_between_rows_independent_check() -> None:
    assert _trajectories(12, seed=4) >= 4


@pytest.mark.slow
def test_thousand_trajectories_never_overlap_independent_check() -> None:
    assert _trajectories(1000, seed=8) >= 300


def test_a_robot_passing_straight_through_a_switch_keeps_its_heading_there() -> None:
    """The case of seed 21: B passes the switch SE straight (main to east, heading 0) while A waits on the siding's
    diagonal, touching B's body at heading 0. Turned to the siding's heading B would overlap A by centimetres; the
    model never turns it there, so the checker along the motion finds no overlap, and still finds the overlap of a
    B that arrives on main and leaves onto the siding."""
    tr = GraphTrack.from_layout(passing_loop(0.8, 3.0, 30.0))
    dr = drawn_of(tr)
    fp = (2.0, 0.8)
    main, siding, east = (tr.edge_names.index(n) for n in ("main", "siding", "east"))
    lm, ls = float(tr.lengths[main]), float(tr.lengths[siding])
    b_at_se = (main, lm)

    def depth_at_heading_0(o: float) -> float:
        return overlap_depth(dr, fp, (siding, o), fp, b_at_se, heads_b=[0.0])

    lo, hi = 0.0, ls  # A's offset on the siding where it just touches B (heading 0) at SE, by bisection
    for _ in range(80):
        mid = 0.5 * (lo + hi)
        lo, hi = (lo, mid) if depth_at_heading_0(mid) > 0.0 else (mid, hi)
    a = (siding, lo)
    assert depth_at_heading_0(lo) == 0.0 and depth_at_heading_0(lo + 1e-3) > 0.0
    every = overlap_depth(dr, fp, a, fp, b_at_se)  # B in every orientation at SE, the siding's included
    assert every > 0.05, every
    ea, oa = np.full(3, siding), np.full(3, lo)
    straight = depth_many(dr, fp, fp, ea, oa, np.array([main, main, east]), np.array([lm - 1e-3, lm, 1e-3]), along=True)
    assert float(straight.max()) <= DEPTH_TOL, straight
    turning = depth_many(
        dr, fp, fp, ea, oa, np.array([main, main, siding]), np.array([lm - 1e-3, lm, ls - 1e-3]), along=True
    )
    assert turning[1] > 0.05, turning
