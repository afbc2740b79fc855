"""Every planner at equal time per tick as well as at equal K: which one a user should run.

    python -m benchmarks.equal_time [--quick]

One process, the engine's threads (TDP_THREADS, default 2), warm (each planner kind's kernels compiled before any
timing). Planners: exact replanning unbudgeted and with budgets of BUDGETS_MS per tick; accelerating nodes and
plain DP at K = 1 and 4 and with budgets of DP_BUDGETS_MS (at least one iteration a tick whatever the budget);
D* Lite (plain Python) on maps of at most DSTAR_MAX_SIDE cells a side. Worlds: the eight random-world families at
100 and 200 (SEEDS: three at 100, two at 200), the named scenarios, quick worlds with BOXES shuttling boxes and
with a box appearing on the route on MovingAI maps (arena and den312d from tests/data, and from ../shared/data
when present maze512-32-0, random512-10-0 and 8room_000, start and goal from their longest scenario), and nav2's
warehouse and depot maps (inflated by 0.2 m, start and goal from the largest free region) with six shuttling
boxes and with a box appearing; and two halls (HALLS: a corridor 24 cells wide and 600 long, 12 % obstacles, lying
and standing, three boxes shuttling across it), driven end to end. On maps of more than LARGE cells the DP planners
run K = 1 and a budget of 1 ms only (a tick costs tens of milliseconds there).

Per world, the exact planner (unbudgeted: the oracle) is checked against a goal field converged fully every tick
(``benchmarks.reference_planner``): the same trajectory, tick for tick. Per world group and planner setting:
reached %, mean and max ratio to the oracle, collisions, and the planner's time per tick - its tick() and its
update_map of the tick's changed cells - pooled over the group's ticks: median, 95th percentile and maximum; and
apart, the longest tick() alone (what a budget bounds). Figure: the mean ratio against the median and the 95th
percentile of ms per tick, one column per group (the Pareto view).

--quick: two small worlds, four settings, a few dozen ticks.
"""
from __future__ import annotations

import dataclasses
import time
from pathlib import Path

import numpy as np

import tdp
from benchmarks.common import freeze_heap, print_table, quick_parser, save_results
from benchmarks.convergence import NAV2, ROBOT_RADIUS_M, SHARED, largest_free_region
from benchmarks.reference_planner import FullConverge
from tdp.dstar_lite import DStarLite
from tdp.random_worlds import FAMILIES, boxes_on_map, make_world
from tdp.simulate import oracle_run, run_planner, start_grid

ROOT = Path(__file__).resolve().parents[1]
BUDGETS_MS = (0.1, 0.3, 1.0, 3.0, 10.0)
#: The DP planners spend their whole budget every tick (as many iterations as fit), so 10 ms would cost 10 ms a tick
#: in every world; their budgets stop at 3 ms (K = 4 and the exact planner bound them from above).
DP_BUDGETS_MS = (0.3, 1.0, 3.0)
SEEDS = {100: (0, 1, 2), 200: (0, 1)}
BOXES = 6
DSTAR_MAX_SIDE = 100
LARGE = 512 * 512
MOVINGAI_TESTS = ("arena", "den312d")
MOVINGAI_SHARED = ("maze512-32-0", "random512-10-0", "8room_000")
#: Halls (rows, cols): a long corridor lying and standing, where a box crossing it sends the news along its length.
HALLS = ((24, 600), (600, 24))


def settings(cells: int) -> list[tuple[str, dict]]:
    """(label, NavigatorConfig fields) of every planner setting run on a map of ``cells`` cells."""
    exact = [("exact", {"planner": "exact"})] + [(f"exact {b:g} ms", {"planner": "exact", "budget_ms": b})
                                                 for b in BUDGETS_MS]
    dp = []
    for planner, name in (("accelerating", "accelerating"), ("plain-dp", "plain DP")):
        ks, budgets = ((1,), (1.0,)) if cells > LARGE else ((1, 4), DP_BUDGETS_MS)
        dp += [(f"{name} K={k}", {"planner": planner, "updates_per_move": k}) for k in ks]
        dp += [(f"{name} {b:g} ms", {"planner": planner, "budget_ms": b}) for b in budgets]
    return exact + dp


