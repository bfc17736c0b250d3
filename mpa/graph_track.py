"""A track of any shape: :class:`GraphTrack`, a metric graph read from a JSON layout, with positions on its edges.

Layout (a superset of what ``mpa topology --graph`` reads)::

    {"vertices": {"name": [x, y], ...},          # optional; metres, for drawing and export
     "edges": [[u, v], [u, v, length],
               {"name": "e1", "from": u, "to": v, "length": 2.0, "points": [[x, y], ...]}]}

- An edge without a name is called ``e<i>``, its index in the list. Loops and parallel edges are allowed.
- A missing length is the straight distance of the end coordinates when both are given, else 1 (a loop drawn
  with coordinates therefore needs a length).
- When ``"vertices"`` is given, every edge end must be one of its keys (a typo is an error, not a new vertex); a
  vertex value is ``[x, y]`` or ``null`` (no coordinates). Vertex names are strings (integers in ``[u, v]`` lists
  are turned into strings).
- ``points`` is an optional polyline between the end coordinates, for drawing only.
- ``"oneway": true`` (optional): the edge may be driven from ``from`` to ``to`` only (a robot may stand on it);
  ``"speed_limit": v`` (optional, m/s, > 0): no robot moves faster than ``v`` on the edge.
- :meth:`GraphTrack.from_file` also reads Open-RMF building maps and navigation graphs (:mod:`mpa.openrmf`).

A position is ``(edge, offset)``: metres from the edge's ``from`` vertex, ``0 <= offset <= length``. As text it is
``EDGE:OFFSET`` or a vertex name. *Canonical name* of a position (used on output): the vertex name when the offset is
exactly 0 or the length (the robot stands on a vertex), else ``EDGE:OFFSET``; the canonical ``(edge, offset)`` of a
vertex is on the lowest-indexed edge incident to it (offset 0 if it is that edge's tail, else the length).
"""

from __future__ import annotations

import functools
import math
from collections.abc import Mapping
from dataclasses import dataclass
from functools import cached_property
from pathlib import Path
from typing import Any, TypeGuard

import numpy as np
from numpy.typing import ArrayLike, NDArray

from mpa._arrays import FloatArray
from mpa.errors import InvalidInputError
from mpa.geometry import GraphGeometry
from mpa.graph import Edge, MetricGraph, read_json_file

__all__ = ["GraphTrack", "Position", "paper_from_graph_position", "paper_to_graph_position", "paper_track_as_graph"]

Position = tuple[int, float]
_EDGE_KEYS = {"name", "from", "to", "length", "points", "oneway", "speed_limit"}
#: Largest coordinate and edge length of a layout (m): sums of lengths and squared coordinates stay finite.
MAX_EXTENT = 1e12


def _is_number(x: object) -> TypeGuard[int | float]:
    """A real number (not a bool) that converts to a float (an integer beyond ±1.8e308 does not)."""
    if isinstance(x, bool) or not isinstance(x, (int, float)):
        return False
    if isinstance(x, int):
        try:
            float(x)
        except OverflowError:
            return False
    return True


def _point(value: object, what: str) -> tuple[float, float]:
    if (
        not isinstance(value, (list, tuple))
        or len(value) != 2
        or not all(_is_number(c) and math.isfinite(c) for c in value)
    ):
        raise InvalidInputError(f"{what} is {value!r}, expected [x, y] with two finite numbers (metres)")
    if max(abs(float(value[0])), abs(float(value[1]))) > MAX_EXTENT:
        raise InvalidInputError(f"{what} is {value!r}, expected coordinates within ±{MAX_EXTENT:g} m")
    return float(value[0]), float(value[1])


def _vertex_name(value: object, what: str) -> str:
    if isinstance(value, bool) or not isinstance(value, (str, int)):
        raise InvalidInputError(f"{what} is {value!r}, expected a vertex name (string)")
    name = str(value)
    if not name:
        raise InvalidInputError(f"{what} is an empty string, expected a vertex name")
    return name


