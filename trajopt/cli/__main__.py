"""``python -m trajopt.cli``: the ``mpa`` command."""

import sys

from trajopt.cli.main import main

sys.exit(main())
