"""The compiled sampler (trajopt.verify.sampling) against the numpy formulas it replaced, and track coordinates
against mpa's Route.position, on the fast path, the hard path and the fallback, at grid and random times."""

from __future__ import annotations

import numpy as np

from mpa import Circle, Lollipop, MPAError
from trajopt import Limits, TrajectoryGenerator
from trajopt.generator import time_grid
from trajopt.path.planview import plan_view


def _numpy_sample(sc, t):  # type: ignore[no-untyped-def]
    """TimeScaling.sample as it was written with numpy (phase polynomial, path derivatives, chain rule)."""
    tt = np.asarray(t, dtype=float)
    k = np.maximum(np.searchsorted(sc.t0, tt, side="right") - 1, 0)
    s, sd, sdd, sddd = sc._param(tt, k)
    pc = np.where(tt >= sc.duration, len(sc.path.coef) - 1, sc.piece[k]) if len(sc.piece) == len(sc.t0) else None
    q0, q1, q2, q3 = sc.path.derivatives(s, pc)
    sd_, sdd_, sddd_ = sd[:, None], sdd[:, None], sddd[:, None]
    if sc.path.degree <= 1:
        return q0, q1 * sd_, q1 * sdd_ + 0.0, q1 * sddd_ + 0.0
    return q0, q1 * sd_, q2 * sd_**2 + q1 * sdd_, q3 * sd_**3 + 3 * q2 * sd_ * sdd_ + q1 * sddd_


def test_sampler_and_track_coordinates_match_the_numpy_formulas() -> None:
    rng = np.random.default_rng(11)
    paths: dict[str, int] = {}
    for track in (Lollipop(1.0, 1.0), Lollipop(0.3, 1.2), Lollipop(1.5, 0.8), Circle(1.0)):
        for optimize in (True, False):
            gen = TrajectoryGenerator(track, clearance=0.05, limits=Limits((0.5, 0.8), 1.0, 5.0), optimize=optimize)
            n = 0
            while n < 40:
                try:
                    traj = gen.generate(rng.uniform(0, track.total_length, 2), rng.uniform(0, track.total_length, 2))
                except MPAError:
                    continue
                n += 1
                key = traj.solver_stats.get("path", "fallback")
                paths[key] = paths.get(key, 0) + 1
                sc = traj.sampler.__self__
                t = np.concatenate(
                    [time_grid(sc.duration, 731.0), rng.uniform(-0.2, sc.duration + 0.2, 200), sc.t0, [sc.duration]]
                )
                got, want = sc.sample(t), _numpy_sample(sc, t)
                for name, g, w in zip("svaj", got, want):
                    scale = max(1.0, float(np.max(np.abs(w))))
                    assert np.max(np.abs(g - w)) <= 1e-12 * scale, (track, key, name, np.max(np.abs(g - w)))
                    assert g.shape == (len(t), 2)
                view = plan_view(traj.plan)
                routes = traj.plan.routes
                S = got[0]
                pos = view.track_coordinates(S)
                assert np.array_equal(pos[:, 0], routes[0].position(S[:, 0]))
                assert np.array_equal(pos[:, 1], routes[1].position(S[:, 1]))
    assert paths.get("fast", 0) > 50 and paths.get("hard", 0) > 5 and paths.get("fallback", 0) > 50, paths


def test_sample_keeps_the_shape_of_the_times() -> None:
    traj = TrajectoryGenerator(Lollipop(1.0, 1.0), clearance=0.05).generate((0.1, 0.6), (0.3, 0.8))
    sc = traj.sampler.__self__
    t = np.linspace(0, sc.duration, 12).reshape(3, 4)
    for x, flat in zip(sc.sample(t), sc.sample(t.ravel())):
        assert x.shape == (3, 4, 2)
        assert np.array_equal(x.reshape(12, 2), flat)
