"""Open-RMF building maps and navigation graphs as layouts.

Lanes merged into edges, vertex names, and coordinates in metres (from the reference image's scale, cartesian
metres or WGS84).
"""

from __future__ import annotations

import json
import math
from collections.abc import Mapping
from dataclasses import dataclass
from pathlib import Path
from typing import Any

from mpa.errors import InvalidInputError
from mpa.graph import _json_int
from mpa.openrmf.files import _load_yaml, _read_text

#: WGS 84 ellipsoid: semi-major axis (m) and first eccentricity squared.
WGS84_A = 6378137.0


WGS84_E2 = 6.69437999014e-3


EARTH_RADIUS = 6371008.8


COORDINATE_SYSTEMS = ("reference_image", "cartesian_meters", "wgs84")


# ------------------------------------------------------------------------------------------------ helpers
def _param(params: object, key: str, default: Any = None) -> Any:
    """The value of a traffic-editor parameter ``[type, value]`` (or a plain value) in ``params``."""
    if not isinstance(params, Mapping) or key not in params:
        return default
    raw = params[key]
    if isinstance(raw, list) and len(raw) == 2 and isinstance(raw[0], int) and not isinstance(raw[0], bool):
        return raw[1]
    return raw


def _number(x: object) -> bool:
    return isinstance(x, (int, float)) and not isinstance(x, bool) and math.isfinite(float(x))


def _speed_limit(raw: object, what: str) -> float | None:
    if raw is None:
        return None
    if not _number(raw):
        raise InvalidInputError(f"speed_limit of {what} is {raw!r}, expected a number >= 0 (m/s; 0: no limit)")
    v = float(raw)  # type: ignore[arg-type]
    if v < 0:
        raise InvalidInputError(f"speed_limit of {what} is {raw!r}, expected a number >= 0 (m/s; 0: no limit)")
    return v if v > 0 else None


def _bidirectional(raw: object, what: str) -> bool:
    if raw is None:
        return True
    if isinstance(raw, bool):
        return raw
    if isinstance(raw, int) and raw in (0, 1):
        return bool(raw)
    raise InvalidInputError(f"bidirectional of {what} is {raw!r}, expected true or false")


def _levels(data: Mapping[str, Any], what: str) -> Mapping[str, Any]:
    levels = data.get("levels")
    if not isinstance(levels, Mapping) or not levels:
        raise InvalidInputError(f'{what} has levels {levels!r}, expected a non-empty mapping "levels: {{NAME: ...}}"')
    for name, level in levels.items():
        if not isinstance(level, Mapping):
            raise InvalidInputError(f"level {name!r} of the {what} is {level!r}, expected a mapping")
    return levels


def _pick_level(levels: Mapping[str, Any], level: str | None, default: str, what: str) -> str:
    names = [str(n) for n in levels]
    if level is None:
        level = default
    if level not in names:
        raise InvalidInputError(f"level is {level!r}, expected one of the {what}'s levels {names}")
    return level


@dataclass
class _Lane:
    index: int
    u: int
    v: int
    bidirectional: bool
    speed_limit: float | None


def _merge_lanes(
    lanes: list[_Lane], names: dict[int, str], coords: dict[int, tuple[float, float]]
) -> tuple[list[dict[str, Any]], int, int]:
    """Our edges from lanes: repeated lanes merged, zero-length lanes dropped. Also how many of each."""
    groups: dict[tuple[int, int], list[_Lane]] = {}
    order: list[tuple[int, int]] = []
    dropped = 0
    for ln in lanes:
        a, b = coords[ln.u], coords[ln.v]
        if ln.u == ln.v or math.hypot(b[0] - a[0], b[1] - a[1]) == 0.0:
            dropped += 1
            continue
        key = (min(ln.u, ln.v), max(ln.u, ln.v))
        if key not in groups:
            groups[key] = []
            order.append(key)
        groups[key].append(ln)
    edges = []
    merged = 0
    for key in order:
        group = groups[key]
        merged += len(group) - 1
        first = group[0]
        directions = {(ln.u, ln.v) for ln in group}
        two_way = any(ln.bidirectional for ln in group) or len(directions) == 2
        limits = [ln.speed_limit for ln in group]
        limit = None if any(x is None for x in limits) else max(x for x in limits if x is not None)
        a, b = coords[first.u], coords[first.v]
        edge: dict[str, Any] = {
            "name": f"lane{first.index}",
            "from": names[first.u],
            "to": names[first.v],
            "length": math.hypot(b[0] - a[0], b[1] - a[1]),
        }
        if not two_way:
            edge["oneway"] = True
        if limit is not None:
            edge["speed_limit"] = limit
        edges.append(edge)
    return edges, merged, dropped


