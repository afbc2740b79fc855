"""Two versions of the engine side by side in one process, for an engine change's A/B.

    python -m benchmarks.ab [BEFORE [AFTER]] [--pairs N] [--costs {inflation,random}] [--quick]

BEFORE and AFTER are git revisions of this repository (BEFORE: HEAD when left out; AFTER: the working tree, so that
a plain run times an uncommitted change against the last commit). A revision's ``tdp`` is exported (``git
archive``), and each version is loaded as a package of its own, so that both run in one process on one Taichi runtime.
Each pass times both, one after the other, the first swapped every pass: a from-scratch converge (``reset()``, then
``converge()``), and ``converge()`` after a 3 x 3 box, a wall of 16 cells on the route, a ring that seals the goal in
a room, noise and boxes (``benchmarks.convergence.repair_edit``), and after each edit's undo, on random, dense, maze
(perfect and braided), serpentine, ring and ROS maps. Per case: each version's median and the median of the passes'
ratios AFTER / BEFORE (a pass of both takes milliseconds to a fraction of a second, so the VM's drift reaches both
alike); per kind the geometric mean. Both versions' fields are checked equal before the timing starts. With
``--costs``, every map carries a cost grid of that kind (``benchmarks.costs.edited_costs``: nav2's inflation shape
or uniform 1-10; 1 on obstacles), so that a change to the weighted layers' kernels is timed where robots meet it
(results/ab-costs-KIND.json).

Why one process, pass by pass: this VM's speed drifts between processes by 10-20 % for the same code, and within a
process over seconds. In the twenty-first session an A/B in alternating processes credited a change with searches
0.74-0.99x that took 1.04x here, and one round by round (each version's median of seven in turn) blamed another
for a 5-16 % loss on mazes that is 0.98-1.04x here. A version against itself gives geometric means of 0.999-1.006
per kind and single cases 0.96-1.07.
"""
from __future__ import annotations

import importlib.util
import io
import math
import statistics
import subprocess
import sys
import tarfile
import tempfile
import time
from pathlib import Path

import numpy as np

from benchmarks import convergence, costs
from benchmarks.common import print_table, quick_parser, save_results

ROOT = Path(__file__).resolve().parents[1]
#: The edits of ``benchmarks.convergence.repair_edit`` timed, each undone too: a box and a wall on the route (a
#: raise, then a lowering), a pocket sealed round the farthest cell (its cells raised: a mend's look), the goal sealed
#: in a room of a sixteenth of the map (the race), noise and boxes (cells blocked and freed, boxes set down, all over
#: the map: many raises and lowerings in one mend, on a maze a race), and their undoing.
EDITS = ("box", "wall", "seal", "goal-room", "noise", "boxes")
KINDS = ("scratch",) + tuple(kind for edit in EDITS for kind in (edit, f"{edit} undone"))
#: The maps and goals timed: a ``benchmarks.convergence`` case builder, its arguments, and the cases it builds to keep.
MAPS = [(convergence.random_cases, (256,), ("random 256² corner", "random 256² random")),
        (convergence.random_cases, (512,), ("random 512² random",)),
        (convergence.random_cases, (1024,), ("random 1024² corner",)),
        (convergence.random_cases, (512, 0.4), ("random 512² 40 % centre",)),
        (convergence.maze_cases, (512, 1), ("maze 512² 1-cell corner",)),
        (convergence.maze_cases, (512, 2), ("maze 512² 2-cell random",)),
        (convergence.maze_cases, (512, 1, 0.1), ("maze 512² 1-cell braided 10 % random",)),
        (convergence.serpentine_cases, (512,), ("serpentine 512² centre",)),
        (convergence.rings_cases, (512,), ("rings 512² centre",)),
        (convergence.ros_cases, (), ("turtlebot3_world #0", "nav2 depot #0"))]
QUICK_MAPS = [(convergence.random_cases, (64,), ("random 64² corner",)),
              (convergence.random_cases, (128,), ("random 128² random",)),
              (convergence.maze_cases, (64, 1), ("maze 64² 1-cell corner",))]
PAIRS, QUICK_PAIRS = 30, 3  # passes of both versions a map (after a warm-up pass)


def exported(revision: str, into: Path) -> Path:
    """The ``tdp`` package of ``revision``, written under ``into``; a ValueError if git cannot export it."""
    done = subprocess.run(["git", "-C", str(ROOT), "archive", "--format=tar", revision, "tdp"], capture_output=True)
    if done.returncode != 0:
        raise ValueError(f"cannot export revision {revision!r}: {done.stderr.decode().strip()}")
    with tarfile.open(fileobj=io.BytesIO(done.stdout)) as archive:
        archive.extractall(into, filter="data")
    return into


def loaded(name: str, root: Path):
    """``root``/tdp imported as the package ``name``, its Taichi left to the one this process initialised (a
    second ``ti.init`` would reset the runtime every loaded version shares)."""
    spec = importlib.util.spec_from_file_location(name, root / "tdp" / "__init__.py",
                                                  submodule_search_locations=[str(root / "tdp")])
    package = importlib.util.module_from_spec(spec)
    sys.modules[name] = package
    spec.loader.exec_module(package)
    package.engine._initialised = True
    return package