def _layout_parts(data: object) -> tuple[list[object], object]:
    """The layout's non-empty edge list and its ``vertices`` entry (None if absent), after checking the keys."""
    if not isinstance(data, Mapping):
        raise InvalidInputError(f'layout is a {type(data).__name__}, expected an object with the key "edges"')
    unknown = sorted(set(map(str, data)) - {"vertices", "edges"})
    if unknown:
        raise InvalidInputError(f'layout has unknown keys {unknown}, expected "vertices" and "edges"')
    if "edges" not in data:
        raise InvalidInputError('layout has no key "edges", expected a list of edges')
    edges = data["edges"]
    if not isinstance(edges, list):
        raise InvalidInputError(f'layout "edges" is a {type(edges).__name__}, expected a list')
    if not edges:
        raise InvalidInputError('layout "edges" is empty, expected at least one edge')
    return edges, data.get("vertices")


def _layout_vertices(raw_vertices: object) -> dict[str, tuple[float, float] | None]:
    """The layout's listed vertices: name to coordinates (None where the layout gives none)."""
    if not isinstance(raw_vertices, Mapping):
        raise InvalidInputError(
            f'layout "vertices" is a {type(raw_vertices).__name__}, expected an object {{"name": [x, y]}}'
        )
    vertex_xy: dict[str, tuple[float, float] | None] = {}
    for raw_name, xy in raw_vertices.items():
        vname = _vertex_name(raw_name, "vertex name")
        vertex_xy[vname] = None if xy is None else _point(xy, f"coordinates of vertex {vname!r}")
    return vertex_xy


def _edge_fields(i: int, item: object) -> tuple[object, object, object, object, object]:
    """The raw name, end vertices, length and points of edge ``i`` (a list ``[u, v(, length)]`` or an object);
    absent ones are None, the name defaults to ``e{i}``."""
    name: object = f"e{i}"
    length: object = None
    pts: object = None
    if isinstance(item, list):
        if len(item) not in (2, 3):
            raise InvalidInputError(f"edge {i} is {item!r}, expected [u, v], [u, v, length] or an object")
        if len(item) == 3:
            length = item[2]
        return name, item[0], item[1], length, pts
    if isinstance(item, Mapping):
        bad = sorted(set(map(str, item)) - _EDGE_KEYS)
        if bad:
            raise InvalidInputError(f"edge {i} has unknown keys {bad}, expected keys among {sorted(_EDGE_KEYS)}")
        for key in ("from", "to"):
            if key not in item:
                raise InvalidInputError(f'edge {i} has no "{key}", expected "from" and "to" vertex names')
        return item.get("name", name), item["from"], item["to"], item.get("length"), item.get("points")
    raise InvalidInputError(f"edge {i} is {item!r}, expected [u, v], [u, v, length] or an object")


def _edge_rules(i: int, item: object, name: str) -> tuple[bool, float | None]:
    """Edge ``i``'s one-way flag and speed limit (m/s, None: no limit), checked."""
    if not isinstance(item, Mapping):
        return False, None
    oneway = item.get("oneway", False)
    if not isinstance(oneway, bool):
        raise InvalidInputError(f"oneway of edge {name!r} is {oneway!r}, expected true or false")
    limit = item.get("speed_limit")
    if limit is None:
        return oneway, None
    if not _is_number(limit) or not math.isfinite(limit) or float(limit) <= 0:
        raise InvalidInputError(f"speed_limit of edge {name!r} is {limit!r}, expected a finite number > 0 (m/s)")
    return oneway, float(limit)


def _edge_name(i: int, name: object, used: set[str]) -> str:
    """Edge ``i``'s name, checked: a non-empty string without ':' not in ``used``."""
    if not isinstance(name, str) or not name:
        raise InvalidInputError(f"name of edge {i} is {name!r}, expected a non-empty string")
    if name in used:
        raise InvalidInputError(f"edge name {name!r} is used twice, expected distinct edge names")
    if ":" in name:
        raise InvalidInputError(f"edge name {name!r} contains ':', expected a name without ':'")
    return name


