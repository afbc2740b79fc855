"""The navigator on a real ROS map: setup and tick times on nav2's warehouse (1674 x 1006 cells) with moving boxes.

    python -m benchmarks.warehouse [--quick] [--seeds 0 1 2]

nav2's warehouse map (benchmarks/data/nav2_maps, inflated by 0.2 m), start and goal random cells of the largest free
region, two worlds per seed (:func:`tdp.random_worlds.boxes_on_map`): six boxes shuttling over free ground all the
time ("boxes"), and one box appearing in a narrow place of the robot's route a third of the way along and staying
there ("appear"; run for twice as many ticks so that the robot meets it). Per world, exact replanning (unbudgeted
and with a 1 ms budget), accelerating nodes (25 nodes) and plain DP at K = 4, and accelerating nodes with a time
budget of 1 ms per tick instead of a fixed K:

* setup: ``Navigator(...)`` (node placement, windows) plus ``setup()`` (every layer converged; the exact
  planner's goal layer as far as the start needs), warm: a first navigator of the same kind compiled every kernel
  in this process; apart, per seed, the exact planner's setup with the start moved to the reachable cell farthest
  from the goal (its worst case);
* tick: the planner's ``tick()`` (the exact planner's repair and successor; the DP planners' iterations,
  monitor, search), median, 95th percentile and maximum over the run's ticks (TICKS at most, twice that in
  "appear" worlds; fewer when the robot arrives); apart, the map hand-over: the planner's ``update_map`` of the
  tick's changed cells (building the world's map and finding those cells is the harness's, left out);
* side by side, what recomputing instead of iterating would cost: a from-scratch ``converge()`` of the goal field
  on the same map, and scipy's Dijkstra solve on the 16-neighbour graph.

--quick: nav2's depot map (307 x 604), one seed, 30 ticks. --seeds: the worlds' seeds (default 0 1 2; others are
worlds the figures in RESULTS.md were not tuned on), saved under their own name.
"""
from __future__ import annotations

import dataclasses
import time
from pathlib import Path

import numpy as np
from scipy.sparse.csgraph import dijkstra

import tdp
from benchmarks.common import freeze_heap, median_time, print_table, quick_parser, save_results
from benchmarks.convergence import NAV2, ROBOT_RADIUS_M, largest_free_region
from benchmarks.reference_graph import grid_graph
from tdp.contract import timing_summary
from tdp.random_worlds import boxes_on_map
from tdp.simulate import run_planner, start_grid

SEEDS, TICKS, BOXES = [0, 1, 2], 300, 6
PLANNERS = [("exact", {"planner": "exact"}), ("exact, 1 ms budget", {"planner": "exact", "budget_ms": 1.0}),
            ("accelerating", {"planner": "accelerating"}), ("plain DP", {"planner": "plain-dp"}),
            ("accelerating, 1 ms budget", {"planner": "accelerating", "budget_ms": 1.0})]


def worlds(quick: bool, seeds: list[int] = SEEDS) -> list[tdp.Scenario]:
    """Per seed, shuttling boxes and a box appearing on the route, on the inflated map; start and goal in its
    largest free region."""
    grid = tdp.load_map(NAV2 / ("depot.yaml" if quick else "warehouse.yaml"))
    grid = grid.inflate(ROBOT_RADIUS_M / grid.resolution)
    free = largest_free_region(grid.occupied)
    scenarios = []
    for seed in seeds[:1] if quick else seeds:
        start, goal = (tuple(int(v) for v in free[k]) for k in np.random.default_rng(seed).choice(len(free), 2))
        scenarios.append(boxes_on_map(grid, start, goal, boxes=2 if quick else BOXES, seed=seed))
        appear = boxes_on_map(grid, start, goal, boxes=0, seed=seed, blockage=True)
        scenarios.append(dataclasses.replace(appear, name=f"appear-{seed}"))
    return scenarios


def navigator(scenario: tdp.Scenario, config: tdp.NavigatorConfig):
    return tdp.make_planner(start_grid(scenario), scenario.start, scenario.goal, config)


def run(scenario: tdp.Scenario, options: dict, ticks: int) -> dict:
    """Setup and tick times of one planner on one world (its kernels already compiled)."""
    config = tdp.NavigatorConfig(**options)
    began = time.perf_counter()
    planner = navigator(scenario, config)
    built = time.perf_counter()
    rounds = planner.setup()
    done = time.perf_counter()
    freeze_heap()  # after each setup, as a control loop would: the runs before left objects a collection would walk
    record = run_planner(scenario, planner, config, ticks)
    results = record["results"]
    tick = timing_summary([sum(v for k, v in r.timings.items() if k != "update") for r in results])
    update = timing_summary([r.timings["update"] for r in results])
    return {"construct_ms": (built - began) * 1e3, "converge_ms": (done - built) * 1e3,
            "setup_ms": (done - began) * 1e3, "rounds": rounds, "nodes": len(planner.nodes), "ticks": record["ticks"],
            "tick_median_ms": tick["median"], "tick_p95_ms": tick["p95"], "tick_max_ms": tick["max"],
            "update_median_ms": update["median"], "collisions": record["collisions"], "hits": record["hits"],
            "reached": record["reached"]}


