"""Naming (docs/conventions.md, "Naming"): ``validate_*`` checks the caller's input and raises
:class:`mpa.errors.InvalidInputError`; ``check_*`` checks what the library computed. The former ``check_*`` names of
the input validators still work, as deprecated aliases that warn."""

from __future__ import annotations

import ast
import importlib
import inspect
import re
from pathlib import Path

import numpy as np
import pytest

from mpa import Lollipop
from mpa.cspace import ConfigurationSpace
from mpa.errors import InvalidInputError

ROOT = Path(__file__).resolve().parents[2]

#: (module, former name, current name) of every public input validator that was renamed.
RENAMED = [
    ("mpa.freespace", "check_size", "validate_size"),
    ("trajopt.grid", "check_rate", "validate_rate"),
    ("trajopt.export", "check_rate", "validate_rate"),
    ("trajopt.cli.common", "check_output_dir", "validate_output_dir"),
    ("trajopt.cli.outputs", "check_output_options", "validate_output_options"),
    ("trajopt.cli.serve", "check_serve_extra", "validate_serve_extra"),
    ("trajopt.io.ros", "check_joint_names", "validate_joint_names"),
    ("trajopt.io.ros", "check_topic", "validate_topic"),
    ("trajopt.io.directory", "check_output_path", "validate_output_path"),
    ("trajopt.io", "check_output_path", "validate_output_path"),
    ("trajopt.export", "check_output_path", "validate_output_path"),
    ("trajopt.analysis.delay", "check_delay_tolerance", "validate_delay_tolerance"),
    ("trajopt.analysis.min_margin", "check_min_margin", "validate_min_margin"),
]


@pytest.mark.parametrize(("module", "old", "new"), RENAMED)
def test_the_former_name_is_a_deprecated_alias_of_the_validator(module: str, old: str, new: str) -> None:
    mod = importlib.import_module(module)
    alias, func = getattr(mod, old), getattr(mod, new)
    public = getattr(mod, "__all__", [new])
    assert new in public and old not in public, (module, old, new)
    assert alias is not func and alias.__name__ == old and new in (alias.__doc__ or "")
    assert inspect.signature(alias) == inspect.signature(func)


@pytest.mark.parametrize(
    ("module", "old", "args", "returns", "error"),
    [
        ("trajopt.grid", "check_rate", (0,), None, "rate is 0.0, expected a positive finite number (Hz)"),
        ("trajopt.grid", "check_rate", (50,), 50.0, None),
        ("trajopt.analysis.min_margin", "check_min_margin", (-0.5,), None, "min_margin is -0.5"),
        ("trajopt.analysis.min_margin", "check_min_margin", (0.25,), 0.25, None),
        ("trajopt.analysis.delay", "check_delay_tolerance", ("soon",), None, "delay tolerance is 'soon'"),
        ("trajopt.io.ros", "check_topic", ("a/b",), "/a/b", None),
        ("trajopt.io.ros", "check_topic", ("1a",), None, "topic is '1a'"),
        ("trajopt.io.ros", "check_joint_names", (("x", "x"),), None, "joint"),
        ("trajopt.io.directory", "check_output_path", ("",), None, "path"),
    ],
)
def test_the_deprecated_alias_warns_and_behaves_as_the_validator(
    module: str, old: str, args: tuple[object, ...], returns: object, error: str | None
) -> None:
    alias = getattr(importlib.import_module(module), old)
    with pytest.warns(DeprecationWarning, match=rf"{old} is deprecated, use validate_"):
        if error is None:
            assert alias(*args) == returns
        else:
            with pytest.raises(InvalidInputError, match=re.escape(error)):
                alias(*args)


def test_the_configuration_space_methods_keep_their_former_names_with_a_warning() -> None:
    cs = ConfigurationSpace(Lollipop(1.0, 1.0), 0.1)
    with pytest.warns(DeprecationWarning, match="ConfigurationSpace.check_state is deprecated"):
        got = cs.check_state((0.2, 1.5))
    assert np.array_equal(got, cs.validate_state((0.2, 1.5)))
    with pytest.warns(DeprecationWarning, match="ConfigurationSpace.check_query is deprecated"):
        s, g = cs.check_query((0.2, 0.5), (0.5, 0.2))
    assert np.array_equal(s, [0.2, 0.5]) and np.array_equal(g, [0.5, 0.2])
    with pytest.warns(DeprecationWarning), pytest.raises(InvalidInputError, match="start"):
        cs.check_query((0.2, 9.0), (0.5, 0.2))


def _functions(prefix: tuple[str, ...]) -> list[tuple[str, ast.FunctionDef]]:
    out = []
    for path in sorted([*ROOT.joinpath("mpa").rglob("*.py"), *ROOT.joinpath("trajopt").rglob("*.py")]):
        tree = ast.parse(path.read_text(encoding="utf-8"))
        for node in ast.walk(tree):
            if isinstance(node, ast.FunctionDef) and node.name.lstrip("_").startswith(prefix):
                out.append((f"{path.relative_to(ROOT)}:{node.lineno} {node.name}", node))
    return out


def _raises_invalid_input(fn: ast.FunctionDef) -> bool:
    for node in ast.walk(fn):
        if isinstance(node, ast.Raise) and node.exc is not None:
            exc = node.exc.func if isinstance(node.exc, ast.Call) else node.exc
            if isinstance(exc, ast.Name) and exc.id == "InvalidInputError":
                return True
    return False


def test_no_check_function_validates_input() -> None:
    """A ``check_*`` (or ``_check_*``) function never raises InvalidInputError itself: that is a validator's job."""
    found = _functions(("check_", "check"))
    assert len(found) >= 8  # the output checks: check_setpoints, check_rows, check_pvt, ...
    bad = [where for where, fn in found if fn.name.lstrip("_").split("_")[0] == "check" and _raises_invalid_input(fn)]
    assert not bad, bad


def test_every_validator_raises_invalid_input() -> None:
    """Each ``validate_*`` function of mpa and trajopt raises InvalidInputError itself or through another validator
    (a name of the form ``validate_*``, ``positive_number`` or the like that it calls)."""
    found = _functions(("validate_", "validate"))
    assert len(found) >= 15
    lazy = []
    for where, fn in found:
        calls = {
            (n.func.attr if isinstance(n.func, ast.Attribute) else getattr(n.func, "id", ""))
            for n in ast.walk(fn)
            if isinstance(n, ast.Call)
        }
        if not _raises_invalid_input(fn) and not any(c.lstrip("_").startswith("validate") for c in calls):
            lazy.append((where, sorted(calls)))
    # the rest call the error helpers of mpa.errors (positive_number, ...) or a track's validate
    allowed_helpers = {"positive_number", "nonnegative_number", "validate", "finite_number"}
    assert all(set(c) & allowed_helpers for _, c in lazy), lazy