def _vertex_names(raw_names: dict[int, object]) -> dict[int, str]:
    """Vertex names: the given name, or ``v<i>`` when it is empty, already taken or not a string."""
    out: dict[int, str] = {}
    taken: set[str] = set()
    for i in sorted(raw_names):
        n = raw_names[i]
        if isinstance(n, (int, float)) and not isinstance(n, bool):
            n = str(n)
        if isinstance(n, str) and n and n not in taken:
            out[i] = n
            taken.add(n)
    for i in sorted(raw_names):
        if i in out:
            continue
        name = f"v{i}"
        while name in taken:
            name += "_"
        out[i] = name
        taken.add(name)
    return out


def _layout(
    lanes: list[_Lane], raw_names: dict[int, object], coords: dict[int, tuple[float, float]], what: str
) -> tuple[dict[str, Any], dict[str, Any]]:
    used = sorted({ln.u for ln in lanes} | {ln.v for ln in lanes})
    names = _vertex_names({i: raw_names[i] for i in used})
    edges, merged, dropped = _merge_lanes(lanes, names, coords)
    if not edges:
        raise InvalidInputError(f"{what} has no lane of positive length, expected at least one lane")
    ends = {e["from"] for e in edges} | {e["to"] for e in edges}
    kept = [i for i in used if names[i] in ends]
    layout = {"vertices": {names[i]: list(coords[i]) for i in kept}, "edges": edges}
    info = {"lanes": len(lanes), "merged_lanes": merged, "dropped_lanes": dropped, "edges": len(edges)}
    return layout, info


# ------------------------------------------------------------------------------------------- building maps
def _reference_scale(level: Mapping[str, Any], vertices: list[Any], name: str) -> float | None:
    """Metres per pixel of a level from its measurements (None without measurements)."""
    ratios = []
    for k, m in enumerate(level.get("measurements") or []):
        if not isinstance(m, list) or len(m) < 3:
            raise InvalidInputError(f"measurement {k} of level {name!r} is {m!r}, expected [i, j, {{distance: ...}}]")
        i, j = m[0], m[1]
        for end in (i, j):
            if not isinstance(end, int) or isinstance(end, bool) or not 0 <= end < len(vertices):
                raise InvalidInputError(
                    f"vertex index {end!r} of measurement {k} of level {name!r} does not exist, expected an index in "
                    f"[0, {len(vertices) - 1}]"
                )
        dist = _param(m[2], "distance")
        if not _number(dist) or float(dist) <= 0:
            raise InvalidInputError(
                f"distance of measurement {k} of level {name!r} is {dist!r}, expected a number > 0 (metres)"
            )
        (x0, y0), (x1, y1) = vertices[i][:2], vertices[j][:2]
        px = math.hypot(float(x1) - float(x0), float(y1) - float(y0))
        if px <= 0:
            raise InvalidInputError(
                f"measurement {k} of level {name!r} has length 0 pixels, expected two distinct vertices"
            )
        ratios.append(float(dist) / px)
    return sum(ratios) / len(ratios) if ratios else None


def _validate_vertices(level: Mapping[str, Any], name: str, lon_lat: bool) -> list[Any]:
    vertices = level.get("vertices") or []
    if not isinstance(vertices, list):
        raise InvalidInputError(f"vertices of level {name!r} is {vertices!r}, expected a list of [x, y, z, name]")
    for i, v in enumerate(vertices):
        if not isinstance(v, list) or len(v) < 2 or not _number(v[0]) or not _number(v[1]):
            raise InvalidInputError(
                f"vertex {i} of level {name!r} is {v!r}, expected [x, y, z, name, {{params}}] with finite numbers"
            )
        if lon_lat and not (-180 <= float(v[0]) <= 180 and -90 <= float(v[1]) <= 90):
            raise InvalidInputError(
                f"vertex {i} of level {name!r} is at longitude {v[0]!r}, latitude {v[1]!r}, expected degrees within "
                "[-180, 180] and [-90, 90] (wgs84 map)"
            )
    return vertices