def _edge_points(pts: object, name: str) -> tuple[tuple[float, float], ...]:
    """An edge's drawn polyline (interior points; empty if the layout gives none)."""
    if pts is None:
        return ()
    if not isinstance(pts, list):
        raise InvalidInputError(f"points of edge {name!r} is {pts!r}, expected a list of [x, y]")
    return tuple(_point(p, f"point {j} of edge {name!r}") for j, p in enumerate(pts))


def _edge_length(length: object, name: str, a: tuple[float, float] | None, b: tuple[float, float] | None) -> float:
    """An edge's length (m): as given, else the straight distance of its ends' coordinates ``a, b``, else 1."""
    if length is None:
        length_f = math.hypot(b[0] - a[0], b[1] - a[1]) if a is not None and b is not None else 1.0
        if length_f <= 0:
            raise InvalidInputError(
                f"length of edge {name!r} is {length_f!r} (the straight distance of its end coordinates), "
                "expected a finite number > 0: give a length"
            )
        return length_f
    if not _is_number(length) or not math.isfinite(length) or float(length) <= 0:
        raise InvalidInputError(f"length of edge {name!r} is {length!r}, expected a finite number > 0")
    if float(length) > MAX_EXTENT:
        raise InvalidInputError(f"length of edge {name!r} is {length!r}, expected at most {MAX_EXTENT:g} m")
    return float(length)


