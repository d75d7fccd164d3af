"""``python -m blockmesh``: the same command line as ``blockmesh``."""

import sys

from .cli import main

sys.exit(main())
