"""A time budget per tick against a fixed number of DP iterations per move.

    python -m benchmarks.budget [--quick]

Accelerating nodes (defaults) on the two blockage scenarios and on real maps (arena, MovingAI, with shuttling boxes
and a blockage on the route; the TurtleBot3 world example, ROS): fixed K = 1 and 4 against budgets of 1, 5 and 20 ms
per tick. Per run: the ratio to the oracle, the DP iterations a tick ran (median) and the planner's time per tick
(median, ms). Budget runs depend on the machine (how many iterations fit), so they are measured, not asserted.
"""
from __future__ import annotations

from pathlib import Path

import numpy as np

import tdp
from benchmarks.common import print_table, quick_parser, save_results
from tdp.contract import timing_summary
from tdp.random_worlds import boxes_on_map
from tdp.simulate import oracle_run, run_planner

ROOT = Path(__file__).resolve().parents[1]
SETTINGS = [("K = 1", {"updates_per_move": 1}), ("K = 4", {"updates_per_move": 4}), ("1 ms", {"budget_ms": 1.0}),
            ("5 ms", {"budget_ms": 5.0}), ("20 ms", {"budget_ms": 20.0})]


def worlds(quick: bool) -> list[tdp.Scenario]:
    named = [tdp.scenarios.get("sudden-blockage")]
    if quick:
        return named
    arena = tdp.load_map(ROOT / "tests" / "data" / "arena.map")
    return named + [tdp.scenarios.get("moving-blockage"),
                    boxes_on_map(arena, (1, 3), (47, 46), boxes=4, seed=1, blockage=True),
                    tdp.load_world(ROOT / "examples" / "turtlebot3-world.yaml")]


def run(scenario: tdp.Scenario, options: dict, oracle_length: float) -> dict:
    config = tdp.NavigatorConfig(planner="accelerating", **options)
    navigator = tdp.Navigator(tdp.GridMap(scenario.occupancy(0), scenario.grid.resolution), scenario.start,
                              scenario.goal, config)
    navigator.setup()
    record = run_planner(scenario, navigator, config, scenario.max_ticks)
    results = record["results"]
    return {"reached": record["reached"], "ratio": record["length"] / oracle_length if record["reached"] else None,
            "iterations": float(np.median([r.iterations for r in results])),
            "ms": timing_summary([sum(r.timings.values()) for r in results])["median"]}


def figure(rows: list[dict], path) -> None:
    from tdp.plot import pyplot, save_figure

    plt = pyplot()
    fig, ax = plt.subplots(figsize=(7, 4))
    for world in dict.fromkeys(r["world"] for r in rows):
        mine = [r for r in rows if r["world"] == world]
        ax.plot([r["ms"] for r in mine], [r["ratio"] or np.nan for r in mine], "o-", label=world)
        for r in mine:
            ax.annotate(r["setting"], (r["ms"], r["ratio"] or np.nan), fontsize=6, xytext=(2, 2),
                        textcoords="offset points")
    ax.set_xscale("log")
    ax.set_xlabel("planner ms per tick (median)")
    ax.set_ylabel("path length / oracle")
    ax.set_title("fixed K against a time budget per tick", fontsize=9)
    ax.legend(fontsize=7)
    save_figure(fig, path)


def main() -> None:
    args = quick_parser(__doc__).parse_args()
    settings = SETTINGS[:1] + SETTINGS[2:4] if args.quick else SETTINGS
    rows = []
    for scenario in worlds(args.quick):
        oracle = oracle_run(scenario, tdp.NavigatorConfig(), scenario.max_ticks)
        run(scenario, {"updates_per_move": 1}, oracle["length"])  # warm-up (caches, first launches)
        for label, options in settings:
            rows.append({"world": scenario.name, "setting": label, **run(scenario, options, oracle["length"])})
            r = rows[-1]
            print(f"  {scenario.name}, {label}: ratio {r['ratio']}, {r['iterations']:.0f} iterations/tick, "
                  f"{r['ms']:.2f} ms/tick", flush=True)
    print_table(["world", "setting", "reached", "ratio", "iterations per tick (median)", "ms/tick (median)"],
                [[r["world"], r["setting"], str(r["reached"]), "-" if r["ratio"] is None else f"{r['ratio']:.3f}",
                  f"{r['iterations']:.0f}", f"{r['ms']:.2f}"] for r in rows])
    save_results("budget-quick" if args.quick else "budget", {"rows": rows}, lambda png: figure(rows, png))


if __name__ == "__main__":
    main()
