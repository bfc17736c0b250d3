"""Every ``>>>`` example in the docstrings of :mod:`mpa` and :mod:`trajopt` runs and prints what it shows.

Every module of both packages is collected (one test each, modules without examples included, so a new module is
never skipped by omission); the only module not imported is ``trajopt.cli.__main__``, the ``python -m`` entry
point, whose import runs the command line.
"""

from __future__ import annotations

import doctest
import importlib
import pkgutil

import pytest

import mpa
import trajopt

#: Modules that are scripts, not libraries: importing them runs them.
NOT_IMPORTED = ("trajopt.cli.__main__",)


def _module_names() -> list[str]:
    names = []
    for pkg in (mpa, trajopt):
        names.append(pkg.__name__)
        names += [m.name for m in pkgutil.walk_packages(pkg.__path__, pkg.__name__ + ".")]
    return names


ALL_MODULES = _module_names()
MODULES = [m for m in ALL_MODULES if m not in NOT_IMPORTED]


def _examples(name: str) -> list[doctest.DocTest]:
    module = importlib.import_module(name)
    return [t for t in doctest.DocTestFinder().find(module, name) if t.examples]


@pytest.mark.parametrize("name", MODULES)
def test_docstring_examples_run(name: str) -> None:
    runner = doctest.DocTestRunner(optionflags=doctest.ELLIPSIS)
    report: list[str] = []
    for test in _examples(name):
        runner.run(test, out=report.append)
    result = runner.summarize(verbose=False)
    assert result.failed == 0, "".join(report)


def test_every_module_is_collected() -> None:
    assert set(NOT_IMPORTED) <= set(ALL_MODULES), "a module listed as not imported no longer exists"
    for expected in ("mpa.topology.cohomology", "mpa.planners.factory", "trajopt.generator", "trajopt.viz.drawing"):
        assert expected in MODULES
    assert sum(len(t.examples) for name in MODULES for t in _examples(name)) >= 50
