"""Graded costs: converge and repair on a cost grid against the same map binary, and against scipy's Dijkstra on the
weighted graph.

    python -m benchmarks.costs [--quick] [--dear | --edits]

--dear: the dear-corridor table alone (results/costs-dear.json); --edits: the edits' table alone
(results/costs-edits.json).

For each map, a goal in its largest free region and two kinds of cost: ``inflation`` (nav2's inflation layer's
shape: 1 + 49 exp(-0.3 (d - 1)) at d cells from the nearest obstacle, a steep gradient near walls) and ``random``
(uniform 1-10, every cell its own). Timed in pairs with the binary map (median of the pairs' ratios, warm): the
from-scratch converge (a search) and the repair after a 3 x 3 box on the weighted optimal route from the farthest
reachable cell (the same cells on both maps); the weighted field is checked against scipy's float64 Dijkstra on the
weighted graph (relative 1e-4: float32 sums over long routes). Then the paths: on the ROS maps, how much farther
from the walls a path keeps with nav2's inflation cost than on the binary map, and at what length - for converged
fields, for every planner driving through shuttling boxes at grid level (EPISODE_PAIRS pairs a map, the same boxes
on both maps), and in PyBullet (the named scenarios and the TurtleBot3 world, the inflation cost round walls and
boxes: ``SimConfig(cost_scaling_factor, inflation_radius)``).

Dear cells: a hall joined to a room by a corridor whose cells cost ``DEAR_COSTS`` (1 to 1e6), so that the room's
distances reach 2**24 and past, where float32 stops telling a move of 1 apart (ARCHITECTURE §4): the converge from
scratch against scipy's Dijkstra solve on the same weighted graph (timed in turn), the largest distance, whether the
field equals Dijkstra's, and the repair after a 3 x 3 box in the room.

Edits on cost grids: every repair of ``benchmarks.convergence`` (a box, a wall, a pocket sealed and opened, the goal
sealed in, let out and in a room, a goal move, noise, eight boxes) on a random map, a maze with 1-cell corridors, a
cave map and the ROS maps, each with both kinds of cost, against a fresh field's from-scratch converge on the same
cost grid (``measure_repair``: the edit and its converge over the fresh converge, the median of the pairs' ratios),
and whether the repaired field is bit-equal to the fresh one.
"""
from __future__ import annotations

import math
import time

import numpy as np
from scipy import ndimage
from scipy.sparse.csgraph import dijkstra

import tdp
from benchmarks.common import machine, paired_times, print_table, quick_parser, save_results, write_json
from tdp.engine import ABSORBING
from benchmarks import convergence
from benchmarks.convergence import NAV2, ROBOT_RADIUS_M, ROOT, largest_free_region, ros_cases, route_middle
from benchmarks.reference_graph import grid_graph
from tdp.random_worlds import maze

REPEATS, QUICK_REPEATS = 7, 3
EPISODE_PAIRS = 3
GRID_PLANNERS = ("exact", "accelerating", "plain-dp", "dstar-lite")
#: The largest side (cells) of a map the planner episodes run on: D* Lite is Python, and the warehouse (1674 x 1006)
#: would take it hours; the converged fields' paths above cover the warehouse.
EPISODE_MAX_SIDE = 700
DSTAR_MAX_SIDE = 400
NAV2_INFLATION = {"cost_scaling_factor": 3.0, "inflation_radius": 1.05}  # per metre, metres
ROS_MAPS = [("turtlebot3_world", ROOT / "tests" / "data" / "turtlebot3_world" / "map.yaml"),
            ("nav2 warehouse", NAV2 / "warehouse.yaml"), ("nav2 depot", NAV2 / "depot.yaml")]
PAIRS = 8
EQUAL_RTOL = 1e-4
DEAR_COSTS = [1.0, 1e2, 1e4, 1e5, 1e6]  # a corridor cell's cost (``dear_rows``)


