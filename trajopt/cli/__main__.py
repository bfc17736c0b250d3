"""``python -m trajopt.cli``: the ``mpa`` command."""

import sys

from trajopt.cli.main import console_main

sys.exit(console_main())
