"""The ``mpa`` command line (console script entry point).

Subcommands: ``plan`` (the paper's planner), ``trajectory`` and ``demo`` (jerk-limited setpoints), ``animate``
(animations), ``topology`` (topology of two robots on any graph), ``replan`` (re-plan a written trajectory from
its moving state), ``plot`` (a PNG of written setpoints), ``domains`` (the domain of every start or goal of a
paper track), ``serve`` (a local web explorer), ``layout`` (Open-RMF maps converted, layouts drawn),
``batch`` (many queries on a layout, locally or on a Dask cluster); ``mpa --version``.

Exit statuses (one line on stderr in every failing case, never a traceback, no output file left behind):

- 0: done;
- 2: the input is wrong (``error: ...``): :class:`mpa.errors.InvalidInputError`, a usage error, an output that
  cannot be written (``error: --out: cannot write ...: reason``); a bare ``mpa`` prints the usage on stderr
  and exits 2;
- 3: the input is valid but no collision-free motion exists (``no motion: <reason>``,
  :class:`mpa.errors.NoMotionError`);
- 4: an internal failure (``internal error: ...``): :class:`mpa.errors.PlanningError` or any unexpected
  exception (a bug);
- 130: interrupted (Ctrl-C), one line ``interrupted``.

One query runs on one core: unless the environment already says how many threads the linear algebra may use
(``OPENBLAS_NUM_THREADS``, ``MKL_NUM_THREADS`` or ``OMP_NUM_THREADS``), :func:`main` sets all three to 1 before
numpy is imported (:func:`single_threaded_blas`). The matrices of one query are small; a BLAS thread pool gains
nothing on them, and its threads wait for work by spinning, which cost a run of ``mpa trajectory`` on a converted
building map about 0.4 s of CPU time (docs/performance.md, "mpa trajectory within 2 s"). Processes the command
starts (``mpa batch``'s workers) inherit the setting; a process that imported numpy before calling :func:`main`
keeps its own.

The console script (:func:`console_main`) runs every subcommand but ``batch`` and ``serve`` with the numpy twins of
the compiled kernels (:mod:`trajopt._numba`): one trajectory per process does not pay numba's 0.5 s of import and
kernel load; ``TRAJOPT_KERNELS`` in the environment chooses otherwise.
"""

from __future__ import annotations

import argparse
import importlib
import os
import sys
from collections.abc import Sequence
from typing import Any

from mpa.errors import MPAError, NoMotionError, PlanningError

__all__ = [
    "BLAS_THREAD_VARIABLES",
    "EXIT_INTERNAL",
    "EXIT_INTERRUPTED",
    "EXIT_NO_MOTION",
    "EXIT_USAGE",
    "build_parser",
    "console_main",
    "main",
    "single_threaded_blas",
]

#: Modules that add subcommands through a ``register(subparsers)`` function.
SUBCOMMAND_MODULES = (
    "trajopt.cli.plan",
    "trajopt.cli.trajectory",
    "trajopt.cli.animate",
    "trajopt.cli.topology",
    "trajopt.cli.replan",
    "trajopt.cli.plot",
    "trajopt.cli.domains",
    "trajopt.cli.serve",
    "trajopt.cli.layout",
    "trajopt.cli.batch",
)
#: Every subcommand in help order: its module and its one-line help (equal to what the module registers; tested).
#: ``mpa --help`` lists them without importing the modules (and so numpy, the planners, CasADi, matplotlib).
SUBCOMMANDS = {
    "plan": ("trajopt.cli.plan", "plan a motion (the paper's algorithm, or the complete graph planner) and print it"),
    "trajectory": ("trajopt.cli.trajectory", "verified jerk-limited setpoints for a query (CSV, ROS 2, PVT, JSON)"),
    "demo": ("trajopt.cli.trajectory", "the embedded default job: a lollipop swap, files and a PNG"),
    "animate": ("trajopt.cli.animate", "animate a query: raw plan and jerk-limited trajectory side by side"),
    "topology": ("trajopt.cli.topology", "Betti numbers, Euler characteristic and TC of two robots on a graph"),
    "replan": (
        "trajopt.cli.replan",
        "re-plan a written trajectory from the carts' moving state at a time to a new goal",
    ),
    "plot": ("trajopt.cli.plot", "draw a setpoints file or an output directory of mpa into a PNG"),
    "domains": (
        "trajopt.cli.domains",
        "which domain every start (for a fixed goal) or goal (for a fixed start) falls in",
    ),
    "serve": ("trajopt.cli.serve", "a local web page to drag the robots and watch domains, plans and motions"),
    "layout": ("trajopt.cli.layout", "convert an Open-RMF map to a JSON layout, or describe and draw a layout"),
    "batch": ("trajopt.cli.batch", "plan and verify every query of a CSV file on a layout (local or Dask)"),
}
#: Exit status of bad input (``error:``).
EXIT_USAGE = 2
#: Exit status of a valid query without a collision-free motion (``no motion:``).
EXIT_NO_MOTION = 3
#: Exit status of an internal failure (``internal error:``).
EXIT_INTERNAL = 4
#: Exit status after Ctrl-C.
EXIT_INTERRUPTED = 130


#: The environment variables that size the BLAS thread pools (OpenBLAS, MKL, OpenMP), set to 1 by :func:`main`.
BLAS_THREAD_VARIABLES = ("OPENBLAS_NUM_THREADS", "MKL_NUM_THREADS", "OMP_NUM_THREADS")


