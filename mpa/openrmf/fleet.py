"""Open-RMF fleet configurations: the robots' footprint, vicinity and limits."""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass
from pathlib import Path

from mpa.errors import InvalidInputError
from mpa.openrmf.building import _number
from mpa.openrmf.files import read_yaml_file


# ------------------------------------------------------------------------------------------- fleet files
@dataclass(frozen=True)
class FleetConfig:
    """What a fleet configuration says about the robots' motion.

    Attributes
    ----------
    name : str
        ``rmf_fleet.name`` (empty if absent).
    vmax, amax : float
        ``rmf_fleet.limits.linear``: speed (m/s) and acceleration (m/s²) limits, > 0.
    footprint, vicinity : float or None
        ``rmf_fleet.profile``: disc radii (m) of the robot's body and of the space it wants kept clear.
    reversible : bool
        ``rmf_fleet.reversible`` (default true).
    """

    name: str
    vmax: float
    amax: float
    footprint: float | None
    vicinity: float | None
    reversible: bool

    def radius(self, which: str = "footprint") -> float:
        """The disc radius (m) of ``"footprint"`` or ``"vicinity"``; InvalidInputError when the file has none."""
        if which not in ("footprint", "vicinity"):
            raise InvalidInputError(f"fleet radius is {which!r}, expected 'footprint' or 'vicinity'")
        r = self.footprint if which == "footprint" else self.vicinity
        if r is None:
            raise InvalidInputError(
                f"rmf_fleet.profile.{which} of the fleet file is missing, expected a disc radius in metres"
            )
        return r


def fleet_config(data: object, what: str = "fleet file") -> FleetConfig:
    """Read an Open-RMF fleet configuration (``rmf_fleet: {limits: {linear: [v, a]}, profile: {...}}``).

    Raises
    ------
    InvalidInputError
        No ``rmf_fleet``, no ``limits.linear`` or limits that are not two numbers > 0, radii that are not numbers > 0.
    """
    fleet = data.get("rmf_fleet") if isinstance(data, Mapping) else None
    if not isinstance(fleet, Mapping):
        raise InvalidInputError(f"{what} has no rmf_fleet section, expected an Open-RMF fleet configuration")
    limits = fleet.get("limits")
    linear = limits.get("linear") if isinstance(limits, Mapping) else None
    if not isinstance(linear, list) or len(linear) != 2 or not all(_number(x) and float(x) > 0 for x in linear):
        raise InvalidInputError(
            f"rmf_fleet.limits.linear of the {what} is {linear!r}, expected [velocity, acceleration] > 0 (m/s, m/s^2)"
        )
    profile = fleet.get("profile")
    radii: list[float | None] = []
    for key in ("footprint", "vicinity"):
        r = profile.get(key) if isinstance(profile, Mapping) else None
        if r is not None and not (_number(r) and float(r) > 0):
            raise InvalidInputError(f"rmf_fleet.profile.{key} of the {what} is {r!r}, expected a radius > 0 (metres)")
        radii.append(None if r is None else float(r))
    rev = fleet.get("reversible", True)
    return FleetConfig(
        name=str(fleet.get("name") or ""),
        vmax=float(linear[0]),
        amax=float(linear[1]),
        footprint=radii[0],
        vicinity=radii[1],
        reversible=bool(rev),
    )


def read_fleet_file(path: str | Path) -> FleetConfig:
    """:func:`fleet_config` of a YAML file (errors also for a missing or unreadable file)."""
    return fleet_config(read_yaml_file(path, "fleet"), f"fleet file {str(path)!r}")
