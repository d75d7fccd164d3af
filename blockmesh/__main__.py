"""``python -m blockmesh``: the same command line as ``blockmesh``."""

import sys

from blockmesh.cli import main

sys.exit(main())
