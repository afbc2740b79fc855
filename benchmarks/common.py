"""Shared helpers of the benchmark scripts: timing, machine description, result files."""
from __future__ import annotations

import gc
import json
import math
import os
import platform
import statistics
import time
from pathlib import Path
from typing import Callable


RESULTS = Path(__file__).parent / "results"
SPECS = Path(__file__).parent / "specs"


def freeze_heap() -> None:
    """Move every object alive now out of the garbage collector's reach (``gc.freeze``), as a real-time control
    loop in Python does after its setup: a full collection of this process's heap (Taichi, the maps, the worlds)
    takes 30-40 ms, and one falling inside a tick was the longest tick of a run (nav2's warehouse, seed 2)."""
    gc.collect()
    gc.freeze()


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


def paired_times(first: Callable[[], object], second: Callable[[], object], repeats: int,
                 warmup: int = 1) -> tuple[float, float, float]:
    """Medians (seconds) of ``repeats`` calls of ``first`` and of ``second`` timed in turn, and the median of the
    per-pair ratios first / second, after ``warmup`` untimed calls of each. This VM's speed drifts over seconds:
    the two of a pair run at the same speed, so the ratio of each pair keeps the drift out."""
    for _ in range(warmup):
        first()
        second()
    pairs = []
    for _ in range(repeats):
        pair = []
        for run in (first, second):
            began = time.perf_counter()
            run()
            pair.append(time.perf_counter() - began)
        pairs.append(pair)
    return (statistics.median(a for a, _ in pairs), statistics.median(b for _, b in pairs),
            statistics.median(a / b for a, b in pairs))


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


def sweep_parser(doc: str, workers_default: str):
    """The command line of a benchmark that is a sweep spec: --quick, --workers N (a local Dask cluster),
    --resume (keep the journal of an interrupted run instead of measuring afresh)."""
    parser = quick_parser(doc)
    parser.add_argument("--workers", type=int, default=None,
                        help=f"worker processes of a local Dask cluster (default: {workers_default})")
    parser.add_argument("--resume", action="store_true",
                        help="finish an interrupted run: keep the episodes its journal holds")
    return parser


def run_spec(name: str, args, serial: bool) -> tuple:
    """Run ``specs/<name>.yaml`` (``<name>-quick.yaml`` with --quick) through tdp.sweep into
    ``results/sweeps/<spec name>/`` (the journal, episodes.csv, summary.csv, ratio.png), afresh unless --resume;
    ``serial`` unless --workers is given. Returns (spec, the journal's rows, the tidy table, in the same order)."""
    from tdp.sweep import JOURNAL, load_spec, run_sweep, write_report
    from tdp.sweep.report import tidy

    spec = load_spec(SPECS / f"{name}{'-quick' if args.quick else ''}.yaml")
    out = RESULTS / "sweeps" / spec.name
    out.mkdir(parents=True, exist_ok=True)
    if not args.resume:
        (out / JOURNAL).unlink(missing_ok=True)
    rows = run_sweep(spec, out, workers=args.workers, serial=serial and args.workers is None)
    write_report(spec, rows, out)
    return spec, rows, tidy(spec, rows)


#: Table columns (header, cell) of every world-benchmark summary row: how the runs ended.
OUTCOME_COLUMNS = [("worlds", lambda s: str(s["worlds"])), ("reached %", lambda s: f"{s['reached_pct']:.0f}"),
                   ("coll.", lambda s: str(s["collisions"])), ("hits", lambda s: str(s["hits"])),
                   ("mean ratio", lambda s: f"{s['mean_ratio']:.3f}"), ("max ratio", lambda s: f"{s['max_ratio']:.3f}")]
#: Blockage detections and the share the exact pair distances justify.
DETECTION_COLUMNS = [("detections", lambda s: str(s.get("detections", "-"))),
                     ("justified", lambda s: f"{s['justified'] / s['detections']:.0%}" if s.get("detections") else "-")]


def sweep_benchmark(doc: str, name: str, summarise: Callable[[list[dict]], list[dict]],
                    columns: list[tuple[str, Callable[[dict], str]]], figure: Callable, extra: dict | None = None,
                    held_out: str | None = None):
    """The main of a benchmark that is a sweep spec: run ``specs/<name>.yaml`` (on a local cluster unless
    --workers says otherwise), print ``summarise(table)`` as a table of ``columns`` (header, cell of a summary row),
    and save the spec's name, ``extra``, the summary and the tidy table as JSON with ``figure(summary, png)``.
    --quick runs serially in this process unless --workers is given (a smoke run: a cluster's workers would each
    compile the kernels for a few episodes). With ``held_out`` (what it holds, for --help), --held-out runs
    ``specs/<name>-held-out.yaml`` instead: worlds of seeds the benchmark's rules were not tuned on."""
    parser = sweep_parser(doc, "one per core; serially with --quick")
    if held_out:
        parser.add_argument("--held-out", action="store_true", help=f"run {name}-held-out.yaml: {held_out}")
    args = parser.parse_args()
    spec, _, table = run_spec(f"{name}-held-out" if getattr(args, "held_out", False) else name, args,
                              serial=args.quick)
    summary = summarise(table)
    print_table([header for header, _ in columns], [[cell(s) for _, cell in columns] for s in summary])
    save_results(spec.name, {"spec": f"benchmarks/specs/{spec.name}.yaml", **(extra or {}), "summary": summary,
                             "rows": table}, lambda png: figure(summary, png))


