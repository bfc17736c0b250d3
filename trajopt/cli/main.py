"""The ``mpa`` command line (console script entry point).

Subcommands: ``plan`` (the paper's planner), ``trajectory`` and ``demo`` (jerk-limited setpoints), ``animate``
(animations), ``topology`` (topology of two robots on any graph). Every error the user can cause ends with exit
status 2 and one line on stderr starting with ``error:``; no traceback, no output file left behind.
"""

from __future__ import annotations

import argparse
import importlib
import sys
from collections.abc import Sequence

from mpa.errors import MPAError

__all__ = ["build_parser", "main"]

#: Modules that add subcommands through a ``register(subparsers)`` function.
SUBCOMMAND_MODULES = ("trajopt.cli.plan", "trajopt.cli.trajectory", "trajopt.cli.animate", "trajopt.cli.topology")


class _Parser(argparse.ArgumentParser):
    def error(self, message: str) -> None:  # type: ignore[override]
        self.exit(2, f"error: {message}\n")


def build_parser() -> argparse.ArgumentParser:
    """The argument parser of the ``mpa`` command."""
    parser = _Parser(
        prog="mpa", description="Topological motion planning for two robots on a track (Boughrira & Colman)."
    )
    sub = parser.add_subparsers(dest="command", required=True, parser_class=_Parser)
    for name in SUBCOMMAND_MODULES:
        importlib.import_module(name).register(sub)
    return parser


def main(argv: Sequence[str] | None = None) -> int:
    """Run the ``mpa`` command; returns the exit status."""
    parser = build_parser()
    args = parser.parse_args(argv)
    try:
        return int(args.func(args))
    except MPAError as exc:
        print(f"error: {exc}", file=sys.stderr)
        return 2
    except BrokenPipeError:  # output piped into e.g. `head`: stop quietly
        sys.stderr.close()
        return 0
    except OSError as exc:
        print(f"error: {exc}", file=sys.stderr)
        return 2


if __name__ == "__main__":  # pragma: no cover
    sys.exit(main())
