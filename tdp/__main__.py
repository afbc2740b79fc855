"""Command line: ``python -m tdp plan MAP --start R C --goal R C [--out DIR]``."""
from __future__ import annotations

import argparse
import math
import sys
import time
from pathlib import Path


def _cell(text: list[str], name: str) -> tuple[int, int]:
    return int(text[0]), int(text[1])


def plan(args: argparse.Namespace) -> int:
    """Plan on any loadable map: print the distance and path length, write a PNG of the path."""
    import tdp
    from tdp.plot import save_path_figure

    grid = tdp.load_map(args.map, unknown_is_free=args.unknown_free)
    start = grid.check_free_cell(tuple(args.start), "--start")
    field = tdp.DistanceField(grid, args.goal, neighbourhood=args.neighbourhood, corner_cutting=args.corner_cutting)
    began = time.perf_counter()
    sweeps = field.converge()
    elapsed = time.perf_counter() - began
    path = field.path(start)
    distance = field.distance(start)
    print(f"map {args.map}: {grid.shape[0]} x {grid.shape[1]} cells, {int(grid.occupied.sum())} obstacles")
    print(f"setup (converge): {sweeps} sweeps in {elapsed * 1e3:.1f} ms (first run includes JIT compilation)")
    if not path:
        print(f"goal {tuple(args.goal)} is not reachable from {start}")
        return 1
    length = sum(math.dist(a, b) for a, b in zip(path, path[1:]))
    print(f"distance from {start} to {tuple(args.goal)}: {distance:.4f} cells "
          f"({distance * grid.resolution:.3f} m); path: {len(path)} cells, length {length:.4f}")
    title = f"{Path(args.map).name}: {args.neighbourhood}-neighbour, length {length:.2f} cells"
    figure = save_path_figure(grid, path, Path(args.out) / "plan.png", title, field.distances())
    print(f"figure: {figure}")
    return 0


def parser() -> argparse.ArgumentParser:
    main = argparse.ArgumentParser(prog="python -m tdp", description=__doc__)
    commands = main.add_subparsers(dest="command", required=True)
    p = commands.add_parser("plan", help="shortest path on a map file (MovingAI .map, ROS .yaml, image)")
    p.add_argument("map")
    p.add_argument("--start", nargs=2, type=int, required=True, metavar=("ROW", "COL"))
    p.add_argument("--goal", nargs=2, type=int, required=True, metavar=("ROW", "COL"))
    p.add_argument("--neighbourhood", type=int, default=16, choices=(4, 8, 16))
    p.add_argument("--corner-cutting", action="store_true", help="allow diagonal moves through corners")
    p.add_argument("--unknown-free", action="store_true", help="ROS maps: treat unknown cells as free")
    p.add_argument("--out", default="out", help="folder for the figure (default: out)")
    p.set_defaults(run=plan)
    return main


def main(argv: list[str] | None = None) -> int:
    args = parser().parse_args(argv)
    try:
        return args.run(args)
    except (ValueError, FileNotFoundError) as error:
        print(f"error: {error}", file=sys.stderr)
        return 2


if __name__ == "__main__":
    sys.exit(main())