@dataclass(frozen=True)
class GraphTrack:
    """A track given as a metric graph, with optional drawing coordinates.

    Parameters
    ----------
    graph : MetricGraph
        Vertex names are strings; every edge has a name and a finite length > 0.
    coords : tuple
        One entry per vertex of ``graph.vertices``: ``(x, y)`` in metres or ``None``.
    points : tuple
        One entry per edge: a tuple of interior polyline points ``(x, y)`` (metres) or ``()``.
    oneway : tuple of bool
        One entry per edge (default all False): the edge may be driven from its tail to its head only.
    speed_limits : tuple of (float or None)
        One entry per edge (default all None): the speed limit on the edge (m/s, > 0), None for none.

    Notes
    -----
    Frozen and hashable, so free spaces can be cached per ``(track, clearance)``.
    """

    graph: MetricGraph
    coords: tuple[tuple[float, float] | None, ...] = ()
    points: tuple[tuple[tuple[float, float], ...], ...] = ()
    oneway: tuple[bool, ...] = ()
    speed_limits: tuple[float | None, ...] = ()
    kind = "graph"

    def __post_init__(self) -> None:
        g = self.graph
        if not isinstance(g, MetricGraph):
            raise InvalidInputError(f"graph is a {type(g).__name__}, expected a MetricGraph")
        if g.n_edges == 0:
            raise InvalidInputError("layout has no edges, expected at least one edge")
        for e in g.edges:
            if not (math.isfinite(e.length) and e.length > 0):
                raise InvalidInputError(f"length of edge {e.name!r} is {e.length!r}, expected a finite number > 0")
        if not self.coords:
            object.__setattr__(self, "coords", (None,) * g.n_vertices)
        if not self.points:
            object.__setattr__(self, "points", ((),) * g.n_edges)
        if not self.oneway:
            object.__setattr__(self, "oneway", (False,) * g.n_edges)
        if not self.speed_limits:
            object.__setattr__(self, "speed_limits", (None,) * g.n_edges)
        if len(self.coords) != g.n_vertices or len(self.points) != g.n_edges:
            raise InvalidInputError("coords must have one entry per vertex and points one per edge")
        if len(self.oneway) != g.n_edges or len(self.speed_limits) != g.n_edges:
            raise InvalidInputError("oneway and speed_limits must have one entry per edge")
        for e, v in zip(g.edges, self.speed_limits):
            if v is not None and not (math.isfinite(v) and v > 0):
                raise InvalidInputError(f"speed_limit of edge {e.name!r} is {v!r}, expected a finite number > 0 (m/s)")

    # ----------------------------------------------------------------------------------------- parse
    @classmethod
    def from_layout(cls, data: object) -> GraphTrack:
        """Build a track from a decoded JSON layout (see the module docstring).

        Parameters
        ----------
        data : dict
            ``{"vertices": {...} (optional), "edges": [...]}``.

        Returns
        -------
        GraphTrack

        Raises
        ------
        InvalidInputError
            Malformed or empty layout, unknown vertex, duplicate names, bad length (negative, zero, non-finite, not a
            number), bad coordinates; the message names the quantity, its value and what was expected.

        Examples
        --------
        >>> t = GraphTrack.from_layout({"edges": [["F", "P", 1.0], ["P", "P", 2.0]]})
        >>> [e.name for e in t.graph.edges], t.graph.edges[1].length
        (['e0', 'e1'], 2.0)
        """
        edges, raw_vertices = _layout_parts(data)
        listed = raw_vertices is not None
        vertex_xy = _layout_vertices(raw_vertices) if raw_vertices is not None else {}
        order: list[str] = list(vertex_xy)
        out_edges: list[Edge] = []
        out_points: list[tuple[tuple[float, float], ...]] = []
        rules: list[tuple[bool, float | None]] = []
        names: set[str] = set()
        for i, item in enumerate(edges):
            raw_name, u_raw, v_raw, length, pts = _edge_fields(i, item)
            name = _edge_name(i, raw_name, names)
            names.add(name)
            u = _vertex_name(u_raw, f"vertex 'from' of edge {name!r}")
            v = _vertex_name(v_raw, f"vertex 'to' of edge {name!r}")
            for w in (u, v):
                if w not in vertex_xy:
                    if listed:
                        raise InvalidInputError(
                            f"vertex {w!r} of edge {name!r} is unknown, expected one of the layout's vertices "
                            f"{sorted(vertex_xy)[:20]}"
                        )
                    vertex_xy[w] = None
                    order.append(w)
            poly = _edge_points(pts, name)
            out_edges.append(Edge(name, u, v, _edge_length(length, name, vertex_xy[u], vertex_xy[v])))
            out_points.append(poly)
            rules.append(_edge_rules(i, item, name))
        graph = MetricGraph(tuple(order), tuple(out_edges))
        return cls(
            graph,
            tuple(vertex_xy[w] for w in order),
            tuple(out_points),
            tuple(r[0] for r in rules),
            tuple(r[1] for r in rules),
        )

    @classmethod
    def from_json(cls, path: str | Path) -> GraphTrack:
        """Read a layout file (UTF-8 JSON); errors as :meth:`from_layout`, plus missing or unreadable files."""
        data = read_json_file(path, "layout")
        return cls.from_layout(data)

    @classmethod
    def from_file(cls, path: str | Path, level: str | None = None, nav_graph: int | None = None) -> GraphTrack:
        """Read a layout file: our JSON layout, an Open-RMF building map or a navigation graph (:mod:`mpa.openrmf`).

        Parameters
        ----------
        path : str or Path
        level : str, optional
            Open-RMF maps: the level (default: the building's reference level, the navigation graph's first).
        nav_graph : int, optional
            Building maps: the navigation graph, the lanes' ``graph_idx`` (default 0).

        Raises
        ------
        InvalidInputError
            As :meth:`from_layout` and :func:`mpa.openrmf.read_layout_file` (a file of none of the three kinds, a
            level or graph index that does not exist, a lane naming a missing vertex, a negative speed limit).
        """
        from mpa.openrmf import read_layout_file

        layout, _ = read_layout_file(path, level, nav_graph)
        return cls.from_layout(layout)

    @cached_property
    def has_rules(self) -> bool:
        """Whether some edge is one-way or has a speed limit (computed once per layout)."""
        return any(self.oneway) or any(v is not None for v in self.speed_limits)

    def to_dict(self) -> dict[str, Any]:
        """The layout as a JSON-friendly dict (round-trips through :meth:`from_layout`)."""
        out: dict[str, Any] = {}
        out["vertices"] = {
            str(v): (list(xy) if xy is not None else None) for v, xy in zip(self.graph.vertices, self.coords)
        }
        edges = []
        for e, pts in zip(self.graph.edges, self.points):
            item: dict[str, Any] = {"name": e.name, "from": e.tail, "to": e.head, "length": e.length}
            if pts:
                item["points"] = [list(p) for p in pts]
            edges.append(item)
        for item, ow, lim in zip(edges, self.oneway, self.speed_limits):
            if ow:
                item["oneway"] = True
            if lim is not None:
                item["speed_limit"] = lim
        out["edges"] = edges
        return out

    # ---------------------------------------------------------------------------------------- indices
    @cached_property
    def edge_names(self) -> tuple[str, ...]:
        """Edge names in index order."""
        return tuple(e.name for e in self.graph.edges)

    @cached_property
    def _edge_index(self) -> dict[str, int]:
        return {n: i for i, n in enumerate(self.edge_names)}

    @cached_property
    def _vertex_index(self) -> dict[str, int]:
        return {str(v): i for i, v in enumerate(self.graph.vertices)}

    @cached_property
    def tails(self) -> NDArray[np.int64]:
        """Tail vertex index of each edge, shape (E,)."""
        return np.array([self._vertex_index[str(e.tail)] for e in self.graph.edges], dtype=np.int64)

    @cached_property
    def heads(self) -> NDArray[np.int64]:
        """Head vertex index of each edge, shape (E,)."""
        return np.array([self._vertex_index[str(e.head)] for e in self.graph.edges], dtype=np.int64)

    @cached_property
    def lengths(self) -> FloatArray:
        """Edge lengths (metres), shape (E,)."""
        return np.array([e.length for e in self.graph.edges], dtype=float)

    @cached_property
    def geometry(self) -> GraphGeometry:
        """Exact distances on this track (built once)."""
        return GraphGeometry(self.graph.n_vertices, self.tails, self.heads, self.lengths)

    @property
    def n_edges(self) -> int:
        """Number of edges."""
        return self.graph.n_edges

    @property
    def has_coordinates(self) -> bool:
        """Whether every vertex with an edge has coordinates (then :meth:`embed` works)."""
        used = set(self.tails.tolist()) | set(self.heads.tolist())
        return all(self.coords[i] is not None for i in used)

    @property
    def total_length(self) -> float:
        """Sum of the edge lengths (metres)."""
        return float(self.lengths.sum())

    def edge_index(self, edge: str | int | np.integer) -> int:
        """Index of an edge given by name or index."""
        if isinstance(edge, (int, np.integer)) and not isinstance(edge, bool):
            if 0 <= int(edge) < self.n_edges:
                return int(edge)
            raise InvalidInputError(f"edge index is {edge!r}, expected 0 <= index < {self.n_edges}")
        if isinstance(edge, str) and edge in self._edge_index:
            return self._edge_index[edge]
        raise InvalidInputError(f"edge is {edge!r}, expected one of {list(self.edge_names)[:20]}")

    def vertex_index(self, vertex: str) -> int:
        """Index of a vertex given by name."""
        if isinstance(vertex, str) and vertex in self._vertex_index:
            return self._vertex_index[vertex]
        raise InvalidInputError(f"vertex is {vertex!r}, expected one of {list(self._vertex_index)[:20]}")

    def degree(self, vertex: int) -> int:
        """Degree of vertex index ``vertex`` (a loop counts twice)."""
        return int(np.sum(self.tails == vertex) + np.sum(self.heads == vertex))

    # -------------------------------------------------------------------------------------- positions
    def vertex_position(self, vertex: str | int) -> Position:
        """Canonical ``(edge, offset)`` of a vertex: on its lowest-indexed edge (0 at a tail, else the length)."""
        w = self.vertex_index(vertex) if isinstance(vertex, str) else int(vertex)
        for i in range(self.n_edges):
            if self.tails[i] == w:
                return i, 0.0
            if self.heads[i] == w:
                return i, float(self.lengths[i])
        raise InvalidInputError(f"vertex {self.graph.vertices[w]!r} has no edge, expected a vertex on the track")

    def vertex_at(self, edge: int, offset: float) -> int | None:
        """Vertex index if ``(edge, offset)`` is exactly an end of the edge, else None."""
        if offset == 0.0:
            return int(self.tails[edge])
        if offset == self.lengths[edge]:
            return int(self.heads[edge])
        return None

    def position(self, pos: object, name: str = "position") -> Position:
        """Validate a position given as ``(edge, offset)``, ``"EDGE:OFFSET"`` or a vertex name.

        Parameters
        ----------
        pos : tuple or str
            ``(edge name or index, offset)``, ``"EDGE:OFFSET"`` or a vertex name.
        name : str
            What to call it in error messages (e.g. ``"start of robot A"``).

        Returns
        -------
        (int, float)
            Edge index and offset (metres).

        Raises
        ------
        InvalidInputError
            Unknown edge or vertex, offset not a number or outside ``[0, length]``.
        """
        if isinstance(pos, str):
            if pos in self._vertex_index:
                other = self._edge_reading(pos)
                if other is not None:
                    e, o = other
                    raise InvalidInputError(
                        f"{name} is {pos!r}, which names two places: vertex {pos!r} and {o:g} m along edge "
                        f"{self.edge_names[e]!r}; expected one reading (write the vertex as an end of one of its "
                        f"edges, EDGE:0 or EDGE:LENGTH, or the offset in another form, e.g. "
                        f"{self.edge_names[e] + ':' + repr(float(o))!r})"
                    )
                return self.vertex_position(pos)
            if ":" not in pos:
                raise InvalidInputError(
                    f"{name} is {pos!r}, expected EDGE:OFFSET or a vertex name (vertices: "
                    f"{list(self._vertex_index)[:20]})"
                )
            edge_text, off_text = pos.rsplit(":", 1)
            try:
                off: object = float(off_text)
            except ValueError:
                raise InvalidInputError(f"offset of {name} is {off_text!r}, expected a number (metres)") from None
            edge: object = edge_text
        elif isinstance(pos, (tuple, list)) and len(pos) == 2:
            edge, off = pos
        else:
            raise InvalidInputError(f"{name} is {pos!r}, expected (edge, offset), 'EDGE:OFFSET' or a vertex name")
        if not isinstance(edge, (str, int, np.integer)) or isinstance(edge, bool):
            raise InvalidInputError(f"edge of {name} is {edge!r}, expected an edge name")
        try:
            i = self.edge_index(edge)
        except InvalidInputError:
            raise InvalidInputError(
                f"edge of {name} is {edge!r}, expected one of {list(self.edge_names)[:20]}"
            ) from None
        if isinstance(off, bool) or not isinstance(off, (int, float, np.integer, np.floating)):
            raise InvalidInputError(f"offset of {name} is {off!r}, expected a number (metres)")
        o = float(off)
        length = float(self.lengths[i])
        if not math.isfinite(o) or o < 0.0 or o > length:
            raise InvalidInputError(
                f"offset of {name} on edge {self.edge_names[i]!r} is {off!r}, expected a number in [0, {length:g}]"
            )
        return i, o

    def _edge_reading(self, text: str) -> Position | None:
        """``text`` read as ``EDGE:OFFSET`` on an edge of this track with the offset on it, else None."""
        if ":" not in text:
            return None
        edge_text, off_text = text.rsplit(":", 1)
        i = self._edge_index.get(edge_text)
        if i is None:
            return None
        try:
            o = float(off_text)
        except ValueError:
            return None
        if not (math.isfinite(o) and 0.0 <= o <= float(self.lengths[i])):
            return None
        return i, o

    def parse_position(self, text: str) -> Position:
        """Parse ``"EDGE:OFFSET"`` or a vertex name (see :meth:`position`)."""
        return self.position(text)

    def position_name(self, edge: int, offset: float) -> str:
        """Canonical text of a position: the vertex name at an exact end of the edge, else ``EDGE:OFFSET``."""
        w = self.vertex_at(edge, offset)
        if w is not None:
            name = str(self.graph.vertices[w])
            if self._edge_reading(name) is None:
                return name
            offset = float(offset)  # a vertex name that also reads as EDGE:OFFSET: name it by its edge
            return f"{self.edge_names[edge]}:{offset!r}"
        text = f"{self.edge_names[edge]}:{offset:.12g}"
        if text in self._vertex_index:  # the short form is a vertex's name: all the digits, another spelling
            text = f"{self.edge_names[edge]}:{float(offset)!r}"
        return text

    # ----------------------------------------------------------------------------------------- drawing
    @cached_property
    def _polylines(self) -> list[tuple[FloatArray, FloatArray] | None]:
        out: list[tuple[FloatArray, FloatArray] | None] = []
        for i in range(self.n_edges):
            a, b = self.coords[self.tails[i]], self.coords[self.heads[i]]
            if a is None or b is None:
                out.append(None)
                continue
            pts = np.array([a, *self.points[i], b], dtype=float)
            seg = np.hypot(*np.diff(pts, axis=0).T)
            cum = np.concatenate([[0.0], np.cumsum(seg)])
            out.append((pts, cum / cum[-1] if cum[-1] > 0 else np.linspace(0.0, 1.0, len(pts))))
        return out

    def embed(self, edge: ArrayLike, offset: ArrayLike) -> FloatArray:
        """Planar point ``(x, y)`` (metres) of positions, along the edge's polyline or straight segment.

        Parameters
        ----------
        edge : array_like of int
        offset : array_like of float
            Offsets (metres); the point is at the same fraction of the drawn polyline's length.

        Returns
        -------
        ndarray, shape ``broadcast(edge, offset).shape + (2,)``

        Raises
        ------
        InvalidInputError
            If an end vertex of a requested edge has no coordinates.
        """
        e, o = np.broadcast_arrays(np.asarray(edge, dtype=np.int64), np.asarray(offset, dtype=float))
        out = np.empty((*e.shape, 2))
        for i in np.unique(e):
            poly = self._polylines[int(i)]
            if poly is None:
                raise InvalidInputError(
                    f"edge {self.edge_names[int(i)]!r} has an end without coordinates, expected [x, y] for both ends"
                )
            pts, frac = poly
            m = e == i
            f = np.clip(o[m] / self.lengths[i], 0.0, 1.0)
            out[m, 0] = np.interp(f, frac, pts[:, 0])
            out[m, 1] = np.interp(f, frac, pts[:, 1])
        return out

    def as_graph(self) -> MetricGraph:
        """The underlying :class:`MetricGraph` (what :func:`mpa.configuration_space_topology` reads)."""
        return self.graph

    def as_graph_track(self) -> GraphTrack:
        """Itself."""
        return self


