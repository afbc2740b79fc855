"""Time of one all-layer DP iteration: tdp's Taichi engine (dense: every tile relaxed; steady: converged map,
no change) next to a numpy implementation of the same update and next to the memory-bandwidth floor, for 1 and
2 threads.

    python -m benchmarks.kernel [--quick]

Each thread count runs in its own process (Taichi is initialised once per process); within a process the
engine, numpy and the copy bandwidth are measured side by side, warm, as medians of repeats.
"""
from __future__ import annotations

import argparse
import json
import os
import subprocess
import sys

import numpy as np

from benchmarks.common import median_time, print_table, quick_parser, save_results
from tdp.engine import LANES

CASES = [(size, nodes) for size in (100, 256, 512, 1024, 2048) for nodes in (0, 25, 64, 256)]
QUICK_CASES = [(100, 25), (256, 16)]  # a smoke run
#: The floor of a streaming update, bytes per cell-layer: read the value and the penalty, write the value. The goal
#: layer's penalty is a float; a node window's is a 32-bit word per cell for all LANES lanes (a bit each).
GOAL_BYTES_PER_CELL_LAYER = 12
NODE_BYTES_PER_CELL_LAYER = 8 + 4 / LANES


def copy_bandwidth() -> float:
    """Bytes per second that a large numpy copy moves (read + write)."""
    src = np.ones(64 * 1024 * 1024 // 4 * 4, np.float32)  # 256 MiB
    dst = np.empty_like(src)
    seconds = median_time(lambda: np.copyto(dst, src), repeats=5)
    return 2 * src.nbytes / seconds


def engine_times(size: int, count: int, repeats: int) -> tuple[dict, tuple]:
    """The engine's side of a case: a ``size``² map with 10 % random obstacles, the goal and ``count`` lattice nodes;
    one all-layer iteration with every tile relaxed (dense) and on the converged map (steady), medians in ms, and the
    engine's inputs for a reference of the same update."""
    from tdp.engine import Engine
    from tdp.nodes import place_nodes

    lattice = place_nodes(np.zeros((size, size), bool), count=max(count, 1))
    if not count:
        lattice = lattice._replace(cells=lattice.cells[:0])
    occupied = np.random.default_rng(size).random((size, size)) < 0.1  # 10% random obstacles,
    occupied[tuple(lattice.cells.T)] = False  # but every lattice node free: the node counts are exact
    cap = 2.5 * lattice.spacing
    goal = tuple(np.argwhere(~occupied)[0])
    engine = Engine(occupied, goal, nodes=lattice.cells, node_cap=cap)
    side = 2 * int(np.ceil(cap)) + 1 if count else 0
    cell_layers = size * size + len(lattice.cells) * side * side

    def dense_step():
        engine.activate_all()  # every tile relaxed: the dense cost of an iteration
        engine.step()
        engine.changed()  # waits for the kernels to finish

    def steady_step():
        engine.step()
        engine.changed()

    engine.step(5)
    taichi_s = median_time(dense_step, repeats, warmup=3)
    engine.converge()
    steady_s = median_time(steady_step, repeats, warmup=3)
    times = {"size": size, "nodes": len(lattice.cells), "window": side, "cell_layers": cell_layers,
             "taichi_ms": taichi_s * 1e3, "steady_ms": steady_s * 1e3, "updates_per_s": cell_layers / taichi_s}
    return times, (occupied, goal, lattice.cells, cap)


def measure(size: int, count: int, repeats: int, bandwidth: float) -> dict:
    from benchmarks.numpy_reference import NumpyDP

    times, inputs = engine_times(size, count, repeats)
    numpy_s = median_time(NumpyDP(*inputs).step, max(2, repeats // 4), warmup=1)
    floor_s = (GOAL_BYTES_PER_CELL_LAYER * size * size
               + NODE_BYTES_PER_CELL_LAYER * (times["cell_layers"] - size * size)) / bandwidth
    taichi_s = times["taichi_ms"] / 1e3
    return {**times, "numpy_ms": numpy_s * 1e3, "floor_ms": floor_s * 1e3, "speedup_vs_numpy": numpy_s / taichi_s,
            "ratio_to_floor": taichi_s / floor_s}


def worker(cases: list[tuple[int, int]], repeats: int) -> None:
    bandwidth = copy_bandwidth()
    for size, count in cases:
        result = measure(size, count, repeats, bandwidth)
        result.update(threads=int(os.environ["TDP_THREADS"]), copy_gb_s=bandwidth / 1e9)
        print("RESULT " + json.dumps(result), flush=True)


def run_threads(threads: int, cases: list[tuple[int, int]], repeats: int) -> list[dict]:
    env = dict(os.environ, TDP_THREADS=str(threads))
    command = [sys.executable, "-m", "benchmarks.kernel", "--worker", "--repeats", str(repeats),
               "--cases", json.dumps(cases)]
    results = []
    with subprocess.Popen(command, env=env, stdout=subprocess.PIPE, text=True) as process:
        for line in process.stdout:
            if line.startswith("RESULT "):
                result = json.loads(line[7:])
                results.append(result)
                print(f"  {threads} thread(s), {result['size']}^2, {result['nodes']} nodes: "
                      f"{result['taichi_ms']:.2f} ms (numpy {result['numpy_ms']:.1f} ms)", flush=True)
    if process.returncode:
        raise SystemExit(f"benchmark worker failed with exit code {process.returncode}")
    return results


def figure(results: list[dict], path) -> None:
    from tdp.plot import pyplot, save_figure

    plt = pyplot()

    labels = sorted({(r["size"], r["nodes"]) for r in results})
    fig, ax = plt.subplots(figsize=(max(7, 0.7 * len(labels)), 4.5))
    width = 0.2
    series = [("numpy", 1, "numpy_ms"), ("taichi 1 thread", 1, "taichi_ms"), ("taichi 2 threads", 2, "taichi_ms"),
              ("bandwidth floor", 2, "floor_ms")]
    for k, (name, threads, key) in enumerate(series):
        values = [next(r[key] for r in results if (r["size"], r["nodes"]) == label and r["threads"] == threads)
                  for label in labels]
        ax.bar(np.arange(len(labels)) + (k - 1.5) * width, values, width, label=name)
    ax.set_xticks(range(len(labels)), [f"{s}², {n}" for s, n in labels], rotation=60, fontsize=7)
    ax.set_xlabel("map side², nodes")
    ax.set_yscale("log")
    ax.set_ylabel("ms per all-layer iteration")
    ax.legend()
    save_figure(fig, path)


def main() -> None:
    parser = quick_parser(__doc__)
    parser.add_argument("--repeats", type=int, default=15)
    parser.add_argument("--worker", action="store_true", help=argparse.SUPPRESS)
    parser.add_argument("--cases", help=argparse.SUPPRESS)
    args = parser.parse_args()
    if args.worker:
        worker([tuple(c) for c in json.loads(args.cases)], args.repeats)
        return
    cases = QUICK_CASES if args.quick else CASES
    repeats = 5 if args.quick else args.repeats
    print(f"kernel benchmark: {len(cases)} sizes x threads 1, 2 (median of {repeats}, warm)")
    results = [r for threads in (1, 2) for r in run_threads(threads, cases, repeats)]
    rows = [[f"{r['size']}x{r['size']}", str(r["nodes"]), str(r["threads"]), f"{r['taichi_ms']:.2f}",
             f"{r['numpy_ms']:.1f}", f"{r['speedup_vs_numpy']:.1f}x", f"{r['updates_per_s'] / 1e9:.2f}",
             f"{r['floor_ms']:.2f}", f"{r['ratio_to_floor']:.1f}", f"{r['steady_ms']:.3f}"] for r in results]
    print_table(["map", "nodes", "threads", "dense ms", "numpy ms", "vs numpy", "G cell-layer/s",
                 "floor ms", "x floor", "steady ms"], rows)
    name = "kernel-quick" if args.quick else "kernel"
    save_results(name, {"results": results}, lambda png: figure(results, png))


if __name__ == "__main__":
    main()
