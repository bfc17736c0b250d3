"""The compiled CSV writer gives byte for byte the text of the row-by-row writer it replaced.

The reference below is the writer of the library before the compiled formatting (``"%.12g"`` of every number with
:func:`numpy.char.mod`, names as :func:`trajopt.export.csv_field`, ``str`` of the directions), kept here as the
definition of the format (docs/conventions.md).
"""

from __future__ import annotations

import io
import json
from pathlib import Path
from typing import Any

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

import trajopt.io.csvfile as csvfile
from mpa import GraphTrack, Lollipop
from mpa.footprint import Disc
from trajopt import generate_trajectory
from trajopt.cli.main import main
from trajopt.export import Streamed, Trajectory, csv_field, csv_line
from trajopt.io.csv_kernels import csv_rows, format_g12, text_column

ROOT = Path(__file__).resolve().parents[2]
TRACKS = ROOT / "examples" / "tracks"


def reference_csv(tr: Trajectory) -> str:
    """The setpoints CSV as the row-by-row writer made it."""
    names = np.asarray([csv_field(n) for n in tr.edge_names], dtype=object)
    e, o, d = tr._positions()
    col: dict[str, Any] = {"time": tr.t}
    for r, x in enumerate("ab"):
        col.update(
            {
                f"{x}_track": tr.track[:, r],
                f"{x}_s": tr.s[:, r],
                f"{x}_v": tr.v[:, r],
                f"{x}_a": tr.a[:, r],
                f"{x}_j": tr.j[:, r],
                f"{x}_edge": names[e[:, r]],
                f"{x}_offset": o[:, r],
                f"{x}_dir": d[:, r],
            }
        )
    columns = tr.columns
    if "b_y" in columns:
        p = tr.xy()
        col.update({"a_x": p[:, 0, 0], "a_y": p[:, 0, 1], "b_x": p[:, 1, 0], "b_y": p[:, 1, 1]})
    if "b_heading" in columns:
        h = tr.headings()
        col.update({"a_heading": h[:, 0], "b_heading": h[:, 1]})
    text = []
    for name in columns:
        x = col[name]
        if x.dtype == object or np.issubdtype(x.dtype, np.integer):
            text.append(x.astype(str))
        else:
            text.append(np.char.mod("%.12g", x))
    buf = io.StringIO()
    buf.write(csv_line(columns))
    if len(tr.t):
        rows = text[0].astype(object)
        for x in text[1:]:
            rows = rows + "," + x.astype(object)
        buf.write("\n".join(rows.tolist()) + "\n")
    return buf.getvalue()


def _layout(name: str) -> GraphTrack:
    return GraphTrack.from_layout(json.loads((TRACKS / name).read_text()))


CASES = {
    "lollipop": lambda: generate_trajectory(Lollipop(1, 1), (0.2, 0.5), (0.5, 0.2)),
    "lollipop 1 Hz": lambda: generate_trajectory(Lollipop(2, 1.5), (0.1, 1.3), (1.9, 0.4), rate=1),
    "lollipop 1 kHz": lambda: generate_trajectory(Lollipop(1, 1), (0.1, 0.6), (0.8, 0.3), rate=1000),
    "y junction": lambda: generate_trajectory(_layout("y_junction.json"), ("left", "right"), ("right", "left")),
    "passing loop, disc": lambda: generate_trajectory(
        _layout("passing_loop.json"), ("W", "E"), ("E", "W"), footprint=Disc(0.3), clearance=0.0
    ),
    "names with commas, quotes, line breaks": lambda: generate_trajectory(
        GraphTrack.from_layout({"edges": [['J "x"', "a,1", 1.0], ['J "x"', "b\r\n", 2.0], ['J "x"', "ç", 2.0]]}),
        ("a,1", "b\r\n"),
        ("b\r\n", "a,1"),
        clearance=0.3,
    ),
    "start equals goal": lambda: generate_trajectory(Lollipop(1, 1), (0.2, 0.6), (0.2, 0.6)),
}


