"""Topology of two robots on a graph: Abrams' discretized model, homology, cup products and complexity.

:mod:`mpa.topology.discretized` builds the cube complex D₂(Γ); :mod:`mpa.topology.algebra` holds the exact
elimination, :mod:`mpa.topology.cohomology` the cohomology ring and the zero-divisor cup-length,
:mod:`mpa.topology.configuration` the Betti numbers, homotopy dimension and TC of F(Γ, 2),
:mod:`mpa.topology.complexity` the topological complexity of the paper's tracks and
:mod:`mpa.topology.graph_json` reads an edge list.
"""

from mpa.topology.algebra import FIELD_PRIME
from mpa.topology.cohomology import zero_divisor_cup_length
from mpa.topology.complexity import component_betti_numbers, rules_needed, topological_complexity
from mpa.topology.configuration import (
    ComponentTopology,
    ConfigurationSpaceTopology,
    HomotopyDimension,
    configuration_space_topology,
    cube_complex_topology,
    euler_characteristic_formula,
)
from mpa.topology.graph_json import graph_from_json_data, load_graph_json

__all__ = [
    "FIELD_PRIME",
    "ComponentTopology",
    "ConfigurationSpaceTopology",
    "HomotopyDimension",
    "component_betti_numbers",
    "configuration_space_topology",
    "cube_complex_topology",
    "euler_characteristic_formula",
    "graph_from_json_data",
    "load_graph_json",
    "rules_needed",
    "topological_complexity",
    "zero_divisor_cup_length",
]
