"""The blockage scenarios, side by side: accelerating nodes (several lattices), plain DP, the oracle and D* Lite.

    python -m benchmarks.blockage [--quick]

For K (DP iterations per move) in 1, 2, 4, 8, on sudden-blockage and moving-blockage: the path-length ratio to
the oracle, the ticks from the change to the robot's turn (the first tick it leaves the route it would have driven
without the blockage), the closest approach to the blocking box (cells), and planner time per tick (ms: mean, p95,
max, warm). D* Lite (plain Python, same graph and corner rule) and the oracle repair or redo their search every
tick, so K does not apply to them.
"""
from __future__ import annotations


import tdp
from tdp.dstar_lite import DStarLite
from benchmarks.common import (blockage_metrics, print_table, quick_parser, run_navigator, save_results,
                               unblocked_route)
from tdp.simulate import oracle_run, run_planner

VARIANTS = {"accelerating, 16 nodes": {"nodes": 16}, "accelerating, 25 nodes": {"nodes": 25},
            "accelerating, 49 nodes": {"nodes": 49}, "plain DP": {"planner": "plain-dp"}}
QUICK_VARIANTS = {"accelerating, 25 nodes": {"nodes": 25}, "plain DP": {"planner": "plain-dp"}}


def run_scenario(name: str, ks: list[int], variants: dict) -> list[dict]:
    scenario = tdp.scenarios.get(name)
    base = tdp.NavigatorConfig()
    route = unblocked_route(scenario)  # also warms up the oracle's kernels
    oracle = oracle_run(scenario, base, scenario.max_ticks)
    rows = [{"scenario": name, "planner": "oracle", "k": None,
             **blockage_metrics(scenario, oracle, oracle["length"], route)}]
    dstar = DStarLite(scenario.occupancy(0), scenario.start, scenario.goal)
    rows.append({"scenario": name, "planner": "D* Lite (Python)", "k": None,
                 **blockage_metrics(scenario, run_planner(scenario, dstar, base, scenario.max_ticks),
                                    oracle["length"], route)})
    warm = tdp.NavigatorConfig(planner="accelerating", updates_per_move=1)
    run_navigator(scenario, warm)  # warm-up: caches (setup() compiles the kernels)
    for k in ks:
        for label, options in variants.items():
            config = tdp.NavigatorConfig(**{"planner": "accelerating", "updates_per_move": k, **options})
            record, _ = run_navigator(scenario, config)
            rows.append({"scenario": name, "planner": label, "k": k,
                         **blockage_metrics(scenario, record, oracle["length"], route)})
            r = rows[-1]
            print(f"  {name}, K = {k}, {label}: ratio {r['ratio']:.3f}, turn +{r['turn_after']}, "
                  f"closest {r['closest']:.1f}, {r['ms_mean']:.2f} ms/tick", flush=True)
    return rows


def figure(rows: list[dict], path) -> None:
    from tdp.plot import pyplot, save_figure

    plt = pyplot()

    names = list(dict.fromkeys(r["scenario"] for r in rows))
    fig, axes = plt.subplots(2, len(names), figsize=(5.5 * len(names), 7), squeeze=False)
    for column, name in enumerate(names):
        mine = [r for r in rows if r["scenario"] == name]
        for label in dict.fromkeys(r["planner"] for r in mine if r["k"] is not None):
            series = [r for r in mine if r["planner"] == label]
            ks = [r["k"] for r in series]
            axes[0, column].plot(ks, [r["ratio"] for r in series], "o-", label=label)
            axes[1, column].plot(ks, [r["ms_mean"] for r in series], "o-", label=label)
        for r in mine:
            if r["k"] is None:
                colour = "0.4" if r["planner"] == "oracle" else "tab:red"
                axes[0, column].axhline(r["ratio"], ls="--", lw=1, color=colour, label=r["planner"])
                axes[1, column].axhline(r["ms_mean"], ls="--", lw=1, color=colour, label=r["planner"])
        axes[0, column].set_title(name)
        axes[0, column].set_ylabel("path length / oracle")
        axes[1, column].set_ylabel("planner ms per tick (mean)")
        axes[1, column].set_yscale("log")
        for ax in axes[:, column]:
            ax.set_xscale("log", base=2)
            ax.set_xlabel("K (DP iterations per move)")
        axes[0, column].legend(fontsize=7)
    save_figure(fig, path)


def main() -> None:
    parser = quick_parser(__doc__)
    args = parser.parse_args()
    names = ["sudden-blockage"] if args.quick else ["sudden-blockage", "moving-blockage"]
    ks, variants = ([1, 4], QUICK_VARIANTS) if args.quick else ([1, 2, 4, 8], VARIANTS)
    rows = [row for name in names for row in run_scenario(name, ks, variants)]
    print_table(["scenario", "planner", "K", "reached", "ratio", "turn after (ticks)", "closest (cells)",
                 "ms/tick median", "mean", "p95", "max"],
                [[r["scenario"], r["planner"], "-" if r["k"] is None else str(r["k"]), str(r["reached"]),
                  f"{r['ratio']:.3f}", str(r["turn_after"]), f"{r['closest']:.1f}", f"{r['ms_median']:.2f}",
                  f"{r['ms_mean']:.2f}",
                  f"{r['ms_p95']:.2f}", f"{r['ms_max']:.2f}"] for r in rows])
    save_results("blockage-quick" if args.quick else "blockage", {"rows": rows}, lambda png: figure(rows, png))


if __name__ == "__main__":
    main()
