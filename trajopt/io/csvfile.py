"""The setpoints CSV: its pinned columns, RFC 4180 fields and lines, and the file's text a piece at a time.

Paper tracks: header ``time,a_track,a_s,a_v,a_a,a_j,b_track,b_s,b_v,b_a,b_j,a_edge,a_offset,a_dir,b_edge,b_offset,
b_dir`` (:data:`CSV_COLUMNS`); one row every ``1/rate`` seconds from 0. ``*_track`` is the track coordinate,
``*_s`` the route coordinate σ (signed distance travelled along the robot's own route, continuous through P and
round the loop), ``*_v/_a/_j`` its first three time derivatives. Graph tracks (layouts): header
``time,a_edge,a_offset,a_s,a_v,a_a,a_j,b_edge,b_offset,b_s,b_v,b_a,b_j,a_dir,b_dir`` (:data:`GRAPH_CSV_COLUMNS`)
and ``a_x,a_y,b_x,b_y`` when the layout has vertex coordinates (:data:`XY_COLUMNS`); ``*_s`` is the distance
travelled along the robot's route. On both, ``*_edge`` is the edge's name (the paper tracks' graph form:
``stick``, ``loop``), ``*_offset`` metres from the edge's ``from`` vertex, ``*_dir`` the direction of travel on
that edge (+1 along its orientation, -1 against, 0 at rest). See docs/conventions.md, "Command line and files".
"""

from __future__ import annotations

import csv
import io
import os
from collections.abc import Iterable, Iterator
from typing import TYPE_CHECKING, Any

import numpy as np

from trajopt.io.directory import validate_output_path, write_output_file

if TYPE_CHECKING:
    from trajopt.result import Trajectory
from trajopt.io.atomic import Streamed

#: The pinned CSV columns of the paper's tracks, in order.
CSV_COLUMNS = (
    "time",
    "a_track",
    "a_s",
    "a_v",
    "a_a",
    "a_j",
    "b_track",
    "b_s",
    "b_v",
    "b_a",
    "b_j",
    "a_edge",
    "a_offset",
    "a_dir",
    "b_edge",
    "b_offset",
    "b_dir",
)
#: The pinned CSV columns on a layout (:class:`mpa.GraphTrack`), in order.
GRAPH_CSV_COLUMNS = (
    "time",
    "a_edge",
    "a_offset",
    "a_s",
    "a_v",
    "a_a",
    "a_j",
    "b_edge",
    "b_offset",
    "b_s",
    "b_v",
    "b_a",
    "b_j",
    "a_dir",
    "b_dir",
)
#: Appended to :data:`GRAPH_CSV_COLUMNS` when the layout has vertex coordinates: points on the drawn edges (m).
XY_COLUMNS = ("a_x", "a_y", "b_x", "b_y")
#: Columns after :data:`XY_COLUMNS` when the motion was made with a footprint: each robot's heading (radians, the
#: direction of its piece of the drawing, :class:`mpa.footprint.Drawing`).
HEADING_COLUMNS = ("a_heading", "b_heading")


#: Rows of one piece of :meth:`Trajectory.csv_chunks` (about 12 MB of text on a layout with coordinates).
CSV_CHUNK_ROWS = 65536


def csv_field(value: str) -> str:
    """``value`` as one CSV field, quoted as RFC 4180 asks when it holds a comma, a quote or a line break.

    Written by :mod:`csv`'s writer (``QUOTE_MINIMAL`` with the RFC's ``\\r\\n`` as the line terminator, so a
    lone ``\\r`` is quoted too); :func:`csv.reader` reads back exactly ``value`` (the empty string as ``""``).
    """
    buf = io.StringIO()
    csv.writer(buf, lineterminator="\r\n", quoting=csv.QUOTE_MINIMAL).writerow([value])
    return buf.getvalue()[:-2]


def csv_line(cells: Iterable[Any]) -> str:
    """One CSV record: the cells as :func:`csv_field` (``str`` of each), comma-separated, ending in ``\\n``."""
    return ",".join(csv_field(str(c)) for c in cells) + "\n"


def csv_chunks(traj: Trajectory) -> Iterator[bytes]:
    """The CSV text of ``traj``'s rows (UTF-8) in pieces of at most :data:`CSV_CHUNK_ROWS` rows, the header first.

    Each piece is formatted when it is asked for. Numbers are ``"%.12g"``, the edge names RFC 4180 fields
    (:func:`csv_field`), ``*_dir`` integers (:mod:`trajopt.io.csv_kernels`).
    """
    from trajopt.io.csv_kernels import csv_rows, format_g12, text_column

    columns = traj.columns
    names = [csv_field(n) for n in traj.edge_names]
    e, o, d = traj._positions()
    col: dict[str, tuple[str, Any]] = {"time": ("f", traj.t)}
    for r, x in enumerate("ab"):
        col.update(
            {
                f"{x}_track": ("f", traj.track[:, r]),
                f"{x}_s": ("f", traj.s[:, r]),
                f"{x}_v": ("f", traj.v[:, r]),
                f"{x}_a": ("f", traj.a[:, r]),
                f"{x}_j": ("f", traj.j[:, r]),
                f"{x}_edge": ("name", e[:, r]),
                f"{x}_offset": ("f", o[:, r]),
                f"{x}_dir": ("int", d[:, r]),
            }
        )
    if "b_y" in columns:
        p = traj.xy()
        col.update({"a_x": ("f", p[:, 0, 0]), "a_y": ("f", p[:, 0, 1]), "b_x": ("f", p[:, 1, 0])})
        col["b_y"] = ("f", p[:, 1, 1])
    if "b_heading" in columns:
        h = traj.headings()
        col.update({"a_heading": ("f", h[:, 0]), "b_heading": ("f", h[:, 1])})
    yield csv_line(columns).encode("utf-8")
    for i in range(0, len(traj.t), CSV_CHUNK_ROWS):
        cells = []
        for name in columns:
            kind, x = col[name]
            x = x[i : i + CSV_CHUNK_ROWS]
            if kind == "f":
                cells.append(format_g12(x))
            elif kind == "name":
                cells.append(text_column(names, x))
            else:
                values, index = np.unique(x, return_inverse=True)
                cells.append(text_column([str(int(v)) for v in values], index.reshape(-1)))
        yield csv_rows(cells)


def write_csv(traj: Trajectory, path: str | os.PathLike[str], rate: float | None = None) -> None:
    """Write ``traj``'s setpoints as CSV (atomically, piece by piece); ``rate`` (Hz) defaults to its own.

    At another rate the rows are verified at that rate first (:meth:`trajopt.result.Trajectory.at_rate`);
    nothing is written if that fails.

    Raises
    ------
    InvalidInputError
        ``path`` is not a file path (empty, a directory, not a string or path), the file cannot be written
        (the message names the path and the reason), or ``rate`` is invalid or too low.
    """
    target = validate_output_path(path)
    chunks = traj.csv_chunks(rate)  # verified at the rate before anything is written
    write_output_file(target, Streamed(lambda: chunks))