def recompute_ms(scenario: tdp.Scenario) -> dict:
    """A from-scratch converge() of the goal field and scipy's Dijkstra solve on the world's first map."""
    occupied = scenario.occupancy(0)
    field = tdp.DistanceField(tdp.GridMap(occupied), scenario.goal)

    def from_scratch():
        field.reset()
        field.converge()

    graph = grid_graph(occupied).T.tocsr()
    source = scenario.goal[0] * occupied.shape[1] + scenario.goal[1]
    return {"recompute_ms": median_time(from_scratch, 3) * 1e3,
            "dijkstra_ms": median_time(lambda: dijkstra(graph, indices=source), 3) * 1e3}


def far_setup_ms(scenario: tdp.Scenario, repeats: int = 3) -> dict:
    """The exact planner's setup (construction and ``setup()``, median of ``repeats``) with the world's goal and the
    start moved to the reachable cell farthest from it: the worst case of a search focused on the start."""
    grid = start_grid(scenario)
    field = tdp.DistanceField(grid, scenario.goal)
    field.converge()
    distances = np.where(np.isfinite(field.distances()), field.distances(), -1.0)
    far = tuple(int(v) for v in np.unravel_index(np.argmax(distances), distances.shape))
    config = tdp.NavigatorConfig(planner="exact")
    return {"far_start": far, "far_cells": float(distances[far]),
            "far_setup_ms": median_time(lambda: tdp.make_planner(grid, far, scenario.goal, config).setup(), repeats)
            * 1e3}


def figure(rows: list[dict], path: Path) -> None:
    from tdp.plot import pyplot, save_figure

    plt = pyplot()
    fig, ax = plt.subplots(figsize=(14, 4.5))
    labels = [f"{r['world']}\n{r['planner'].replace(', ', chr(10))}" for r in rows]
    x = np.arange(len(rows))
    for k, (key, name) in enumerate([("tick_median_ms", "tick median"), ("tick_p95_ms", "tick p95"),
                                     ("tick_max_ms", "tick max"), ("recompute_ms", "goal field from scratch")]):
        ax.bar(x + (k - 1.5) * 0.2, [r[key] for r in rows], 0.2, label=name)
    ax.axhline(1.0, color="k", lw=0.8, ls="--")
    ax.axhline(20.0, color="k", lw=0.8, ls=":")
    ax.set_title("nav2 warehouse, 6 shuttling boxes (boxes-6-*) or a box appearing on the route (appear-*): planner "
                 "time per tick (lines: the 1 ms median and 20 ms max targets)", fontsize=9)
    ax.set_xticks(x, labels, fontsize=6)
    ax.set_yscale("log")
    ax.set_ylabel("ms")
    ax.legend(fontsize=7, loc="upper left", bbox_to_anchor=(1.0, 1.0))
    save_figure(fig, path)


def main() -> None:
    parser = quick_parser(__doc__)
    parser.add_argument("--seeds", type=int, nargs="+", default=SEEDS, help="the worlds' seeds (default 0 1 2)")
    args = parser.parse_args()
    ticks = 30 if args.quick else TICKS
    scenarios = worlds(args.quick, args.seeds)
    for _, options in PLANNERS:  # compile every kernel of both kinds (excluded from every timing)
        navigator(scenarios[0], tdp.NavigatorConfig(**options)).setup()
    rows, far = [], []
    for scenario in scenarios:
        reference = recompute_ms(scenario)
        if scenario.change_tick is None:  # one per seed: both worlds share the map and the goal
            far.append({"world": scenario.name, **far_setup_ms(scenario)})
            print(f"  {scenario.name}: exact setup {far[-1]['far_setup_ms']:.0f} ms with the start "
                  f"{far[-1]['far_cells']:.0f} cells from the goal", flush=True)
        for name, options in PLANNERS:
            limit = ticks if scenario.change_tick is None else 2 * ticks
            rows.append({"world": scenario.name, "planner": name, **run(scenario, options, limit), **reference})
            r = rows[-1]
            print(f"  {scenario.name}, {name}: setup {r['setup_ms']:.0f} ms, tick median {r['tick_median_ms']:.2f} "
                  f"ms, max {r['tick_max_ms']:.1f} ms (goal field from scratch {r['recompute_ms']:.0f} ms)",
                  flush=True)
    print_table(["world", "planner", "nodes", "setup ms", "of which converge", "ticks", "tick median ms", "tick p95 ms",
                 "tick max ms", "map hand-over ms", "from scratch ms", "Dijkstra ms", "coll.", "arrived"],
                [[r["world"], r["planner"], str(r["nodes"]), f"{r['setup_ms']:.0f}", f"{r['converge_ms']:.0f}",
                  str(r["ticks"]), f"{r['tick_median_ms']:.2f}", f"{r['tick_p95_ms']:.2f}", f"{r['tick_max_ms']:.1f}",
                  f"{r['update_median_ms']:.2f}", f"{r['recompute_ms']:.0f}", f"{r['dijkstra_ms']:.0f}",
                  str(r["collisions"]), "yes" if r["reached"] else "no"] for r in rows])
    print_table(["world", "farthest start", "its distance (cells)", "exact setup ms"],
                [[r["world"], str(r["far_start"]), f"{r['far_cells']:.0f}", f"{r['far_setup_ms']:.0f}"] for r in far])
    name = "warehouse" + ("-quick" if args.quick else "") + ("" if args.seeds == SEEDS else "-seeds-" +
                                                             "-".join(map(str, args.seeds)))
    save_results(name, {"rows": rows, "far_setup": far}, lambda png: figure(rows, png))


if __name__ == "__main__":
    main()
