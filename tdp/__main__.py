"""Command line of tdp.

    python -m tdp list                                   the named scenarios
    python -m tdp run --scenario NAME | --world FILE [options] --out DIR   an episode: metrics.json and a figure
    python -m tdp plan MAP --start R C --goal R C [--out DIR]  shortest path on a map file
    python -m tdp sweep SPEC.yaml [--out DIR] [--serial | --scheduler ADDRESS | --workers N]
                                                         many episodes: tables and a figure (docs/sweeps.md)
"""
from __future__ import annotations

import argparse
import math
import os
import sys
import time
from pathlib import Path


def list_scenarios(args: argparse.Namespace) -> int:
    from tdp import scenarios

    for name in scenarios.names():
        print(f"{name:18s} {scenarios.get(name).description}")
    return 0


def run(args: argparse.Namespace) -> int:
    """Run one episode and write metrics.json and episode.png into --out."""
    import tdp
    from tdp.cli import config_from, limit_note, output_folder, save_json, world_from
    from tdp.plot import oracle_text, save_episode_figure

    scenario = world_from(args)
    config = config_from(args, args.planner)
    out = output_folder(args.out)
    print(f"running {scenario.name} ({config.label()})", flush=True)
    episode = tdp.simulate(scenario, config, max_ticks=args.max_ticks, progress=True)
    metrics = save_json(episode.to_dict(), out / "metrics.json")
    figure = save_episode_figure(scenario, episode, out / "episode.png")
    if args.animate:
        from tdp.animate import save_episode_animation

        figure = ", ".join(str(f) for f in [figure, *save_episode_animation(scenario, [episode], out / "episode.gif",
                                                                         progress=True)])
    ran_out = limit_note(episode.reached, episode.ticks, args.max_ticks or scenario.tick_limit)
    print(f"reached: {episode.reached}{ran_out} in {episode.ticks} ticks; length {episode.length:.1f} cells, oracle "
          f"{oracle_text(episode)}, ratio {episode.ratio:.3f}; collisions {episode.collisions}, hits "
          f"{episode.hits}; detections {len(episode.detections)} "
          f"({sum(d['relevant'] for d in episode.detections)} relevant); planner "
          f"{episode.timings['total']['median']:.2f} ms/tick (median)")
    print(f"wrote {metrics} and {figure}")
    return 0


def plan(args: argparse.Namespace) -> int:
    """Plan on any loadable map: print the distance and path length, write a PNG of the path."""
    import tdp
    from tdp.cli import map_from, output_folder
    from tdp.plot import save_path_figure

    out = output_folder(args.out)
    grid = map_from(args, unknown_is_free=args.unknown_free)
    start = grid.check_free_cell(tuple(args.start), "--start")
    grid.check_free_cell(tuple(args.goal), "--goal")
    field = tdp.DistanceField(grid, args.goal, neighbourhood=args.neighbourhood, corner_cutting=args.corner_cutting)
    began = time.perf_counter()
    rounds = field.converge()
    elapsed = time.perf_counter() - began
    path = field.path(start)
    distance = field.distance(start)
    print(f"map {args.map}: {grid.shape[0]} x {grid.shape[1]} cells, {int(grid.occupied.sum())} obstacles")
    print(f"setup (converge): {rounds} rounds in {elapsed * 1e3:.1f} ms (first run includes JIT compilation)")
    if not path:
        print(f"goal {tuple(args.goal)} is not reachable from {start}")
        return 1
    length = sum(math.dist(a, b) for a, b in zip(path, path[1:]))
    if grid.cost is None:
        print(f"distance from {start} to {tuple(args.goal)}: {distance:.4f} cells "
              f"({distance * grid.resolution:.3f} m); path: {len(path)} cells, length {length:.4f}")
    else:
        print(f"cost from {start} to {tuple(args.goal)}: {distance:.4f} (cells x traversal cost); path: "
              f"{len(path)} cells, length {length:.4f} cells ({length * grid.resolution:.3f} m)")
    title = f"{Path(args.map).name}: {args.neighbourhood}-neighbour, length {length:.2f} cells"
    figure = save_path_figure(grid, path, out / "plan.png", title, field.distances())
    print(f"figure: {figure}")
    return 0


