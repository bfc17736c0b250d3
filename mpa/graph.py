"""Finite metric graphs: vertices, edges with lengths, Betti numbers and Farber's TC of a graph.

A :class:`MetricGraph` is the combinatorial object behind every track and every skeleton of the paper.
Loops (an edge from a vertex to itself) and multiple edges are allowed.
"""

from __future__ import annotations

import json
import numbers
from collections.abc import Hashable, Iterable, Sequence
from dataclasses import dataclass, field
from functools import cached_property
from pathlib import Path

import numpy as np
from numpy.typing import NDArray

from mpa.errors import InvalidInputError

__all__ = ["Edge", "MetricGraph", "farber_tc_of_graph", "parse_json", "read_json_file"]

Vertex = Hashable


def read_json_file(path: str | Path, what: str) -> object:
    """The decoded content of a UTF-8 JSON file describing a graph or a layout (``what``: "graph", "layout").

    Raises
    ------
    InvalidInputError
        If the file is missing or unreadable, or is not JSON (the message names the file as ``what`` file).
    """
    p = Path(path)
    try:
        text = p.read_text(encoding="utf-8")
    except FileNotFoundError:
        raise InvalidInputError(f"{what} file {str(p)!r} does not exist, expected a JSON file") from None
    except (OSError, UnicodeDecodeError) as exc:
        raise InvalidInputError(f"{what} file {str(p)!r} cannot be read ({exc}), expected a UTF-8 JSON file") from None
    return parse_json(text, f"{what} file {str(p)!r}")


def _json_int(text: str) -> int | float:
    """A JSON integer; one of more than 300 digits becomes a float (±inf beyond ±1.8e308, refused later)."""
    return int(text) if len(text) <= 300 else float(text)


def parse_json(text: str, what: str) -> object:
    """Decode JSON ``text`` read from ``what`` (e.g. ``"layout file 'x.json'"``).

    Integers of more than 300 digits are read as floats (so a length of 400 digits is an infinite length, refused
    by the caller as not finite, never an ``OverflowError``); nesting too deep for the decoder is an error.

    Raises
    ------
    InvalidInputError
        Not valid JSON, or nested too deeply.
    """
    try:
        return json.loads(text, parse_int=_json_int)
    except json.JSONDecodeError as exc:
        raise InvalidInputError(
            f"{what} is not valid JSON ({exc.msg} at line {exc.lineno} column {exc.colno})"
        ) from None
    except RecursionError:
        raise InvalidInputError(
            f"{what} is nested too deeply, expected JSON nested at most a few hundred levels"
        ) from None
    except ValueError as exc:  # e.g. a number the decoder refuses
        raise InvalidInputError(f"{what} is not valid JSON ({exc})") from None


@dataclass(frozen=True)
class Edge:
    """An oriented edge ``tail -> head`` of length ``length`` (metres, or skeleton arc length)."""

    name: str
    tail: Vertex
    head: Vertex
    length: float = 1.0