# --------------------------------------------------------------------------- the paper's tracks as graphs
def _circle_points(n: int, centre: tuple[float, float], r: float, phase: float) -> tuple[tuple[float, float], ...]:
    ang = phase + 2 * np.pi * np.arange(1, n) / n
    return tuple((float(centre[0] + r * np.cos(a)), float(centre[1] + r * np.sin(a))) for a in ang)


@functools.lru_cache(maxsize=64)
def paper_track_as_graph(track: Any) -> GraphTrack:
    """The graph track of a paper track (:class:`~mpa.tracks.Interval`, ``Circle`` or ``Lollipop``).

    Edge names: interval ``stick`` (``F`` -> ``E``); circle ``loop`` (``P`` -> ``P``, counter-clockwise from the
    track's coordinate 0); lollipop ``stick`` (free end ``F`` -> pole ``P``) and ``loop`` (``P`` -> ``P``,
    counter-clockwise). Coordinates follow the track's own ``embed``.
    """
    kind = getattr(track, "kind", None)
    if kind == "interval":
        ell = float(track.stick)
        g = MetricGraph(("F", "E"), (Edge("stick", "F", "E", ell),))
        return GraphTrack(g, ((0.0, 0.0), (ell, 0.0)), ((),))
    if kind == "circle":
        c = float(track.loop)
        r = c / (2 * np.pi)
        g = MetricGraph(("P",), (Edge("loop", "P", "P", c),))
        return GraphTrack(g, ((r, 0.0),), (_circle_points(48, (0.0, 0.0), r, 0.0),))
    if kind == "lollipop":
        ell, c = float(track.stick), float(track.loop)
        r = c / (2 * np.pi)
        g = MetricGraph(("F", "P"), (Edge("stick", "F", "P", ell), Edge("loop", "P", "P", c)))
        pts = np.asarray(track.embed(ell + c * np.arange(1, 48) / 48), dtype=float)
        return GraphTrack(g, ((-ell, 0.0), (0.0, 0.0)), ((), tuple(map(tuple, pts.tolist()))))
    raise InvalidInputError(f"track is a {type(track).__name__}, expected an Interval, Circle or Lollipop")