def _fiducials(level: Mapping[str, Any]) -> dict[str, tuple[float, float]]:
    out: dict[str, tuple[float, float]] = {}
    for f in level.get("fiducials") or []:
        if isinstance(f, list) and len(f) >= 3 and _number(f[0]) and _number(f[1]) and isinstance(f[2], str) and f[2]:
            out[f[2]] = (float(f[0]), -float(f[1]))
    return out


def _pixel_transform(levels: Mapping[str, Any], name: str, ref: str) -> tuple[float, float, float, float]:
    """``(scale, rotation, tx, ty)``: pixel ``p = (x, -y)`` of level ``name`` is at ``R(rotation) p · scale + t``."""
    ref_level = levels[ref]
    ref_vertices = _validate_vertices(ref_level, ref, False)
    ref_scale = _reference_scale(ref_level, ref_vertices, ref)
    if ref_scale is None:
        raise InvalidInputError(
            f"reference level {ref!r} has no measurements, expected at least one measurement with a distance to "
            "scale a reference_image map"
        )
    if name == ref:
        return ref_scale, 0.0, 0.0, 0.0
    f_ref, f_lvl = _fiducials(ref_level), _fiducials(levels[name])
    pairs = [(f_ref[k], f_lvl[k]) for k in f_ref if k in f_lvl]
    if len(pairs) < 2:
        own = _reference_scale(levels[name], _validate_vertices(levels[name], name, False), name)
        return (own if own is not None else ref_scale), 0.0, 0.0, 0.0
    bearings = []
    ratios = []
    for a in range(len(pairs)):
        for b in range(a + 1, len(pairs)):
            (r0, t0), (r1, t1) = pairs[a], pairs[b]
            rb = math.atan2(r1[1] - r0[1], r1[0] - r0[0])
            tb = math.atan2(t1[1] - t0[1], t1[0] - t0[0])
            bearings.append(tb - rb)
            rd = math.hypot(r1[0] - r0[0], r1[1] - r0[1])
            td = math.hypot(t1[0] - t0[0], t1[1] - t0[1])
            if rd > 0:
                ratios.append(td / rd)
    rot = -math.atan2(sum(math.sin(d) for d in bearings), sum(math.cos(d) for d in bearings))
    rel = sum(ratios) / len(ratios) if ratios else 1.0
    cr, sr = math.cos(rot), math.sin(rot)
    mx = my = 0.0
    for r, t in pairs:
        fx, fy = t[0] / rel, t[1] / rel
        mx += cr * fx - sr * fy - r[0]
        my += sr * fx + cr * fy - r[1]
    n = len(pairs)
    return ref_scale / rel, rot, -ref_scale * mx / n, -ref_scale * my / n


def _wgs84_plane(points: dict[int, tuple[float, float]]) -> tuple[dict[int, tuple[float, float]], float]:
    """Longitude/latitude (degrees) -> local tangent plane (metres) at the points' centre; the error bound."""
    lons = [p[0] for p in points.values()]
    lats = [p[1] for p in points.values()]
    lon0 = 0.5 * (min(lons) + max(lons))
    lat0 = 0.5 * (min(lats) + max(lats))
    phi0 = math.radians(lat0)
    w = math.sqrt(1.0 - WGS84_E2 * math.sin(phi0) ** 2)
    n_rad = WGS84_A / w
    m_rad = WGS84_A * (1.0 - WGS84_E2) / w**3
    out = {}
    for i, (lon, lat) in points.items():
        dlon = (lon - lon0 + 180.0) % 360.0 - 180.0
        out[i] = (n_rad * math.cos(phi0) * math.radians(dlon), m_rad * math.radians(lat - lat0))
    xs = [p[0] for p in out.values()]
    ys = [p[1] for p in out.values()]
    extent = math.hypot(max(xs) - min(xs), max(ys) - min(ys))
    dphi = max(abs(math.radians(lat - lat0)) for lat in lats)
    error = abs(math.tan(phi0)) * dphi + (extent / EARTH_RADIUS) ** 2
    return out, error


