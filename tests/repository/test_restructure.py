"""The split modules: old import paths still give the same objects, the summary computes margins only when asked,
the prose of a motion has its own name, and the one atomic write leaves nothing half-written."""

from __future__ import annotations

import json
import os
from pathlib import Path

import pytest

import trajopt.export as export
import trajopt.io as tio
import trajopt.result as result
import trajopt.timing as timing
from mpa import Lollipop
from trajopt.generator import generate_trajectory
from trajopt.io.atomic import atomic_path, atomic_write_text

#: Every name imported from ``trajopt.timing`` by the project's modules, tests and experiments.
TIMING_NAMES = (
    "BlendedPath Limits PieceLimits RestToRest TimeScaling blend_polyline filtered_scaling jerk_limited_scaling "
    "min_time_rest_to_rest piece_limits reachable_speed rest_to_rest_profile spline_path toppra_profile "
    "_constant_acceleration_phases _eroded_flat_top_profile _window_extreme _window_min"
).split()


def test_timing_names_are_reexported_from_their_modules() -> None:
    import importlib

    for name in TIMING_NAMES:
        obj = getattr(timing, name)
        home = importlib.import_module(obj.__module__)
        assert home.__name__.startswith("trajopt.timing."), (name, home.__name__)
        assert getattr(home, name) is obj


def test_the_gates_margin_and_the_reachable_speed_keep_their_generator_names() -> None:
    """``separation_margin`` lives with the gate and ``reachable_speed`` with the jerk-limited timing; the
    generator's names are the same objects, and the margin is ``2·Σ amax·Δt²/8 + 1e-9`` for equal limits."""
    import trajopt.generator as generator
    import trajopt.verify.gate as verify
    from trajopt.timing import Limits

    assert generator.separation_margin is verify.separation_margin
    assert generator.reachable_speed is timing.reachable_speed
    lim = Limits(vmax=1.0, amax=(2.0, 3.0), jmax=5.0)
    assert verify.separation_margin(lim, 100.0) == pytest.approx(2.0 * 5.0 * 1e-4 / 8.0 + 1e-9, rel=1e-12)


def test_export_names_are_the_result_and_io_objects() -> None:
    assert export.Trajectory is result.Trajectory and export.Source is result.Source
    assert export.verified_rows is result.verified_rows
    for name in ("CSV_COLUMNS", "GRAPH_CSV_COLUMNS", "XY_COLUMNS", "Streamed", "atomic_write_text", "write_directory"):
        assert getattr(export, name) is getattr(tio, name), name


@pytest.fixture(scope="module")
def swap():  # type: ignore[no-untyped-def]
    return generate_trajectory(Lollipop(1.0, 1.0), (0.2, 0.5), (0.5, 0.2))


def test_summary_computes_margins_only_when_asked(swap, tmp_path: Path) -> None:  # type: ignore[no-untyped-def]
    plain = swap.summary()
    assert "margins" not in plain
    assert "_margins" not in swap.__dict__  # nothing computed behind the caller's back
    full = swap.summary(margins=True)
    assert full["margins"] == swap.margins().to_dict()
    assert list(full) == [*[k for k in plain if k != "words"], "margins", "words"]  # the file's key order
    swap.to_json(tmp_path / "s.json")
    on_disk = json.loads((tmp_path / "s.json").read_text())
    assert on_disk["margins"] == json.loads(json.dumps(full["margins"]))
    swap.to_json(tmp_path / "bare.json", margins=False)
    assert "margins" not in json.loads((tmp_path / "bare.json").read_text())


def test_description_is_the_prose_and_words_is_deprecated(swap) -> None:  # type: ignore[no-untyped-def]
    prose = swap.description()
    assert set(prose) == {"A", "B"} and all(isinstance(v, str) and v for v in prose.values())
    assert isinstance(swap.word, tuple)  # the homotopy class keeps its name
    with pytest.warns(DeprecationWarning, match="description"):
        assert swap.words() == prose


def test_atomic_path_replaces_only_on_success(tmp_path: Path) -> None:
    target = tmp_path / "out.gif"
    atomic_write_text(target, "old")
    with pytest.raises(RuntimeError), atomic_path(target, suffix=".gif") as tmp:
        assert tmp.parent == tmp_path and tmp.name.endswith(".tmp.gif") and tmp.exists()
        tmp.write_text("half")
        raise RuntimeError("writer died")
    assert target.read_text() == "old"
    assert sorted(p.name for p in tmp_path.iterdir()) == ["out.gif"]
    with atomic_path(target, suffix=".gif") as tmp:
        tmp.write_text("new")
    assert target.read_text() == "new"
    mask = os.umask(0)
    os.umask(mask)
    assert target.stat().st_mode & 0o777 == 0o666 & ~mask
    assert sorted(p.name for p in tmp_path.iterdir()) == ["out.gif"]


def test_atomic_path_removes_a_dead_writers_temporary(tmp_path: Path) -> None:
    target = tmp_path / "a.png"
    dead = 2**22 + 12345  # above the default pid_max: no such process
    stale = tmp_path / f".a.png.{dead}.abcd.tmp.png"
    stale.write_text("left by kill -9")
    with atomic_path(target, suffix=".png") as tmp:
        tmp.write_text("x")
    assert not stale.exists() and target.read_text() == "x"


def test_former_flat_names_are_the_moved_modules() -> None:
    """``trajopt.margins`` & co. (the modules before they moved into trajopt.path, .verify, .analysis and .io)
    import as the very module objects of their new places, by ``import`` and by ``from trajopt import``."""
    import importlib

    from trajopt._aliases import FORMER_NAMES

    assert len(FORMER_NAMES) == 18
    for old, new in FORMER_NAMES.items():
        assert importlib.import_module(f"trajopt.{old}") is importlib.import_module(new), old
    from trajopt import gate_kernels, stability
    from trajopt.analysis import stability as moved
    from trajopt.verify import kernels

    assert stability is moved and gate_kernels is kernels
    with pytest.raises(ModuleNotFoundError):
        importlib.import_module("trajopt.no_such_module")
