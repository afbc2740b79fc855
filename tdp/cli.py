"""Running a command line: argparse, then the chosen command, with bad input and warnings reported in one line each;
output folders checked before the work starts, and results that cannot be written where asked saved elsewhere, never
lost."""
from __future__ import annotations

import argparse
import json
import math
import sys
import tempfile
import warnings
from pathlib import Path


def run(parser: argparse.ArgumentParser, argv: list[str] | None = None) -> int:
    """Parse ``argv`` and run the command it names (``args.run(args)``). Bad input and failed file operations
    (ValueError, OSError such as FileNotFoundError or PermissionError) become ``error: ...`` on stderr and exit
    code 2, and a warning ``warning: ...`` (Python's format adds the file, line and source line of the call that
    warned); Ctrl-C exits with 130. Any other exception is a bug of tdp's and keeps its traceback."""
    args = parser.parse_args(argv)
    formatted = warnings.formatwarning
    warnings.formatwarning = _one_line
    try:
        return args.run(args)
    except (ValueError, OSError) as error:
        print(f"error: {error}", file=sys.stderr)
        return 2
    except KeyboardInterrupt:
        print("interrupted", file=sys.stderr)
        return 130
    finally:
        warnings.formatwarning = formatted


def _one_line(message, category, filename, lineno, line=None) -> str:
    """A warning as a command line prints it (``warnings.formatwarning``'s signature)."""
    return f"warning: {message}\n"


#: (argparse destination, flag) of the options that shape a quick world on ``--map`` only, and of the cost options.
_QUICK_ONLY = (("start", "--start"), ("goal", "--goal"), ("boxes", "--boxes"), ("seed", "--seed"),
               ("blockage", "--blockage"), ("graded", "--graded"))
_COST_OPTIONS = (("cost_scaling_factor", "--cost-scaling-factor"), ("inflation_radius", "--inflation-radius"))


def add_world_arguments(parser: argparse.ArgumentParser) -> None:
    """The world to run, exactly one of: ``--scenario NAME`` (a named scenario), ``--world FILE`` (a world file) or
    ``--map FILE`` with ``--start``/``--goal`` (a quick world: ``--boxes N`` shuttling boxes from ``--seed S``, and a
    blockage on the route with ``--blockage``)."""
    which = parser.add_mutually_exclusive_group(required=True)
    which.add_argument("--scenario", help="a named scenario (list them with the list command)")
    which.add_argument("--world", help="a world file (YAML: see docs/worlds.md)")
    which.add_argument("--map", help="a map file for a quick world (needs --start and --goal)")
    quick = parser.add_argument_group("quick world on --map")
    quick.add_argument("--start", nargs=2, type=int, metavar=("ROW", "COL"))
    quick.add_argument("--goal", nargs=2, type=int, metavar=("ROW", "COL"))
    quick.add_argument("--boxes", type=int, help="shuttling boxes (default 3)")
    quick.add_argument("--seed", type=int, help="seed of the boxes (default 0)")
    quick.add_argument("--blockage", action="store_true", help="a box appears in a narrow place of the route")
    add_cost_arguments(quick)


def add_cost_arguments(group) -> None:
    """Traversal costs for a map file, as nav2 makes them: ``--cost-scaling-factor`` and ``--inflation-radius``
    (the inflation layer's cost around obstacles) and ``--graded`` (a ROS scale or raw map's values as costs)."""
    group.add_argument("--cost-scaling-factor", type=float, default=None, metavar="K",
                       help="nav2's inflation cost around obstacles: decay per metre (with --inflation-radius)")
    group.add_argument("--inflation-radius", type=float, default=None, metavar="M",
                       help="nav2's inflation cost: metres from obstacles (with --cost-scaling-factor)")
    group.add_argument("--graded", action="store_true",
                       help="ROS scale/raw maps: graded values as costs (nav2's trinary_costmap: false)")


def map_from(args: argparse.Namespace, unknown_is_free: bool = False):
    """The GridMap of ``args.map`` with the costs :func:`add_cost_arguments` asks for."""
    import tdp

    inflation = (args.cost_scaling_factor, args.inflation_radius)
    if (inflation[0] is None) != (inflation[1] is None):
        raise ValueError("--cost-scaling-factor and --inflation-radius go together (nav2's inflation layer)")
    return tdp.load_map(args.map, unknown_is_free=unknown_is_free, trinary_costmap=not args.graded,
                        cost_scaling_factor=inflation[0], inflation_radius=inflation[1])


def add_planner_argument(parser: argparse.ArgumentParser) -> None:
    """--planner: the planner of the run (NavigatorConfig's ``planner``)."""
    from tdp.config import PLANNERS

    parser.add_argument("--planner", choices=PLANNERS, default="exact",
                        help="exact replanning every tick (default), the paper's accelerating nodes, or plain DP")