def building_layout(
    data: object, level: str | None = None, nav_graph: int | None = None
) -> tuple[dict[str, Any], dict[str, Any]]:
    """Our layout dict of one level and one navigation graph of a traffic-editor building map.

    Parameters
    ----------
    data : dict
        The decoded ``*.building.yaml``.
    level : str, optional
        The level's name (default: ``reference_level_name``, else the first level).
    nav_graph : int, optional
        The lanes' ``graph_idx`` (default 0; 9 is the human lanes).

    Returns
    -------
    layout : dict
        ``{"vertices": {name: [x, y]}, "edges": [{"name", "from", "to", "length", "oneway"?, "speed_limit"?}]}``,
        coordinates and lengths in metres (see the module docstring).
    info : dict
        ``kind`` ("building"), ``level``, ``nav_graph``, ``coordinate_system``, ``lanes`` (lanes of that graph),
        ``merged_lanes``, ``dropped_lanes`` (zero length), ``edges``, ``projection_error`` (wgs84: the relative
        distance error bound, else 0).

    Raises
    ------
    InvalidInputError
        Unknown coordinate system, level or graph index (the message lists the existing ones), a lane naming a
        missing vertex, a negative speed limit, bad coordinates or measurements.
    """
    if not isinstance(data, Mapping):
        raise InvalidInputError(f"building map is a {type(data).__name__}, expected a mapping with levels")
    system = data.get("coordinate_system", "reference_image") or "reference_image"
    if system not in COORDINATE_SYSTEMS:
        raise InvalidInputError(
            f"coordinate_system of the building map is {system!r}, expected one of {list(COORDINATE_SYSTEMS)}"
        )
    levels = _levels(data, "building map")
    ref = data.get("reference_level_name")
    ref = str(ref) if ref is not None and str(ref) in levels else str(next(iter(levels)))
    name = _pick_level(levels, level, ref, "building map")
    lvl = levels[name]
    if isinstance(nav_graph, bool) or (nav_graph is not None and not isinstance(nav_graph, int)):
        raise InvalidInputError(f"nav graph is {nav_graph!r}, expected a graph index (an integer)")
    graph_idx = 0 if nav_graph is None else int(nav_graph)
    vertices = _validate_vertices(lvl, name, system == "wgs84")
    raw_lanes = lvl.get("lanes") or []
    if not isinstance(raw_lanes, list):
        raise InvalidInputError(f"lanes of level {name!r} is {raw_lanes!r}, expected a list of [i, j, {{params}}]")
    present: set[int] = set()
    lanes: list[_Lane] = []
    for k, ln in enumerate(raw_lanes):
        if not isinstance(ln, list) or len(ln) < 2:
            raise InvalidInputError(f"lane {k} of level {name!r} is {ln!r}, expected [i, j, {{params}}]")
        params = ln[2] if len(ln) > 2 else {}
        gi = _param(params, "graph_idx", 0)
        if isinstance(gi, bool) or not isinstance(gi, int):
            raise InvalidInputError(f"graph_idx of lane {k} of level {name!r} is {gi!r}, expected an integer")
        present.add(gi)
        if gi != graph_idx:
            continue
        for end in ln[:2]:
            if not isinstance(end, int) or isinstance(end, bool) or not 0 <= end < len(vertices):
                raise InvalidInputError(
                    f"vertex {end!r} of lane {k} of level {name!r} does not exist, expected a vertex index in "
                    f"[0, {len(vertices) - 1}]"
                )
        what = f"lane {k} of level {name!r}"
        lanes.append(
            _Lane(
                k,
                ln[0],
                ln[1],
                _bidirectional(_param(params, "bidirectional"), what),
                _speed_limit(_param(params, "speed_limit"), what),
            )
        )
    if not lanes:
        raise InvalidInputError(
            f"nav graph is {graph_idx}, expected one of the graph indices with lanes on level {name!r}: "
            f"{sorted(present)}"
        )
    used = sorted({ln.u for ln in lanes} | {ln.v for ln in lanes})
    raw = {i: float(vertices[i][0]) for i in used}, {i: float(vertices[i][1]) for i in used}
    error = 0.0
    if system == "reference_image":
        scale, rot, tx, ty = _pixel_transform(levels, name, ref)
        cr, sr = math.cos(rot), math.sin(rot)
        coords = {}
        for i in used:
            x, y = raw[0][i], -raw[1][i]
            coords[i] = ((cr * x - sr * y) * scale + tx, (sr * x + cr * y) * scale + ty)
    elif system == "cartesian_meters":
        coords = {i: (raw[0][i], raw[1][i]) for i in used}
    else:
        coords, error = _wgs84_plane({i: (raw[0][i], raw[1][i]) for i in used})
    names = {i: (vertices[i][3] if len(vertices[i]) > 3 else "") for i in used}
    layout, info = _layout(lanes, names, coords, f"graph {graph_idx} of level {name!r}")
    info.update(kind="building", level=name, nav_graph=graph_idx, coordinate_system=system, projection_error=error)
    return layout, info