def single_threaded_blas() -> bool:
    """One BLAS thread for this process and the processes it starts, unless the environment already sizes the pools.

    Sets every variable of :data:`BLAS_THREAD_VARIABLES` to ``"1"`` when none of them is set and numpy is not
    imported yet (the thread pool is sized when the library loads: a process that already has numpy, such as a
    test calling :func:`main` in-process, keeps its pools and its environment).

    Returns
    -------
    bool
        Whether the variables were set (False: numpy was loaded, or the environment had one of them, left as is).
    """
    if "numpy" in sys.modules or any(name in os.environ for name in BLAS_THREAD_VARIABLES):
        return False
    for name in BLAS_THREAD_VARIABLES:
        os.environ[name] = "1"
    return True


class _Parser(argparse.ArgumentParser):
    def error(self, message: str) -> None:  # type: ignore[override]
        self.exit(EXIT_USAGE, f"error: {message}\n")


class _VersionAction(argparse.Action):
    """``--version``: prints ``mpa (lollipop-mpa) VERSION`` and exits 0; the version is read only when asked for."""

    def __call__(self, parser: argparse.ArgumentParser, *args: Any, **kwargs: Any) -> None:
        from mpa import __version__

        print(f"mpa (lollipop-mpa) {__version__}")
        parser.exit()


def build_parser(command: str | None = None, *, full: bool = True) -> argparse.ArgumentParser:
    """The argument parser of the ``mpa`` command.

    Parameters
    ----------
    command : str, optional
        With ``full=False``: the subcommand about to run; only its module is imported and registered, every
        other subcommand is listed by name and help only.
    full : bool
        Register every subcommand (imports every subcommand module).
    """
    parser = _Parser(
        prog="mpa", description="Topological motion planning for two robots on a track (Boughrira & Colman)."
    )
    parser.add_argument("--version", action=_VersionAction, nargs=0, help="show the program's version and exit")
    sub = parser.add_subparsers(dest="command", required=True, parser_class=_Parser)
    if full:
        for name in SUBCOMMAND_MODULES:
            importlib.import_module(name).register(sub)
        return parser
    wanted = SUBCOMMANDS[command][0] if command in SUBCOMMANDS else None
    done: set[str] = set()
    for name, (module, text) in SUBCOMMANDS.items():
        if module == wanted:
            if module not in done:
                importlib.import_module(module).register(sub)
                done.add(module)
        else:
            sub.add_parser(name, help=text)
    tabled = {m for m, _ in SUBCOMMANDS.values()}
    for module in SUBCOMMAND_MODULES:  # a module missing from the table still works (imported, so not lazily)
        if module not in tabled:
            importlib.import_module(module).register(sub)
    return parser


def _command_of(args: Sequence[str]) -> str | None:
    """The subcommand named on the command line (the first argument that is not an option), if any."""
    return next((a for a in args if not a.startswith("-")), None)


def _line(prefix: str, exc: object) -> None:
    text = " ".join(str(exc).split()) or type(exc).__name__
    print(f"{prefix}: {text}", file=sys.stderr)


#: Subcommands that make many trajectories in one process (``batch``) or live long (``serve``): numba's compiled
#: kernels pay for their load there; every other subcommand runs with their numpy twins (:func:`console_main`).
COMPILED_KERNEL_COMMANDS = frozenset({"batch", "serve"})


def console_main() -> int:
    """The ``mpa`` console script and ``python -m trajopt.cli``: :func:`main` on ``sys.argv``, in a process of its
    own, whose kernels run as numpy twins, numba not imported (:func:`trajopt._numba.use_numpy_twins`), unless the
    subcommand is one of :data:`COMPILED_KERNEL_COMMANDS` or ``TRAJOPT_KERNELS`` is set."""
    from trajopt import _numba

    if _numba.ENV not in os.environ and _command_of(sys.argv[1:]) not in COMPILED_KERNEL_COMMANDS:
        _numba.use_numpy_twins()
    return main()


def main(argv: Sequence[str] | None = None) -> int:
    """Run the ``mpa`` command; returns the exit status (see the module docstring)."""
    single_threaded_blas()
    try:
        args_list = list(sys.argv[1:] if argv is None else argv)
        command = _command_of(args_list)
        parser = build_parser(command, full=command is not None and command not in SUBCOMMANDS)
        if not args_list:
            parser.print_usage(sys.stderr)
            return EXIT_USAGE
        args = parser.parse_args(args_list)  # --help, --version and usage errors raise SystemExit (0 or 2)
        return int(args.func(args))
    except KeyboardInterrupt:
        print("interrupted", file=sys.stderr)
        return EXIT_INTERRUPTED
    except NoMotionError as exc:
        _line("no motion", exc)
        return EXIT_NO_MOTION
    except PlanningError as exc:
        _line("internal error", exc)
        return EXIT_INTERNAL
    except MPAError as exc:
        _line("error", exc)
        return EXIT_USAGE
    except BrokenPipeError:  # output piped into e.g. `head`: stop quietly
        sys.stderr.close()
        return 0
    except OSError as exc:
        _line("error", exc)
        return EXIT_USAGE
    except Exception as exc:  # a bug: one line, no traceback
        _line("internal error", f"{type(exc).__name__}: {exc}")
        return EXIT_INTERNAL


if __name__ == "__main__":  # pragma: no cover
    sys.exit(main())
