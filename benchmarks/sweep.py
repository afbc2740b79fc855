"""Sweeps on a local Dask cluster against the same sweep run serially.

    python -m benchmarks.sweep [--quick] [--workers N]

Runs ``specs/speedup.yaml`` (200 episodes on 40 random worlds) twice, each into a fresh folder: serially (one
process, Taichi on every core) and on a local Dask cluster (one worker process per core unless --workers, one
Taichi thread each). Each wall time counts everything a user waits for: the cluster's start, the workers' imports
and kernel compiles, every episode and the journal. A one-world sweep on each backend runs first, untimed, so
that Taichi's on-disk kernel cache is warm for both thread counts. Prints both times, the speed-up, and whether
the two tables are equal apart from the measured times (they must be). --quick runs ``specs/speedup-quick.yaml``
without the warm-up sweeps (a smoke run: its times include the kernels' compiles).
"""
from __future__ import annotations

import io
import tempfile
import time
from pathlib import Path

from benchmarks.common import SPECS, print_table, quick_parser, save_results, seconds_bars
from tdp.sweep import TIMED, load_spec, run_sweep
from tdp.sweep.report import tidy


def timed_sweep(spec, folder: Path, **backend) -> tuple[float, list[dict]]:
    """Wall seconds of a whole sweep into the empty ``folder``, and its tidy table without the measured times."""
    began = time.perf_counter()
    rows = run_sweep(spec, folder, log=io.StringIO(), **backend)
    seconds = time.perf_counter() - began
    return seconds, [{k: v for k, v in r.items() if k not in TIMED} for r in tidy(spec, rows)]


def figure(rows: list[dict], path) -> None:
    seconds_bars(path, [r["backend"] for r in rows], [r["seconds"] for r in rows], ["0.6", "tab:blue"],
                 f"wall time of {rows[0]['episodes']} episodes (s)",
                 f"local cluster: {rows[0]['seconds'] / rows[1]['seconds']:.2f}x faster", digits=0)


def main() -> None:
    parser = quick_parser(__doc__)
    parser.add_argument("--workers", type=int, default=None, help="local cluster workers (default: one per core)")
    args = parser.parse_args()
    spec = load_spec(SPECS / ("speedup-quick.yaml" if args.quick else "speedup.yaml"))
    warm = load_spec(SPECS / "speedup-quick.yaml")
    with tempfile.TemporaryDirectory() as folder:
        folder = Path(folder)
        for name, backend in () if args.quick else (("warm-serial", {"serial": True}),
                                                       ("warm-cluster", {"workers": args.workers})):
            (folder / name).mkdir()
            run_sweep(warm, folder / name, log=io.StringIO(), **backend)
        (folder / "serial").mkdir()
        (folder / "cluster").mkdir()
        serial_s, serial = timed_sweep(spec, folder / "serial", serial=True)
        cluster_s, cluster = timed_sweep(spec, folder / "cluster", workers=args.workers)
    episodes = len(spec.episodes())
    rows = [{"backend": "serial", "episodes": episodes, "seconds": serial_s},
            {"backend": f"local cluster ({args.workers or 'one worker per core'})", "episodes": episodes,
             "seconds": cluster_s}]
    same = serial == cluster
    print_table(["backend", "episodes", "wall s", "speed-up"],
                [[r["backend"], str(episodes), f"{r['seconds']:.1f}", f"{serial_s / r['seconds']:.2f}x"]
                 for r in rows])
    print(f"tables equal apart from measured times: {same}")
    save_results("sweep-quick" if args.quick else "sweep", {"spec": spec.name, "rows": rows,
                                                            "speedup": serial_s / cluster_s, "tables_equal": same},
                 lambda png: figure(rows, png))
    if not same:
        raise SystemExit("the serial and cluster tables differ")


if __name__ == "__main__":
    main()
