"""``python -m pendula``: the command line (see pendula.cli)."""

import sys

from .cli import main

sys.exit(main())
