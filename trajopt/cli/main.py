"""The ``mpa`` command line (console script entry point).

Subcommands: ``plan`` (the paper's planner), ``trajectory`` and ``demo`` (jerk-limited setpoints), ``animate``
(animations), ``topology`` (topology of two robots on any graph), ``replan`` (re-plan a written trajectory from
its moving state), ``plot`` (a PNG of written setpoints); ``mpa --version``.

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
"""

from __future__ import annotations

import argparse
import importlib
import sys
from collections.abc import Sequence

from mpa import __version__
from mpa.errors import MPAError, NoMotionError, PlanningError

__all__ = ["EXIT_INTERNAL", "EXIT_INTERRUPTED", "EXIT_NO_MOTION", "EXIT_USAGE", "build_parser", "main"]

#: Modules that add subcommands through a ``register(subparsers)`` function.
SUBCOMMAND_MODULES = (
    "trajopt.cli.plan",
    "trajopt.cli.trajectory",
    "trajopt.cli.animate",
    "trajopt.cli.topology",
    "trajopt.cli.replan",
    "trajopt.cli.plot",
)
#: Exit status of bad input (``error:``).
EXIT_USAGE = 2
#: Exit status of a valid query without a collision-free motion (``no motion:``).
EXIT_NO_MOTION = 3
#: Exit status of an internal failure (``internal error:``).
EXIT_INTERNAL = 4
#: Exit status after Ctrl-C.
EXIT_INTERRUPTED = 130


class _Parser(argparse.ArgumentParser):
    def error(self, message: str) -> None:  # type: ignore[override]
        self.exit(EXIT_USAGE, f"error: {message}\n")


def build_parser() -> argparse.ArgumentParser:
    """The argument parser of the ``mpa`` command."""
    parser = _Parser(
        prog="mpa", description="Topological motion planning for two robots on a track (Boughrira & Colman)."
    )
    parser.add_argument("--version", action="version", version=f"mpa (lollipop-mpa) {__version__}")
    sub = parser.add_subparsers(dest="command", required=True, parser_class=_Parser)
    for name in SUBCOMMAND_MODULES:
        importlib.import_module(name).register(sub)
    return parser


def _line(prefix: str, exc: object) -> None:
    text = " ".join(str(exc).split()) or type(exc).__name__
    print(f"{prefix}: {text}", file=sys.stderr)


def main(argv: Sequence[str] | None = None) -> int:
    """Run the ``mpa`` command; returns the exit status (see the module docstring)."""
    try:
        parser = build_parser()
        args_list = list(sys.argv[1:] if argv is None else argv)
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
