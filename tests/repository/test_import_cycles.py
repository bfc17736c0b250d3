"""No import cycles among the modules of ``mpa`` and ``trajopt``.

The imports are read from the source with :mod:`ast`: top-level imports and imports inside functions both count
(a function-level import only defers a cycle, it does not remove it). Imports under ``if TYPE_CHECKING:`` do not
count: they never run. A module importing a package's submodule depends on that submodule, not on the package's
``__init__`` (every submodule import runs its package's ``__init__`` first, which would make each package a cycle
with its own re-exports).
"""

from __future__ import annotations

import ast
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]

#: Cycles that remain, each with the reason it is not removed here. A new cycle, or a known one that grows, fails.
KNOWN_CYCLES: set[frozenset[str]] = set()  # none: the function-level imports go to the modules that define
# the names (mpa.planners.graph.assemble, .search, .reasons), not through the package that imports the planners


def _modules() -> dict[str, Path]:
    mods = {}
    for pkg in ("mpa", "trajopt"):
        for p in sorted((ROOT / pkg).rglob("*.py")):
            parts = list(p.relative_to(ROOT).with_suffix("").parts)
            if parts[-1] == "__init__":
                parts = parts[:-1]
            mods[".".join(parts)] = p
    return mods


def _imports(name: str, path: Path, mods: dict[str, Path]) -> set[str]:
    """The modules of ``mods`` that ``name`` (at ``path``) imports, outside ``if TYPE_CHECKING:``."""
    tree = ast.parse(path.read_text(encoding="utf-8"))
    skip: set[int] = set()
    for node in ast.walk(tree):
        if isinstance(node, ast.If) and "TYPE_CHECKING" in ast.unparse(node.test):
            skip.update(id(n) for stmt in node.body for n in ast.walk(stmt))
    targets: set[str] = set()
    for node in ast.walk(tree):
        if id(node) in skip:
            continue
        if isinstance(node, ast.Import):
            targets.update(a.name for a in node.names)
        elif isinstance(node, ast.ImportFrom):
            base = node.module or ""
            if node.level:
                pkg = name.split(".") if path.name == "__init__.py" else name.split(".")[:-1]
                pkg = pkg[: len(pkg) - (node.level - 1)]
                base = ".".join([*pkg, base] if base else pkg)
            targets.add(base)
            targets.update(f"{base}.{a.name}" for a in node.names)  # ``from pkg import submodule``
    found = set()
    for t in targets:
        while t and t not in mods:
            t = t.rpartition(".")[0]
        if t and t != name:
            found.add(t)
    return found


def import_cycles() -> list[frozenset[str]]:
    """The strongly connected components (more than one module) of the import graph of ``mpa`` and ``trajopt``."""
    mods = _modules()
    graph = {m: _imports(m, p, mods) for m, p in mods.items()}
    index: dict[str, int] = {}
    low: dict[str, int] = {}
    stack: list[str] = []
    on_stack: set[str] = set()
    cycles: list[frozenset[str]] = []
    counter = 0
    for root in graph:  # Tarjan's algorithm, iterative
        if root in index:
            continue
        work = [(root, iter(sorted(graph[root])))]
        index[root] = low[root] = counter
        counter += 1
        stack.append(root)
        on_stack.add(root)
        while work:
            v, it = work[-1]
            w = next(it, None)
            if w is not None:
                if w not in index:
                    index[w] = low[w] = counter
                    counter += 1
                    stack.append(w)
                    on_stack.add(w)
                    work.append((w, iter(sorted(graph[w]))))
                elif w in on_stack:
                    low[v] = min(low[v], index[w])
                continue
            work.pop()
            if work:
                low[work[-1][0]] = min(low[work[-1][0]], low[v])
            if low[v] == index[v]:
                comp = set()
                while True:
                    w = stack.pop()
                    on_stack.discard(w)
                    comp.add(w)
                    if w == v:
                        break
                if len(comp) > 1:
                    cycles.append(frozenset(comp))
    return cycles


def test_no_import_cycles_but_the_known_ones() -> None:
    new = [sorted(c) for c in import_cycles() if c not in KNOWN_CYCLES]
    assert not new, f"import cycles: {new}"


def test_the_cycle_finder_finds_a_cycle(tmp_path: Path) -> None:
    """The finder is not vacuous: two modules importing each other (one inside a function) are a cycle, and an
    import under ``if TYPE_CHECKING:`` is not."""
    (tmp_path / "a.py").write_text("def f():\n    from pkg import b\n", encoding="utf-8")
    (tmp_path / "b.py").write_text("from pkg.a import f\n", encoding="utf-8")
    (tmp_path / "c.py").write_text("from typing import TYPE_CHECKING\nif TYPE_CHECKING:\n    from pkg import a\n")
    mods = {"pkg.a": tmp_path / "a.py", "pkg.b": tmp_path / "b.py", "pkg.c": tmp_path / "c.py"}
    assert _imports("pkg.a", mods["pkg.a"], mods) == {"pkg.b"}
    assert _imports("pkg.b", mods["pkg.b"], mods) == {"pkg.a"}
    assert _imports("pkg.c", mods["pkg.c"], mods) == set()


def test_the_cycles_this_layout_removed_stay_removed() -> None:
    joined = {m for c in import_cycles() for m in c}
    for pair in [
        ("trajopt.export", "trajopt.analysis.margins"),
        ("trajopt.result", "trajopt.analysis.margins"),
        ("trajopt.viz.animation", "trajopt.viz.layout_animation"),
        ("trajopt.replan", "trajopt.replan_graph"),
        ("trajopt.analysis.delay", "trajopt.generator"),
        ("trajopt.generator", "trajopt.analysis.min_margin"),
    ]:
        assert not set(pair) <= joined, pair
