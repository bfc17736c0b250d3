"""The ``mpa`` command line: one module per subcommand on top of the pipeline and the drawings.

:mod:`trajopt.cli.main` builds the parser and maps errors to exit statuses; :mod:`trajopt.cli.common` holds the
options shared by the subcommands; :mod:`trajopt.cli.plan`, :mod:`trajopt.cli.trajectory` (``trajectory`` and
``demo``), :mod:`trajopt.cli.animate` and :mod:`trajopt.cli.topology` add one subcommand each.
"""

from trajopt.cli.main import build_parser, console_main, main

__all__ = ["build_parser", "console_main", "main"]