def paper_to_graph_position(track: Any, p: ArrayLike) -> tuple[NDArray[np.int64], FloatArray]:
    """Track coordinate ``p`` -> ``(edge index, offset)`` on :func:`paper_track_as_graph` (vectorized).

    The pole ``P`` of a lollipop (``p = stick``) maps to the end of ``stick``.
    """
    p = np.asarray(p, dtype=float)
    kind = getattr(track, "kind", None)
    if kind in ("interval", "circle"):
        return np.zeros(p.shape, dtype=np.int64), p.copy()
    if kind == "lollipop":
        ell = float(track.stick)
        on_loop = p > ell
        return on_loop.astype(np.int64), np.where(on_loop, p - ell, p)
    raise InvalidInputError(f"track is a {type(track).__name__}, expected an Interval, Circle or Lollipop")


def paper_from_graph_position(track: Any, edge: ArrayLike, offset: ArrayLike) -> FloatArray:
    """``(edge index, offset)`` on :func:`paper_track_as_graph` -> track coordinate ``p`` (vectorized).

    The loop's end (offset = circumference) maps to coordinate 0 on a circle and to ``stick`` (P) on a lollipop.
    """
    e, o = np.broadcast_arrays(np.asarray(edge, dtype=np.int64), np.asarray(offset, dtype=float))
    kind = getattr(track, "kind", None)
    if kind == "interval":
        return o.copy()
    if kind == "circle":
        c = float(track.loop)
        return np.where(o >= c, 0.0, o)
    if kind == "lollipop":
        ell, c = float(track.stick), float(track.loop)
        return np.where(e == 0, o, np.where(o >= c, ell, ell + o))
    raise InvalidInputError(f"track is a {type(track).__name__}, expected an Interval, Circle or Lollipop")


def as_graph_track(track: object) -> GraphTrack:
    """A :class:`GraphTrack` from a GraphTrack, a paper track, a layout dict or a JSON path."""
    if isinstance(track, GraphTrack):
        return track
    if isinstance(track, Mapping):
        return GraphTrack.from_layout(track)
    if isinstance(track, (str, Path)):
        return GraphTrack.from_json(track)
    conv = getattr(track, "as_graph_track", None)
    if callable(conv):
        out = conv()
        if isinstance(out, GraphTrack):
            return out
    raise InvalidInputError(f"track is a {type(track).__name__}, expected a GraphTrack, a paper track or a layout")