@pytest.mark.parametrize("case", list(CASES))
def test_csv_is_byte_identical_to_the_row_by_row_writer(case: str, monkeypatch: pytest.MonkeyPatch) -> None:
    tr = CASES[case]()
    ref = reference_csv(tr)
    assert tr.csv_text() == ref
    monkeypatch.setattr(csvfile, "CSV_CHUNK_ROWS", 7)  # many pieces: the seams between them too
    pieces = list(tr.csv_chunks())
    assert len(pieces) == 1 + -(-len(tr.t) // 7)
    assert b"".join(pieces).decode("utf-8") == ref


def test_cli_writes_the_same_bytes(tmp_path: Path) -> None:
    q = ["--graph", str(TRACKS / "y_junction.json"), "--start", "left", "right", "--goal", "right", "left"]
    assert main(["trajectory", *q, "--rate", "250", "--out", str(tmp_path / "o")]) == 0
    tr = generate_trajectory(_layout("y_junction.json"), ("left", "right"), ("right", "left"), rate=250)
    assert (tmp_path / "o" / "setpoints.csv").read_bytes() == reference_csv(tr).encode("utf-8")


def test_to_csv_streams_the_same_bytes(tmp_path: Path) -> None:
    tr = CASES["lollipop"]()
    tr.to_csv(tmp_path / "x.csv")
    assert (tmp_path / "x.csv").read_text(encoding="utf-8") == reference_csv(tr)
    assert Streamed(tr.csv_chunks).data().decode() == reference_csv(tr)


def _python_g12(x: np.ndarray) -> list[str]:
    return ["%.12g" % v for v in x.tolist()]  # noqa: UP031 - the format under test


def _kernel_g12(x: np.ndarray) -> list[str]:
    text, lens = format_g12(x)
    return [bytes(text[i, : lens[i]]).decode("ascii") for i in range(len(x))]


@settings(max_examples=300, deadline=None)
@given(st.lists(st.floats(allow_nan=True, allow_infinity=True, width=64), min_size=1, max_size=50))
def test_g12_is_pythons_format(values: list[float]) -> None:
    x = np.asarray(values, dtype=np.float64)
    got, want = _kernel_g12(x), _python_g12(x)
    bad = [(v, g, w) for v, g, w in zip(values, got, want, strict=True) if g != w]
    assert not bad, bad


def test_g12_on_seeded_magnitudes_ties_and_powers_of_ten() -> None:
    rng = np.random.default_rng(28)
    x = np.concatenate(
        [
            rng.normal(size=20000) * 10.0 ** rng.uniform(-320, 308, 20000),
            rng.normal(size=20000) * 10.0 ** rng.uniform(-6, 14, 20000),
            np.round(rng.normal(size=20000) * 1e4, 3),
            np.arange(-5000, 5000) / 100.0,
            10.0 ** np.arange(-323, 309),
            np.nextafter(10.0 ** np.arange(-20, 20), 0.0),
            np.nextafter(10.0 ** np.arange(-20, 20), np.inf),
            [0.0, -0.0, 0.1 + 0.2, 999999999999.5, 9999999999995.0, 123456789012.5, 5e-324, 1.7976931348623157e308],
        ]
    )
    got, want = _kernel_g12(x), _python_g12(x)
    bad = [(v, g, w) for v, g, w in zip(x.tolist(), got, want, strict=True) if g != w]
    assert not bad, bad[:20]


def test_rows_join_cells_with_commas_and_end_in_newlines() -> None:
    names = [csv_field(n) for n in ("a", 'q"', "x,y")]
    cols = [format_g12(np.array([1.5, -0.0, 1e-7])), text_column(names, np.array([2, 0, 1]))]
    assert csv_rows(cols) == b'1.5,"x,y"\n-0,a\n1e-07,"q"""\n'
    assert csv_rows([format_g12(np.zeros(0))]) == b""


def reference_points_yaml(tr: Trajectory) -> str:
    """The ``points`` of the ROS 2 YAML as the point-by-point writer made them."""
    from trajopt.io.ros import _f, joint_points, split_ns

    pts = joint_points(tr)
    out = []
    for k in range(len(pts.t)):
        sec, nsec = split_ns(int(pts.ns[k]))
        out += [
            f"- positions: [{', '.join(_f(v) for v in pts.positions[k])}]",
            f"  velocities: [{', '.join(_f(v) for v in pts.velocities[k])}]",
            f"  accelerations: [{', '.join(_f(v) for v in pts.accelerations[k])}]",
            "  effort: []",
            "  time_from_start:",
            f"    sec: {sec}",
            f"    nanosec: {nsec}",
        ]
    return "\n".join(out) + "\n"


@pytest.mark.parametrize("case", ["lollipop 1 kHz", "y junction", "start equals goal"])
def test_ros2_yaml_points_are_byte_identical_to_the_point_by_point_writer(
    case: str, monkeypatch: pytest.MonkeyPatch
) -> None:
    import trajopt.io.ros as ros

    tr = CASES[case]()
    monkeypatch.setattr(ros, "_POINTS_PER_PIECE", 5)
    text = ros.ros2_yaml_text(tr)
    assert text.split("points:\n", 1)[1] == reference_points_yaml(tr)


def test_ros2_yaml_floats_are_reprs_with_a_point_before_the_exponent() -> None:
    from trajopt.io.ros import _f, _floats_yaml

    x = np.array([0.0, -0.0, 1e-4, 9.9e-5, 1e16, 9999999999999998.0, -3e-300, 5e-324, 2.5, np.inf, -np.inf, np.nan])
    assert _floats_yaml(x) == [_f(v) for v in x.tolist()]
