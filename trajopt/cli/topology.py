"""``mpa topology``: Betti numbers, Euler characteristic and topological complexity of two robots on any graph.

The graph is read from a JSON file ``{"edges": [[u, v], [u, v, length], ...]}`` (vertex names are strings or
integers; loops and multiple edges are allowed). Every input error raises :class:`mpa.errors.InvalidInputError`,
which the main command turns into exit status 2 and one ``error:`` line.
"""

from __future__ import annotations

import argparse
import json
from typing import Any

from mpa.freespace import free_space
from mpa.graph_track import GraphTrack
from mpa.openrmf import read_layout_file
from mpa.topology import ConfigurationSpaceTopology, configuration_space_topology
from mpa.topology.graph_json import graph_from_json_data
from trajopt.cli.common import add_map_arguments

__all__ = ["format_topology", "free_space_report", "register", "run_topology"]


def _count(n: int, singular: str, plural: str | None = None) -> str:
    return f"{n} {singular}" if n == 1 else f"{n} {plural or singular + 's'}"


def format_topology(top: ConfigurationSpaceTopology) -> str:
    """Human-readable report of :func:`mpa.topology.configuration_space_topology`.

    Parameters
    ----------
    top : ConfigurationSpaceTopology

    Returns
    -------
    str
        Several lines, without a trailing newline.
    """
    b, b2 = top.betti, top.betti_f2
    hd = top.homotopy_dimension
    lines = [
        f"subdivided graph   {_count(top.subdivided_graph[0], 'vertex', 'vertices')}, "
        f"{_count(top.subdivided_graph[1], 'edge')}; "
        f"{_count(top.essential_vertices, 'essential vertex', 'essential vertices')} (degree >= 3)",
        f"D2 cells           {_count(top.cell_counts.vertices, 'vertex', 'vertices')}, "
        f"{_count(top.cell_counts.edges, 'edge')}, {_count(top.cell_counts.squares, 'square')}",
        f"Betti over Q       b0 = {b[0]}, b1 = {b[1]}, b2 = {b[2]}",
        f"Betti over F2      b0 = {b2[0]}, b1 = {b2[1]}, b2 = {b2[2]}",
        f"Euler              {top.euler} (formula chi^2 + chi - sum (d-1)(d-2) = {top.euler_formula})",
        f"connected          {'yes' if top.connected else f'no ({b[0]} path components)'}",
        f"homotopy dimension {hd.lower if hd.exact else f'{hd.lower} .. {hd.upper}'}"
        f"{' (collapses onto a graph)' if hd.collapsed_to_graph else ''}",
    ]
    tc = "undecided" if top.tc is None else str(top.tc)
    lines.append(f"TC (Farber, non-reduced) {tc}, bounds {top.tc_bounds[0]} <= TC <= {top.tc_bounds[1]}")
    if len(top.components) > 1:
        lines.append("  (max over path components; per component below)")
        for i, c in enumerate(top.components):
            ctc = "undecided" if c.tc is None else str(c.tc)
            lines.append(
                f"  component {i}: betti {c.betti}, TC {ctc} in [{c.tc_bounds[0]}, {c.tc_bounds[1]}]"
                + ("" if c.graph_components is None else f", robots on graph components {c.graph_components}")
            )
    return "\n".join(lines)


def free_space_report(
    path: str, clearance: float, level: str | None = None, nav_graph: int | None = None
) -> dict[str, Any]:
    """Path components of the free space ``{d >= D}`` of the layout in ``path`` and whether the robots can swap.

    Returns
    -------
    dict
        ``clearance`` (m), ``free_components`` (int: path components of the free configuration space) and
        ``can_swap`` (bool: some configuration ``(x, y)`` lies in one component with ``(y, x)``, i.e. the two robots
        can exchange places somewhere on the layout).
    """
    fs = free_space(GraphTrack.from_file(path, level, nav_graph), clearance)
    return {"clearance": fs.clearance, "free_components": fs.components(), "can_swap": fs.can_swap()}