def maps(quick: bool) -> list[tuple[str, np.ndarray, tuple[int, int]]]:
    """(name, occupied, goal): random maps, a maze, MovingAI's den312d and the ROS maps (inflated by the robot)."""
    sizes = [64] if quick else [256, 512]
    cases = []
    for size in sizes:
        occupied = np.random.default_rng(size).random((size, size)) < 0.2
        cases.append((f"random {size}²", occupied, _free_cell(occupied, size)))
    if not quick:
        occupied = maze(256, 2, seed=7)
        cases.append(("maze 256² (2-cell corridors)", occupied, _free_cell(occupied, 7)))
        den = tdp.load_map("tests/data/den312d.map").occupied
        cases.append(("den312d", den, _free_cell(den, 3)))
        cases += [case for case in ros_cases() if case[0].endswith("#0")]
    return cases


def _free_cell(occupied: np.ndarray, seed: int) -> tuple[int, int]:
    free = np.argwhere(~occupied)
    return tuple(int(v) for v in free[np.random.default_rng(seed).integers(len(free))])


def costs(occupied: np.ndarray, kind: str) -> np.ndarray:
    """The cost grid of ``kind`` on the map (distances to obstacles from scipy's exact Euclidean transform)."""
    if kind == "inflation":
        away = ndimage.distance_transform_edt(~occupied)
        return 1.0 + 49.0 * np.exp(-0.3 * np.maximum(away - 1.0, 0.0))
    return 1.0 + 9.0 * np.random.default_rng(occupied.size).random(occupied.shape)


def edited_costs(occupied: np.ndarray, kind: str) -> np.ndarray:
    """The cost grid of ``kind`` (``costs``) with 1 on the map's obstacles, as ``GridMap`` keeps them: a field
    built on it and one edited into the same map agree on what a freed cell costs."""
    cost = costs(occupied, kind)
    cost[occupied] = 1.0
    return cost


def measure(name: str, occupied: np.ndarray, goal, kind: str, repeats: int) -> dict:
    binary = tdp.DistanceField(tdp.GridMap(occupied), goal)
    grid = tdp.GridMap(occupied, cost=costs(occupied, kind))
    weighted = tdp.DistanceField(grid, goal)
    for field in (binary, weighted):
        field.converge()

    def scratch(field):
        return lambda: (field.reset(), field.converge())

    weighted_s, binary_s, scratch_ratio = paired_times(scratch(weighted), scratch(binary), repeats)
    reference = dijkstra(grid_graph(occupied, cost=grid.cost).T, indices=goal[0] * occupied.shape[1] + goal[1])
    reference = reference.reshape(occupied.shape)
    equal = equal_to_dijkstra(weighted.distances(), reference)
    repair_ratio, repair_ms = repair_pairs(binary, weighted, repeats)
    return {"map": name, "cost": kind, "cells": occupied.size, "scratch_ms": weighted_s * 1e3,
            "binary_scratch_ms": binary_s * 1e3, "scratch_ratio": scratch_ratio, "repair_ms": repair_ms,
            "repair_ratio": repair_ratio, "equal": equal}


def equal_to_dijkstra(ours: np.ndarray, reference: np.ndarray) -> bool:
    """Whether a field is inf where scipy's Dijkstra is and within EQUAL_RTOL of it elsewhere."""
    finite = np.isfinite(reference)
    return bool(np.array_equal(np.isfinite(ours), finite)
                and np.allclose(ours[finite], reference[finite], rtol=EQUAL_RTOL))


def box_repair_s(field: tdp.DistanceField, box: list[tuple[int, int]]) -> float:
    """Seconds of the converge after ``box`` is blocked; the box is then freed and converged again."""
    field.set_occupied(box)
    began = time.perf_counter()
    field.converge()
    took_s = time.perf_counter() - began
    field.set_occupied(box, False)
    field.converge()
    return took_s


def median_box_repair_ms(field: tdp.DistanceField, box: list[tuple[int, int]], repeats: int) -> float:
    """The median ms of ``repeats`` box repairs (``box_repair_s``), after one more as a warm-up."""
    return float(np.median([box_repair_s(field, box) for _ in range(repeats + 1)][1:])) * 1e3


