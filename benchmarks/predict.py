"""Obstacle prediction (NavigatorConfig.predict_ticks, avoid_boxes) on and off, on random worlds and the named
blockage scenarios.

    python -m benchmarks.predict [--quick] [--held-out] [--workers N] [--resume]

A sweep spec (``benchmarks/specs/predict.yaml``) run through :mod:`tdp.sweep` on a local Dask cluster: the eight
random-world families at 100 x 100 and 200 x 200 (8 seeds each) and the named scenarios moving-blockage and
sudden-blockage; accelerating nodes at K = 1 and 4 with prediction in the node layers off or at a 4-tick horizon,
and box avoidance off or on; exact replanning (K column "exact") with box avoidance off or on. Per group, K and
setting: worlds, reached %, collisions, hits (ticks a box sat on the robot), mean and max ratio to the oracle (over
the worlds the oracle reached), hit events (runs of hit ticks: how often a box drove onto the robot), detections and
the fraction the exact pair distances justify (as in ``benchmarks.worlds``; a detection made ahead of a predicted
closure counts as justified only if the closure comes within the look-back window), yields, and for the named
scenarios the ticks from the change to the turn.
``--held-out`` runs ``benchmarks/specs/predict-held-out.yaml`` instead: box avoidance on seeds the tracker's rules
were not tuned on (crossing and passing worlds of seeds 400-599, cluttered, moving-target and wandering ones of
400-449, at 60² and 100²).
"""
from __future__ import annotations

import math

import numpy as np

import tdp
from benchmarks.common import DETECTION_COLUMNS, OUTCOME_COLUMNS, grouped_bars, sweep_benchmark, turn_against_unblocked
from benchmarks.worlds import truth_metrics

#: The settings compared, as the tables name them: (predict_ticks, avoid_boxes).
SETTINGS = {(0, False): "off", (4, False): "predict 4", (0, True): "avoid", (4, True): "predict 4 + avoid"}


def prediction_metrics(scenario: tdp.Scenario, record: dict, planner, config: tdp.NavigatorConfig) -> dict:
    """Sweep metric: :func:`benchmarks.worlds.truth_metrics`, the hit events (:func:`tdp.simulate.run_planner`'s),
    and for a scenario with a blocking box the ticks from the change to the turn and the closest approach
    (:func:`benchmarks.common.turn_and_closest`)."""
    row = {**truth_metrics(scenario, record, planner, config), "hit_events": record["hit_events"]}
    if scenario.blocking is not None and scenario.change_tick is not None:
        row.update(turn_against_unblocked(scenario, record["trajectory"]))
    return row


def planner_k(row: dict) -> str:
    """The K column of an episode: accelerating nodes' DP iterations per move, or "exact" for exact replanning."""
    return "exact" if row["planner"] == "exact" else str(row.get("updates_per_move"))


def summarise(table: list[dict]) -> list[dict]:
    """Per group, K (or the exact planner) and setting."""
    out = []
    ks = [str(k) for k in sorted({r["updates_per_move"] for r in table if r["planner"] == "accelerating"})]
    ks += ["exact"] if any(r["planner"] == "exact" for r in table) else []
    for group in dict.fromkeys(r["group"] for r in table):
        for k in ks:
            for (ticks, avoid), label in SETTINGS.items():
                mine = [r for r in table if r["group"] == group and planner_k(r) == k
                        and (r.get("predict_ticks") or 0) == ticks and r["avoid_boxes"] == avoid]
                if not mine:
                    continue
                ratios = [r["ratio"] for r in mine if r["reached"] and r["ratio"] is not None
                          and math.isfinite(r["ratio"])]
                turns = [r["turn_after"] for r in mine if r.get("turn_after") is not None]
                out.append({"group": group, "k": k, "setting": label, "worlds": len(mine),
                            "reached_pct": 100.0 * sum(r["reached"] for r in mine) / len(mine),
                            "collisions": sum(r["collisions"] for r in mine), "hits": sum(r["hits"] for r in mine),
                            "hit_events": sum(r.get("hit_events", 0) for r in mine),
                            "mean_ratio": float(np.mean(ratios)) if ratios else math.nan,
                            "max_ratio": float(np.max(ratios)) if ratios else math.nan,
                            "detections": sum(r["detections"] for r in mine),
                            "justified": sum(r.get("justified", 0) for r in mine),
                            "yields": sum(r["yields"] for r in mine),
                            "stuck_waits": sum(r.get("stuck_waits", 0) for r in mine),
                            "turn_after": float(np.mean(turns)) if turns else None,
                            "ms_median": float(np.median([r["ms_median"] for r in mine]))})
    return out


def figure(summary: list[dict], path) -> None:
    """Hits and mean ratio per group and setting, one panel pair per K."""
    from tdp.plot import pyplot, save_figure

    plt = pyplot()
    groups = list(dict.fromkeys(s["group"] for s in summary))
    ks = list(dict.fromkeys(s["k"] for s in summary))
    labels = list(SETTINGS.values())
    fig, axes = plt.subplots(2, len(ks), figsize=(6 * len(ks), 7), squeeze=False)
    for column, k in enumerate(ks):
        for row, (field, title) in enumerate((("hits", "hits (ticks a box sat on the robot)"),
                                              ("mean_ratio", "mean path length / oracle"))):
            ax = axes[row][column]
            grouped_bars(ax, groups, {label: [next((s[field] for s in summary if s["group"] == g and s["k"] == k
                                                    and s["setting"] == label), math.nan) for g in groups]
                                      for label in labels})
            ax.set_title(f"{'exact replanning' if k == 'exact' else f'K = {k}'}: {title}", fontsize=9)
            if field == "mean_ratio":
                ax.set_ylim(0.9, None)
    save_figure(fig, path)


def main() -> None:
    sweep_benchmark(__doc__, "predict", summarise, [
        ("group", lambda s: s["group"]), ("K", lambda s: str(s["k"])), ("setting", lambda s: s["setting"]),
        *OUTCOME_COLUMNS, ("hit events", lambda s: str(s["hit_events"])), *DETECTION_COLUMNS,
        ("yields", lambda s: str(s["yields"])),
        ("turn after", lambda s: "-" if s["turn_after"] is None else f"{s['turn_after']:.0f}"),
        ("ms/tick", lambda s: f"{s['ms_median']:.2f}")], figure,
        held_out="crossing and passing worlds of seeds 400-599 and cluttered and moving-target ones of 400-449 at 60² "
                 "and 100², box avoidance with exact replanning and accelerating nodes at K = 1")


if __name__ == "__main__":
    main()
