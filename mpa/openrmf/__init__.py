"""Open-RMF maps as layouts: building maps (``*.building.yaml``), navigation graphs and fleet configurations.

Three readers turn Open-RMF files into the layout dict of :meth:`mpa.GraphTrack.from_layout` (``{"vertices": ...,
"edges": [...]}`` with the optional edge keys ``"oneway"`` and ``"speed_limit"``):

- :func:`building_layout` reads a traffic-editor building map (``*.building.yaml``): one level (default: the
  reference level) and the lanes of one navigation graph (``graph_idx``, default 0).
- :func:`nav_graph_layout` reads the navigation graph that ``building_map_generator nav`` writes (``levels: {NAME:
  {vertices: [[x, y, {name: ...}]], lanes: [[i, j, {...}]]}}``; metres; every two-way lane written as two one-way
  lanes).
- :func:`fleet_config` reads a fleet configuration (``rmf_fleet.limits.linear``, ``rmf_fleet.profile``).

:func:`read_layout_file` tells the three file kinds our JSON, a building map and a navigation graph apart by their
content and returns the layout dict; :meth:`mpa.GraphTrack.from_file` builds the track from it.

**Coordinates** (metres, x east, y north), following the traffic editor's ``rmf_building_map_tools``:

- ``reference_image`` (also when ``coordinate_system`` is absent): pixels. ``y`` is negated and every coordinate
  multiplied by the reference level's scale, the mean over its ``measurements`` of the ``distance`` parameter
  (metres) divided by the measurement's length in pixels. Another level is aligned to the reference level through
  the fiducials the two levels share by name: rotation the circular mean of the bearing differences, scale the
  reference scale divided by the mean ratio of the fiducial distances, translation the mean residual (the traffic
  editor's ``Transform.set_from_fiducials``). A level without common fiducials keeps its own measurements' scale.
- ``cartesian_meters``: coordinates are metres, as written.
- ``wgs84``: vertices are ``[longitude, latitude]`` in degrees. They are projected onto the local tangent plane at the
  centre of the level's lane vertices (east, north): ``x = N(φ0) cos φ0 Δλ``, ``y = M(φ0) Δφ`` with the WGS 84
  ellipsoid's radii of curvature ``N`` and ``M``. Distances between projected points differ from distances on the
  ellipsoid by a relative error of at most about ``|tan φ0| Δφmax + (dmax / R)²`` (``Δφmax`` the largest latitude
  difference from the centre in radians, ``dmax`` the map's extent, ``R`` the Earth's radius): below 1e-4 for a
  campus of a kilometre at latitudes below 60 degrees. :func:`building_layout` reports it as ``"projection_error"``
  in its ``info``.

**Lanes to edges.** Only the lanes of the chosen level and graph are kept, with the vertices they use; vertices keep
their names (an unnamed vertex, or the second of two with one name, is called ``v<i>``, ``i`` its index in the
level's vertex list). A lane is a straight edge with the Euclidean length of its ends, named ``lane<k>`` (``k`` the
lane's index in the level's lane list). Lanes between the same two vertices merge into one edge: it is two-way when
one of them is two-way or they run both ways, else one-way (``"oneway": true``, from the lanes' start to their end);
its speed limit is the largest of theirs (none when one of them has none). A lane ``bidirectional: false`` is
one-way; ``speed_limit`` 0 means no limit, a positive value is kept, a negative one is an error. Lanes whose ends
coincide (zero length) are dropped. A disconnected graph is kept whole: a query between two parts is "no motion".
"""

from __future__ import annotations

from mpa.openrmf.building import (  # noqa: F401
    COORDINATE_SYSTEMS,
    EARTH_RADIUS,
    WGS84_A,
    WGS84_E2,
    _bidirectional,
    _fiducials,
    _Lane,
    _layout,
    _levels,
    _merge_lanes,
    _number,
    _param,
    _pick_level,
    _pixel_transform,
    _reference_scale,
    _speed_limit,
    _validate_vertices,
    _vertex_names,
    _wgs84_plane,
    building_layout,
    layout_kind,
    nav_graph_layout,
    read_layout_file,
)
from mpa.openrmf.files import (  # noqa: F401
    C_LOADER_DEPTH,
    C_LOADER_STACK,
    _load_yaml,
    _nesting_bound,
    _read_text,
    _safe_load,
    read_yaml_file,
)
from mpa.openrmf.fleet import FleetConfig, fleet_config, read_fleet_file

__all__ = [
    "FleetConfig",
    "building_layout",
    "fleet_config",
    "layout_kind",
    "nav_graph_layout",
    "read_fleet_file",
    "read_layout_file",
    "read_yaml_file",
]
