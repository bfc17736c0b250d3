"""Rows as one object: the gate, the plan's view and the independent checker take a ``Setpoints`` and give the same
answers as with the rows' arrays one by one."""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest

from mpa import GraphTrack, InvalidInputError, Lollipop, MPAError
from trajopt import Limits, TrajectoryGenerator
from trajopt.path.planview import plan_view
from trajopt.testing import check_graph_setpoints, check_setpoints
from trajopt.verify.gate import verify_graph_setpoints, verify_setpoints
from trajopt.verify.rows import Setpoints, rows_of

Y = {"edges": [["J", "a", 1.0], ["J", "b", 1.5], ["J", "c", 2.0]]}


def _trajectories(track, n: int, seed: int):  # type: ignore[no-untyped-def]
    rng = np.random.default_rng(seed)
    gen = TrajectoryGenerator(track, clearance=0.1, limits=Limits(), rate=100.0)
    out = []
    while len(out) < n:
        if isinstance(track, GraphTrack):
            e = rng.integers(0, track.n_edges, 4)
            o = rng.uniform(0, 1, 4) * track.lengths[e]
            st, gl = ((int(e[0]), o[0]), (int(e[1]), o[1])), ((int(e[2]), o[2]), (int(e[3]), o[3]))
        else:
            st, gl = rng.uniform(0, track.total_length, 2), rng.uniform(0, track.total_length, 2)
        try:
            out.append(gen.generate(st, gl))
        except MPAError:
            continue
    return out


def _same(r1, r2) -> None:  # type: ignore[no-untyped-def]
    assert (r1.ok, r1.failures, r1.word) == (r2.ok, r2.failures, r2.word)
    assert r1.min_separation == r2.min_separation and r1.min_separation_between == r2.min_separation_between
    assert r1.peak_ratio == r2.peak_ratio


def test_paper_gate_same_with_setpoints_and_arrays() -> None:
    track = Lollipop(1.0, 1.0)
    for k, tr in enumerate(_trajectories(track, 12, seed=3)):
        p = tr.plan
        kw = {"limits": tr.limits, "clearance": tr.clearance, "start": p.start, "goal": p.goal, "word": p.word}
        rows = tr.rows()
        a = verify_setpoints(track, p.routes, rows, rate=tr.rate, **kw)
        b = verify_setpoints(track, p.routes, tr.t, tr.track, tr.s, tr.v, tr.a, tr.j, rate=tr.rate, **kw)
        _same(a, b)
        assert a.ok, (k, a.failures)
        # a broken row is found the same way by both forms
        bad = dataclasses.replace(rows, v=np.asarray(rows.v) * 3.0)
        c = verify_setpoints(track, p.routes, bad, rate=tr.rate, **kw)
        d = verify_setpoints(track, p.routes, tr.t, tr.track, tr.s, tr.v * 3.0, tr.a, tr.j, rate=tr.rate, **kw)
        _same(c, d)
        if np.max(np.abs(tr.v)) > 0.4:
            assert not c.ok, k
        _same(plan_view(p).verify(rows, limits=tr.limits, clearance=tr.clearance, rate=tr.rate), a)
        ch = {"rate": tr.rate, "clearance": tr.clearance, "vmax": tr.limits.v, "amax": tr.limits.a}
        ch |= {"jmax": tr.limits.j, "start": p.start, "goal": p.goal}
        assert check_setpoints(track, rows, **ch) == check_setpoints(
            track, tr.t, tr.track, tr.s, tr.v, tr.a, tr.j, **ch
        )


def test_graph_gate_same_with_setpoints_and_arrays() -> None:
    g = GraphTrack.from_layout(Y)
    for k, tr in enumerate(_trajectories(g, 12, seed=5)):
        p = tr.plan
        view = plan_view(p)
        kw = {"limits": tr.limits, "clearance": tr.clearance, "start": p.layout_start, "goal": p.layout_goal}
        rows = Setpoints(tr.t, tr.s, tr.v, tr.a, tr.j, edges=tr.edges, offsets=tr.offsets, dirs=tr.directions)
        a = verify_graph_setpoints(g.geometry, view.routes, rows, rate=tr.rate, **kw)
        b = verify_graph_setpoints(
            g.geometry, view.routes, tr.t, tr.edges, tr.offsets, tr.s, tr.v, tr.a, tr.j, rate=tr.rate, **kw
        )
        _same(a, b)
        assert a.ok, (k, a.failures)
        _same(view.verify(tr.rows(), limits=tr.limits, clearance=tr.clearance, rate=tr.rate), a)
        _same(view.verify(tr.t, tr.s, tr.v, tr.a, tr.j, limits=tr.limits, clearance=tr.clearance, rate=tr.rate), a)
        ch = {"rate": tr.rate, "clearance": tr.clearance, "vmax": tr.limits.v, "amax": tr.limits.a}
        ch |= {"jmax": tr.limits.j, "start": p.layout_start, "goal": p.layout_goal}
        one = check_graph_setpoints(g, rows, **ch)
        assert one == check_graph_setpoints(
            g, tr.t, tr.edges, tr.offsets, tr.s, tr.v, tr.a, tr.j, dirs=tr.directions, **ch
        )
        assert one == [], (k, one)
        # the rows' dirs are checked: flipping them is a failure
        flipped = dataclasses.replace(rows, dirs=-np.asarray(rows.dirs))
        if np.any(np.asarray(rows.dirs) != 0):
            assert check_graph_setpoints(g, flipped, **ch), k


def test_trajectory_rows_are_its_arrays() -> None:
    for track in (Lollipop(1.0, 1.0), GraphTrack.from_layout(Y)):
        tr = _trajectories(track, 1, seed=9)[0]
        rows = tr.rows()
        assert len(rows) == len(tr.t)
        for x, y in zip((rows.t, *rows.svaj), (tr.t, tr.s, tr.v, tr.a, tr.j)):
            assert x is y
        assert (rows.track is None) == tr.is_graph


def test_rows_of_refuses_mixed_or_short_forms() -> None:
    rows = Setpoints(np.zeros(2), *(np.zeros((2, 2)) for _ in range(4)))
    assert rows_of(rows, (), ("t", "s", "v", "a", "j")) is rows
    with pytest.raises(InvalidInputError, match="Setpoints alone"):
        rows_of(rows, (np.zeros(2),), ("t", "s", "v", "a", "j"))
    with pytest.raises(InvalidInputError, match="expected Setpoints or the 5 arrays t, s, v, a, j"):
        rows_of(np.zeros(2), (np.zeros((2, 2)),), ("t", "s", "v", "a", "j"))
    g = GraphTrack.from_layout(Y)
    with pytest.raises(InvalidInputError, match="edges and offsets"):
        verify_graph_setpoints(
            g.geometry,
            (),
            rows,
            limits=Limits(),
            clearance=0.0,
            start=((0, 0.0), (1, 0.0)),
            goal=((0, 0.0), (1, 0.0)),
            rate=10.0,
        )
