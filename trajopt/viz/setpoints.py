"""A figure of setpoints read back from files (``mpa plot``): no :class:`~trajopt.result.Trajectory` needed.

:func:`read_rows` reads a setpoints file of the project (``setpoints.csv``: ``time,a_track,a_s,...``; ``pvt.csv``:
``time,a_s,a_v,b_s,b_v``; any CSV with a ``time`` column and ``a_*``/``b_*`` columns) into columns;
:func:`plot_rows` draws the track with both carts' motion (when the track is known: a paper track, or a graph
layout drawn with :mod:`trajopt.viz.layout`), the configuration space (track coordinates of A and B, with the band
``d < D`` on a paper track) and the profiles ``s, v, a, j`` that the file has, A solid and B dashed.
"""

from __future__ import annotations

import csv
from collections.abc import Mapping, Sequence
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np

from mpa._arrays import FloatArray
from mpa.errors import InvalidInputError

if TYPE_CHECKING:  # pragma: no cover
    from matplotlib.figure import Figure

__all__ = ["plot_rows", "read_rows"]

_PROFILES = (("s", "m"), ("v", "m/s"), ("a", "m/s²"), ("j", "m/s³"))


def read_rows(path: str | Path) -> dict[str, FloatArray]:
    """The numeric columns of a setpoints CSV (name -> values, shape (N,)); ``*_edge`` columns (edge names) are left
    out.

    Raises
    ------
    InvalidInputError
        Unreadable file, no ``time`` column or no ``a_*``/``b_*`` column, non-numeric values, no rows.
    """
    p = Path(path)
    try:
        with p.open(encoding="utf-8", newline="") as fh:
            reader = csv.reader(fh)
            header = [h.strip() for h in next(reader, [])]
            body = [row for row in reader if row]
    except (OSError, UnicodeDecodeError, csv.Error) as exc:
        raise InvalidInputError(f"{str(p)!r} cannot be read as a setpoints file ({exc})") from None
    if "time" not in header or not any(h.startswith(("a_", "b_")) for h in header):
        raise InvalidInputError(
            f"{str(p)!r} has header {','.join(header)!r}, expected a setpoints file of mpa (time,a_...,b_...)"
        )
    if not body or any(len(row) != len(header) for row in body):
        raise InvalidInputError(f"{str(p)!r} has no rows or ragged rows, expected a setpoints file")
    keep = [i for i, h in enumerate(header) if not h.endswith("_edge")]  # edge names are not numbers
    try:
        data = np.array([[row[i] for i in keep] for row in body], dtype=float)
    except ValueError:
        raise InvalidInputError(f"{str(p)!r} holds values that are not numbers, expected a setpoints file") from None
    return {header[i]: data[:, k] for k, i in enumerate(keep)}


def _draw_graph_track(ax: Any, layout: Mapping[str, Any]) -> bool:
    try:
        from mpa.graph_track import GraphTrack
        from trajopt.viz.layout import draw_layout

        draw_layout(ax, GraphTrack.from_layout(dict(layout)))
    except Exception:  # an unknown layout: no track panel rather than no figure
        return False
    ax.set_title("track layout")
    return True


