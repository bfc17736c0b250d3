"""The options every animation takes (``trajopt.viz.movie``): validated once for the paper's tracks and the
layouts, and the frames' times on the shared clock."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest

from mpa import Lollipop, plan
from mpa.errors import InvalidInputError
from mpa.graph_track import GraphTrack
from trajopt.viz import animation as A
from trajopt.viz.layout_animation import animate_layout, graph_plan_motion
from trajopt.viz.movie import frame_times, validate_movie_options


def test_frame_times_span_the_motion_at_the_rate_or_capped() -> None:
    rng = np.random.default_rng(22)
    for _ in range(500):
        t0 = float(rng.uniform(-5.0, 5.0))
        t1 = t0 + float(rng.choice([0.0, rng.uniform(0.0, 30.0)]))
        fps = float(rng.uniform(1.0, 60.0))
        cap = None if rng.random() < 0.3 else int(rng.integers(2, 400))
        times, speedup = frame_times(t0, t1, fps, cap)
        case = (t0, t1, fps, cap, len(times), speedup)
        assert times[0] == t0 and times[-1] == t1, case
        assert np.all(np.diff(times) >= 0.0), case
        full = math.ceil((t1 - t0) * fps) + 1
        if cap is not None and full > cap:
            assert len(times) == cap and speedup == pytest.approx((full - 1) / (cap - 1)), case
        else:
            assert len(times) == full and speedup == 1.0, case
            if len(times) > 1:  # real time: steps of at most 1/fps
                assert float(np.max(np.diff(times))) <= 1.0 / fps * (1 + 1e-9), case


@pytest.mark.parametrize(
    ("kw", "message"),
    [
        ({"fps": 0}, "fps is 0, expected a finite number >= 1"),
        ({"fps": True}, "fps is True, expected a number >= 1"),
        ({"fps": "20"}, "fps is '20', expected a number >= 1"),
        ({"dpi": math.nan}, "dpi is nan, expected a finite number >= 10"),
        ({"max_frames": 2.5}, "max_frames is 2.5, expected an integer >= 2"),
        ({"max_frames": 1}, "max_frames is 1, expected an integer >= 2"),
        ({"fmt": "avi"}, "format is 'avi', expected one of ['gif', 'mp4']"),
    ],
)
def test_both_animations_refuse_the_same_bad_options_with_the_same_message(
    tmp_path: Path, kw: dict[str, object], message: str
) -> None:
    opts: dict[str, object] = {"fmt": None, "fps": 20.0, "dpi": 80.0, "max_frames": None} | kw
    with pytest.raises(InvalidInputError) as direct:
        validate_movie_options(tmp_path / "a.gif", **opts)
    assert str(direct.value) == message
    p = plan(Lollipop(1.0, 1.0), (0.2, 0.5), (0.5, 0.2))
    with pytest.raises(InvalidInputError) as paper:
        A.animate_motions(p.track, [A.plan_motion(p, 0.5)], tmp_path / "p.gif", progress=False, **kw)
    track = GraphTrack.from_layout({"edges": [["a", "b", 2.0], ["b", "c", 2.0]]})
    gp = plan(track, (track.position("a"), track.position("c")), ((0, 1.0), (1, 1.5)), 0.2, planner="graph")
    t, s = graph_plan_motion(gp, 20)
    with pytest.raises(InvalidInputError) as layout:
        animate_layout(track, *gp.layout_routes, t, s, tmp_path / "l.gif", progress=False, **kw)
    assert str(paper.value) == str(layout.value) == message
    assert not any(tmp_path.iterdir())  # nothing written


def test_the_paper_animation_refuses_no_motions(tmp_path: Path) -> None:
    p = plan(Lollipop(1.0, 1.0), (0.2, 0.5), (0.5, 0.2))
    with pytest.raises(InvalidInputError, match="motions is empty"):
        A.animate_motions(p.track, [], tmp_path / "p.gif", progress=False)
