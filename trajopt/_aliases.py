"""The modules' former flat names (``trajopt.margins``, ``trajopt.gate_kernels``, ...) as aliases of their places
in the packages :mod:`trajopt.path`, :mod:`trajopt.verify`, :mod:`trajopt.analysis` and :mod:`trajopt.io`.

``import trajopt.margins`` returns the module object :mod:`trajopt.analysis.margins` itself (one module, so a
monkeypatch through either name is seen by both); nothing is imported until a former name is used.
"""

from __future__ import annotations

import importlib
import importlib.abc
import importlib.machinery
import sys
from types import ModuleType

#: former name (below ``trajopt.``) -> module path
FORMER_NAMES = {
    "fastpath": "trajopt.path.fastpath",
    "corridor": "trajopt.path.corridor",
    "switch": "trajopt.path.switch",
    "braking": "trajopt.path.braking",
    "planning": "trajopt.path.planning",
    "planview": "trajopt.path.planview",
    "gate_kernels": "trajopt.verify.kernels",
    "sample_kernels": "trajopt.verify.sampling",
    "planar_gate": "trajopt.verify.planar",
    "rows": "trajopt.verify.rows",
    "margins": "trajopt.analysis.margins",
    "min_margin": "trajopt.analysis.min_margin",
    "delay": "trajopt.analysis.delay",
    "stability": "trajopt.analysis.stability",
    "words": "trajopt.analysis.words",
    "pvt": "trajopt.io.pvt",
    "ros": "trajopt.io.ros",
    "csv_kernels": "trajopt.io.csv_kernels",
}


class _AliasLoader(importlib.abc.Loader):
    def __init__(self, target: str) -> None:
        self.target = target

    def create_module(self, spec: importlib.machinery.ModuleSpec) -> ModuleType:
        return importlib.import_module(self.target)

    def exec_module(self, module: ModuleType) -> None:
        """The target module is already executed."""


class _AliasFinder(importlib.abc.MetaPathFinder):
    def find_spec(
        self, fullname: str, path: object = None, target: object = None
    ) -> importlib.machinery.ModuleSpec | None:
        pkg, _, name = fullname.rpartition(".")
        if pkg != "trajopt" or name not in FORMER_NAMES:
            return None
        return importlib.machinery.ModuleSpec(fullname, _AliasLoader(FORMER_NAMES[name]))


def install() -> None:
    """Put the finder on :data:`sys.meta_path` once."""
    if not any(isinstance(f, _AliasFinder) for f in sys.meta_path):
        sys.meta_path.append(_AliasFinder())
