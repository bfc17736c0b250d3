"""The planar free space's fast build (culled sub-cells, clips skipped where they keep or drop every vertex, cached
turn blocks) gives the same pieces as the plain construction, polygon by polygon, and agrees with a direct check of
the bodies in the plane at seeded random configurations."""

from __future__ import annotations

from pathlib import Path
from typing import Any

import numpy as np
import pytest

from mpa.footprint import Disc, Rectangle
from mpa.freespace import _clip, _dedupe
from mpa.graph_track import GraphTrack
from mpa.planar import PlanarFreeSpace, _area, bodies_gap
from tests.mpa.test_footprints import random_layout

ROOT = Path(__file__).resolve().parents[2]
EXAMPLES = ROOT / "examples" / "tracks"
OFFICE = ROOT / "tests" / "data" / "openrmf" / "office.building.yaml"


def _plain_pieces(space: PlanarFreeSpace) -> list[tuple[Any, Any, np.ndarray]]:
    """The free pieces by the definition: every sub-cell (none culled) cut by its whole obstacle, one clip after
    the other (module docstring of :mod:`mpa.planar`)."""
    base, d = space.base, space.drawing
    eps = 1e-12 * max(1.0, float(space.track.lengths.max()))
    out = []
    for e, f, k in base.polygon_ids:
        bpoly = [tuple(x) for x in base.vertices((e, f, k))]
        for pa in d.edge_pieces[e]:
            ra = _clip(_clip(bpoly, 1.0, 0.0, float(d.piece_s0[pa])), -1.0, 0.0, -float(d.piece_s1[pa]))
            for pb in d.edge_pieces[f] if ra else ():
                t0, t1 = float(d.piece_s0[pb]), float(d.piece_s1[pb])
                r = _dedupe(_clip(_clip(ra, 0.0, 1.0, t0), 0.0, -1.0, -t1), eps)
                if not r:
                    continue
                key = ((e, f, k), (int(pa), int(pb)))
                hp = space._obstacle(int(pa), int(pb)) or []
                inner = r
                for a_, b_, c_ in hp:
                    inner = _clip(inner, -a_, -b_, -c_) if inner else inner
                small = not inner or _area(inner) <= eps * eps or len(_dedupe(inner, eps)) < 3
                if small and (not inner or abs(_area(r)) > eps * eps):
                    out.append((*key, np.asarray(r, dtype=float)))
                    continue
                for i, (a_, b_, c_) in enumerate(hp):
                    if abs(a_) + abs(b_) <= 1e-15:
                        continue
                    q = _clip(r, a_, b_, c_)
                    for a2, b2, c2 in hp[:i]:
                        q = _clip(q, -a2, -b2, -c2) if q else q
                    q = _dedupe(q, eps)
                    if q:
                        out.append((*key, np.asarray(q, dtype=float)))
    return out


CASES = [
    (OFFICE, Disc(0.3), 0.5),
    (OFFICE, Rectangle(0.6, 0.4), 0.5),
    (EXAMPLES / "figure_eight.json", Disc(0.5), 1.0),
    (EXAMPLES / "two_sidings.json", Rectangle(1.5, 0.8), 1.0),
    (EXAMPLES / "theta.json", (Disc(0.3), Rectangle(1.0, 0.5)), 0.7),
]


@pytest.mark.parametrize(("path", "fp", "clearance"), CASES, ids=lambda x: getattr(x, "name", None))
def test_fast_build_equals_plain_construction(path: Path, fp: Any, clearance: float) -> None:
    tr = GraphTrack.from_file(path)
    space = PlanarFreeSpace(tr, clearance, fp)
    plain = _plain_pieces(space)
    assert len(space.pieces) == len(plain) > 0
    for n, (p, (cell, sub, poly)) in enumerate(zip(space.pieces, plain, strict=True)):
        same = p.cell == cell and p.sub == sub and np.array_equal(p.poly, poly)
        assert same, f"piece {n}: fast {p.cell} {p.sub} {p.poly.tolist()} vs plain {cell} {sub} {poly.tolist()}"


def test_pieces_agree_with_the_bodies_at_random_configurations() -> None:
    """A configuration lies in a free piece iff it is free by a direct check (along-track clearance and the exact
    distance of the bodies), away from the boundary: the discs' circumscribed polygon is at most 0.5 % of the
    summed radius conservative."""
    rng = np.random.default_rng(23)
    checked = 0
    for _ in range(4):
        tr = GraphTrack.from_layout(random_layout(rng))
        for fp, band in ((Disc(float(rng.uniform(0.1, 0.6))), 0.006), (Rectangle(1.2, 0.5), 1e-6)):
            space = PlanarFreeSpace(tr, 0.8, fp)
            reach = 2.0 * space.footprints.a.reach
            for _ in range(300):
                pa, pb = [(int(e), float(rng.uniform(0.0, tr.lengths[e]))) for e in rng.integers(tr.n_edges, size=2)]
                g = bodies_gap(tr, space.footprints, pa, pb)
                if abs(g) <= band * reach:
                    continue
                direct = space.base.is_free(pa, pb) and g > 0.0
                placed = bool(space.placements(pa, pb))
                assert placed == direct, f"{fp} at {pa}, {pb}: pieces say {placed}, bodies {g:.6g} m apart"
                checked += 1
    assert checked > 1500