def cases(maps: list[tuple]) -> list[tuple[str, np.ndarray, tuple[int, int]]]:
    """The (name, occupied, goal) cases that ``maps`` (as MAPS) keeps, each builder run once."""
    return [case for build, arguments, names in maps for case in build(*arguments) if case[0] in names]


def one_pass(field, edits: dict) -> dict[str, float]:
    """Each kind (``KINDS``) timed once on ``field``, converged, in seconds; the field is left converged."""
    field.reset()
    began = time.perf_counter()
    field.converge()
    seconds = {"scratch": time.perf_counter() - began}
    for kind, (apply, undo) in edits.items():
        for step, name in ((apply, kind), (undo, f"{kind} undone")):
            step()
            began = time.perf_counter()
            field.converge()
            seconds[name] = time.perf_counter() - began
    return seconds


def compare(versions: dict, name: str, occupied: np.ndarray, goal, pairs: int, cost: np.ndarray | None = None
            ) -> list[dict]:
    """Both versions on one map (with ``cost``, if given), ``pairs`` passes of each in turn (the first of each a
    warm-up, the order swapped every pass): one row per kind - each version's median ms and the median of the
    passes' after / before."""
    fields = {label: package.DistanceField(package.GridMap(occupied, cost=cost), goal)
              for label, package in versions.items()}
    for field in fields.values():
        field.converge()
    before, after = (field.distances() for field in fields.values())
    if not np.array_equal(before, after):
        raise AssertionError(f"{name}: the two versions' fields differ")
    edits = {label: {kind: convergence.repair_edit(field, kind, before) for kind in EDITS}
             for label, field in fields.items()}
    passes = []
    for turn in range(pairs + 1):
        order = list(fields) if turn % 2 == 0 else list(fields)[::-1]
        passes.append({label: one_pass(fields[label], edits[label]) for label in order})
    rows = []
    for kind in KINDS:
        first, second = ([done[label][kind] for done in passes[1:]] for label in fields)
        rows.append({"map": name, "kind": kind, "before_ms": statistics.median(first) * 1e3,
                     "after_ms": statistics.median(second) * 1e3,
                     "ratio": statistics.median(b / a for a, b in zip(first, second))})
    return rows


def figure(rows: list[dict], path: Path) -> None:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots(figsize=(8, 0.22 * len(rows) + 1.5))
    labels = [f"{row['map']}: {row['kind']}" for row in rows]
    ratios = [row["ratio"] for row in rows]
    ax.barh(range(len(rows)), ratios, color=["C2" if ratio < 1 else "C3" for ratio in ratios])
    ax.axvline(1.0, color="k", lw=0.8)
    ax.set_xlim(min(0.5, min(ratios) - 0.05), max(1.5, max(ratios) + 0.05))
    ax.set_yticks(range(len(rows)), labels, fontsize=7)
    ax.invert_yaxis()
    ax.set_xlabel("after / before (time, one process)")
    fig.tight_layout()
    fig.savefig(path, dpi=120)
    plt.close(fig)


def main() -> None:
    parser = quick_parser(__doc__)
    parser.add_argument("before", nargs="?", default="HEAD", help="a git revision of this repository (default HEAD)")
    parser.add_argument("after", nargs="?", help="another revision (default: the working tree)")
    parser.add_argument("--pairs", type=int, default=None, help=f"passes of both versions a map (default {PAIRS})")
    parser.add_argument("--costs", choices=("inflation", "random"), default=None,
                        help="give every map a cost grid of this kind (default: binary maps)")
    args = parser.parse_args()
    pairs = args.pairs if args.pairs is not None else (QUICK_PAIRS if args.quick else PAIRS)
    if pairs < 1:
        parser.error(f"--pairs must be at least 1, got {pairs}")
    import tdp.engine

    tdp.engine.init_taichi()
    with tempfile.TemporaryDirectory() as scratch:
        try:
            before_root = exported(args.before, Path(scratch) / "before")
            after_root = ROOT if args.after is None else exported(args.after, Path(scratch) / "after")
        except ValueError as error:
            parser.error(str(error))
        versions = {"before": loaded("tdp_before", before_root), "after": loaded("tdp_after", after_root)}
        rows = []
        for name, occupied, goal in cases(QUICK_MAPS if args.quick else MAPS):
            cost = None if args.costs is None else costs.edited_costs(occupied, args.costs)
            rows += compare(versions, name, occupied, goal, pairs, cost)
            print(f"  {name}: " + ", ".join(f"{row['kind']} {row['ratio']:.2f}x" for row in rows[-len(KINDS):]),
                  flush=True)
    means = {kind: math.exp(statistics.fmean(math.log(row["ratio"]) for row in rows if row["kind"] == kind))
             for kind in KINDS}
    print_table(["map", "kind", "before ms", "after ms", "after / before"],
                [[row["map"], row["kind"], f"{row['before_ms']:.3f}", f"{row['after_ms']:.3f}", f"{row['ratio']:.2f}"]
                 for row in rows])
    print_table(["kind", "geometric mean after / before"], [[kind, f"{mean:.3f}"] for kind, mean in means.items()])
    name = "ab" if args.costs is None else f"ab-costs-{args.costs}"
    save_results(f"{name}-quick" if args.quick else name,
                 {"before": args.before, "after": args.after or "working tree", "pairs": pairs, "costs": args.costs,
                  "rows": rows,
                  "geometric_means": means}, lambda path: figure(rows, path))


if __name__ == "__main__":
    main()