def route_box(field: tdp.DistanceField) -> list[tuple[int, int]]:
    """The free cells (the goal's left out) of a 3 x 3 box on the converged field's optimal route from its farthest
    reachable cell, at the route's middle."""
    (r, c), _ = route_middle(field, field.distances())
    rows, cols = field.occupied.shape
    return [(r + i, c + j) for i in (-1, 0, 1) for j in (-1, 0, 1)
            if (r + i, c + j) != field.goal and 0 <= r + i < rows and 0 <= c + j < cols
            and not field.occupied[r + i, c + j]]


def repair_pairs(binary: tdp.DistanceField, weighted: tdp.DistanceField, repeats: int) -> tuple[float, float]:
    """The median ratio weighted / binary of the same edit's repair - a 3 x 3 box on the weighted field's optimal
    route from its farthest reachable cell (``route_box``) - timed in turn, and the weighted repair's median in ms."""
    box = route_box(weighted)
    ratios, times = [], []
    for _ in range(repeats + 1):
        pair = [box_repair_s(field, box) for field in (weighted, binary)]
        ratios.append(pair[0] / pair[1])
        times.append(pair[0])
    return float(np.median(ratios[1:])), float(np.median(times[1:])) * 1e3


def dear_corridor(rows: int, dear: float) -> tuple[tdp.GridMap, tuple[int, int]]:
    """A hall (rows x 5/3 rows, the goal at the middle of its left side) joined to a room (rows x rows / 2) by a
    corridor of rows / 3 cells, each costing ``dear``; the rest costs 1."""
    hall, corridor, room = 5 * rows // 3, rows // 3, rows // 2
    occupied = np.zeros((rows, hall + corridor + room), bool)
    cost = np.ones(occupied.shape)
    occupied[:, hall:hall + corridor] = True
    occupied[rows // 2, hall:hall + corridor] = False
    cost[rows // 2, hall:hall + corridor] = dear
    return tdp.GridMap(occupied, cost=cost), (rows // 2, 2)


def dear_rows(quick: bool, repeats: int) -> list[dict]:
    """Per corridor cost: converge from scratch against scipy's Dijkstra solve, in turn; the largest distance;
    the field against Dijkstra's (EQUAL_RTOL); the repair after a 3 x 3 box in the middle of the room."""
    rows_cells = 60 if quick else 120
    out = []
    for dear in DEAR_COSTS[::2] if quick else DEAR_COSTS:
        grid, goal = dear_corridor(rows_cells, dear)
        field = tdp.DistanceField(grid, goal)
        field.converge()
        graph = grid_graph(grid.occupied, cost=grid.cost).T.tocsr()
        source = goal[0] * grid.shape[1] + goal[1]
        ours_s, scipy_s, ratio = paired_times(lambda: (field.reset(), field.converge()),
                                              lambda: dijkstra(graph, indices=source), repeats)
        reference = dijkstra(graph, indices=source).reshape(grid.shape)
        largest, equal = float(reference[np.isfinite(reference)].max()), equal_to_dijkstra(field.distances(), reference)
        centre = (rows_cells // 2, grid.shape[1] - rows_cells // 4)
        box = [(centre[0] + i, centre[1] + j) for i in (-1, 0, 1) for j in (-1, 0, 1)]
        out.append({"dear": dear, "cells": grid.occupied.size, "largest": largest,
                    "past_absorbing": largest >= ABSORBING, "scratch_ms": ours_s * 1e3,
                    "dijkstra_ms": scipy_s * 1e3, "ratio": ratio, "equal": equal,
                    "repair_ms": median_box_repair_ms(field, box, repeats)})
        print(f"  dear corridor, cost {dear:g}: done", flush=True)
    return out


def edit_maps(quick: bool) -> list[tuple[str, np.ndarray, tuple[int, int]]]:
    """(name, occupied, goal) of the edits' table: ``benchmarks.convergence``'s random map (64² quick, else 512²)
    with the centre goal; in full its 1-cell maze of 512² (corner goal), cave map of 512² (random goal) and ROS maps
    (turtlebot3's world and nav2's warehouse, the first goal)."""
    if quick:
        return [case for case in convergence.random_cases(64) if case[0].endswith("centre")]
    picks = [(convergence.random_cases(512), "centre"), (convergence.maze_cases(512, 1), "corner"),
             (convergence.caves_cases(512), "random"), (ros_cases(), "#0")]
    return [case for cases, goal in picks for case in cases
            if case[0].endswith(goal) and not case[0].startswith("nav2 depot")]


def edit_rows(quick: bool, repeats: int) -> list[dict]:
    """Every repair kind of ``benchmarks.convergence`` (``REPAIRS``) on each map of :func:`edit_maps` with each kind
    of cost, against a fresh converge on the same cost grid (``measure_repair``; ``edited_costs``)."""
    out = []
    for name, occupied, goal in edit_maps(quick):
        for kind in ("inflation", "random"):
            cost = edited_costs(occupied, kind)
            field = convergence.field_on(occupied, goal, cost=cost)
            field.converge()
            reference = field.distances()
            for edit in convergence.REPAIRS:
                row = convergence.measure_repair(field, edit, reference, repeats, cost=cost)
                out.append({"map": name, "cost": kind, **row})
            print(f"  edits on {name}, {kind}: done", flush=True)
    return out


def print_edits(rows: list[dict]) -> None:
    """The edits' table: a row per map and kind of cost, a column per edit ((edit + converge) / fresh converge)."""
    tables = list(dict.fromkeys((row["map"], row["cost"]) for row in rows))
    print_table(["map", "cost", *convergence.REPAIRS, "all equal"],
                [[name, kind, *(f"{row['ratio']:.2f}" for row in rows if (row["map"], row["cost"]) == (name, kind)),
                  str(all(row["equal"] for row in rows if (row["map"], row["cost"]) == (name, kind)))]
                 for name, kind in tables])


def inflated(grid: tdp.GridMap) -> tuple[tdp.GridMap, tdp.GridMap]:
    """``grid`` inflated by ROBOT_RADIUS_M: binary, and with nav2's inflation cost (NAV2_INFLATION)."""
    radius = ROBOT_RADIUS_M / grid.resolution
    return grid.inflate(radius), grid.inflate(radius, **NAV2_INFLATION)


def ros_worlds(quick: bool, max_side: float = math.inf):
    """(name, binary, costed, away_m, free) for each ROS map (the first only, quick) of at most ``max_side`` cells
    a side: :func:`inflated`'s two maps, the metres from each cell to the nearest obstacle of the map as loaded and
    the cells of the binary map's largest free region."""
    for name, path in ROS_MAPS[:1] if quick else ROS_MAPS:
        grid = tdp.load_map(path)
        if max(grid.shape) <= max_side:
            binary, costed = inflated(grid)
            away_m = ndimage.distance_transform_edt(~grid.occupied) * grid.resolution
            yield name, binary, costed, away_m, largest_free_region(binary.occupied)


def mean_clearance_m(cells: list, away_m: np.ndarray) -> float:
    """The mean of ``away_m`` over ``cells``."""
    return float(np.mean([away_m[tuple(cell)] for cell in cells]))


def clearance(quick: bool) -> list[dict]:
    """On the ROS maps inflated by ROBOT_RADIUS_M, the converged field's path between random pairs of the largest
    free region with nav2's inflation cost (``cost_scaling_factor`` 3 per metre, ``inflation_radius`` 1.05 m)
    against the binary map's: the mean clearance of its cells (metres to the nearest obstacle of the map as loaded)
    and its length, as ratios."""
    rows = []
    for name, binary, costed, away_m, free in ros_worlds(quick):
        rng = np.random.default_rng(1)
        for pair in range(2 if quick else PAIRS):
            start, goal = (tuple(int(v) for v in free[rng.integers(len(free))]) for _ in range(2))
            routes = []
            for which in (binary, costed):
                field = tdp.DistanceField(which, goal)
                field.converge()
                routes.append(field.path(start))
            lengths = [sum(np.hypot(b[0] - a[0], b[1] - a[1]) for a, b in zip(r, r[1:])) for r in routes]
            clear = [mean_clearance_m(r, away_m) for r in routes]
            rows.append({"map": name, "pair": pair, "clearance_ratio": clear[1] / clear[0],
                         "length_ratio": lengths[1] / max(lengths[0], 1e-9), "start": start, "goal": goal})
    return rows


def paths_figure(rows: list[dict], path) -> None:
    """The cost shading of turtlebot3's world with nav2's inflation cost and the two paths of its pair whose
    clearance gained most: on the binary map and on the costed one."""
    from tdp.plot import cost_bar, draw_map, pyplot, save_figure

    name, map_path = ROS_MAPS[0]
    best = max((r for r in rows if r["map"] == name), key=lambda r: r["clearance_ratio"])
    binary, costed = inflated(tdp.load_map(map_path))
    maps = {"path on the binary map": binary, "path with nav2's inflation cost": costed}
    rows_free, cols_free = np.nonzero(~binary.occupied)
    top, bottom, left, right = rows_free.min() - 3, rows_free.max() + 4, cols_free.min() - 3, cols_free.max() + 4
    plt = pyplot()
    fig, ax = plt.subplots(figsize=(6, 6))
    cost_bar(fig, ax, draw_map(ax, binary.occupied, costed.cost))
    for (label, which), colour in zip(maps.items(), ("tab:blue", "black")):
        field = tdp.DistanceField(which, tuple(best["goal"]))
        field.converge()
        route = np.array(field.path(tuple(best["start"])))
        ax.plot(route[:, 1], route[:, 0], "-", color=colour, lw=2, label=label)
    ax.set_xlim(left, right)
    ax.set_ylim(bottom, top)
    ax.legend(loc="lower left", fontsize=8)
    ax.set_title(f"turtlebot3_world: clearance x{best['clearance_ratio']:.2f} at x{best['length_ratio']:.2f} the "
                 "length", fontsize=9)
    save_figure(fig, path)


def grid_episodes(quick: bool) -> list[dict]:
    """Every planner (GRID_PLANNERS) driving through three shuttling boxes on the ROS maps inflated by the robot (of
    at most EPISODE_MAX_SIDE cells a side; D* Lite on those of DSTAR_MAX_SIDE), binary and with nav2's inflation cost
    (the same boxes: they are placed by occupancy): reached, collisions, the trajectory's mean clearance (metres to
    the nearest obstacle of the map as loaded) and its length."""
    from tdp.dstar_lite import DStarLite
    from tdp.random_worlds import boxes_on_map
    from tdp.simulate import run_planner, start_grid

    rows = []
    for name, binary, costed, away_m, free in ros_worlds(quick, EPISODE_MAX_SIDE):
        maps = {"binary": binary, "costed": costed}
        rng = np.random.default_rng(2)
        for pair in range(1 if quick else EPISODE_PAIRS):
            start, goal = (tuple(int(v) for v in free[rng.integers(len(free))]) for _ in range(2))
            for planner in GRID_PLANNERS[:2] if quick else GRID_PLANNERS:
                if planner == "dstar-lite" and max(binary.shape) > DSTAR_MAX_SIDE:
                    continue
                row = {"map": name, "pair": pair, "planner": planner}
                for kind, which in maps.items():
                    world = boxes_on_map(which, start, goal, boxes=3, seed=pair)
                    config = tdp.NavigatorConfig(planner="exact" if planner == "dstar-lite" else planner)
                    if planner == "dstar-lite":
                        driver = DStarLite(world.occupancy(0), start, goal, cost=world.grid.cost)
                    else:
                        driver = tdp.make_planner(start_grid(world), start, goal, config)
                        driver.setup()
                    record = run_planner(world, driver, config, world.tick_limit)
                    row[kind] = {"reached": bool(record["reached"]), "collisions": record["collisions"],
                                 "clearance_m": mean_clearance_m(record["trajectory"], away_m),
                                 "length": record["length"]}
                rows.append(row)
            print(f"  {name} pair {pair}: episodes done", flush=True)
    return rows


def pybullet_episodes(quick: bool) -> list[dict]:
    """The named scenarios and the TurtleBot3 world in PyBullet, exact replanning and accelerating nodes, without
    and with nav2's inflation cost round every grown obstacle (``SimConfig``: 3 per metre, 0.8 m): reached,
    contacts, the closest approach and the mean clearance (to the nearest body, up to 1 m) and the path length."""
    from sim.episode import SimConfig, run_episode

    worlds = [tdp.load_world(ROOT / "examples" / "turtlebot3-world.yaml")]
    worlds += [] if quick else [tdp.scenarios.get(name) for name in tdp.scenarios.names()]
    sims = {"binary": SimConfig(), "costed": SimConfig(cost_scaling_factor=3.0, inflation_radius=0.8)}
    rows = []
    for world in worlds:
        for planner in ("exact", "accelerating"):
            row = {"world": world.name, "planner": planner}
            for kind, sim in sims.items():
                metrics = run_episode(world, tdp.NavigatorConfig(planner=planner), sim)
                row[kind] = {key: metrics[key] for key in ("reached", "contacts", "min_clearance_m",
                                                           "mean_clearance_m", "path_length_m")}
            rows.append(row)
        print(f"  {world.name}: PyBullet done", flush=True)
    return rows


def print_episodes(grid_rows: list[dict], bullet_rows: list[dict]) -> None:
    print_table(["map", "pair", "planner", "reached (binary, costed)", "collisions", "clearance m binary",
                 "costed", "ratio", "length ratio"],
                [[r["map"], str(r["pair"]), r["planner"], f"{r['binary']['reached']}, {r['costed']['reached']}",
                  f"{r['binary']['collisions']}, {r['costed']['collisions']}", f"{r['binary']['clearance_m']:.3f}",
                  f"{r['costed']['clearance_m']:.3f}", f"{r['costed']['clearance_m'] / r['binary']['clearance_m']:.2f}",
                  f"{r['costed']['length'] / max(r['binary']['length'], 1e-9):.2f}"] for r in grid_rows])
    for planner in dict.fromkeys(r["planner"] for r in grid_rows):
        mine = [r for r in grid_rows if r["planner"] == planner]
        print(f"{planner}: mean clearance ratio "
              f"{np.mean([r['costed']['clearance_m'] / r['binary']['clearance_m'] for r in mine]):.2f}, mean length "
              f"ratio {np.mean([r['costed']['length'] / max(r['binary']['length'], 1e-9) for r in mine]):.2f}")
    print_table(["world", "planner", "reached", "contacts", "closest m binary", "costed", "mean clearance m binary",
                 "costed", "ratio", "length ratio"],
                [[r["world"], r["planner"], f"{r['binary']['reached']}, {r['costed']['reached']}",
                  f"{r['binary']['contacts']}, {r['costed']['contacts']}", f"{r['binary']['min_clearance_m']:.3f}",
                  f"{r['costed']['min_clearance_m']:.3f}", f"{r['binary']['mean_clearance_m']:.3f}",
                  f"{r['costed']['mean_clearance_m']:.3f}",
                  f"{r['costed']['mean_clearance_m'] / r['binary']['mean_clearance_m']:.2f}",
                  f"{r['costed']['path_length_m'] / r['binary']['path_length_m']:.2f}"] for r in bullet_rows])


def figure(rows: list[dict], path) -> None:
    from tdp.plot import pyplot, save_figure

    plt = pyplot()
    fig, ax = plt.subplots(figsize=(9, 4))
    labels = [f"{row['map']}\n{row['cost']}" for row in rows]
    x = np.arange(len(rows))
    ax.bar(x - 0.2, [row["scratch_ratio"] for row in rows], 0.4, label="converge from scratch")
    ax.bar(x + 0.2, [row["repair_ratio"] for row in rows], 0.4, label="repair after a 3 x 3 box")
    ax.axhline(1.5, color="tab:red", ls="--", lw=1, label="target 1.5x")
    ax.axhline(1.0, color="0.5", lw=0.8)
    ax.set_xticks(x, labels, fontsize=7, rotation=30, ha="right")
    ax.set_ylabel("time on the cost grid / on the same map binary")
    ax.legend(fontsize=8)
    save_figure(fig, path)


def print_dear(dear: list[dict]) -> None:
    print_table(["corridor cost", "cells", "largest distance", "converge ms", "Dijkstra ms", "ratio",
                 "box repair ms", "equal to scipy"],
                [[f"{r['dear']:g}", str(r["cells"]), f"{r['largest']:.4g}", f"{r['scratch_ms']:.2f}",
                  f"{r['dijkstra_ms']:.2f}", f"{r['ratio']:.2f}", f"{r['repair_ms']:.2f}", str(r["equal"])]
                 for r in dear])


#: The tables the command line may run alone (``--dear``, ``--edits``): how each is measured and printed.
TABLES = {"dear": (dear_rows, print_dear), "edits": (edit_rows, print_edits)}


def table_rows(table: str, quick: bool, repeats: int) -> list[dict]:
    """The rows of one of TABLES, measured and printed."""
    measure_rows, show = TABLES[table]
    rows = measure_rows(quick, repeats)
    show(rows)
    return rows


def main() -> None:
    parser = quick_parser(__doc__)
    alone = parser.add_mutually_exclusive_group()
    alone.add_argument("--dear", action="store_true", help="the dear-corridor table alone")
    alone.add_argument("--edits", action="store_true", help="the edits' table alone")
    args = parser.parse_args()
    repeats = QUICK_REPEATS if args.quick else REPEATS
    for table in TABLES:
        if getattr(args, table):
            rows = table_rows(table, args.quick, repeats)
            name = f"costs-{table}-quick" if args.quick else f"costs-{table}"
            print(f"wrote {write_json(name, {'machine': machine(), table: rows})}")
            return
    rows = []
    for name, occupied, goal in maps(args.quick):
        for kind in ("inflation", "random"):
            rows.append(measure(name, occupied, goal, kind, repeats))
            print(f"  {name}, {kind}: done", flush=True)
    print_table(["map", "cost", "converge ms", "binary ms", "ratio", "repair ms", "ratio", "equal to scipy"],
                [[r["map"], r["cost"], f"{r['scratch_ms']:.2f}", f"{r['binary_scratch_ms']:.2f}",
                  f"{r['scratch_ratio']:.2f}", f"{r['repair_ms']:.2f}", f"{r['repair_ratio']:.2f}", str(r["equal"])]
                 for r in rows])
    dear, edits = (table_rows(table, args.quick, repeats) for table in ("dear", "edits"))
    paths = clearance(args.quick)
    print_table(["map", "pair", "clearance, costed / binary", "length, costed / binary"],
                [[r["map"], str(r["pair"]), f"{r['clearance_ratio']:.2f}", f"{r['length_ratio']:.2f}"] for r in paths])
    for name in dict.fromkeys(r["map"] for r in paths):
        mine = [r for r in paths if r["map"] == name]
        print(f"{name}: mean clearance ratio {np.mean([r['clearance_ratio'] for r in mine]):.2f}, "
              f"mean length ratio {np.mean([r['length_ratio'] for r in mine]):.2f}")
    grid_rows, bullet_rows = grid_episodes(args.quick), pybullet_episodes(args.quick)
    print_episodes(grid_rows, bullet_rows)
    written = save_results("costs-quick" if args.quick else "costs",
                           {"rows": rows, "dear": dear, "edits": edits, "clearance": paths, "grid_episodes": grid_rows,
                            "pybullet_episodes": bullet_rows}, lambda path: figure(rows, path))
    figure_path = written.with_name("costs-paths-quick.png" if args.quick else "costs-paths.png")
    paths_figure(paths, figure_path)
    print(f"wrote {figure_path}")


if __name__ == "__main__":
    main()
