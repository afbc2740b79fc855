"""PyBullet runs of tdp's scenarios (headless by default).

    python -m sim list
    python -m sim run --scenario NAME | --world FILE [--planner exact|accelerating|plain-dp] [--updates K] [--gui]
                      --out DIR
    python -m sim compare --scenario NAME | --world FILE [--updates K] --out DIR   the three planners side by side

--cost-scaling-factor K --inflation-radius M give the planner's map nav2's inflation cost around every grown
obstacle, boxes included (sim.episode.SimConfig), whatever the world.
"""
from __future__ import annotations

import argparse
import sys
from pathlib import Path


def _config(args: argparse.Namespace, planner: str):
    """The planner's config from the options: ``compare`` runs every planner with them, each taking those it reads
    (K for the DP planners only); ``run`` refuses one its planner does not read."""
    from tdp.cli import config_from

    return config_from(args, planner, strict=args.command == "run")


def _run_and_save(args: argparse.Namespace, planner: str, out: Path, stem: str, frames: list | None = None) -> dict:
    from tdp.cli import save_json, world_from

    from .episode import SimConfig, run_episode
    from .render import save_trace_figure

    scenario, config = world_from(args, costs_on_any_world=True), _config(args, planner)
    margin = {} if args.margin is None else {"margin_m": args.margin}
    sim = SimConfig(cost_scaling_factor=args.cost_scaling_factor, inflation_radius=args.inflation_radius, **margin)
    print(f"running {scenario.name} in PyBullet ({config.label()})", flush=True)
    metrics = run_episode(scenario, config, sim, gui=getattr(args, "gui", False), progress=True, frames=frames)
    metrics["json"] = str(save_json(metrics, out / f"{stem}.json"))
    metrics["figure"] = str(save_trace_figure(scenario, metrics, out / f"{stem}.png"))
    return metrics


def _ratio(metrics: dict) -> str:
    return "-" if metrics["ratio"] is None else f"{metrics['ratio']:.3f}"


def _summary(metrics: dict) -> str:
    from tdp.cli import limit_note

    from .render import oracle_text

    limit = limit_note(metrics["reached"], metrics["ticks"], metrics["max_ticks"])
    return (f"reached {metrics['reached']}{limit} in {metrics['time_s']:.1f} s; path {metrics['path_length_m']:.2f} m, "
            f"oracle {oracle_text(metrics)}, ratio {_ratio(metrics)}; contacts {metrics['contacts']}, "
            f"min clearance {metrics['min_clearance_m']:.3f} m (mean {metrics['mean_clearance_m']:.3f}); planner "
            f"{metrics['planner_ms_per_tick']['median']:.2f} ms/tick (median); wall {metrics['wall_s']:.1f} s")


def _animate(out: Path, films: list[tuple[str, list]]) -> str:
    """Write the camera films side by side as animation.gif in ``out``; returns its path."""
    from .render import save_frames_animation

    path = save_frames_animation(films, out / "animation.gif")
    print(f"animation: {path}")
    return str(path)


def run(args: argparse.Namespace) -> int:
    from tdp.cli import output_folder

    out = output_folder(args.out)
    frames = [] if args.animate else None
    metrics = _run_and_save(args, args.planner, out, "metrics", frames)
    print(_summary(metrics))
    print(f"wrote {metrics['json']} and {metrics['figure']}")
    if args.animate:
        _animate(out, [(_config(args, args.planner).label(), frames)])
    return 0


def compare(args: argparse.Namespace) -> int:
    from tdp.cli import output_folder

    from .render import oracle_text

    out = output_folder(args.out)
    films = {kind: [] if args.animate else None for kind in ("exact", "accelerating", "plain-dp")}
    rows = [(kind, _run_and_save(args, kind, out, kind, frames)) for kind, frames in films.items()]
    print(f"\n{rows[0][1]['scenario']}, K = {_config(args, 'plain-dp').updates_per_move} for the DP planners, "
          "PyBullet DIRECT")
    print("| planner | reached | time s | path m | oracle | ratio | contacts | min clearance m | "
          "planner ms/tick (median) |")
    print("|---|---|---|---|---|---|---|---|---|")
    for kind, m in rows:
        print(f"| {kind} | {m['reached']} | {m['time_s']:.1f} | {m['path_length_m']:.2f} | {oracle_text(m)} "
              f"| {_ratio(m)} | {m['contacts']} | {m['min_clearance_m']:.3f} | "
              f"{m['planner_ms_per_tick']['median']:.2f} |")
    print("figures: " + ", ".join(m["figure"] for _, m in rows))
    if args.animate:
        _animate(out, [(_config(args, kind).label(), frames) for kind, frames in films.items()])
    return 0


def list_scenarios(args: argparse.Namespace) -> int:
    import tdp

    for name in tdp.scenarios.names():
        print(f"{name:18s} {tdp.scenarios.get(name).description}")
    return 0


def _positive(text: str) -> int:
    value = int(text)
    if value < 1:
        raise argparse.ArgumentTypeError(f"must be a positive integer, got {text}")
    return value


def parser() -> argparse.ArgumentParser:
    from tdp.cli import add_planner_argument, add_world_arguments

    main = argparse.ArgumentParser(prog="python -m sim", description=__doc__,
                                   formatter_class=argparse.RawDescriptionHelpFormatter)
    commands = main.add_subparsers(dest="command", required=True)
    commands.add_parser("list", help="list the scenarios").set_defaults(run=list_scenarios)
    for name, function in (("run", run), ("compare", compare)):
        sub = commands.add_parser(name, help=f"{name} a scenario in PyBullet")
        add_world_arguments(sub)
        sub.add_argument("--updates", type=_positive, help="K, DP iterations per move (default 4)")
        sub.add_argument("--budget-ms", type=float, default=None,
                         help="a planning budget per control tick instead of K (at most the world's tick_s)")
        sub.add_argument("--predict-ticks", type=int,
                         help="obstacle prediction's horizon in ticks for the node layers (default 0: off)")
        sub.add_argument("--avoid-boxes", action="store_true",
                         help="yield or step aside instead of moving into a cell a box is about to enter")
        sub.add_argument("--margin", type=float, metavar="M",
                         help="metres obstacles grow by beyond the robot's radius (default SimConfig's, 0.1; at least "
                              "half a cell's diagonal: 0.708 on 1 m cells)")
        sub.add_argument("--out", default=f"out/sim-{name}", help="output folder")
        sub.add_argument("--animate", action="store_true",
                         help="also write animation.gif from the simulator's own camera (headless)")
        if name == "run":
            add_planner_argument(sub)
            sub.add_argument("--gui", action="store_true", help="open the PyBullet window (needs a display)")
        sub.set_defaults(run=function)
    return main


def main(argv: list[str] | None = None) -> int:
    from tdp.cli import run as run_command

    return run_command(parser(), argv)


if __name__ == "__main__":
    sys.exit(main())
