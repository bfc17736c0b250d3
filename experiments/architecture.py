"""Draw the layers of the project (docs/img/architecture.png) and check that the imports respect them.

Layers, bottom to top: ``mpa`` (numpy only), the ``trajopt`` pipeline, ``trajopt.cli`` and ``trajopt.viz``, then
``experiments``. A module may import from its own layer and the layers below, never from a layer above. The
modules of each layer are read from the source tree, so the picture follows the code.

Usage::

    python experiments/architecture.py --out docs/img/architecture.png
    python experiments/architecture.py --check           # only check the imports; exit 1 on a violation

Headless (Agg).
"""

from __future__ import annotations

import argparse
import ast
import os
import sys
from collections.abc import Sequence
from dataclasses import dataclass
from itertools import pairwise
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]

__all__ = ["LAYERS", "Layer", "check_layers", "draw_layers", "main"]


@dataclass(frozen=True)
class Layer:
    """One layer: its name, the source folders it holds (relative to the repository), what it may import from
    outside the project, and the colour of its band."""

    name: str
    folders: tuple[str, ...]
    third_party: str
    color: str


def _packages(root: str, exclude: tuple[str, ...] = ()) -> tuple[str, ...]:
    """``root`` and every folder below it that holds Python modules (relative to the repository), sorted, without
    the folders of ``exclude`` and what lies below them."""
    found = []
    for d in [ROOT / root, *sorted((ROOT / root).rglob("*"))]:
        rel = d.relative_to(ROOT).as_posix()
        if not d.is_dir() or "__pycache__" in d.parts or not any(d.glob("*.py")):
            continue
        if any(rel == x or rel.startswith(x + "/") for x in exclude):
            continue
        found.append(rel)
    return tuple(found)


_TOP = ("trajopt/cli", "trajopt/viz", "trajopt/web")

#: The layers, bottom first; a layer holds its folders and every package below them.
LAYERS = (
    Layer(
        "mpa — the paper (numpy only)",
        _packages("mpa"),
        "numpy; PyYAML: Open-RMF maps (openrmf) only",
        "#dbe9f6",
    ),
    Layer(
        "trajopt — the pipeline",
        _packages("trajopt", exclude=_TOP),
        "casadi, toppra, ruckig, numba (compiled kernels); rosbags: ROS 2 bags only",
        "#e2f0d9",
    ),
    Layer(
        "trajopt.cli, trajopt.viz and trajopt.web",
        tuple(f for top in _TOP for f in _packages(top)),
        "matplotlib (viz only); starlette, uvicorn (web only); dask, tqdm (mpa batch only, optional)",
        "#fde9d9",
    ),
    Layer("experiments — figures, animations, benchmarks", _packages("experiments"), "ompl, dask", "#eee"),
)

#: Top-level imports each layer may use besides the standard library and the layers below.
_ALLOWED = (
    {"numpy", "mpa"},
    {"numpy", "mpa", "trajopt", "casadi", "toppra", "ruckig", "rosbags", "numba"},
    {
        "numpy",
        "mpa",
        "trajopt",
        "casadi",
        "toppra",
        "ruckig",
        "rosbags",
        "numba",
        "matplotlib",
        "mpl_toolkits",
        "PIL",
        "imageio_ffmpeg",
        "starlette",
        "uvicorn",
        "dask",
        "tqdm",
    },
    None,  # experiments: anything
)


#: Third-party imports allowed in single modules beyond their layer's (PyYAML reads Open-RMF maps in mpa.openrmf;
#: scipy's sparse graphs give the free space's components and the vertex distances of large layouts, and the search
#: of the free space with footprints (Dijkstra over the moves) and one robot's least time under lane rules (Dijkstra
#: over the vertices, mpa.planners.rules); the graph planner's corner re-solve is a least-distance
#: programme solved by scipy's non-negative least squares (its compiled routine, loaded by mpa._nnls); the PVT rows'
#: velocity fit is a linear program solved by scipy's HiGHS).
_MODULE_ALLOWED = {
    "mpa.openrmf": {"yaml"},
    "mpa.freespace": {"scipy"},
    "mpa.geometry": {"scipy"},
    "mpa.planar.search": {"scipy"},
    "mpa.planners.rules": {"scipy"},
    "mpa._nnls": {"scipy"},
    "trajopt.io.pvt": {"scipy"},
}


def _layer_of(module: str) -> int | None:
    """Index of the layer a dotted module name belongs to (the deepest folder that holds it), or None."""
    best, depth = None, -1
    for i, layer in enumerate(LAYERS):
        for folder in layer.folders:
            prefix = folder.replace("/", ".")
            if (module == prefix or module.startswith(prefix + ".")) and prefix.count(".") > depth:
                best, depth = i, prefix.count(".")
    return best


def _imports(path: Path) -> list[str]:
    """Every module a source file imports (top level and inside functions), as dotted names."""
    tree = ast.parse(path.read_text(encoding="utf-8"))
    names = []
    for node in ast.walk(tree):
        if isinstance(node, ast.Import):
            names += [a.name for a in node.names]
        elif isinstance(node, ast.ImportFrom) and node.module and node.level == 0:
            names.append(node.module)
    return names


def _module_allowed(module: str) -> set[str]:
    """The extra third-party imports of a module: those of its own entry in ``_MODULE_ALLOWED`` and of the package
    entries that hold it."""
    out: set[str] = set()
    for name, tops in _MODULE_ALLOWED.items():
        if module == name or module.startswith(name + "."):
            out |= tops
    return out