def sweep(args: argparse.Namespace) -> int:
    """Run a sweep spec's episodes not yet done, then write its tables and figure into --out."""
    from tdp.cli import output_folder
    from tdp.sweep import JOURNAL, Journal, load_spec, local_workers, run_sweep, write_report

    spec = load_spec(args.spec)
    if args.workers is not None and (args.workers < 1 or args.serial or args.scheduler):
        raise ValueError(f"--workers {args.workers}: a positive number of local workers, without --serial or "
                         "--scheduler")
    local_workers(args.workers, os.cpu_count() or 1, 1)  # too many fails before the output folder is made
    out = output_folder(args.out or f"sweep-{spec.name}")
    episodes = spec.episodes()
    where = "serially" if args.serial else f"on {args.scheduler or 'a local cluster'}"
    print(f"sweep {spec.name}: {len(episodes)} episodes on {len(spec.worlds)} worlds, {where}; results in {out}",
          flush=True)
    try:
        rows = run_sweep(spec, out, args.scheduler, args.workers, args.serial)
    except KeyboardInterrupt:
        rows = Journal(out / JOURNAL).rows_of(episodes)
        write_report(spec, rows, out)
        print(f"interrupted: {len(rows)} of {len(episodes)} episodes are saved in {out / JOURNAL}; the same command "
              "finishes the rest", file=sys.stderr)
        return 130
    written = write_report(spec, rows, out)
    print(f"{len(rows)} of {len(episodes)} episodes done; wrote {', '.join(str(p) for p in written)}")
    if len(rows) < len(episodes):
        print(f"{len(episodes) - len(rows)} episodes failed (their errors are in {out / JOURNAL}); the same "
              "command retries them", file=sys.stderr)
        return 1
    return 0


def parser() -> argparse.ArgumentParser:
    from tdp.cli import add_cost_arguments, add_planner_argument, add_world_arguments

    main = argparse.ArgumentParser(prog="python -m tdp", description=__doc__,
                                   formatter_class=argparse.RawDescriptionHelpFormatter)
    commands = main.add_subparsers(dest="command", required=True)
    commands.add_parser("list", help="list the named scenarios").set_defaults(run=list_scenarios)
    r = commands.add_parser("run", help="run a scenario: metrics.json and episode.png")
    add_world_arguments(r)
    add_planner_argument(r)
    r.add_argument("--updates", type=int, help="K, DP iterations per robot move (default 4)")
    r.add_argument("--budget-ms", type=float, default=None,
                   help="a time budget per tick instead of K: as many DP iterations as fit (at least one)")
    r.add_argument("--nodes", type=int, help="number of accelerating nodes (default 25)")
    r.add_argument("--vision", type=float, help="DmaxQ / node spacing (default 2.5)")
    r.add_argument("--detect-window", type=int, help="J (default 6)")
    r.add_argument("--detect-rise", type=float, help="U (default J - 1)")
    r.add_argument("--predict-ticks", type=int,
                   help="obstacle prediction's horizon in ticks for the node layers (default 0: off)")
    r.add_argument("--avoid-boxes", action="store_true",
                   help="yield or step aside instead of moving into a cell a box is about to enter")
    r.add_argument("--neighbourhood", type=int, choices=(4, 8, 16), help="moves of the stencil (default 16)")
    r.add_argument("--corner-cutting", action="store_true")
    r.add_argument("--max-ticks", type=int, default=None)
    r.add_argument("--out", default="out", help="output folder (default: out)")
    r.add_argument("--animate", action="store_true", help="also write episode.gif (and .mp4 where ffmpeg exists)")
    r.set_defaults(run=run)
    p = commands.add_parser("plan", help="shortest path on a map file (MovingAI .map, ROS .yaml, image)")
    p.add_argument("map")
    p.add_argument("--start", nargs=2, type=int, required=True, metavar=("ROW", "COL"))
    p.add_argument("--goal", nargs=2, type=int, required=True, metavar=("ROW", "COL"))
    p.add_argument("--neighbourhood", type=int, default=16, choices=(4, 8, 16))
    p.add_argument("--corner-cutting", action="store_true", help="allow diagonal moves through corners")
    p.add_argument("--unknown-free", action="store_true", help="ROS maps: treat unknown cells as free")
    add_cost_arguments(p)
    p.add_argument("--out", default="out", help="folder for the figure (default: out)")
    p.set_defaults(run=plan)
    s = commands.add_parser("sweep", help="run a sweep spec: many episodes, tables and a figure")
    s.add_argument("spec", help="a sweep spec (YAML: see docs/sweeps.md)")
    s.add_argument("--out", default=None, help="output folder (default: sweep-NAME); a rerun skips what it holds")
    where = s.add_mutually_exclusive_group()
    where.add_argument("--serial", action="store_true", help="run the episodes one after another in this process")
    where.add_argument("--scheduler", help="address of a running Dask scheduler (default: start a local cluster)")
    s.add_argument("--workers", type=int, default=None, help="local cluster: worker processes (default: one per core)")
    s.set_defaults(run=sweep)
    return main


def main(argv: list[str] | None = None) -> int:
    from tdp.cli import run as run_command

    return run_command(parser(), argv)


if __name__ == "__main__":
    sys.exit(main())
