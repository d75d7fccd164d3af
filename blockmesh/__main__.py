"""``python -m blockmesh``: the same command line as ``blockmesh``."""

import sys

from blockmesh.cli import main

if __name__ == "__main__":  # not when imported (documentation tools import every module)
    sys.exit(main())