#: The NavigatorConfig field of each planner option of the command lines, by its argparse destination.
_CONFIG_OPTIONS = {"updates": "updates_per_move", "budget_ms": "budget_ms", "nodes": "nodes", "vision": "vision",
                   "detect_window": "detect_window", "detect_rise": "detect_rise", "predict_ticks": "predict_ticks",
                   "avoid_boxes": "avoid_boxes", "neighbourhood": "neighbourhood", "corner_cutting": "corner_cutting"}


def config_from(args: argparse.Namespace, planner: str, strict: bool = True):
    """The NavigatorConfig of ``planner`` with the planner options given on the command line, the rest at their
    defaults (an option left out is None, or False for a switch). An option the planner does not read
    (:func:`tdp.config.fields_read`) is a ValueError naming it; with ``strict`` False it is left out (a command that
    runs every planner with the same options)."""
    from tdp.config import PLANNER_NAMES, NavigatorConfig, fields_read

    given = {dest: getattr(args, dest) for dest in _CONFIG_OPTIONS if _given(args, dest)}
    read = fields_read(planner)
    unread = ["--" + dest.replace("_", "-") for dest in given if _CONFIG_OPTIONS[dest] not in read]
    if unread and strict:
        raise ValueError(f"{', '.join(unread)}: not read by {PLANNER_NAMES[planner]} (--planner {planner})")
    return NavigatorConfig(planner=planner, **{_CONFIG_OPTIONS[dest]: value for dest, value in given.items()
                                               if _CONFIG_OPTIONS[dest] in read})


def _given(args: argparse.Namespace, dest: str) -> bool:
    """Whether the option of argparse destination ``dest`` was given (left out, it is None, or False for a switch;
    0 is a value given)."""
    value = getattr(args, dest, None)
    return value is not None and value is not False


def world_from(args: argparse.Namespace, costs_on_any_world: bool = False):
    """The Scenario that ``--scenario``, ``--world`` or ``--map`` names. The options of a quick world on ``--map``
    given with another world are a ValueError naming them, rather than ignored; so are the cost options unless
    ``costs_on_any_world`` (a command that applies them to every world)."""
    import tdp
    from tdp.random_worlds import boxes_on_map

    if not args.map:
        quick_only = _QUICK_ONLY + (() if costs_on_any_world else _COST_OPTIONS)
        given = [flag for dest, flag in quick_only if _given(args, dest)]
        if given:
            raise ValueError(f"{', '.join(given)}: options of a quick world on --map; --scenario and --world "
                             "are worlds of their own")
    if args.world:
        return tdp.load_world(args.world)
    if args.map:
        if args.start is None or args.goal is None:
            raise ValueError("--map needs --start ROW COL and --goal ROW COL")
        given = {dest: getattr(args, dest) for dest in ("boxes", "seed") if _given(args, dest)}  # else its defaults
        negative = [f"--{dest} {value}" for dest, value in given.items() if value < 0]
        if negative:
            raise ValueError(f"{', '.join(negative)}: must be >= 0")
        return boxes_on_map(map_from(args), tuple(args.start), tuple(args.goal), blockage=args.blockage, **given)
    return tdp.scenarios.get(args.scenario)


def limit_note(reached: bool, ticks: int, max_ticks: int) -> str:
    """The words a run's summary line adds when the episode stopped because its ``max_ticks`` ran out, else none."""
    return (f" (the episode's limit, {max_ticks} ticks, ran out; a world file's max_ticks or max_s, or tdp run's "
            "--max-ticks, sets it)") if not reached and ticks >= max_ticks else ""


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
    """Write ``payload`` as JSON at ``path``, a number that is not finite (a ratio with no oracle, the clearance of a
    run that never moved) as null - NaN and Infinity are not JSON, and other readers refuse them; if writing fails
    (the folder vanished, the disk filled), write it to a temporary file instead and say so on stderr: a finished
    run's results are never lost. Returns the file."""
    text = json.dumps(_finite(payload), indent=1, allow_nan=False)
    try:
        path.write_text(text)
        return path
    except OSError as error:
        fallback = Path(tempfile.mkstemp(prefix=f"tdp-{path.stem}-", suffix=".json")[1])
        fallback.write_text(text)
        print(f"warning: could not write {path} ({error.strerror}); the results are in {fallback}", file=sys.stderr)
        return fallback


def _finite(value):
    """``value`` with every float that is not finite, however deep in dicts, lists and tuples, replaced by None."""
    if isinstance(value, float):
        return value if math.isfinite(value) else None
    if isinstance(value, dict):
        return {key: _finite(item) for key, item in value.items()}
    if isinstance(value, (list, tuple)):
        return [_finite(item) for item in value]
    return value
