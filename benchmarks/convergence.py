"""The setup phase: DistanceField.converge() next to scipy's Dijkstra on the same 16-neighbour graph.

    python -m benchmarks.convergence [--quick]

Random maps (20 % obstacles) of growing size and the MovingAI maps in ../shared/data (skipped when absent). The
graph is built once and timed apart; Dijkstra's solve and converge() are warm medians of repeats in the same
process; the results are checked equal. Also counted: converge()'s rounds of tile settling, and, up to
512 x 512, the synchronous (Jacobi) iterations that step() needs to reach the same fixed point.
"""
from __future__ import annotations

import time
from pathlib import Path

import numpy as np
from scipy.sparse.csgraph import dijkstra

import tdp
from benchmarks.common import median_time, print_table, quick_parser, save_results
from benchmarks.reference_graph import grid_graph

SHARED = Path(__file__).resolve().parents[2] / "shared" / "data" / "movingai"
SIZES, QUICK_SIZES = [128, 256, 512, 1024], [64, 128]
MAPS, QUICK_MAPS = ["arena", "den312d", "maze512-32-0", "random512-10-0", "8room_000"], ["arena"]


def random_map(size: int) -> tuple[np.ndarray, tuple[int, int]]:
    occupied = np.random.default_rng(size).random((size, size)) < 0.2
    occupied[0, 0] = False
    return occupied, (0, 0)


def movingai_map(name: str) -> tuple[np.ndarray, tuple[int, int]] | None:
    path = SHARED / f"{name}.map"
    if not path.exists():
        return None
    grid = tdp.load_map(path)
    goal = tdp.load_scenarios(SHARED / f"{name}.map.scen", grid)[-1].goal
    return grid.occupied, goal


def jacobi_iterations(occupied: np.ndarray, goal) -> int:
    field = tdp.DistanceField(tdp.GridMap(occupied), goal)
    iterations = 0
    while field.step():
        iterations += 1
    return iterations


def measure(name: str, occupied: np.ndarray, goal, repeats: int) -> dict:
    rows, cols = occupied.shape
    began = time.perf_counter()
    graph = grid_graph(occupied).T.tocsr()  # transposed: distances *to* the goal
    build_s = time.perf_counter() - began
    source = goal[0] * cols + goal[1]
    reference = dijkstra(graph, indices=source).reshape(rows, cols)
    dijkstra_s = median_time(lambda: dijkstra(graph, indices=source), repeats)
    field = tdp.DistanceField(tdp.GridMap(occupied), goal)
    rounds = field.converge()
    converge_s = median_time(field.converge, repeats)
    ours = field.distances()
    finite = np.isfinite(reference)
    exact = bool(np.array_equal(np.isfinite(ours), finite)) and bool(
        np.allclose(ours[finite], reference[finite], rtol=1e-5))
    result = {"map": name, "cells": rows * cols, "free": int((~occupied).sum()), "build_ms": build_s * 1e3,
              "dijkstra_ms": dijkstra_s * 1e3, "converge_ms": converge_s * 1e3, "rounds": rounds,
              "ratio": converge_s / dijkstra_s, "equal": exact}
    if rows * cols <= 512 * 512:
        result["jacobi_iterations"] = jacobi_iterations(occupied, goal)
    return result


def figure(results: list[dict], path: Path) -> None:
    from tdp.plot import pyplot, save_figure

    plt = pyplot()

    randoms = [r for r in results if r["map"].startswith("random ")]
    fig, ax = plt.subplots(figsize=(6.5, 4.2))
    cells = [r["cells"] for r in randoms]
    for key, label in (("converge_ms", "tdp converge()"), ("dijkstra_ms", "scipy Dijkstra (solve)"),
                       ("build_ms", "graph build (scipy side)")):
        ax.loglog(cells, [r[key] for r in randoms], "o-", label=label)
    for r in results:
        if not r["map"].startswith("random "):
            ax.loglog(r["cells"], r["converge_ms"], "k^")
            ax.annotate(r["map"], (r["cells"], r["converge_ms"]), fontsize=7, xytext=(3, 3), textcoords="offset points")
    ax.set_xlabel("cells")
    ax.set_ylabel("ms (median, warm)")
    ax.set_title("setup phase: random maps (20% obstacles); triangles: MovingAI maps", fontsize=9)
    ax.legend(fontsize=8)
    save_figure(fig, path)


def main() -> None:
    parser = quick_parser(__doc__)
    parser.add_argument("--repeats", type=int, default=5)
    args = parser.parse_args()
    sizes, maps = (QUICK_SIZES, QUICK_MAPS) if args.quick else (SIZES, MAPS)
    repeats = 3 if args.quick else args.repeats
    cases = [(f"random {s}x{s}", *random_map(s)) for s in sizes]
    for name in maps:
        loaded = movingai_map(name)
        if loaded is None:
            print(f"  {name}: not found in {SHARED}, skipped")
        else:
            cases.append((name, *loaded))
    results = []
    for name, occupied, goal in cases:
        results.append(measure(name, occupied, goal, repeats))
        r = results[-1]
        print(f"  {name}: converge {r['converge_ms']:.1f} ms ({r['rounds']} rounds), "
              f"Dijkstra {r['dijkstra_ms']:.1f} ms", flush=True)
    print_table(["map", "cells", "graph build ms", "Dijkstra ms", "converge ms", "converge / Dijkstra", "rounds",
                 "Jacobi iterations", "equal"],
                [[r["map"], str(r["cells"]), f"{r['build_ms']:.1f}", f"{r['dijkstra_ms']:.1f}",
                  f"{r['converge_ms']:.1f}", f"{r['ratio']:.2f}", str(r["rounds"]),
                  str(r.get("jacobi_iterations", "-")), str(r["equal"])] for r in results])
    save_results("convergence-quick" if args.quick else "convergence", {"results": results},
                 lambda png: figure(results, png))


if __name__ == "__main__":
    main()
