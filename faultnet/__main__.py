"""``python -m faultnet`` and the ``faultnet`` console script."""

from __future__ import annotations

import sys

EXIT_INTERRUPTED = 130


def main(argv=None) -> int:
    """Entry point: run the command line and return its exit status.

    A Ctrl-C while the command line loads its modules ends with one line and
    exit status 130, like a Ctrl-C during a command.
    """
    try:
        from faultnet.cli.commands import main as cli_main
    except KeyboardInterrupt:
        print("\nfaultnet: interrupted while starting; nothing was written", file=sys.stderr)
        return EXIT_INTERRUPTED
    return cli_main(argv)


if __name__ == "__main__":
    sys.exit(main())
