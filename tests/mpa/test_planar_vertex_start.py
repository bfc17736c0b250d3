"""A start or goal with a rectangle standing on a corner of the drawing (a vertex or polyline corner where the
pieces' orientations differ): the body takes every orientation there and, turning between them, sweeps the disc of
its half-diagonal about the corner. ``mpa.plan``, ``trajopt.generate_trajectory`` and the command line refuse such a
query with one and the same ``InvalidInputError`` when that disc reaches into the other body; otherwise the plan is
made and the trajectory verified. Reproduced by a seeded search over the example layouts (theta: ``v`` and
``middle:0.95`` with 1x0.5 rectangles was planned, then failed the gate between its first two rows, exit 4). The
expected answer is computed here with the test's own geometry (``tests.helpers.planar_checker``), not the planner's."""

from __future__ import annotations

import math
import random
from pathlib import Path

import numpy as np
import pytest

import mpa
import trajopt
from mpa import InvalidInputError
from mpa.graph_track import GraphTrack
from tests.helpers.planar_checker import Drawn, _inside, _pt_seg, rect
from tests.mpa.test_footprints import drawn_of
from trajopt.cli.main import main

EXAMPLES = Path(__file__).resolve().parents[2] / "examples" / "tracks"


def _headings(dr: Drawn, e: int, o: float) -> float:
    """Heading of the polyline piece holding offset ``o`` of edge ``e`` (inside the piece)."""
    off, pts = dr.offs[e], dr.polys[e]
    k = int(np.clip(np.searchsorted(off, o, side="right") - 1, 0, len(off) - 2))
    d = pts[k + 1] - pts[k]
    return math.atan2(d[1], d[0])


def _point_to_rect(p: np.ndarray, quad: np.ndarray) -> float:
    if _inside(p, quad):
        return 0.0
    return min(_pt_seg(p, quad[j], quad[(j + 1) % 4]) for j in range(4))


def _turning_vertices(tr: GraphTrack, dr: Drawn) -> list[tuple[str, list[tuple[int, float, float]]]]:
    """Vertices where the drawing turns: per vertex its edges as (edge, offset at the vertex, +1/-1 inwards)."""
    out = []
    for name in tr.graph.vertices:
        ends = []
        heads = []
        for e, (a, b) in enumerate(dr.ends):
            L = float(tr.lengths[e])
            if a == name:
                ends.append((e, 0.0, 1.0))
                heads.append(_headings(dr, e, 0.0))
            if b == name:
                ends.append((e, L, -1.0))
                heads.append(_headings(dr, e, L))
        turn = max((abs(math.remainder(h - g, math.pi)) for h in heads for g in heads), default=0.0)
        if turn > 1e-6:
            out.append((name, ends))
    return out


CASES = [("theta.json", (1.0, 0.5)), ("two_sidings.json", (2.0, 0.8)), ("rail_yard.json", (1.0, 0.5))]


@pytest.mark.parametrize(("name", "rect_lw"), CASES)
def test_vertex_start_refused_iff_the_turning_disc_reaches_the_other_body(
    name: str, rect_lw: tuple[float, float]
) -> None:
    tr = GraphTrack.from_json(EXAMPLES / name)
    dr = drawn_of(tr)
    length, width = rect_lw
    reach = 0.5 * math.hypot(length, width)
    fp = mpa.Rectangle(length, width)
    rng = random.Random(23)
    verts = _turning_vertices(tr, dr)
    assert verts, name
    refused = accepted = 0
    for _ in range(80):
        vname, ends = rng.choice(verts)
        e, o_v, inward = rng.choice(ends)
        dist = rng.uniform(0.3, reach + 0.5 * length + 1.0)
        if dist >= float(tr.lengths[e]) - 0.05:
            continue
        ob = o_v + inward * dist
        centre = dr.point(e, o_v)
        body_b = rect(dr.point(e, ob), _headings(dr, e, ob), length, width)
        depth = reach - _point_to_rect(centre, body_b)  # > 0: the turning disc reaches into B's body
        if abs(depth) < 1e-6:
            continue
        a_first = rng.random() < 0.5
        pos_v, pos_b = tr.position(vname), (e, ob)
        start = (pos_v, pos_b) if a_first else (pos_b, pos_v)
        try:
            mpa.plan(tr, start, start, 0.0, footprint=fp)
        except InvalidInputError as exc:
            msg = str(exc)
            assert depth > 0, f"{name} {vname} B at {tr.position_name(e, ob)}: refused with depth {depth}: {msg}"
            robot = "A" if a_first else "B"
            assert f"robot {robot}" in msg and vname in msg and "overlap" in msg, msg
            refused += 1
        else:
            assert depth < 0, f"{name} {vname} B at {tr.position_name(e, ob)}: planned with depth {depth}"
            accepted += 1
    assert refused >= 5 and accepted >= 5, (refused, accepted)


