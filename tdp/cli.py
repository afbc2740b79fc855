"""Running a command line: argparse, then the chosen command, with bad input reported in one line; output folders
checked before the work starts, and results that cannot be written where asked saved elsewhere, never lost."""
from __future__ import annotations

import argparse
import json
import sys
import tempfile
from pathlib import Path


def run(parser: argparse.ArgumentParser, argv: list[str] | None = None) -> int:
    """Parse ``argv`` and run the command it names (``args.run(args)``). Bad input and failed file operations
    (ValueError, OSError such as FileNotFoundError or PermissionError) become ``error: ...`` on stderr and exit
    code 2; Ctrl-C exits with 130. Any other exception is a bug of tdp's and keeps its traceback."""
    args = parser.parse_args(argv)
    try:
        return args.run(args)
    except (ValueError, OSError) as error:
        print(f"error: {error}", file=sys.stderr)
        return 2
    except KeyboardInterrupt:
        print("interrupted", file=sys.stderr)
        return 130


def add_world_arguments(parser: argparse.ArgumentParser) -> None:
    """``--scenario NAME`` (a named scenario) or ``--world FILE`` (a world file), exactly one."""
    which = parser.add_mutually_exclusive_group(required=True)
    which.add_argument("--scenario", help="a named scenario (list them with the list command)")
    which.add_argument("--world", help="a world file (YAML: see the README's 'Your own world')")


def world_from(args: argparse.Namespace):
    """The Scenario that ``--scenario`` or ``--world`` names."""
    import tdp

    return tdp.load_world(args.world) if args.world else tdp.scenarios.get(args.scenario)


def output_folder(path: str | Path, option: str = "--out") -> Path:
    """Create the output folder ``path`` (and its parents) now, before any long work, or raise ValueError saying
    why it cannot be one (a file is in the way, no permission)."""
    folder = Path(path)
    try:
        folder.mkdir(parents=True, exist_ok=True)
    except FileExistsError:
        raise ValueError(f"{option} {folder}: a file is in the way of the output folder") from None
    except OSError as error:
        raise ValueError(f"{option} {folder}: cannot create the output folder ({error.strerror})") from None
    probe = folder / ".tdp-write-test"
    try:
        probe.write_text("")
        probe.unlink()
    except OSError as error:
        raise ValueError(f"{option} {folder}: cannot write in the output folder ({error.strerror})") from None
    return folder


def save_json(payload: dict, path: Path) -> Path:
    """Write ``payload`` as JSON at ``path``; if that fails (the folder vanished, the disk filled), write it to a
    temporary file instead and say so on stderr: a finished run's results are never lost. Returns the file."""
    text = json.dumps(payload, indent=1)
    try:
        path.write_text(text)
        return path
    except OSError as error:
        fallback = Path(tempfile.mkstemp(prefix=f"tdp-{path.stem}-", suffix=".json")[1])
        fallback.write_text(text)
        print(f"warning: could not write {path} ({error.strerror}); the results are in {fallback}", file=sys.stderr)
        return fallback
