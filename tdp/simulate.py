"""Grid-level episodes: the world, the navigator and the robot, tick by tick; the oracle baseline; metrics."""
from __future__ import annotations

import math
import sys
from dataclasses import dataclass, field
from typing import Callable

import numpy as np

from . import checks
from .config import NavigatorConfig
from .contract import Mode, Planner, WorldFeed, detection_records, landmarks, timing_summary
from .exact import ExactPlanner
from .grid import GridMap
from .planners import make_planner
from .stencil import moves
from .world import Scenario, box_distance


@dataclass
class Episode:
    """Metrics of one run (ARCHITECTURE §6). Lengths are in cells; timings in milliseconds per tick (median, mean, p95,
    max; the kernels are compiled in the setup phase, before the first tick). ``ratio``: the length over the
    oracle's, nan unless both reached the goal; ``oracle_length`` is nan where the oracle did not reach it
    (``oracle_reached``: no way on the map as it went, within the ticks). ``collisions``: ticks whose move the world
    refused (into or across a cell occupied at that tick); ``hits``: ticks on which a box covered the robot's cell or,
    faster than a cell a tick, passed over it on its way since the tick before (:meth:`Scenario.jumped_over`)."""

    scenario: str
    config: dict
    reached: bool
    ticks: int
    length: float
    oracle_reached: bool
    oracle_length: float
    ratio: float
    collisions: int
    hits: int
    iterations: int
    detections: list[dict]
    trajectory: list[tuple[int, int]]
    modes: list[Mode]
    target_path: list[tuple[int, int]]
    oracle_trajectory: list[tuple[int, int]]
    nodes: list[tuple[int, int]]
    edges: list[tuple[int, int]]
    closest_approach: float | None
    turn_point: tuple[int, int] | None
    switch_back_point: tuple[int, int] | None
    backups: list[dict] = field(default_factory=list)  # {"tick", "path" (node ids; R = n, G = n + 1), "cost"}
    timings: dict = field(default_factory=dict)

    def to_dict(self) -> dict:
        return {k: v for k, v in self.__dict__.items()}


def _allowed_moves(config: NavigatorConfig) -> dict:
    return {(m.dr, m.dc): m for m in moves(config.neighbourhood, config.corner_cutting)}


def _legal(move_table: dict, occupied: np.ndarray, here, there) -> bool:
    """Independent check of a move: a stencil move into a free cell, crossing only free cells."""
    move = move_table.get((there[0] - here[0], there[1] - here[1]))
    if move is None or occupied[there]:
        return False
    return all(not occupied[here[0] + dr, here[1] + dc] for dr, dc in move.crossed)


def run_planner(scenario: Scenario, planner: Planner, config: NavigatorConfig, max_ticks: int, on_tick=None) -> dict:
    """Drive ``planner`` (any :class:`~tdp.contract.Planner`: a :class:`~tdp.navigator.Navigator`, an
    :class:`~tdp.exact.ExactPlanner`, or a baseline such as D* Lite) through the scenario, tick by tick; returns the
    raw record (trajectory, modes, length in cells, collisions, hits, hit_events - the runs of consecutive hit
    ticks: how often a box drove onto the robot -, ticks, reached, the planner's TickResults, the target's path).

    ``config`` gives the stencil the moves are checked against. Each TickResult's ``timings["update"]`` is the time
    the planner spent taking the tick's map and goal changes (its update_map and set_goal; building the world's
    map and finding the changed cells is the world's cost, not the planner's, and is left out).
    """
    table = _allowed_moves(config)
    robot, target = scenario.start, scenario.goal
    feed = WorldFeed(scenario.occupancy(0), target)
    record = {"trajectory": [robot], "modes": [], "length": 0.0, "collisions": 0, "hits": 0, "hit_events": 0,
              "ticks": 0, "reached": robot == target, "results": [], "target_path": [target]}
    was_hit = False
    for tick in range(1, max_ticks + 1):
        if record["reached"]:
            break
        occupied, target = scenario.occupancy(tick), scenario.target(tick)
        if feed.update(planner, occupied, target):
            record["target_path"].append(target)
        hit = bool(occupied[robot] or scenario.jumped_over(tick, robot))
        record["hits"] += hit
        record["hit_events"] += hit and not was_hit
        was_hit = hit
        result = planner.tick()
        result.timings["update"] = feed.planner_s
        wanted = result.next_cell
        if wanted is not None and not (occupied[robot] and scenario.holds(tick, robot)):
            if _legal(table, occupied & ~scenario.parked_over(tick, robot), robot, wanted):
                record["length"] += math.dist(robot, wanted)
                robot = wanted
            else:
                record["collisions"] += 1
        planner.move_robot(robot)
        record["trajectory"].append(robot)
        record["modes"].append(result.mode)
        record["results"].append(result)
        record["ticks"] = tick
        record["reached"] = robot == target
        if on_tick:
            on_tick(tick, robot)
    return record


