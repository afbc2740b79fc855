"""A process's start-up with Taichi's cache warm: tdp's front end against Taichi's own, in fresh processes.

    python -m benchmarks.startup [--quick] [--repeats N]

Every process that plans pays for its kernels again, offline cache or not: Taichi parses each kernel's Python (the
cache is keyed by the IR it builds) and builds the LLVM code it finds for the machine. Each repeat starts, in
turn, a fresh Python process per variant and times, inside it, ``Engine(...)`` and ``warm_up()`` for the goal layer
and for node windows (the default stencil, 2 threads): *tdp*, the engine as it is (``init_taichi`` memoises three
steps of Taichi 1.7's front end, ARCHITECTURE §7), and *Taichi's front end*, the same with that step skipped. One
untimed run of each first (Taichi's cache warm for both). Prints the median seconds of each and the median of the
per-repeat ratios (tdp / Taichi's): each pair runs back to back, so the VM's drift stays out of the ratio.
--quick: the goal layer only, one repeat, no untimed run.
"""
from __future__ import annotations

import json
import statistics
import subprocess
import sys

from benchmarks.common import print_table, quick_parser, save_results, seconds_bars

#: The child's work: build and warm up the layers, print the seconds as JSON. ``{plain}``: skip tdp's front-end step.
CHILD = """
import json, time
import numpy as np
from tdp import engine
if {plain}:
    engine._quicken_taichi_front_end = lambda: None
occupied = np.zeros((64, 64), bool)
began = time.perf_counter()
layers = engine.Engine(occupied, (0, 0), nodes={nodes})
layers.warm_up()
print(json.dumps(time.perf_counter() - began))
"""
VARIANTS = {"tdp": False, "Taichi's front end": True}


def warm_up_s(plain: bool, nodes: bool) -> float:
    """Seconds a fresh process takes to build and warm up the goal layer (and node windows if ``nodes``)."""
    code = CHILD.format(plain=plain, nodes="np.array([[10, 10], [40, 40]])" if nodes else "None")
    done = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=900)
    if done.returncode != 0:
        raise SystemExit(f"the child process failed:\n{done.stderr[-2000:]}")
    return json.loads(done.stdout.strip().splitlines()[-1])


def figure(rows: list[dict], ratio: float, path) -> None:
    seconds_bars(path, [r["variant"] for r in rows], [r["seconds"] for r in rows], ["tab:blue", "0.6"],
                 "engine built and warmed up in a fresh process (s)",
                 f"Taichi's cache warm; tdp / Taichi's front end {ratio:.2f}x (median of the pairs)")


def main() -> None:
    parser = quick_parser(__doc__)
    parser.add_argument("--repeats", type=int, default=5, help="fresh processes per variant (default 5)")
    args = parser.parse_args()
    repeats, nodes = (1, False) if args.quick else (args.repeats, True)
    for plain in () if args.quick else VARIANTS.values():
        warm_up_s(plain, nodes)
    times = {name: [] for name in VARIANTS}
    for _ in range(repeats):
        for name, plain in VARIANTS.items():
            times[name].append(warm_up_s(plain, nodes))
    ratio = statistics.median(ours / theirs for ours, theirs in zip(times["tdp"], times["Taichi's front end"]))
    rows = [{"variant": name, "seconds": statistics.median(values), "runs": values} for name, values in times.items()]
    print_table(["variant", "layers", "repeats", "median s"],
                [[r["variant"], "goal and nodes" if nodes else "goal", str(repeats), f"{r['seconds']:.2f}"]
                 for r in rows])
    print(f"tdp / Taichi's front end: {ratio:.2f}x (median of the pairs)")
    save_results("startup-quick" if args.quick else "startup", {"nodes": nodes, "rows": rows, "ratio": ratio},
                 lambda png: figure(rows, ratio, png))


if __name__ == "__main__":
    main()