# ---------------------------------------------------------------------------------------------- nav graphs
def nav_graph_layout(data: object, level: str | None = None) -> tuple[dict[str, Any], dict[str, Any]]:
    """Our layout dict of one level of a navigation graph written by ``building_map_generator nav``.

    Parameters
    ----------
    data : dict
        ``{"levels": {NAME: {"vertices": [[x, y, {"name": ...}]], "lanes": [[i, j, {...}]]}}}`` (metres).
    level : str, optional
        Default: the first level.

    Returns
    -------
    layout, info : dict
        As :func:`building_layout` (``kind`` "nav_graph"); a lane written both ways is one two-way edge.

    Raises
    ------
    InvalidInputError
        Unknown level (the message lists the existing ones), a lane naming a missing vertex, a negative speed
        limit, bad coordinates.
    """
    if not isinstance(data, Mapping):
        raise InvalidInputError(f"navigation graph is a {type(data).__name__}, expected a mapping with levels")
    levels = _levels(data, "navigation graph")
    name = _pick_level(levels, level, str(next(iter(levels))), "navigation graph")
    lvl = levels[name]
    vertices = lvl.get("vertices") or []
    if not isinstance(vertices, list):
        raise InvalidInputError(f"vertices of level {name!r} is {vertices!r}, expected a list of [x, y, {{name}}]")
    for i, v in enumerate(vertices):
        if not isinstance(v, list) or len(v) < 2 or not _number(v[0]) or not _number(v[1]):
            raise InvalidInputError(f"vertex {i} of level {name!r} is {v!r}, expected [x, y, {{name: ...}}]")
    raw_lanes = lvl.get("lanes") or []
    if not isinstance(raw_lanes, list):
        raise InvalidInputError(f"lanes of level {name!r} is {raw_lanes!r}, expected a list of [i, j, {{params}}]")
    lanes = []
    for k, ln in enumerate(raw_lanes):
        if not isinstance(ln, list) or len(ln) < 2:
            raise InvalidInputError(f"lane {k} of level {name!r} is {ln!r}, expected [i, j, {{params}}]")
        for end in ln[:2]:
            if not isinstance(end, int) or isinstance(end, bool) or not 0 <= end < len(vertices):
                raise InvalidInputError(
                    f"vertex {end!r} of lane {k} of level {name!r} does not exist, expected a vertex index in "
                    f"[0, {len(vertices) - 1}]"
                )
        params = ln[2] if len(ln) > 2 else {}
        lanes.append(
            _Lane(k, ln[0], ln[1], False, _speed_limit(_param(params, "speed_limit"), f"lane {k} of level {name!r}"))
        )
    if not lanes:
        raise InvalidInputError(f"level {name!r} of the navigation graph has no lanes, expected at least one lane")
    used = sorted({ln.u for ln in lanes} | {ln.v for ln in lanes})
    coords = {i: (float(vertices[i][0]), float(vertices[i][1])) for i in used}
    names = {i: _param(vertices[i][2] if len(vertices[i]) > 2 else {}, "name", "") for i in used}
    layout, info = _layout(lanes, names, coords, f"level {name!r} of the navigation graph")
    info.update(kind="nav_graph", level=name, nav_graph=None, coordinate_system="metres", projection_error=0.0)
    return layout, info