def simulate(scenario: Scenario, config: NavigatorConfig = NavigatorConfig(), max_ticks: int | None = None,
             progress: bool = False) -> Episode:
    """Run ``scenario`` with the planner of ``config`` (:func:`tdp.make_planner`) and with the oracle; return the
    Episode's metrics.

    Each tick: the world moves (obstacles, target), the planner plans (the exact planner repairs; the DP planners
    run K iterations and their monitor), then the robot makes one stencil move, unless that cell is occupied.
    ``max_ticks`` defaults to the scenario's (or 4 (H + W)). ``progress`` prints a line every 25 ticks to stderr.
    """
    if not isinstance(scenario, Scenario):
        raise ValueError(f"scenario must be a tdp.Scenario, got {type(scenario).__name__}")
    if not isinstance(config, NavigatorConfig):
        raise ValueError(f"config must be a tdp.NavigatorConfig, got {type(config).__name__}")
    limit = checks.optional_integer(max_ticks, "max_ticks", 1)
    if limit is None:
        limit = scenario.tick_limit
    report = _progress(scenario.name) if progress else None
    navigator = make_planner(start_grid(scenario), scenario.start, scenario.goal, config)
    navigator.setup()
    nodes = [tuple(map(int, c)) for c in navigator.nodes]
    edges = navigator.node_edges()
    record = run_planner(scenario, navigator, config, limit, report)

    oracle_record = oracle_run(scenario, config, limit)
    return _episode(scenario, config, navigator, record, oracle_record, nodes, edges)


def oracle_config(config: NavigatorConfig) -> NavigatorConfig:
    """The oracle of a config: the exact planner, unbudgeted, on the same stencil and ``d_max``."""
    return NavigatorConfig(planner="exact", neighbourhood=config.neighbourhood, corner_cutting=config.corner_cutting,
                           d_max=config.d_max)


def oracle(grid: GridMap, start: tuple[int, int], goal: tuple[int, int], config: NavigatorConfig) -> ExactPlanner:
    """The oracle, set up: the robot with exact distances every tick (:func:`oracle_config`'s planner)."""
    planner = ExactPlanner(grid, start, goal, oracle_config(config))
    planner.setup()
    return planner


def oracle_run(scenario: Scenario, config: NavigatorConfig, max_ticks: int) -> dict:
    """The oracle's run of ``scenario``: a dict with its ``length`` (cells), ``trajectory``, ``reached``, ``ticks``."""
    return run_planner(scenario, oracle(start_grid(scenario), scenario.start, scenario.goal, config), config,
                       max_ticks)


def start_grid(scenario: Scenario) -> GridMap:
    """The scenario's map as it stands at tick 0 (its obstacles at their first positions), with its costs."""
    return GridMap(scenario.occupancy(0), scenario.grid.resolution, scenario.grid.origin, scenario.grid.cost)


def _progress(name: str) -> Callable[[int, tuple[int, int]], None]:
    """A progress report for a run of world ``name``: a line on stderr every 25 ticks."""
    def report(tick: int, robot: tuple[int, int]) -> None:
        if tick % 25 == 0:
            print(f"  [{name}] tick {tick}: robot at {robot}", file=sys.stderr, flush=True)
    return report


def _ratio(record: dict, oracle_record: dict) -> float:
    """The length travelled over the oracle's: nan unless both reached the goal (as a sweep's tables have it), 1
    where both reached it without moving."""
    if not (record["reached"] and oracle_record["reached"]):
        return math.nan
    return record["length"] / oracle_record["length"] if oracle_record["length"] > 0 else 1.0


def _episode(scenario, config, navigator, record, oracle_record, nodes, edges) -> Episode:
    results = record["results"]
    detections = detection_records(results)
    for d in detections:
        d["delay_iterations"] = (None if scenario.change_tick is None
                                 else d["iteration"] - scenario.change_tick * config.updates_per_move)
        d["robot"] = list(record["trajectory"][d["tick"] - 1])
    turn_tick, back_tick = landmarks(results)
    turn = record["trajectory"][turn_tick - 1] if turn_tick else None
    back = record["trajectory"][back_tick] if back_tick else None
    closest = None
    if scenario.blocking is not None:
        obstacle = scenario.obstacles[scenario.blocking]
        distances = [box_distance(cell, obstacle.footprint(tick)) for tick, cell in enumerate(record["trajectory"])
                     if obstacle.present(tick)]
        closest = min(distances) if distances else None
    ratio = _ratio(record, oracle_record)
    phases = dict.fromkeys(name for r in results for name in r.timings)
    timings = {name: timing_summary([r.timings.get(name, 0.0) for r in results]) for name in phases}
    timings["total"] = timing_summary([sum(r.timings.values()) for r in results])
    return Episode(
        scenario=scenario.name, config=config.to_dict(), reached=record["reached"], ticks=record["ticks"],
        length=record["length"], oracle_reached=oracle_record["reached"],
        oracle_length=oracle_record["length"] if oracle_record["reached"] else math.nan, ratio=ratio,
        collisions=record["collisions"], hits=record["hits"], iterations=navigator.engine.iterations,
        detections=detections, trajectory=record["trajectory"], modes=record["modes"],
        target_path=record["target_path"], oracle_trajectory=oracle_record["trajectory"], nodes=nodes, edges=edges,
        closest_approach=closest, turn_point=turn, switch_back_point=back, timings=timings,
        backups=[{"tick": tick, "path": r.backup_path, "cost": r.backup_cost}
                 for tick, r in enumerate(results, start=1) if r.backup_path is not None])