@dataclass(frozen=True)
class MetricGraph:
    """A finite graph with edge lengths.

    Parameters
    ----------
    vertices : tuple
        Vertex names (hashable: strings or integers).
    edges : tuple of Edge
        Oriented edges; loops and multiple edges are allowed. Lengths must be finite and >= 0.
    """

    vertices: tuple[Vertex, ...]
    edges: tuple[Edge, ...] = field(default=())

    def __post_init__(self) -> None:
        vs = set(self.vertices)
        if len(vs) != len(self.vertices):
            raise InvalidInputError(f"graph vertices must be distinct, got {list(self.vertices)!r}")
        names = [e.name for e in self.edges]
        if len(set(names)) != len(names):
            raise InvalidInputError(f"graph edge names must be distinct, got {names!r}")
        for e in self.edges:
            if e.tail not in vs or e.head not in vs:
                raise InvalidInputError(
                    f"edge {e.name!r} joins {e.tail!r} and {e.head!r}, expected vertices among {sorted(map(str, vs))}"
                )
            if not np.isfinite(e.length) or e.length < 0:
                raise InvalidInputError(f"length of edge {e.name!r} is {e.length!r}, expected a finite number >= 0")

    @cached_property
    def adjacent_edges(self) -> NDArray[np.bool_]:
        """``[i, j]``: edges ``i`` and ``j`` share a vertex (an edge shares both of its own). Shape (E, E)."""
        ends = [{e.tail, e.head} for e in self.edges]
        return np.array([[bool(a & b) for b in ends] for a in ends], dtype=bool).reshape(len(ends), len(ends))

    @classmethod
    def from_edge_list(cls, edges: Iterable[Sequence[object]]) -> MetricGraph:
        """Build a graph from ``[[u, v], [u, v, length], ...]`` (vertices taken from the edges).

        Parameters
        ----------
        edges : iterable of sequences
            Each item is ``(u, v)`` or ``(u, v, length)``; the default length is 1.

        Returns
        -------
        MetricGraph
        """
        vertices: list[Vertex] = []
        seen: set[Vertex] = set()
        out: list[Edge] = []
        for i, item in enumerate(edges):
            item = list(item)
            if len(item) not in (2, 3):
                raise InvalidInputError(f"edge {i} is {item!r}, expected [u, v] or [u, v, length]")
            u, v = item[0], item[1]
            for w in (u, v):
                if not isinstance(w, (str, int)) or isinstance(w, bool):
                    raise InvalidInputError(f"vertex {w!r} of edge {i} must be a string or an integer")
                if w not in seen:
                    seen.add(w)
                    vertices.append(w)
            raw = item[2] if len(item) == 3 else 1.0
            if isinstance(raw, bool) or not isinstance(raw, numbers.Real):
                raise InvalidInputError(f"length of edge {i} is {raw!r}, expected a number (metres)")
            length = float(raw)
            out.append(Edge(f"e{i}", u, v, length))
        return cls(tuple(vertices), tuple(out))

    # ----------------------------------------------------------------------------------------------
    @property
    def n_vertices(self) -> int:
        """Number of vertices."""
        return len(self.vertices)

    @property
    def n_edges(self) -> int:
        """Number of edges."""
        return len(self.edges)

    def degree(self, v: Vertex) -> int:
        """Degree of ``v`` (a loop counts twice)."""
        return sum((e.tail == v) + (e.head == v) for e in self.edges)

    def components(self) -> list[set[Vertex]]:
        """Connected components as vertex sets (union-find)."""
        parent = {v: v for v in self.vertices}

        def find(v: Vertex) -> Vertex:
            while parent[v] != v:
                parent[v] = parent[parent[v]]
                v = parent[v]
            return v

        for e in self.edges:
            a, b = find(e.tail), find(e.head)
            if a != b:
                parent[a] = b
        comps: dict[Vertex, set[Vertex]] = {}
        for v in self.vertices:
            comps.setdefault(find(v), set()).add(v)
        return list(comps.values())

    def betti(self) -> tuple[int, int]:
        """Betti numbers ``(b0, b1)``: components and independent cycles, ``b1 = E - V + b0``."""
        b0 = len(self.components())
        return b0, self.n_edges - self.n_vertices + b0

    def euler_characteristic(self) -> int:
        """``V - E``."""
        return self.n_vertices - self.n_edges

    def total_length(self) -> float:
        """Sum of the edge lengths."""
        return float(sum(e.length for e in self.edges))

    def edge(self, name: str) -> Edge:
        """The edge called ``name``."""
        for e in self.edges:
            if e.name == name:
                return e
        raise KeyError(name)


def farber_tc_of_graph(b1: int) -> int:
    """Farber's topological complexity of a connected graph from its first Betti number.

    ``TC = 1, 2, 3`` for ``b1 = 0, 1, >= 2`` (non-reduced convention: TC of a point is 1).

    Parameters
    ----------
    b1 : int
        First Betti number (>= 0).

    Returns
    -------
    int
    """
    if b1 < 0:
        raise InvalidInputError(f"first Betti number is {b1}, expected >= 0")
    return 1 if b1 == 0 else (2 if b1 == 1 else 3)
