"""Shared helpers of the benchmark scripts: timing, machine description, result files."""
from __future__ import annotations

import json
import math
import os
import platform
import statistics
import time
from pathlib import Path
from typing import Callable


RESULTS = Path(__file__).parent / "results"


def median_time(run: Callable[[], object], repeats: int, warmup: int = 1) -> float:
    """Median wall time in seconds of ``repeats`` calls, after ``warmup`` untimed calls (JIT, caches)."""
    for _ in range(warmup):
        run()
    times = []
    for _ in range(repeats):
        began = time.perf_counter()
        run()
        times.append(time.perf_counter() - began)
    return statistics.median(times)


def machine() -> dict:
    """What the numbers were measured on."""
    cpu = "unknown"
    try:
        for line in Path("/proc/cpuinfo").read_text().splitlines():
            if line.startswith("model name"):
                cpu = line.split(":", 1)[1].strip()
                break
    except OSError:
        pass
    return {"cpu": cpu, "cores": os.cpu_count(), "python": platform.python_version(),
            "date": time.strftime("%Y-%m-%d")}


def save_results(name: str, payload: dict, figure: Callable[[Path], object]) -> Path:
    """Write ``payload`` (with the machine) as results/<name>.json, then the figure drawn by ``figure(png_path)``
    beside it - the JSON first, so that a failing figure loses no result - and print both paths."""
    path = write_json(name, {"machine": machine(), **payload})
    figure(path.with_suffix(".png"))
    print(f"wrote {path} and {path.with_suffix('.png')}")
    return path


def write_json(name: str, payload: dict) -> Path:
    RESULTS.mkdir(parents=True, exist_ok=True)
    path = RESULTS / f"{name}.json"
    path.write_text(json.dumps(payload, indent=2))
    return path


def quick_parser(doc: str):
    """The command line every benchmark script takes: --quick for a smoke run of under a minute."""
    import argparse

    parser = argparse.ArgumentParser(description=doc, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--quick", action="store_true", help="a smoke run of under a minute")
    return parser


def print_table(headers: list[str], rows: list[list[str]]) -> None:
    widths = [max(len(h), *(len(r[i]) for r in rows)) for i, h in enumerate(headers)]
    print("| " + " | ".join(h.ljust(w) for h, w in zip(headers, widths)) + " |")
    print("|" + "|".join("-" * (w + 2) for w in widths) + "|")
    for row in rows:
        print("| " + " | ".join(c.rjust(w) for c, w in zip(row, widths)) + " |")


def run_navigator(scenario, config, max_ticks: int | None = None) -> tuple[dict, object]:
    """One grid-level run of a Navigator (setup, then the tick loop); returns (record, navigator)."""
    import tdp
    from tdp.simulate import run_planner

    navigator = tdp.Navigator(tdp.GridMap(scenario.occupancy(0)), scenario.start, scenario.goal, config)
    navigator.setup()
    record = run_planner(scenario, navigator, config, max_ticks or scenario.max_ticks)
    return record, navigator


def unblocked_route(scenario) -> list[tuple[int, int]]:
    """The oracle's route through the scenario without its blocking obstacle: the way every planner drives
    until the blockage tells it otherwise."""
    import tdp
    from tdp.simulate import oracle_run

    others = [o for k, o in enumerate(scenario.obstacles) if k != scenario.blocking]
    free = tdp.Scenario(scenario.grid, scenario.start, scenario.goal, obstacles=others, name=scenario.name)
    return oracle_run(free, tdp.NavigatorConfig(), scenario.max_ticks)["trajectory"]


def blockage_metrics(scenario, record: dict, oracle_length: float, route: list[tuple[int, int]]) -> dict:
    """Ratio to the oracle; ticks from the change to the turn (the first tick at which the robot leaves
    ``route``, the way it would have gone without the blockage); the closest approach to the blocking box (cells)
    after the change; planner time per tick (ms: median, mean, p95, max; map update, DP, monitor and search
    together)."""
    from tdp.contract import timing_summary
    from tdp.world import box_distance

    box = scenario.obstacles[scenario.blocking]
    approach = [box_distance(cell, box.footprint(tick)) for tick, cell in enumerate(record["trajectory"])
                if tick >= scenario.change_tick and box.present(tick)]
    closest = min(approach) if approach else math.nan
    trajectory = record["trajectory"]
    turn = next((t for t in range(scenario.change_tick, len(trajectory))
                 if t >= len(route) or trajectory[t] != route[t]), len(trajectory))
    per_tick = timing_summary([sum(r.timings.values()) for r in record["results"]])
    return {"reached": record["reached"], "ticks": record["ticks"], "length": record["length"],
            "ratio": record["length"] / oracle_length, "turn_after": turn - scenario.change_tick,
            "closest": closest, **{f"ms_{name}": value for name, value in per_tick.items()}}