def test_vertex_start_same_error_from_every_entry_point(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    theta = EXAMPLES / "theta.json"
    tr = GraphTrack.from_json(theta)
    start, goal = ("v", "middle:0.95"), ("upper:1.43626551009", "lower:0.386306940165")
    with pytest.raises(InvalidInputError) as planned:
        mpa.plan(tr, start, goal, 0.0, footprint="1.0x0.5")
    msg = str(planned.value)
    assert "robot A" in msg and " v," in msg and "by 0.00902 m" in msg, msg  # 0.559 - (1.05 - 0.5)
    with pytest.raises(InvalidInputError) as generated:
        trajopt.generate_trajectory(tr, start, goal, clearance=0.0, footprint="1.0x0.5")
    assert str(generated.value) == msg
    # the goal the same way (robots swapped)
    with pytest.raises(InvalidInputError) as at_goal:
        mpa.plan(tr, goal[::-1], start[::-1], 0.0, footprint="1.0x0.5")
    assert str(at_goal.value).startswith("goal has robot B (1x0.5) on a corner at v")
    out = tmp_path / "out"
    argv = ["trajectory", "--graph", str(theta), "--start", *start, "--goal", *goal, "--clearance", "0"]
    assert main([*argv, "--footprint", "1.0x0.5", "--out", str(out)]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert err == [f"error: {msg}"], err
    assert not out.exists()
    # further from the vertex the disc is clear: planned and verified
    traj = trajopt.generate_trajectory(tr, ("v", "middle:0.8"), goal, clearance=0.0, footprint="1.0x0.5")
    assert traj.plane is not None and traj.plane["ok"]


def test_vertex_start_free_in_one_orientation_only_is_refused() -> None:
    """The hunted one-way case of tests/mpa/test_planar_corners.py started with A on SW, its body apart from B's only in
    the orientation of the siding (in that of 'west' and 'main' they overlap): refused, not planned."""
    from tests.mpa.test_planar_corners import CASES, _layout

    se, pts, length, oneway, _, (lg, wd) = CASES[1]
    tr = GraphTrack.from_layout(_layout(se, pts, length, oneway))
    dr = drawn_of(tr)
    a, b = (1, 0.0), (0, 2.0583570525992587)
    # independent: in the orientation of 'main' (heading 0) the two rectangles overlap
    body_a = rect(dr.point(*a), _headings(dr, 1, 0.0), lg, wd)
    body_b = rect(dr.point(*b), _headings(dr, 0, b[1]), lg, wd)
    assert any(_inside(v, body_b) for v in body_a) or any(_inside(v, body_a) for v in body_b)
    for clearance in (0.0, 0.5):
        with pytest.raises(InvalidInputError, match=r"^start has robot A \(2.15908x0.413317\) on a corner at SW"):
            mpa.plan(
                tr,
                (a, b),
                ((0, 0.31419821261844083), (0, 3.8365748444234673)),
                clearance,
                footprint=mpa.Rectangle(lg, wd),
            )
