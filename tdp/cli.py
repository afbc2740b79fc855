"""Running a command line: argparse, then the chosen command, with bad input reported in one line."""
from __future__ import annotations

import argparse
import sys


def run(parser: argparse.ArgumentParser, argv: list[str] | None = None) -> int:
    """Parse ``argv`` and run the command it names (``args.run(args)``); a ValueError or FileNotFoundError becomes
    ``error: ...`` on stderr and exit code 2, never a traceback."""
    args = parser.parse_args(argv)
    try:
        return args.run(args)
    except (ValueError, FileNotFoundError) as error:
        print(f"error: {error}", file=sys.stderr)
        return 2