def seconds_bars(path, labels: list[str], seconds: list[float], colours: list[str], xlabel: str, title: str,
                 digits: int = 1) -> None:
    """A figure of one horizontal bar per label at its seconds, each bar's time written beside it."""
    from tdp.plot import pyplot, save_figure

    plt = pyplot()
    fig, ax = plt.subplots(figsize=(5, 3))
    ax.barh(labels, seconds, color=colours)
    for y, value in enumerate(seconds):
        ax.text(value, y, f" {value:.{digits}f} s", va="center", fontsize=8)
    ax.set_xlabel(xlabel)
    ax.set_title(title, fontsize=9)
    save_figure(fig, path)


def grouped_bars(ax, groups: list[str], series: dict[str, list[float]]) -> None:
    """One bar per series side by side over each group, the groups named below and the series in a legend."""
    import numpy as np

    width = 0.8 / len(series)
    for j, (label, values) in enumerate(series.items()):
        ax.bar(np.arange(len(groups)) + j * width, values, width, label=label)
    ax.set_xticks(np.arange(len(groups)) + 0.4 - width / 2)
    ax.set_xticklabels(groups, rotation=20, fontsize=8)
    ax.legend(fontsize=7)


def print_table(headers: list[str], rows: list[list[str]]) -> None:
    widths = [max(len(h), *(len(r[i]) for r in rows)) for i, h in enumerate(headers)]
    print("| " + " | ".join(h.ljust(w) for h, w in zip(headers, widths)) + " |")
    print("|" + "|".join("-" * (w + 2) for w in widths) + "|")
    for row in rows:
        print("| " + " | ".join(c.rjust(w) for c, w in zip(row, widths)) + " |")


def run_navigator(scenario, config, max_ticks: int | None = None) -> tuple[dict, object]:
    """One grid-level run of the planner ``config`` names (setup, then the tick loop); returns (record, planner)."""
    import tdp
    from tdp.simulate import run_planner

    navigator = tdp.make_planner(tdp.GridMap(scenario.occupancy(0)), scenario.start, scenario.goal, config)
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
    """Ratio to the oracle, :func:`turn_and_closest`, and planner time per tick (ms: median, mean, p95, max; map
    update, DP, monitor and search together)."""
    from tdp.contract import timing_summary

    per_tick = timing_summary([sum(r.timings.values()) for r in record["results"]])
    return {"reached": record["reached"], "ticks": record["ticks"], "length": record["length"],
            "ratio": record["length"] / oracle_length, **turn_and_closest(scenario, record["trajectory"], route),
            **{f"ms_{name}": value for name, value in per_tick.items()}}


_UNBLOCKED_ROUTES: dict[str, list] = {}


def turn_against_unblocked(scenario, trajectory: list) -> dict:
    """:func:`turn_and_closest` against the scenario's :func:`unblocked_route`, found once per scenario name and
    process (sweep metrics run once per episode)."""
    if scenario.name not in _UNBLOCKED_ROUTES:
        _UNBLOCKED_ROUTES[scenario.name] = unblocked_route(scenario)
    return turn_and_closest(scenario, trajectory, _UNBLOCKED_ROUTES[scenario.name])


def turn_and_closest(scenario, trajectory: list, route: list[tuple[int, int]]) -> dict:
    """Ticks from the change to the turn (the first tick at which the robot leaves ``route``, the way it would
    have gone without the blockage) and the closest approach to the blocking box (cells) after the change."""
    from tdp.world import box_distance

    box = scenario.obstacles[scenario.blocking]
    approach = [box_distance(tuple(cell), box.footprint(tick)) for tick, cell in enumerate(trajectory)
                if tick >= scenario.change_tick and box.present(tick)]
    turn = next((t for t in range(scenario.change_tick, len(trajectory))
                 if t >= len(route) or tuple(trajectory[t]) != route[t]), len(trajectory))
    return {"turn_after": turn - scenario.change_tick, "closest": min(approach) if approach else math.nan}