# ------------------------------------------------------------------------------------------ file dispatch
def layout_kind(data: object) -> str:
    """``"layout"`` (our JSON), ``"building"`` or ``"nav_graph"``; InvalidInputError for anything else."""
    if isinstance(data, Mapping) and "edges" in data:
        return "layout"
    if isinstance(data, Mapping) and isinstance(data.get("levels"), Mapping):
        for level in data["levels"].values():
            if not isinstance(level, Mapping):
                break
            vs = level.get("vertices")
            if isinstance(vs, list) and vs and isinstance(vs[0], list):
                # building maps: [x, y, z, name, {params}]; nav graphs: [x, y, {params}]
                return "nav_graph" if len(vs[0]) >= 3 and isinstance(vs[0][2], Mapping) else "building"
            if "lanes" in level or "vertices" in level:
                return "nav_graph" if "measurements" not in level and "walls" not in level else "building"
    keys = f" with keys {sorted(map(str, data))[:10]}" if isinstance(data, Mapping) else ""
    raise InvalidInputError(
        f"layout is a {type(data).__name__}{keys}, "
        'expected our JSON layout {"edges": [...]}, an Open-RMF building map (*.building.yaml) or a navigation '
        "graph (levels: {NAME: {vertices, lanes}})"
    )


def read_layout_file(
    path: str | Path, level: str | None = None, nav_graph: int | None = None
) -> tuple[dict[str, Any], dict[str, Any]]:
    """The layout dict of a file: our JSON layout, an Open-RMF building map or a navigation graph.

    Parameters
    ----------
    path : str or Path
    level : str, optional
        Building maps and navigation graphs: the level (default: the reference level, resp. the first).
    nav_graph : int, optional
        Building maps: the lanes' ``graph_idx`` (default 0).

    Returns
    -------
    layout, info : dict
        ``info["kind"]`` is ``"layout"``, ``"building"`` or ``"nav_graph"``. Open-RMF maps are converted once and
        then read from the on-disk cache of :mod:`mpa.openrmf.cache` (``$MPA_CACHE_DIR``; a stale or damaged
        entry is converted again, never trusted).

    Raises
    ------
    InvalidInputError
        Missing or unreadable file, neither of the three kinds, ``level``/``nav_graph`` given for our JSON layout
        or ``nav_graph`` for a navigation graph, and the errors of :func:`building_layout` and
        :func:`nav_graph_layout`.
    """
    from mpa.openrmf.cache import cached_layout

    p = Path(path)
    text = _read_text(p, "layout", "a UTF-8 JSON or YAML layout file")
    return cached_layout(text, level, nav_graph, lambda: _convert_text(p, text, level, nav_graph))


def _convert_text(
    p: Path, text: str, level: str | None, nav_graph: int | None
) -> tuple[dict[str, Any], dict[str, Any]]:
    """:func:`read_layout_file` of the text ``text`` of file ``p``, without the cache."""
    try:
        data: object = json.loads(text, parse_int=_json_int)
    except RecursionError:
        raise InvalidInputError(
            f"layout file {str(p)!r} is nested too deeply, expected JSON nested at most a few hundred levels"
        ) from None
    except json.JSONDecodeError as exc:
        if p.suffix.lower() == ".json":  # a .json file is JSON (a YAML reading would hide the mistake)
            raise InvalidInputError(
                f"layout file {str(p)!r} is not valid JSON ({exc.msg} at line {exc.lineno} column {exc.colno})"
            ) from None
        data = _load_yaml(text, f"layout file {str(p)!r}")
    kind = layout_kind(data)
    if kind == "layout":
        for option, value in (("level", level), ("nav graph", nav_graph)):
            if value is not None:
                raise InvalidInputError(
                    f"{option} is {value!r} for {str(p)!r}, a layout of ours, expected it only with an Open-RMF map"
                )
        assert isinstance(data, dict)
        return data, {"kind": "layout"}
    if kind == "nav_graph":
        if nav_graph is not None:
            raise InvalidInputError(
                f"nav graph is {nav_graph!r} for {str(p)!r}, a navigation graph (one graph per file), expected it "
                "only with a building map"
            )
        return nav_graph_layout(data, level)
    return building_layout(data, level, nav_graph)