def check_layers() -> list[str]:
    """Imports that break the layering: a module importing from a layer above its own, or a third-party package its
    layer may not use. Returns one line per violation (empty: the picture is true)."""
    stdlib = set(sys.stdlib_module_names)
    problems = []
    for i, layer in enumerate(LAYERS):
        allowed = _ALLOWED[i]
        for folder in layer.folders:
            for path in sorted((ROOT / folder).glob("*.py")):
                own = f"{folder.replace('/', '.')}.{path.stem}"
                for name in _imports(path):
                    top = name.split(".")[0]
                    target = _layer_of(name)
                    if target is not None and target > i:
                        problems.append(f"{own} imports {name} from the layer above ({LAYERS[target].name})")
                    elif (
                        allowed is not None
                        and top not in stdlib
                        and top not in allowed | _module_allowed(own)
                        and top != "__future__"
                    ):
                        problems.append(f"{own} imports {name}, not allowed in {layer.name}")
    return problems


#: At most this many module boxes in one row of the picture (a folder with more takes several rows).
MODULES_PER_ROW = 7


def _folder_rows(layer: Layer) -> list[tuple[str, list[str]]]:
    """The modules of a layer, row by row: ``(folder label, module names)``; a folder's later rows have no label."""
    rows = []
    for folder in layer.folders:
        names = [p.stem for p in sorted((ROOT / folder).glob("*.py")) if p.stem not in ("__init__", "__main__")]
        for k in range(0, len(names), MODULES_PER_ROW):
            rows.append((folder.replace("/", ".") + "." if k == 0 else "", names[k : k + MODULES_PER_ROW]))
    return rows


def draw_layers(out: str | os.PathLike[str], dpi: float = 100.0) -> Path:
    """Draw the layers as bands of module boxes (one row per folder) with "imports" arrows pointing down; write a
    PNG atomically."""
    import matplotlib

    matplotlib.use("Agg")
    from matplotlib.figure import Figure
    from matplotlib.patches import FancyBboxPatch

    row_h, head, gap = 0.42, 0.5, 0.4
    heights = [head + row_h * len(_folder_rows(layer)) + 0.1 for layer in LAYERS]
    total = sum(heights) + gap * (len(LAYERS) - 1) + 0.4
    fig = Figure(figsize=(12.0, total))
    ax = fig.add_axes((0.0, 0.0, 1.0, 1.0))
    ax.set_xlim(0, 12)
    ax.set_ylim(0, total)
    ax.axis("off")
    y = 0.2
    bands = []
    for layer, band_h in zip(LAYERS, heights):
        ax.add_patch(
            FancyBboxPatch(
                (0.2, y), 11.6, band_h, boxstyle="round,pad=0.02,rounding_size=0.12", fc=layer.color, ec="0.5"
            )
        )
        ax.text(0.35, y + band_h - 0.25, layer.name, fontsize=12, fontweight="bold", va="center")
        uses = f"uses {layer.third_party}"
        ax.text(11.65, y + band_h - 0.25, uses, fontsize=9, color="0.35", va="center", ha="right")
        rows = _folder_rows(layer)
        for r, (label, names) in enumerate(rows):
            _module_row(ax, label, names, y + band_h - head - (r + 0.5) * row_h)
        bands.append((y, y + band_h))
        y += band_h + gap
    for (_, lo_top), (hi_bottom, _) in pairwise(bands):
        for x in (3.0, 6.0, 9.0):
            ax.annotate(
                "",
                xy=(x, lo_top + 0.02),
                xytext=(x, hi_bottom - 0.02),
                arrowprops={"arrowstyle": "-|>", "color": "0.3", "lw": 1.4},
            )
        ax.text(9.1, (lo_top + hi_bottom) / 2, "imports", fontsize=8, color="0.3", va="center")
    from trajopt.viz.plotting import save_figure

    return save_figure(fig, out, dpi, facecolor="white")


def _module_row(ax: object, label: str, names: Sequence[str], y: float) -> None:
    """One folder's modules as small boxes in a row at height ``y``, after the folder's name."""
    ax.text(0.4, y, label, ha="left", va="center", fontsize=9, color="0.3", family="monospace")  # type: ignore[attr-defined]
    x0, width = 2.3, 9.4
    w = width / MODULES_PER_ROW  # a fixed grid: the boxes of consecutive rows line up
    for k, name in enumerate(names):
        ax.text(  # type: ignore[attr-defined]
            x0 + (k + 0.5) * w,
            y,
            name,
            ha="center",
            va="center",
            fontsize=min(8.5, 160.0 / max(len(name), 1)),  # long names smaller, so neighbours do not overlap
            family="monospace",
            bbox={"boxstyle": "round,pad=0.25", "fc": "white", "ec": "0.6"},
        )


def main(argv: Sequence[str] | None = None) -> int:
    """Command-line entry point; returns the exit status."""
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--out", type=Path, default=ROOT / "docs" / "img" / "architecture.png", help="PNG to write")
    ap.add_argument("--dpi", type=float, default=100.0)
    ap.add_argument("--check", action="store_true", help="only check the imports")
    args = ap.parse_args(argv)
    problems = check_layers()
    for p in problems:
        print(f"layering: {p}", file=sys.stderr)
    if args.check:
        return 1 if problems else 0
    print(draw_layers(args.out, args.dpi))
    return 1 if problems else 0


if __name__ == "__main__":
    sys.exit(main())
