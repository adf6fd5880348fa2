"""``python -m hairbed``: the command line of :mod:`hairbed.cli`."""

import sys

from hairbed.cli import main

__all__: list[str] = []

if __name__ == "__main__":
    sys.exit(main())
