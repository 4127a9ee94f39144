"""``python -m distkin`` is the ``distkin`` command."""

import sys

__all__: list = []

from .app.cli import main

if __name__ == "__main__":
    sys.exit(main())
