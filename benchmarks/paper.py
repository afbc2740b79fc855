"""The paper's section 5.2 on sudden-blockage: paths and time per tick as the number of accelerating nodes grows
(Figs. 11-12), as the DP updates per move grow (Figs. 13-14), and as the vision DmaxQ grows (Fig. 15).

    python -m benchmarks.paper [--quick] [--workers N] [--resume]

A sweep spec (``benchmarks/specs/paper.yaml``) run through :mod:`tdp.sweep`; its tables and ratio figure land in
``results/sweeps/paper/``. Serial unless ``--workers`` is given: the time per tick is part of the result, and
episodes running side by side would share the cores. One figure of paths per sweep, as in the paper, plus the
curves (ratio to the oracle, turn, time per tick). Every run is warm (Navigator.setup() compiles every kernel).
"""
from __future__ import annotations

import numpy as np

import tdp
from benchmarks.common import (RESULTS, machine, print_table, run_spec, sweep_parser, turn_against_unblocked,
                               write_json)

#: The paper's three sweeps: the field swept, its label, and the values the other two hold meanwhile.
SWEEPS = {
    "nodes": ("nodes", "number of accelerating nodes", {"updates_per_move": 1, "vision": 2.5}),
    "updates": ("updates_per_move", "DP updates per move (K)", {"nodes": 25, "vision": 2.5}),
    "vision": ("vision", "vision DmaxQ / spacing", {"nodes": 25, "updates_per_move": 1}),
}


def turn_metrics(scenario: tdp.Scenario, record: dict, planner, config: tdp.NavigatorConfig) -> dict:
    """Sweep metric (the spec's ``metrics``): ticks from the change to the turn, the closest approach to the
    blocking box, and the trajectory for the path figures."""
    return {**turn_against_unblocked(scenario, record["trajectory"]),
            "trajectory": [list(cell) for cell in record["trajectory"]]}


def sweep_rows(name: str, rows: list[dict], table: list[dict]) -> list[dict]:
    """The accelerating runs of one of the paper's sweeps by increasing value: the tidy table's columns, the
    swept ``value`` and the journal's trajectory."""
    field, _, fixed = SWEEPS[name]
    mine = [{**t, "sweep": name, "value": r["config"][field], "trajectory": r["trajectory"]}
            for r, t in zip(rows, table)
            if r["planner"] == "accelerating" and all(r["config"][k] == v for k, v in fixed.items())]
    return sorted(mine, key=lambda r: r["value"])


def path_figure(name: str, rows: list[dict], scenario, oracle: dict, path) -> None:
    from tdp.plot import draw_map, pyplot, save_figure

    plt = pyplot()
    fig, ax = plt.subplots(figsize=(6.5, 6.8))
    draw_map(ax, scenario.occupancy(scenario.change_tick))
    trajectory = np.array(oracle["trajectory"])
    ax.plot(trajectory[:, 1], trajectory[:, 0], ":", color="k", lw=1.5, label="oracle")
    colours = plt.cm.viridis(np.linspace(0, 0.9, len(rows)))
    for row, colour in zip(rows, colours):
        t = np.array(row["trajectory"])
        ax.plot(t[:, 1], t[:, 0], "-", color=colour, lw=1.6, label=f"{row['value']} (ratio {row['ratio']:.2f})")
        turn = min(scenario.change_tick + row["turn_after"], len(t) - 1)
        ax.plot(t[turn, 1], t[turn, 0], "o", color=colour, ms=5)
    ax.set_title(f"sudden-blockage: paths for increasing {SWEEPS[name][1]} (dots: turn A)", fontsize=9)
    ax.legend(fontsize=7, loc="lower left")
    save_figure(fig, path)


def curves_figure(rows: list[dict], path) -> None:
    from tdp.plot import pyplot, save_figure

    plt = pyplot()
    fig, axes = plt.subplots(1, 3, figsize=(13, 3.6))
    for ax, (name, (_, label, _)) in zip(axes, SWEEPS.items()):
        mine = [r for r in rows if r["sweep"] == name]
        values = [r["value"] for r in mine]
        ax.plot(values, [r["ms_mean"] for r in mine], "o-", color="tab:blue", label="ms per tick (mean)")
        ax.set_xlabel(label)
        ax.set_ylabel("ms per tick", color="tab:blue")
        twin = ax.twinx()
        twin.plot(values, [r["ratio"] for r in mine], "s--", color="tab:red", label="path / oracle")
        twin.set_ylabel("path length / oracle", color="tab:red")
        if name != "vision":
            ax.set_xscale("log", base=2)
    save_figure(fig, path)


def main() -> None:
    args = sweep_parser(__doc__, "none: serially").parse_args()
    spec, rows, table = run_spec("paper", args, serial=True)
    scenario = tdp.scenarios.get("sudden-blockage")
    oracle = next(r for r in rows if r["planner"] == "oracle")
    baseline = next(t for t in table if t["planner"] == "plain-dp")
    print(f"  plain DP, K = 1: ratio {baseline['ratio']:.3f}")
    suffix = "-quick" if args.quick else ""
    swept = []
    for name in SWEEPS:
        mine = sweep_rows(name, rows, table)
        path_figure(name, mine, scenario, oracle, RESULTS / f"paper-{name}{suffix}.png")
        swept += mine
    print_table(["sweep", "value", "nodes", "relevant detections", "ratio", "turn after", "closest",
                 "ms/tick median", "mean", "p95", "max"],
                [[r["sweep"], str(r["value"]), str(r["nodes_placed"]), str(r["relevant_detections"]),
                  f"{r['ratio']:.3f}", str(r["turn_after"]),
                  "-" if r["closest"] is None else f"{r['closest']:.1f}", f"{r['ms_median']:.2f}",
                  f"{r['ms_mean']:.2f}", f"{r['ms_p95']:.2f}", f"{r['ms_max']:.2f}"] for r in swept])
    curves_figure(swept, RESULTS / f"paper-curves{suffix}.png")
    summary = [{k: v for k, v in r.items() if k != "trajectory"} for r in swept]
    path = write_json(f"paper{suffix}", {"machine": machine(), "spec": spec.name, "plain_dp_k1": baseline,
                                         "rows": summary})
    print(f"wrote {path}, the figures paper-*{suffix}.png and results/sweeps/{spec.name}/")


if __name__ == "__main__":
    main()
