"""Reading a graph for :func:`mpa.topology.configuration_space_topology` from JSON (an edge list)."""

from __future__ import annotations

import math
from pathlib import Path

from mpa.errors import InvalidInputError
from mpa.graph import MetricGraph, read_json_file

__all__ = ["graph_from_json_data", "load_graph_json"]


# ==================================================================================================
# Graph input
# ==================================================================================================
def graph_from_json_data(data: object) -> MetricGraph:
    """Build a graph from decoded JSON ``{"edges": [[u, v], [u, v, length], ...]}`` or a full track layout.

    A layout with ``"vertices"`` or named edges (objects) is read by :meth:`mpa.graph_track.GraphTrack.from_layout`;
    the plain edge list is read here (integer vertex names and zero lengths allowed: only the combinatorics count).

    Parameters
    ----------
    data : object
        Decoded JSON. Vertex names are strings or integers; loops and multiple edges are allowed; the default
        length is 1.

    Returns
    -------
    MetricGraph

    Raises
    ------
    InvalidInputError
        If ``edges`` is missing or empty, or an item is not ``[u, v]`` / ``[u, v, length]`` with string or integer
        vertices and a finite length >= 0.

    Examples
    --------
    >>> graph_from_json_data({"edges": [["F", "P"], ["P", "P", 2.5]]}).n_edges
    2
    """
    edges = data.get("edges") if isinstance(data, dict) else None
    if (
        isinstance(data, dict)
        and isinstance(edges, list)
        and ("vertices" in data or any(isinstance(e, dict) for e in edges))
    ):
        from mpa.graph_track import GraphTrack  # the full layout format (named edges, coordinates)

        return GraphTrack.from_layout(data).as_graph()
    if not isinstance(data, dict):
        raise InvalidInputError(f'graph JSON is a {type(data).__name__}, expected an object with key "edges"')
    if "edges" not in data:
        raise InvalidInputError(f'graph JSON has keys {sorted(map(str, data))}, expected the key "edges"')
    edges = data["edges"]
    if not isinstance(edges, list):
        raise InvalidInputError(f'graph "edges" is a {type(edges).__name__}, expected a list of [u, v] pairs')
    if not edges:
        raise InvalidInputError('graph "edges" is empty, expected at least one edge [u, v]')
    for i, item in enumerate(edges):
        if not isinstance(item, list) or len(item) not in (2, 3):
            raise InvalidInputError(f"edge {i} is {item!r}, expected [u, v] or [u, v, length]")
        for w in item[:2]:
            if isinstance(w, bool) or not isinstance(w, (str, int)):
                raise InvalidInputError(f"vertex {w!r} of edge {i} is not a string or an integer")
        if len(item) == 3:
            length = item[2]
            if isinstance(length, bool) or not isinstance(length, (int, float)) or not math.isfinite(length):
                raise InvalidInputError(f"length of edge {i} is {length!r}, expected a finite number >= 0")
            if length < 0:
                raise InvalidInputError(f"length of edge {i} is {length!r}, expected a finite number >= 0")
    return MetricGraph.from_edge_list(edges)


def load_graph_json(path: str | Path) -> MetricGraph:
    """Read a graph from a JSON file ``{"edges": [[u, v], [u, v, length], ...]}``.

    Parameters
    ----------
    path : str or Path

    Returns
    -------
    MetricGraph

    Raises
    ------
    InvalidInputError
        If the file is missing or unreadable, is not JSON, or does not describe a graph.
    """
    return graph_from_json_data(read_json_file(path, "graph"))
