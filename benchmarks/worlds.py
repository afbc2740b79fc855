"""Random dynamic worlds nobody tuned for: accelerating nodes against plain DP, D* Lite and the oracle.

    python -m benchmarks.worlds [--quick] [--workers N] [--resume]

A sweep spec (``benchmarks/specs/worlds.yaml``; edit it for other seeds, sizes or families) run through
:mod:`tdp.sweep` on a local Dask cluster; its tables and ratio figure land in ``results/sweeps/worlds/``.
Eight seeded families (``tdp.random_worlds``) at 100 x 100 and 200 x 200; accelerating nodes and plain DP at K = 1
and 4 (DP iterations per move); D* Lite (plain Python, same graph) and the oracle (exact distances every tick)
once per world. Per family, K and planner: worlds, reached %, collisions, hits (a box drove onto the robot), mean
and max ratio to the oracle (over the worlds every planner reached), worlds where accelerating nodes are worse
than plain DP by more than 0.01, blockage detections and the fraction justified by the exact pair distances,
wait ticks (and how many of them had a legal move towards the goal), and the median planner time per tick.

A detection of pair (a, b) at tick t is *justified* when the exact distance between a and b (scipy's Dijkstra on
each tick's map, independent of tdp) rose by at least U (``detect_rise``) between two ticks of the window the
detection can be reacting to: the ticks [t - L, t] with L = ceil((J + DmaxQ) / K) + 1 (news of a change reaches
a pair within DmaxQ iterations, and the test looks J iterations back).
"""
from __future__ import annotations

import math

import numpy as np
from scipy.sparse.csgraph import dijkstra

import tdp
from benchmarks.common import DETECTION_COLUMNS, OUTCOME_COLUMNS, grouped_bars, sweep_benchmark
from benchmarks.reference_graph import grid_graph
from tdp.random_worlds import CUTTING

#: The sweep's planners as the tables name them.
LABELS = {"accelerating": "accelerating", "plain-dp": "plain DP", "dstar-lite": "D* Lite", "oracle": "oracle"}


class PairTruth:
    """Exact node-to-node distances on each tick's map of one world (scipy's Dijkstra), cached per tick."""

    def __init__(self, scenario: tdp.Scenario, nodes: np.ndarray, limit: float):
        self.scenario, self.nodes, self.limit = scenario, nodes, limit
        self._cache: dict[int, np.ndarray] = {}

    def at(self, tick: int) -> np.ndarray:
        """(n, n) exact distances between the nodes at ``tick``: inf beyond ``limit``, nan where a node is covered
        (a covered node has no distance to speak of)."""
        if tick not in self._cache:
            occupied = self.scenario.occupancy(tick)
            cols = occupied.shape[1]
            index = self.nodes[:, 0] * cols + self.nodes[:, 1]
            found = dijkstra(grid_graph(occupied), indices=index, limit=self.limit)[:, index]
            covered = occupied[self.nodes[:, 0], self.nodes[:, 1]]
            found[covered, :] = found[:, covered] = np.nan
            self._cache[tick] = found
        return self._cache[tick]

    def justified(self, tick: int, pair: tuple[int, int], lookback: int, rise: float) -> bool:
        """Whether the exact distance of ``pair`` rose by ``rise`` or more within ticks [tick - lookback, tick]
        (ticks where one of its nodes is covered do not count)."""
        a, b = pair
        series = [self.at(t)[a, b] for t in range(max(0, tick - lookback), tick + 1)]
        lowest = math.inf
        for value in series:
            if math.isnan(value):
                continue
            if value - lowest >= rise:
                return True
            lowest = min(lowest, value)
        return False


def waits_with_a_move(scenario: tdp.Scenario, record: dict, config: tdp.NavigatorConfig) -> int:
    """Ticks the robot waited (not at the target) although the exact field of that tick's map offered a move."""
    count = 0
    for tick, (mode, cell) in enumerate(zip(record["modes"], record["trajectory"][:-1]), start=1):
        occupied, target = scenario.occupancy(tick), scenario.target(tick)
        if mode is not tdp.Mode.WAIT or occupied[cell] or occupied[target]:
            continue
        field = tdp.DistanceField(tdp.GridMap(occupied), target, config.neighbourhood, config.corner_cutting)
        field.converge()
        count += field.successor(cell) is not None
    return count


