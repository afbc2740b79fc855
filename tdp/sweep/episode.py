"""One episode of a sweep, run where the scheduler puts it: build the world, run the planner, measure."""
from __future__ import annotations

import time

from ..contract import Mode, timing_summary
from ..dstar_lite import DStarLite
from ..config import NavigatorConfig
from ..planners import make_planner
from ..simulate import oracle, run_planner, start_grid
from .spec import EpisodeSpec, config_planner, metric_function

#: The row's metrics that are measured times: they vary from run to run; every other value of a row is
#: deterministic (unless the config sets budget_ms, which trades iterations for time).
TIMED = ("setup_s", "ms_median", "ms_mean", "ms_p95", "ms_max")


def measure_episode(episode: EpisodeSpec) -> dict:
    """Run ``episode``; return its row: key, the world's coordinates, the planner, its ``config`` (a dict), the
    metrics (lengths in cells, times in seconds for setup and in milliseconds per tick) and any extra metrics."""
    scenario = episode.world.build()
    config = NavigatorConfig(planner=config_planner(episode.planner), **episode.config)
    began = time.perf_counter()
    planner = _planner(episode.planner, scenario, config)
    setup_s = time.perf_counter() - began
    record = run_planner(scenario, planner, config, scenario.tick_limit)
    modes = record["modes"]
    per_tick = timing_summary([sum(r.timings.values()) for r in record["results"]])
    row = {"key": episode.key, **episode.world.coords, "planner": episode.planner, "config": episode.config,
           "reached": bool(record["reached"]), "ticks": record["ticks"], "length": record["length"],
           "collisions": record["collisions"], "hits": record["hits"],
           "waits": sum(m == Mode.WAIT for m in modes), "yields": sum(m == Mode.YIELD for m in modes),
           "backup_ticks": sum(m == Mode.BACKUP for m in modes),
           "detections": sum(len(r.detections) for r in record["results"]),
           "relevant_detections": sum(d.relevant for r in record["results"] for d in r.detections),
           "behind_ticks": sum(m == Mode.BEHIND for m in modes),
           "nodes_placed": len(planner.nodes) if episode.planner == "accelerating" else None,
           "setup_s": setup_s, **{f"ms_{name}": value for name, value in per_tick.items()}}
    for name in episode.metrics:
        row.update(metric_function(name)(scenario, record, planner, config))
    return row


def _planner(kind: str, scenario, config: NavigatorConfig):
    """The planner of ``kind`` on the scenario's map at tick 0, set up (its kernels compiled: no JIT in a tick)."""
    if kind == "oracle":
        return oracle(start_grid(scenario), scenario.start, scenario.goal, config)
    if kind == "dstar-lite":
        return DStarLite(scenario.occupancy(0), scenario.start, scenario.goal, config.neighbourhood,
                         config.corner_cutting, cost=scenario.grid.cost)
    planner = make_planner(start_grid(scenario), scenario.start, scenario.goal, config)
    planner.setup()
    return planner
