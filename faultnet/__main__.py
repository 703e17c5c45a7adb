"""``python -m faultnet`` and the ``faultnet`` console script."""

from __future__ import annotations

import sys


def main(argv=None) -> int:
    """Entry point: run the command line and return its exit status."""
    from faultnet.cli import main as cli_main

    return cli_main(argv)


if __name__ == "__main__":
    sys.exit(main())
