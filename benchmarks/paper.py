"""The paper's section 5.2 on sudden-blockage: paths and time per tick as the number of accelerating nodes grows
(Figs. 11-12), as the DP updates per move grow (Figs. 13-14), and as the vision DmaxQ grows (Fig. 15).

    python -m benchmarks.paper [--quick]

One figure of paths per sweep, as in the paper, plus the curves (ratio to the oracle, turn, time per tick).
Every run is grid-level and warm (a full episode runs first; Navigator.setup() compiles every kernel).
"""
from __future__ import annotations


import numpy as np

import tdp
from benchmarks.common import (RESULTS, blockage_metrics, machine, print_table, quick_parser, run_navigator,
                               unblocked_route, write_json)
from tdp.simulate import oracle_run

SWEEPS = {
    "nodes": ("number of accelerating nodes", [4, 9, 16, 25, 36, 64], lambda v: {"nodes": v, "updates_per_move": 1}),
    "updates": ("DP updates per move (K)", [1, 2, 4, 8, 16], lambda v: {"updates_per_move": v}),
    "vision": ("vision DmaxQ / spacing", [0.6, 1.2, 1.6, 2.5, 4.0, 8.0],
               lambda v: {"vision": v, "updates_per_move": 1}),
}
QUICK = {"nodes": [9, 25], "updates": [1, 4], "vision": [0.6, 2.5]}


def sweep(name: str, values: list, scenario, oracle_length: float, route) -> list[dict]:
    label, _, options = SWEEPS[name]
    rows = []
    for value in values:
        config = tdp.NavigatorConfig(**options(value))
        record, navigator = run_navigator(scenario, config)
        detections = sum(d.relevant for r in record["results"] for d in r.detections)
        rows.append({"sweep": name, "value": value, "nodes_placed": len(navigator.nodes), "detections": detections,
                     "trajectory": record["trajectory"], "modes": record["modes"],
                     **blockage_metrics(scenario, record, oracle_length, route)})
        r = rows[-1]
        print(f"  {label} = {value}: ratio {r['ratio']:.3f}, turn +{r['turn_after']}, {detections} relevant "
              f"detections, {r['ms_mean']:.2f} ms/tick", flush=True)
    return rows


def path_figure(name: str, rows: list[dict], scenario, oracle, path) -> None:
    from tdp.plot import pyplot, save_figure

    plt = pyplot()

    from tdp.plot import draw_map

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
    ax.set_title(f"sudden-blockage: paths for increasing {SWEEPS[name][0]} (dots: turn A)", fontsize=9)
    ax.legend(fontsize=7, loc="lower left")
    save_figure(fig, path)


def curves_figure(rows: list[dict], path) -> None:
    from tdp.plot import pyplot, save_figure

    plt = pyplot()

    fig, axes = plt.subplots(1, 3, figsize=(13, 3.6))
    for ax, (name, (label, _, _)) in zip(axes, SWEEPS.items()):
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
    parser = quick_parser(__doc__)
    args = parser.parse_args()
    scenario = tdp.scenarios.get("sudden-blockage")
    route = unblocked_route(scenario)
    oracle = oracle_run(scenario, tdp.NavigatorConfig(), scenario.max_ticks)
    plain, _ = run_navigator(scenario, tdp.NavigatorConfig(accelerating=False, updates_per_move=1))
    run_navigator(scenario, tdp.NavigatorConfig(updates_per_move=1))  # warm-up: caches (setup() compiles the kernels)
    baseline = blockage_metrics(scenario, plain, oracle["length"], route)
    print(f"  plain DP, K = 1: ratio {baseline['ratio']:.3f}")
    suffix = "-quick" if args.quick else ""
    rows = []
    for name in SWEEPS:
        mine = sweep(name, QUICK[name] if args.quick else SWEEPS[name][1], scenario, oracle["length"], route)
        path_figure(name, mine, scenario, oracle, RESULTS / f"paper-{name}{suffix}.png")
        rows += mine
    print_table(["sweep", "value", "nodes", "relevant detections", "ratio", "turn after", "closest",
                 "ms/tick median", "mean", "p95", "max"],
                [[r["sweep"], str(r["value"]), str(r["nodes_placed"]), str(r["detections"]), f"{r['ratio']:.3f}",
                  str(r["turn_after"]), f"{r['closest']:.1f}", f"{r['ms_median']:.2f}", f"{r['ms_mean']:.2f}",
                  f"{r['ms_p95']:.2f}", f"{r['ms_max']:.2f}"] for r in rows])
    curves_figure(rows, RESULTS / f"paper-curves{suffix}.png")
    summary = [{k: v for k, v in r.items() if k not in ("trajectory", "modes")} for r in rows]
    path = write_json(f"paper{suffix}", {"machine": machine(), "plain_dp_k1": baseline, "rows": summary})
    print(f"wrote {path} and the figures paper-*{suffix}.png")


if __name__ == "__main__":
    main()
