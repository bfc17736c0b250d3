"""Stage 5, the files: atomic writes (:mod:`~trajopt.io.atomic`), the setpoints CSV (:mod:`~trajopt.io.csvfile`),
output paths and run directories (:mod:`~trajopt.io.directory`) and the JSON summary (:mod:`~trajopt.io.summary`).
The ROS 2 and PVT exports are :mod:`trajopt.io.ros` and :mod:`trajopt.io.pvt`.
"""

from __future__ import annotations

from trajopt.io.atomic import (
    Content,
    Streamed,
    atomic_path,
    atomic_write,
    atomic_write_bytes,
    atomic_write_text,
    content_text,
)
from trajopt.io.csvfile import (
    CSV_CHUNK_ROWS,
    CSV_COLUMNS,
    GRAPH_CSV_COLUMNS,
    HEADING_COLUMNS,
    XY_COLUMNS,
    csv_chunks,
    csv_field,
    csv_line,
    write_csv,
)
from trajopt.io.directory import (
    atomic_directory,
    directory_lock,
    validate_output_path,
    write_directory,
    write_output_file,
)
from trajopt.io.directory import check_output_path as check_output_path  # deprecated: validate_output_path
from trajopt.io.summary import summary, write_json

__all__ = [
    "CSV_CHUNK_ROWS",
    "CSV_COLUMNS",
    "GRAPH_CSV_COLUMNS",
    "HEADING_COLUMNS",
    "XY_COLUMNS",
    "Content",
    "Streamed",
    "atomic_directory",
    "atomic_path",
    "atomic_write",
    "atomic_write_bytes",
    "atomic_write_text",
    "content_text",
    "csv_chunks",
    "csv_field",
    "csv_line",
    "directory_lock",
    "summary",
    "validate_output_path",
    "write_csv",
    "write_directory",
    "write_json",
    "write_output_file",
]