def truth_metrics(scenario: tdp.Scenario, record: dict, planner, config: tdp.NavigatorConfig) -> dict:
    """Sweep metric (the spec's ``metrics``): for the navigator, the waits that had a legal move
    (``stuck_waits``); with accelerating nodes, the detections and how many of them the exact pair distances
    justify."""
    if not isinstance(planner, tdp.Navigator):
        return {}
    found = [(tick, d.pair) for tick, result in enumerate(record["results"], start=1) for d in result.detections]
    row = {"stuck_waits": waits_with_a_move(scenario, record, config)}
    if config.accelerating and found:
        truth = PairTruth(scenario, planner.nodes, planner.dmax_q + config.rise + 1)
        lookback = math.ceil((config.detect_window + planner.dmax_q) / config.updates_per_move) + 1
        row["justified"] = sum(truth.justified(tick, pair, lookback, config.rise) for tick, pair in found)
    elif config.accelerating:
        row["justified"] = 0
    return row


def summarise(table: list[dict]) -> list[dict]:
    """Per family, K and planner (D* Lite and the oracle repeated under each K) from the sweep's tidy table. Mean
    and max ratios are over the worlds every planner that ran there reached; D* Lite may have run on some sizes
    only."""
    out = []
    ks = sorted({r["updates_per_move"] for r in table if r["updates_per_move"] is not None})
    for family in dict.fromkeys(r["group"] for r in table):
        mine = [r for r in table if r["group"] == family]
        worlds = sorted({(r["size"], r["seed"]) for r in mine})
        for k in ks:
            runs_of = {label: {(r["size"], r["seed"]): r for r in mine
                               if r["planner"] == planner and r["updates_per_move"] in (k, None)}
                       for planner, label in LABELS.items()}
            runs_of = {planner: runs for planner, runs in runs_of.items() if runs}
            everyone = [w for w in worlds if all(runs[w]["reached"] for runs in runs_of.values() if w in runs)]
            for planner, runs in runs_of.items():
                ratios = [runs[w]["ratio"] for w in everyone if w in runs]
                summary = {"family": family, "k": k, "planner": planner, "worlds": len(runs),
                           "reached_pct": 100.0 * sum(r["reached"] for r in runs.values()) / len(runs),
                           "collisions": sum(r["collisions"] for r in runs.values()),
                           "hits": sum(r["hits"] for r in runs.values()),
                           "mean_ratio": float(np.mean(ratios)) if ratios else math.nan,
                           "max_ratio": float(np.max(ratios)) if ratios else math.nan,
                           "waits": sum(r["waits"] for r in runs.values()),
                           "stuck_waits": sum(r.get("stuck_waits", 0) for r in runs.values()),
                           "ms_median": float(np.median([r["ms_median"] for r in runs.values()]))}
                if planner == "accelerating":
                    plain = runs_of["plain DP"]
                    summary["worse_than_dp"] = sum(
                        (not a["reached"] and plain[w]["reached"]) or a["ratio"] > plain[w]["ratio"] + 0.01
                        for w, a in runs.items())
                    summary["detections"] = sum(r["detections"] for r in runs.values())
                    summary["justified"] = sum(r["justified"] for r in runs.values())
                out.append(summary)
    return out


def figure(summary: list[dict], path) -> None:
    from tdp.plot import pyplot, save_figure

    plt = pyplot()
    families = list(dict.fromkeys(s["family"] for s in summary))
    ks = list(dict.fromkeys(s["k"] for s in summary))
    fig, axes = plt.subplots(1, len(ks), figsize=(6 * len(ks), 4), squeeze=False)
    for ax, k in zip(axes[0], ks):
        planners = list(dict.fromkeys(s["planner"] for s in summary))
        grouped_bars(ax, families, {planner: [next(s["mean_ratio"] for s in summary if s["family"] == f
                                                   and s["k"] == k and s["planner"] == planner) for f in families]
                                    for planner in planners})
        ax.set_ylim(0.95, None)
        ax.set_ylabel("mean path length / oracle")
        ax.set_title(f"K = {k}")
    save_figure(fig, path)


def main() -> None:
    sweep_benchmark(__doc__, "worlds", summarise, [
        ("family", lambda s: s["family"]), ("K", lambda s: str(s["k"])), ("planner", lambda s: s["planner"]),
        *OUTCOME_COLUMNS, ("worse than DP", lambda s: str(s.get("worse_than_dp", "-"))), *DETECTION_COLUMNS,
        ("waits (with a move)", lambda s: f"{s['waits']} ({s['stuck_waits']})"),
        ("ms/tick", lambda s: f"{s['ms_median']:.2f}")], figure, {"cutting_families": list(CUTTING)})


if __name__ == "__main__":
    main()