def plot_rows(
    rows: Mapping[str, FloatArray],
    *,
    track: Any = None,
    clearance: float | None = None,
    layout: Mapping[str, Any] | None = None,
    title: str = "",
    words: Mapping[str, str] | None = None,
) -> Figure:
    """The figure of setpoint columns (see the module docstring).

    Parameters
    ----------
    rows : mapping
        Columns from :func:`read_rows`.
    track : mpa.tracks.Track, optional
        The paper track the rows are on (draws the track panel and the configuration space's band).
    clearance : float, optional
        D (m), for the band ``d < D``.
    layout : mapping, optional
        A graph layout (``GraphTrack.to_dict``) instead of a paper track.
    title : str
    words : mapping, optional
        Each cart's motion in words (``{"A": ..., "B": ...}``), shown under the title.
    """
    from matplotlib.figure import Figure

    profiles = [(k, u) for k, u in _PROFILES if f"a_{k}" in rows and f"b_{k}" in rows]
    fig = Figure(figsize=(12, 8), constrained_layout=True)
    gs = fig.add_gridspec(max(len(profiles), 2), 2, width_ratios=[1.0, 1.2])
    n = max(len(profiles), 2)
    ax_track = fig.add_subplot(gs[0 : n // 2, 0])
    ax_cs = fig.add_subplot(gs[n // 2 : n, 0])
    pos = None
    if "a_track" in rows and "b_track" in rows:
        pos = np.column_stack([rows["a_track"], rows["b_track"]])
    _draw_track_panel(ax_track, pos, track, layout)
    _draw_cspace_panel(ax_cs, rows, pos, track, clearance)
    axes = [fig.add_subplot(gs[i, 1]) for i in range(len(profiles))]
    _draw_profiles(axes, rows, profiles)
    from trajopt.viz.plotting import title_with_words

    title_with_words(fig, title, words)
    return fig


def _draw_track_panel(ax: Any, pos: FloatArray | None, track: Any, layout: Mapping[str, Any] | None) -> None:
    """The robots on the paper track (``pos``: track coordinates, shape (N, 2)) or the graph layout, else a note."""
    from trajopt.viz import plotting as pl

    drawn = False
    if track is not None:
        pl.draw_track(ax, track, pos)
        drawn = True
    elif layout is not None:
        drawn = _draw_graph_track(ax, layout)
    if not drawn:
        ax.set_axis_off()
        ax.text(0.5, 0.5, "track unknown (no summary.json beside the file)", ha="center", va="center")


def _draw_cspace_panel(
    ax: Any, rows: Mapping[str, FloatArray], pos: FloatArray | None, track: Any, clearance: float | None
) -> None:
    """The path in the configuration space: with the band ``d < D`` on a paper track, else the bare path in track
    (``pos``) or route coordinates."""
    from trajopt.viz import plotting as pl

    path = pos if pos is not None else (np.column_stack([rows["a_s"], rows["b_s"]]) if "a_s" in rows else None)
    if track is not None and pos is not None and clearance is not None:
        pl.draw_cspace(ax, track, clearance, {"setpoints": pos})
    elif path is not None:
        from trajopt.viz.drawing import TRAJECTORY_COLOR

        ax.plot(path[:, 0], path[:, 1], color=TRAJECTORY_COLOR, lw=1.6)
        ax.plot(*path[0], "o", color="k")
        ax.plot(*path[-1], "o", mfc="none", color="k")
        which = "track" if pos is not None else "route"
        ax.set_xlabel(f"a ({which} coordinate of A, m)")
        ax.set_ylabel(f"b ({which} coordinate of B, m)")
        ax.set_title("configuration space")
        ax.grid(alpha=0.3)
    else:  # pragma: no cover - read_rows requires a_*/b_* columns
        ax.set_axis_off()


def _draw_profiles(axes: Sequence[Any], rows: Mapping[str, FloatArray], profiles: Sequence[tuple[str, str]]) -> None:
    """One panel per profile (key, unit): both carts' column against time, A and B in their own styles."""
    from trajopt.viz import plotting as pl

    t = rows["time"]
    for ax, (key, unit) in zip(axes, profiles):
        for r, name in enumerate("ab"):
            ax.plot(
                t,
                rows[f"{name}_{key}"],
                color=pl.COLORS[r],
                ls=pl.LINESTYLES[r],
                lw=pl.LINEWIDTHS[r],
                label=name.upper(),
                zorder=3 + r,
            )
        ax.set_ylabel(f"{key} ({unit})")
        ax.grid(alpha=0.3)
    if axes:
        axes[0].legend(fontsize=8, loc="upper left")
        axes[-1].set_xlabel("t (s)")
