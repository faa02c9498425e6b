"""``python -m rockcem`` runs the command line (the same as the ``rockcem`` console script)."""

import sys

from .cli import main

sys.exit(main())
