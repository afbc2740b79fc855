"""The engine and its planners on each of Taichi's backends: CUDA against the CPU, on the same machine.

    python -m benchmarks.backends [--quick] [--archs cpu:2,cpu:16,cuda]

--quick: small maps and one small world on cpu:2 and cuda (a machine without CUDA reports that worker as failed).

Each backend (``arch:threads``; the threads count for the CPU only) runs in a worker process of its own (Taichi is
initialised once per process, from TDP_ARCH and TDP_THREADS), warm (every timed call made before it is timed),
medians of repeats:

- iteration: one all-layer DP iteration with every tile relaxed (``benchmarks.kernel.engine_times``), on random maps
  of 512² to 2048² with 0 to 256 accelerating nodes - the paper's planner's work, every cell at once;
- converge: the goal layer from the initial state by the search (Dial's, one serial launch) and by rounds of tiles
  (parallel launches where many tiles are active), and the node layers' setup (rounds of tiles), on random maps and
  a 1-cell maze;
- repair: a 3 x 3 box on the route from the farthest cell, set and converged (a mend: one serial launch), then
  taken away again;
- costs: the goal layer of a weighted map from scratch (the search) and its repair after a 3 x 3 box on the route:
  a random 1024² map with nav2-like inflation costs, and a corridor of cells costing 1e6 whose distances pass 2^24
  (the absorbing kernels, whose moves add at least one float32 step by the value's bits);
- ticks: the exact planner and the accelerating and plain-DP planners at K = 1 on two random worlds of 200², their
  setup and their median and 95th-percentile tick (its map update included); and the same planners, the DP ones at
  K = 8, on a rooms world of 1024² for its first LARGE_TICKS ticks - the size where a dense iteration pays for a
  launch.

Every goal layer a worker converges is compared bit for bit with the first backend's (saved as .npy in a scratch
folder): the result does not depend on the backend. A converge or repair whose projected time on a backend - its timed
calls at the smaller map's time scaled by the cells - passes SERIAL_LIMIT_S is skipped there and said so: one GPU
thread walks a search's buckets, and rounds of tiles are a launch each (a maze's rounds took 48 s a converge on an
H200, where the projection from the random map said 2). Rows go to results/backends[-quick].jsonl as they come, so a
killed run keeps what it measured; then results/backends[-quick].json and a figure of each case's time on each backend
over the first's.
"""
from __future__ import annotations

import argparse
import json
import os
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

from benchmarks.common import RESULTS, median_time, print_table, quick_parser, save_results

ARCHS = ("cpu:2", "cpu:16", "cuda")
QUICK_ARCHS = ("cpu:2", "cuda")
ITERATION_CASES = [(512, 0), (512, 64), (1024, 0), (1024, 256), (2048, 0), (2048, 256)]
CONVERGE_SIZES = (256, 1024)
QUICK_ITERATION_CASES = [(128, 0), (128, 16)]
QUICK_CONVERGE_SIZES = (64, 128)
WORLDS = [("rooms", 200, 0), ("crossing", 200, 0)]
QUICK_WORLDS = [("rooms", 60, 0)]
PLANNERS = [("exact", {"planner": "exact"}), ("accelerating K=1", {"planner": "accelerating", "updates_per_move": 1}),
            ("plain DP K=1", {"planner": "plain-dp", "updates_per_move": 1})]
LARGE_WORLDS = [("rooms", 1024, 0)]
QUICK_LARGE_WORLDS = [("rooms", 128, 0)]
LARGE_PLANNERS = [("exact", {"planner": "exact"}),
                  ("accelerating K=8", {"planner": "accelerating", "updates_per_move": 8}),
                  ("plain DP K=8", {"planner": "plain-dp", "updates_per_move": 8})]
#: Ticks timed on a large world (its whole episode would take minutes a planner on a slow backend).
LARGE_TICKS = 100
COST_SIZE, QUICK_COST_SIZE = 1024, 128
DEAR_ROWS, QUICK_DEAR_ROWS = 120, 60
NODE_SETUP_NODES = 64
#: A converge or repair case is skipped on a backend where its timed calls, at the smaller map's time scaled by the
#: cells, project past this many seconds.
SERIAL_LIMIT_S = 30.0


def backend_name(arch: str) -> str:
    """``arch:threads`` as a column name: "cpu 2 threads", "cuda"."""
    kind, _, threads = arch.partition(":")
    return f"{kind} {threads} threads" if kind == "cpu" else kind


def parse_archs(text: str) -> list[str]:
    """The backends of ``--archs``: comma-separated ``cpu:N`` or another Taichi arch name (cuda, vulkan ...)."""
    archs = [a.strip() for a in text.split(",") if a.strip()]
    for arch in archs:
        kind, _, threads = arch.partition(":")
        if not kind.isidentifier() or (kind == "cpu" and not (threads.isdigit() and int(threads) > 0)):
            raise SystemExit(f"--archs: {arch!r} is neither cpu:N (N threads) nor a Taichi arch name")
    if not archs:
        raise SystemExit("--archs names no backend")
    return archs