def quick_settings() -> list[tuple[str, dict]]:
    return [("exact", {"planner": "exact"}), ("exact 0.3 ms", {"planner": "exact", "budget_ms": 0.3}),
            ("accelerating K=1", {"planner": "accelerating", "updates_per_move": 1}),
            ("plain DP K=1", {"planner": "plain-dp", "updates_per_move": 1})]


def worlds(quick: bool) -> list[tuple[str, tdp.Scenario]]:
    """(group, scenario) of every world."""
    if quick:
        return [("families-60", make_world("rooms", 60, 0)), ("families-60", make_world("crossing", 60, 0))]
    out = [(f"families-{size}", make_world(family, size, seed))
           for size, seeds in SEEDS.items() for family in FAMILIES for seed in seeds]
    out += [("scenarios", tdp.scenarios.get(name)) for name in tdp.scenarios.names()]
    out += [("movingai", world) for world in movingai_worlds()]
    out += [("nav2", world) for world in nav2_worlds()]
    out += [("halls", world) for world in hall_worlds()]
    return out


def hall_worlds() -> list[tdp.Scenario]:
    """Each of HALLS: random obstacles (12 %) but at its two ends, the robot at the middle of one end and the goal at
    the other's, three 4 x 4 boxes shuttling across it at a quarter, a half and three quarters of its length."""
    out = []
    for rows, cols in HALLS:
        width, length = min(rows, cols), max(rows, cols)
        occupied = np.random.default_rng(length).random((width, length)) < 0.12  # lying: along the columns
        occupied[:, :3] = occupied[:, -3:] = False
        boxes = [((2, c, 6, c + 4), [(width - 6, c), (2, c)], speed)
                 for c, speed in ((length // 4, 0.3), (length // 2, 0.5), (3 * length // 4, 0.4))]
        start, goal = (width // 2, 0), (width // 2, length - 1)
        if rows > cols:  # standing: every coordinate transposed
            occupied = occupied.T
            boxes = [((c0, r0, c1, r1), [(c, r) for r, c in waypoints], speed)
                     for (r0, c0, r1, c1), waypoints, speed in boxes]
            start, goal = start[::-1], goal[::-1]
        obstacles = [tdp.Obstacle(box=box, waypoints=waypoints, speed=speed) for box, waypoints, speed in boxes]
        out.append(tdp.Scenario(tdp.GridMap(occupied), start, goal, obstacles=obstacles, name=f"hall-{rows}x{cols}",
                                max_ticks=4 * length))
    return out


def movingai_worlds() -> list[tdp.Scenario]:
    """Shuttling boxes and a box appearing on the route, on each MovingAI map found, between the start and goal
    of its longest scenario."""
    paths = [ROOT / "tests" / "data" / f"{name}.map" for name in MOVINGAI_TESTS]
    paths += [p for p in (SHARED / "movingai" / f"{name}.map" for name in MOVINGAI_SHARED) if p.exists()]
    out = []
    for path in paths:
        grid = tdp.load_map(path)
        problem = max(tdp.load_scenarios(path.with_suffix(".map.scen"), grid), key=lambda p: p.optimal_length)
        out.append(_named(boxes_on_map(grid, problem.start, problem.goal, boxes=BOXES, seed=0), f"{path.stem}-boxes"))
        try:
            out.append(_named(boxes_on_map(grid, problem.start, problem.goal, boxes=0, seed=0, blockage=True),
                              f"{path.stem}-appear"))
        except ValueError as error:  # a maze's route has no narrow place whose closing leaves another way
            print(f"  {path.stem}: no appearing box ({error})")
    return out


def nav2_worlds() -> list[tdp.Scenario]:
    """nav2's warehouse and depot maps, inflated: six shuttling boxes, and a box appearing on the route."""
    out = []
    for name in ("warehouse", "depot"):
        grid = tdp.load_map(NAV2 / f"{name}.yaml")
        grid = grid.inflate(ROBOT_RADIUS_M / grid.resolution)
        free = largest_free_region(grid.occupied)
        start, goal = (tuple(int(v) for v in free[k]) for k in np.random.default_rng(0).choice(len(free), 2))
        out += [_named(boxes_on_map(grid, start, goal, boxes=BOXES, seed=0), f"{name}-boxes"),
                _named(boxes_on_map(grid, start, goal, boxes=0, seed=0, blockage=True), f"{name}-appear")]
    return out


def _named(scenario: tdp.Scenario, name: str) -> tdp.Scenario:
    return dataclasses.replace(scenario, name=name)


def planner_for(scenario: tdp.Scenario, options: dict):
    """The planner of ``options`` on the world's first map, set up; D* Lite for {"planner": "dstar-lite"}."""
    if options["planner"] == "dstar-lite":
        return DStarLite(scenario.occupancy(0), scenario.start, scenario.goal)
    config = tdp.NavigatorConfig(**options)
    planner = tdp.make_planner(start_grid(scenario), scenario.start, scenario.goal, config)
    planner.setup()
    return planner


def run(scenario: tdp.Scenario, options: dict, oracle_length: float) -> dict:
    """One planner setting on one world: outcome and per-tick times (ms)."""
    config = tdp.NavigatorConfig() if options["planner"] == "dstar-lite" else tdp.NavigatorConfig(**options)
    record = run_planner(scenario, planner_for(scenario, options), config, scenario.tick_limit)
    results = record["results"]
    return {"reached": bool(record["reached"]), "collisions": record["collisions"], "ticks": record["ticks"],
            "ratio": record["length"] / oracle_length if record["reached"] and oracle_length > 0 else None,
            "total_ms": [1e3 * sum(r.timings.values()) for r in results],
            "tick_ms": [1e3 * sum(v for k, v in r.timings.items() if k != "update") for r in results],
            "behind": sum(r.mode == tdp.Mode.BEHIND for r in results)}


def measure(quick: bool) -> list[dict]:
    """Every setting on every world; a row per (world, setting) with its tick times."""
    rows, warm = [], set()
    for group, scenario in worlds(quick):
        oracle = oracle_run(scenario, tdp.NavigatorConfig(), scenario.tick_limit)
        reference = run_planner(scenario, FullConverge(start_grid(scenario), scenario.start, scenario.goal,
                                                       tdp.NavigatorConfig()), tdp.NavigatorConfig(),
                                scenario.tick_limit)
        same = oracle["trajectory"] == reference["trajectory"]
        print(f"{scenario.name}: the exact planner drives a full converge's trajectory: {same}", flush=True)
        cells = scenario.grid.shape[0] * scenario.grid.shape[1]
        chosen = quick_settings() if quick else settings(cells)
        freeze_heap()  # the world, its oracle and what came before: out of the collector's way while ticks are timed
        if not quick and max(scenario.grid.shape) <= DSTAR_MAX_SIDE:
            chosen = chosen + [("D* Lite", {"planner": "dstar-lite"})]
        for label, options in chosen:
            if options["planner"] not in warm:  # compile this kind's kernels before any timing
                planner_for(scenario, options)
                warm.add(options["planner"])
            began = time.perf_counter()
            row = {"group": group, "world": scenario.name, "setting": label, "exact_is_full_converge": same,
                   **run(scenario, options, oracle["length"])}
            rows.append(row)
            print(f"  {scenario.name}, {label}: reached {row['reached']}, ratio {row['ratio']}, tick median "
                  f"{np.median(row['total_ms']):.2f} ms ({time.perf_counter() - began:.1f} s)", flush=True)
    return rows


def summarise(rows: list[dict]) -> list[dict]:
    """Per group and setting: reached %, mean and max ratio, collisions, pooled tick times (ms) and ticks behind."""
    out = []
    for group in dict.fromkeys(r["group"] for r in rows):
        for setting in dict.fromkeys(r["setting"] for r in rows if r["group"] == group):
            runs = [r for r in rows if r["group"] == group and r["setting"] == setting]
            ratios = [r["ratio"] for r in runs if r["ratio"] is not None]
            total = np.concatenate([r["total_ms"] for r in runs])
            tick = np.concatenate([r["tick_ms"] for r in runs])
            out.append({"group": group, "setting": setting, "worlds": len(runs),
                        "reached_pct": 100.0 * sum(r["reached"] for r in runs) / len(runs),
                        "mean_ratio": float(np.mean(ratios)) if ratios else None,
                        "max_ratio": float(np.max(ratios)) if ratios else None,
                        "collisions": sum(r["collisions"] for r in runs),
                        "exact_is_full_converge": all(r["exact_is_full_converge"] for r in runs),
                        "ms_median": float(np.median(total)), "ms_p95": float(np.percentile(total, 95)),
                        "ms_max": float(total.max()), "tick_max_ms": float(tick.max()),
                        "behind_pct": 100.0 * sum(r["behind"] for r in runs) / max(1, sum(r["ticks"] for r in runs))})
    return out


def figure(summary: list[dict], path: Path) -> None:
    """Mean ratio against the median (top) and the 95th percentile (bottom) of ms per tick, one column per world
    group, a marker per setting: the Pareto view (down and left is better)."""
    from tdp.plot import pyplot, save_figure

    plt = pyplot()
    groups = list(dict.fromkeys(s["group"] for s in summary))
    fig, axes = plt.subplots(2, len(groups), figsize=(4.2 * len(groups), 8.0), squeeze=False)
    colours = {"exact": "tab:green", "accelerating": "tab:orange", "plain": "tab:blue", "D*": "tab:gray"}
    for row, (key, name) in enumerate([("ms_median", "median"), ("ms_p95", "95th percentile")]):
        for ax, group in zip(axes[row], groups):
            for s in (s for s in summary if s["group"] == group and s["mean_ratio"] is not None):
                kind = s["setting"].split()[0]
                marker = "o" if "ms" in s["setting"] else ("s" if "K=" in s["setting"] else "*")
                ax.plot(s[key], s["mean_ratio"], marker, color=colours[kind], ms=8 if marker == "*" else 5,
                        alpha=1.0 if s["reached_pct"] == 100 else 0.35)
                ax.annotate(s["setting"].replace("accelerating", "acc.").replace("plain DP", "DP"),
                            (s[key], s["mean_ratio"]), fontsize=5, xytext=(3, 2), textcoords="offset points")
            ax.set_xscale("log")
            ax.set_xlabel(f"planner ms per tick ({name})")
            ax.set_title(group, fontsize=9)
            ax.grid(alpha=0.3)
        axes[row][0].set_ylabel("mean path length / oracle")
    handles = [plt.Line2D([], [], marker="o", ls="", color=c, label=k) for k, c in colours.items()]
    axes[0][-1].legend(handles=handles, fontsize=7, loc="upper right")
    fig.suptitle("equal time: ratio against time per tick (o: budget, s: fixed K, *: unbudgeted; faint: not every "
                 "world reached)", fontsize=9)
    save_figure(fig, path)


def print_summary(summary: list[dict]) -> None:
    """The table of a run's summary (medians to the microsecond: the exact planner's are a few)."""
    print_table(["group", "setting", "worlds", "reached %", "mean ratio", "max ratio", "coll.", "ms median",
                 "ms p95", "ms max", "tick() max ms", "behind %"],
                [[s["group"], s["setting"], str(s["worlds"]), f"{s['reached_pct']:.0f}",
                  "-" if s["mean_ratio"] is None else f"{s['mean_ratio']:.3f}",
                  "-" if s["max_ratio"] is None else f"{s['max_ratio']:.3f}", str(s["collisions"]),
                  f"{s['ms_median']:.3f}", f"{s['ms_p95']:.2f}", f"{s['ms_max']:.1f}", f"{s['tick_max_ms']:.2f}",
                  f"{s['behind_pct']:.0f}"] for s in summary])


def main() -> None:
    args = quick_parser(__doc__).parse_args()
    rows = measure(args.quick)
    summary = summarise(rows)
    print_summary(summary)
    print("the exact planner drove a full converge's trajectory on every world:",
          all(s["exact_is_full_converge"] for s in summary))
    save_results("equal_time-quick" if args.quick else "equal_time",
                 {"summary": summary, "rows": [{k: v for k, v in r.items() if not k.endswith("_ms")} |
                                               {"ms_median": float(np.median(r["total_ms"]))} for r in rows]},
                 lambda png: figure(summary, png))


if __name__ == "__main__":
    main()
