"""The compact free space: polygon numbers and ids from arrays, components merged block by block, bounded memory."""

from __future__ import annotations

import tracemalloc

import numpy as np
import pytest

import mpa.freespace as fsmod
from mpa.errors import InvalidInputError
from mpa.freespace import FreeSpace, check_size
from mpa.graph_track import GraphTrack
from tests.helpers.graph_helpers import random_layout


def _path(n: int) -> GraphTrack:
    return GraphTrack.from_layout({"edges": [[f"v{i}", f"v{i + 1}", 1.0] for i in range(n)]})


def test_polygon_ids_are_a_sequence_equal_to_the_list_of_polygons() -> None:
    rng = np.random.default_rng(11)
    for _ in range(20):
        track = random_layout(rng)
        fs = FreeSpace(track, float(rng.uniform(0.0, 1.5)))
        ids = fs.polygon_ids
        ref = list(zip(fs._pe.tolist(), fs._pf.tolist(), fs._pk.tolist()))
        assert len(ids) == len(ref) == len(fs._index)
        assert list(ids) == ref and ids == ref and ids[1:4] == ref[1:4]
        assert [ids[i] for i in range(-len(ref), len(ref))] == ref + ref
        assert all(fs._index[pid] == i for i, pid in enumerate(ids))
        assert ids != ref[:-1] and ids != [*ref[:-1], (-1, -1, 0)]
        # every polygon is a free cell's piece: piece 1 only on one edge, none of an empty cell
        for e, f, k in ids:
            assert fs.status[e, f] != 0 and (k == 0 or e == f), (track.to_dict(), e, f, k)


def test_nonempty_cells_are_the_cells_with_polygons_in_row_major_order(monkeypatch: pytest.MonkeyPatch) -> None:
    rng = np.random.default_rng(12)
    for block in (1, 7, 50, 1 << 18):
        monkeypatch.setattr(fsmod, "CELL_BLOCK", block)
        track = random_layout(rng)
        fs = FreeSpace(track, float(rng.uniform(0.0, 1.5)))
        ee = np.concatenate([e for e, _ in fs.nonempty_cells()])
        ff = np.concatenate([f for _, f in fs.nonempty_cells()])
        re, rf = np.nonzero(fs.status)
        assert np.array_equal(ee, re) and np.array_equal(ff, rf), (block, track.to_dict())


@pytest.mark.parametrize("seed", range(8))
def test_components_merged_block_by_block_equal_a_union_find(seed: int, monkeypatch: pytest.MonkeyPatch) -> None:
    rng = np.random.default_rng(300 + seed)
    for _ in range(8):
        track = random_layout(rng, loops=bool(rng.integers(2)))
        d = float(rng.uniform(0.0, 1.5))
        ref = FreeSpace(track, d)  # a union-find in Python (tiny layouts)
        block = int(rng.integers(1, 40))
        monkeypatch.setattr(fsmod, "SMALL_POLYGONS", 0)
        monkeypatch.setattr(fsmod, "SCIPY_POLYGONS", 0)
        monkeypatch.setattr(fsmod, "COMPONENT_BLOCK", block)
        merged = FreeSpace(track, d)
        monkeypatch.undo()
        case = (seed, block, d, track.to_dict())
        assert merged.n_components == ref.n_components, case
        assert np.array_equal(merged.polygon_component, ref.polygon_component), case
        assert ref.polygon_component[0] == 0 and set(ref.polygon_component.tolist()) == set(range(ref.n_components))


def test_merged_components_of_a_known_graph() -> None:
    # 0-1-2 joined across two blocks, 3 alone, 4-5 in the second block, 6-0 in the third: {0, 1, 2, 6}, {3}, {4, 5}
    blocks = [
        (np.array([0], dtype=np.int32), np.array([1], dtype=np.int32)),
        (np.array([1, 4], dtype=np.int32), np.array([2, 5], dtype=np.int32)),
        (np.array([], dtype=np.int32), np.array([], dtype=np.int32)),
        (np.array([6], dtype=np.int32), np.array([2], dtype=np.int32)),
    ]
    lab = fsmod._merged_components(7, blocks)
    groups = {i: int(lab[i]) for i in range(7)}
    assert len({groups[i] for i in (0, 1, 2, 6)}) == 1
    assert len({groups[0], groups[3], groups[4]}) == 3 and groups[4] == groups[5]
    assert all(lab[lab[i]] == lab[i] for i in range(7))  # every label a root


def test_the_build_keeps_a_few_bytes_per_cell(monkeypatch: pytest.MonkeyPatch) -> None:
    """A 300-edge layout (90 300 polygons) built as large layouts are (the compact index, the components merged by
    blocks): the build's peak and what it keeps, per cell (``tracemalloc``).

    The compact free space keeps per cell an int8 status, two int32 and an int8 of its polygon's edges and piece, an
    int32 component, and the polygon index's int32 and bit per cell (about 20 bytes), the faces per vertex and edge
    (17 bytes per cell on a path, where there are as many vertices as edges); a Python object per polygon would be
    60-150 bytes per cell.
    """
    track = _path(300)
    monkeypatch.setattr(fsmod, "INDEX_DICT_POLYGONS", 0)
    monkeypatch.setattr(fsmod, "SCIPY_POLYGONS", 0)
    monkeypatch.setattr(fsmod, "CELL_BLOCK", 1 << 12)  # blocks small beside the layout, as on large layouts
    monkeypatch.setattr(fsmod, "COMPONENT_BLOCK", 1 << 12)
    FreeSpace(track, 1.0)  # the vertex distances and imports outside the measurement
    tracemalloc.start()
    fs = FreeSpace(track, 1.0)
    kept, peak = tracemalloc.get_traced_memory()
    tracemalloc.stop()
    cells = track.n_edges**2
    assert len(fs.polygon_ids) > 0.9 * cells
    print(f"kept {kept / cells:.1f} B/cell, peak {peak / cells:.1f} B/cell")
    assert kept < 48 * cells and peak < 120 * cells, (kept / cells, peak / cells)


def test_the_size_budget_admits_3000_edges_and_refuses_above_it_before_any_work() -> None:
    check_size(_path(3000))  # 9e6 cells: inside the budget
    n = int(fsmod.MAX_CELLS**0.5) + 1
    with pytest.raises(InvalidInputError) as err:
        check_size(_path(n))
    msg = str(err.value)
    assert f"{n} edges" in msg and f"{n * n} cells" in msg and str(fsmod.MAX_CELLS) in msg, msg


@pytest.mark.slow
def test_a_3000_edge_layout_plans_exactly_on_its_compact_free_space() -> None:
    """A 3 000-edge path: the robots keep their order (two components) and the plan is the straight move."""
    import mpa

    track = _path(3000)
    plan = mpa.plan(track, ("e0:0.5", "e10:0.5"), ("e2990:0.5", "e2999:0.5"), 1.0, planner="graph")
    assert plan.min_distance() >= 1.0 - 1e-9
    assert plan.makespan == pytest.approx(2990.0, rel=1e-9), plan.makespan
    fs = fsmod.free_space(track, 1.0)
    assert fs.n_components == 2 and len(fs.polygon_ids) == 3000 * 3000 + 3000
