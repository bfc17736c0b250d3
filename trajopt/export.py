"""Compatibility re-exports: the result type and the files' writers (:mod:`trajopt.result`, :mod:`trajopt.grid`,
:mod:`trajopt.io`) under the names of ``trajopt.export``.

:class:`~trajopt.result.Trajectory`, :class:`~trajopt.result.Source` and :func:`~trajopt.result.verified_rows`
live in :mod:`trajopt.result`; the rate and the time grid in :mod:`trajopt.grid`; atomic writes, the CSV, output
directories and the JSON summary in :mod:`trajopt.io`. New code imports from there.
"""

from __future__ import annotations

from trajopt.grid import check_rate as check_rate  # deprecated name of validate_rate
from trajopt.grid import time_grid, validate_rate
from trajopt.io.atomic import Content, Streamed, atomic_write_bytes, atomic_write_text, content_text
from trajopt.io.csvfile import (
    CSV_CHUNK_ROWS,
    CSV_COLUMNS,
    GRAPH_CSV_COLUMNS,
    HEADING_COLUMNS,
    XY_COLUMNS,
    csv_field,
    csv_line,
)
from trajopt.io.directory import PAUSE_ENV, directory_lock, validate_output_path, write_directory, write_output_file
from trajopt.io.directory import check_output_path as check_output_path  # deprecated: validate_output_path
from trajopt.io.summary import _json_default as _json_default
from trajopt.result import Source, Trajectory, verified_rows

__all__ = [
    "CSV_CHUNK_ROWS",
    "CSV_COLUMNS",
    "GRAPH_CSV_COLUMNS",
    "HEADING_COLUMNS",
    "PAUSE_ENV",
    "XY_COLUMNS",
    "Content",
    "Source",
    "Streamed",
    "Trajectory",
    "atomic_write_bytes",
    "atomic_write_text",
    "content_text",
    "csv_field",
    "csv_line",
    "directory_lock",
    "time_grid",
    "validate_output_path",
    "validate_rate",
    "verified_rows",
    "write_directory",
    "write_output_file",
]