# ------------------------------------------------------------------------------------------------ the worker side
def _emit(row: dict) -> None:
    print("RESULT " + json.dumps(row), flush=True)


def _same_as_first(name: str, distances: np.ndarray, scratch: Path, first: bool) -> bool | None:
    """Save ``distances`` as the first backend's, or compare them bit for bit with it (None: nothing to compare)."""
    path = scratch / f"{name}.npy"
    if first:
        np.save(path, distances)
        return None
    return bool(np.array_equal(np.load(path), distances)) if path.exists() else None


def _maps(sizes: tuple[int, ...]) -> list[tuple[str, np.ndarray, tuple[int, int]]]:
    """Random maps (20 % obstacles, corner goal) of each size, and a 1-cell maze of the largest."""
    from benchmarks.convergence import maze_cases, random_cases

    return [random_cases(size)[0] for size in sizes] + [maze_cases(sizes[-1] + 1, 1)[0]]


def _projected_s(timed: dict, name: str, cells: int, calls: int) -> float:
    """The time ``calls`` calls of case ``name`` on ``cells`` cells are projected to take from the smaller map's."""
    if name not in timed:
        return 0.0
    seconds, smaller = timed[name]
    return calls * seconds * cells / smaller


def _converge_rows(sizes, repeats: int, scratch: Path, first: bool) -> None:
    from benchmarks.convergence import field_on, measure_repair

    timed: dict[str, tuple[float, int]] = {}
    for name, occupied, goal in _maps(sizes):
        cells = occupied.size
        field = field_on(occupied, goal)
        for kind, limit in (("search", None), ("rounds", 1 << 30)):
            projected = _projected_s(timed, kind, cells, repeats + 1)
            if projected > SERIAL_LIMIT_S:
                _emit({"case": "converge", "map": name, "kind": kind, "skipped": f"projected {projected:.0f} s"})
                continue

            def fresh(limit=limit):
                field.reset()
                field.converge(max_rounds=limit)
            seconds = median_time(fresh, repeats)
            timed.setdefault(kind, (seconds, cells))
            _emit({"case": "converge", "map": name, "kind": kind, "ms": 1e3 * seconds,
                   "same": _same_as_first(f"{name}-{kind}", field.distances(), scratch, first)})
        projected = _projected_s(timed, "search", cells, 2 * (repeats + 1))  # a fresh search beside each repair
        if projected > SERIAL_LIMIT_S:
            _emit({"case": "repair", "map": name, "kind": "box", "skipped": f"projected {projected:.0f} s"})
            continue
        field.reset()
        field.converge()
        result = measure_repair(field, "box", field.distances(), repeats)
        _emit({"case": "repair", "map": name, "kind": "box", "ms": result["edit_ms"] + result["repair_ms"],
               "back_to_back_ms": result["back_to_back_ms"], "ratio_to_search": result["ratio"],
               "same": result["equal"]})
    _node_setup_row(sizes[-1] // 2, repeats, scratch, first)


def _node_setup_row(size: int, repeats: int, scratch: Path, first: bool) -> None:
    """The node layers' setup (rounds of tiles) on a random ``size``² map with NODE_SETUP_NODES nodes."""
    from tdp.engine import Engine
    from tdp.nodes import place_nodes

    lattice = place_nodes(np.zeros((size, size), bool), count=NODE_SETUP_NODES)
    occupied = np.random.default_rng(size).random((size, size)) < 0.2
    occupied[tuple(lattice.cells.T)] = False
    engine = Engine(occupied, (size // 2, size // 2), nodes=lattice.cells, node_cap=2.5 * lattice.spacing)
    engine.converge()

    def node_setup():
        engine.reset()
        engine.converge()
    seconds = median_time(node_setup, repeats)
    _emit({"case": "converge", "map": f"random {size}² + {len(lattice.cells)} nodes", "kind": "nodes' setup",
           "ms": 1e3 * seconds,
           "same": _same_as_first(f"nodes-{size}", engine.node_distances(len(lattice.cells) // 2), scratch, first)})


def _cost_cases(quick: bool) -> list[tuple[str, object, tuple[int, int]]]:
    """A random map with inflation costs, and the dear corridor (cost 1e6: distances past 2^24)."""
    import tdp
    from benchmarks.convergence import random_cases
    from benchmarks.costs import costs, dear_corridor

    name, occupied, goal = random_cases(QUICK_COST_SIZE if quick else COST_SIZE)[0]
    dear, dear_goal = dear_corridor(QUICK_DEAR_ROWS if quick else DEAR_ROWS, 1e6)
    return [(f"{name}, inflation costs", tdp.GridMap(occupied, cost=costs(occupied, "inflation")), goal),
            (f"dear corridor {dear.shape[0]}x{dear.shape[1]}, cost 1e6", dear, dear_goal)]


def _cost_rows(quick: bool, repeats: int, scratch: Path, first: bool) -> None:
    """Each cost case's converge from scratch and box repair, both compared with the first backend's."""
    import tdp
    from benchmarks.convergence import from_scratch
    from benchmarks.costs import median_box_repair_ms, route_box

    for name, grid, goal in _cost_cases(quick):
        field = tdp.DistanceField(grid, goal)
        seconds = median_time(lambda: from_scratch(field), repeats)
        _emit({"case": "converge", "map": name, "kind": "search", "ms": 1e3 * seconds,
               "same": _same_as_first(f"{name}-search", field.distances(), scratch, first)})
        box = route_box(field)
        repair_ms = median_box_repair_ms(field, box, repeats)
        field.set_occupied(box)
        field.converge()
        _emit({"case": "repair", "map": name, "kind": "box", "ms": repair_ms,
               "same": _same_as_first(f"{name}-box", field.distances(), scratch, first)})


def _tick_rows(worlds, planners, max_ticks: int | None, scratch: Path, first: bool) -> None:
    """Each planner's setup and ticks on each world: its whole episode, or its first ``max_ticks`` ticks."""
    import tdp
    from benchmarks.equal_time import planner_for
    from tdp.random_worlds import make_world
    from tdp.simulate import run_planner

    for family, size, seed in worlds:
        scenario = make_world(family, size, seed)
        ticks_limit = min(scenario.tick_limit, max_ticks or scenario.tick_limit)
        for label, options in planners:
            planner_for(scenario, options)  # this kind's kernels compiled before any timing
            began = time.perf_counter()
            planner = planner_for(scenario, options)
            setup_s = time.perf_counter() - began
            record = run_planner(scenario, planner, tdp.NavigatorConfig(**options), ticks_limit)
            ticks = [1e3 * sum(r.timings.values()) for r in record["results"]]
            _emit({"case": "ticks", "map": f"{family} {size}² #{seed}", "kind": label, "setup_ms": 1e3 * setup_s,
                   "ms": float(np.median(ticks)), "p95_ms": float(np.percentile(ticks, 95)),
                   "ticks": record["ticks"], "reached": bool(record["reached"]),
                   "same": _same_as_first(f"{family}-{size}-{seed}-{label}", np.array(record["trajectory"]),
                                          scratch, first)})


def worker(quick: bool, repeats: int, scratch: Path, first: bool) -> None:
    """Every case on the backend this process was started on, a RESULT line each."""
    from benchmarks.kernel import engine_times
    from tdp.engine import init_taichi

    init_taichi()
    for size, nodes in QUICK_ITERATION_CASES if quick else ITERATION_CASES:
        times, _ = engine_times(size, nodes, repeats)
        _emit({"case": "iteration", "map": f"random {size}²", "kind": f"{times['nodes']} nodes",
               "ms": times["taichi_ms"], "steady_ms": times["steady_ms"],
               "cell_layers_per_s": times["updates_per_s"]})
    _converge_rows(QUICK_CONVERGE_SIZES if quick else CONVERGE_SIZES, repeats, scratch, first)
    _cost_rows(quick, repeats, scratch, first)
    _tick_rows(QUICK_WORLDS if quick else WORLDS, PLANNERS, None, scratch, first)
    _tick_rows(QUICK_LARGE_WORLDS if quick else LARGE_WORLDS, LARGE_PLANNERS, LARGE_TICKS, scratch, first)


# ------------------------------------------------------------------------------------------------ the parent side
def run_backend(arch: str, args, scratch: Path, first: bool, journal: Path) -> list[dict]:
    """One backend's worker; its rows as they come (each appended to ``journal``), or one row saying why none."""
    kind, _, threads = arch.partition(":")
    env = dict(os.environ, TDP_ARCH=kind, TDP_THREADS=threads or "2", PYTHONUNBUFFERED="1")
    command = [sys.executable, "-m", "benchmarks.backends", "--worker", "--repeats", str(args.repeats),
               "--scratch", str(scratch)] + (["--quick"] if args.quick else []) + (["--first"] if first else [])
    rows = []
    with subprocess.Popen(command, env=env, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True) as process:
        for line in process.stdout:
            if not line.startswith("RESULT "):
                continue
            row = {"backend": backend_name(arch), **json.loads(line[7:])}
            rows.append(row)
            with journal.open("a") as out:
                out.write(json.dumps(row) + "\n")
            shown = row.get("skipped") or f"{row['ms']:.3f} ms" + ("" if row.get("same") in (None, True) else
                                                                    " - DIFFERS from the first backend")
            print(f"  {row['backend']}: {', '.join(_case(row))}: {shown}", flush=True)
        error = process.stderr.read()
    if process.returncode:
        lines = error.strip().splitlines() or ["no message"]
        print(f"  {backend_name(arch)}: the worker stopped (exit code {process.returncode}):", flush=True)
        print("\n".join(f"    {line}" for line in lines[-15:]), flush=True)
        rows.append({"backend": backend_name(arch), "case": "failed", "map": "", "kind": "",
                     "error": f"exit code {process.returncode}: {lines[-1]}"})
    return rows


def _case(row: dict) -> tuple[str, str, str]:
    """What a row measured: (case, map, kind)."""
    return row["case"], row["map"], row["kind"]


def summary_rows(rows: list[dict], backends: list[str]) -> list[list[str]]:
    """A table row per case: each backend's ms (or why not) and its ratio to the first backend's."""
    by_case = {}
    for row in rows:
        if row["case"] != "failed":
            by_case.setdefault(_case(row), {})[row["backend"]] = row
    table = []
    for case, by in by_case.items():
        first = by.get(backends[0], {}).get("ms")
        cells = [*case]
        for backend in backends:
            row = by.get(backend)
            if row is None or "ms" not in row:
                cells.append(row["skipped"] if row else "-")
                continue
            ratio = f" ({row['ms'] / first:.2g}x)" if first and backend != backends[0] else ""
            differs = "" if row.get("same") in (None, True) else " DIFFERS"
            cells.append(f"{row['ms']:.3g}{ratio}{differs}")
        table.append(cells)
    return table


def figure(rows: list[dict], backends: list[str], path: Path) -> None:
    from tdp.plot import pyplot, save_figure

    plt = pyplot()
    times = {backend: {_case(r): r["ms"] for r in rows if r["backend"] == backend and "ms" in r}
             for backend in backends}
    first = times[backends[0]]
    cases = list(first)
    fig, ax = plt.subplots(figsize=(max(8, 0.45 * len(cases)), 5))
    width = 0.8 / max(len(backends) - 1, 1)
    for k, backend in enumerate(backends[1:]):
        ratios = [times[backend][c] / first[c] if c in times[backend] else np.nan for c in cases]
        ax.bar(np.arange(len(cases)) + k * width, ratios, width, label=backend)
    ax.axhline(1.0, color="black", linewidth=0.8)
    ax.set_xticks(np.arange(len(cases)) + 0.4 - width / 2, [" / ".join(c) for c in cases], rotation=75, fontsize=6)
    ax.set_yscale("log")
    ax.set_ylabel(f"time / {backends[0]}'s (log)")
    ax.set_title("tdp's engine and planners per backend (below 1: faster than the first)")
    if len(backends) > 1:
        ax.legend(fontsize=7)
    save_figure(fig, path)


def main() -> None:
    parser = quick_parser(__doc__)
    parser.add_argument("--archs", help=f"backends, comma-separated (default: {','.join(ARCHS)}; "
                                        f"with --quick {','.join(QUICK_ARCHS)})")
    parser.add_argument("--repeats", type=int, default=7)
    parser.add_argument("--worker", action="store_true", help=argparse.SUPPRESS)
    parser.add_argument("--first", action="store_true", help=argparse.SUPPRESS)
    parser.add_argument("--scratch", help=argparse.SUPPRESS)
    args = parser.parse_args()
    if args.repeats < 1:
        raise SystemExit(f"--repeats must be at least 1, got {args.repeats}")
    if args.worker:
        worker(args.quick, args.repeats, Path(args.scratch), args.first)
        return
    archs = parse_archs(args.archs or ",".join(QUICK_ARCHS if args.quick else ARCHS))
    name = "backends-quick" if args.quick else "backends"
    RESULTS.mkdir(parents=True, exist_ok=True)
    journal = RESULTS / f"{name}.jsonl"
    journal.write_text("")
    print(f"backends benchmark: {', '.join(map(backend_name, archs))} (median of {args.repeats}, warm); rows in "
          f"{journal} as they come")
    rows = []
    with tempfile.TemporaryDirectory() as scratch:
        for k, arch in enumerate(archs):
            rows += run_backend(arch, args, Path(scratch), k == 0, journal)
    backends = list(dict.fromkeys(r["backend"] for r in rows))
    print_table(["case", "map", "kind", *(f"{b} ms" for b in backends)], summary_rows(rows, backends))
    save_results(name, {"archs": archs, "repeats": args.repeats, "rows": rows},
                 lambda png: figure(rows, backends, png))


if __name__ == "__main__":
    main()