def planar_free_space_report(
    path: str, clearance: float, footprint: str, level: str | None = None, nav_graph: int | None = None
) -> dict[str, Any]:
    """Like :func:`free_space_report` with the robots' bodies in the plane (:mod:`mpa.planar`): also ``footprint``.

    Raises
    ------
    InvalidInputError
        A malformed spec, a layout without vertex coordinates.
    """
    from mpa.footprint import parse_footprint
    from mpa.planar import planar_free_space

    fps = parse_footprint(footprint)
    fs = planar_free_space(GraphTrack.from_file(path, level, nav_graph), clearance, fps)
    return {
        "clearance": fs.clearance,
        "footprint": fps.to_dict(),
        "free_components": fs.n_components,
        "can_swap": fs.can_swap(),
    }


def run_topology(args: argparse.Namespace) -> int:
    """Handler of ``mpa topology``: print the report (or one JSON object with ``--json``); returns 0."""
    footprint = getattr(args, "footprint", None)
    if footprint is not None:
        from mpa.footprint import parse_footprint

        parse_footprint(footprint)  # a malformed spec is refused before any work
    level, nav_graph = getattr(args, "level", None), getattr(args, "nav_graph", None)
    layout, info = read_layout_file(args.graph, level, nav_graph)
    graph = graph_from_json_data(layout) if info["kind"] == "layout" else GraphTrack.from_layout(layout).as_graph()
    top = configuration_space_topology(graph)
    free: dict[str, Any] | None
    if footprint is not None:
        clearance = 0.0 if args.clearance is None else args.clearance
        free = planar_free_space_report(args.graph, clearance, footprint, level, nav_graph)
    else:
        free = None if args.clearance is None else free_space_report(args.graph, args.clearance, level, nav_graph)
    if args.json:
        out: dict[str, Any] = top.to_dict()
        if free is not None:
            out.update(free)
        print(json.dumps(out))
    else:
        print(format_topology(top))
        if free is not None:
            bodies = f", bodies {free['footprint']['spec']} in the plane" if "footprint" in free else ""
            print(
                f"free space D = {free['clearance']:g} m{bodies}: "
                f"{_count(free['free_components'], 'path component')}; "
                f"the robots can exchange places: {'yes' if free['can_swap'] else 'no'}"
            )
    return 0


def register(subparsers: Any) -> argparse.ArgumentParser:
    """Add the ``topology`` subcommand to an argparse subparsers object.

    Parameters
    ----------
    subparsers : argparse._SubParsersAction
        From :meth:`argparse.ArgumentParser.add_subparsers`.

    Returns
    -------
    argparse.ArgumentParser
        The new subcommand parser (its ``func`` default is :func:`run_topology`).
    """
    p = subparsers.add_parser(
        "topology",
        help="Betti numbers, Euler characteristic and TC of two robots on a graph",
        description="Topology of the configuration space F(G, 2) of two ordered robots on the graph G given as "
        'JSON {"edges": [[u, v], [u, v, length], ...]}.',
    )
    p.add_argument(
        "--graph",
        required=True,
        metavar="FILE",
        help="JSON file with the graph's edge list (or a layout, an Open-RMF building map or navigation graph)",
    )
    add_map_arguments(p)
    p.add_argument(
        "--clearance",
        type=float,
        default=None,
        metavar="D",
        help="also report the path components of the free space {d >= D} (m) and whether the robots can swap",
    )
    p.add_argument(
        "--footprint",
        default=None,
        metavar="SPEC",
        help="with the robots' bodies in the plane: R (disc radius, m) or LxW (rectangle, m), or SPEC_A,SPEC_B; "
        "the free space then keeps them apart in the layout's drawing (needs vertex coordinates)",
    )
    p.add_argument("--json", action="store_true", help="print one JSON object")
    p.set_defaults(func=run_topology)
    return p
