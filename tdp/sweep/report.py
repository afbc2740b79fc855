"""A sweep's results as tables and a figure: the tidy table of episodes (one row each, the spec's coordinates as
columns, the ratio to the oracle added), the summary per world group, planner and configuration, and the mean
ratio against each swept parameter, per group."""
from __future__ import annotations

import csv
import math
from pathlib import Path

import numpy as np

from ..config import STENCIL_FIELDS
from .spec import Spec

WORLD_COLUMNS = ("world", "group", "size", "seed", "planner")
METRICS = ("reached", "ticks", "length", "ratio", "collisions", "hits", "waits", "yields", "backup_ticks",
           "detections", "relevant_detections", "nodes_placed", "setup_s", "ms_median", "ms_mean", "ms_p95", "ms_max")


def tidy(spec: Spec, rows: list[dict]) -> list[dict]:
    """The journal's rows as flat records: the world's columns, the planner, the spec's fields (empty where the
    planner has no such field), the metrics with ``ratio`` (length / the oracle's on the same world and stencil;
    nan unless both reached), the extra metrics that are single values, and the episode's key."""
    oracle = {(r["world"], _stencil(r)): r for r in rows if r["planner"] == "oracle"}
    known = set(WORLD_COLUMNS) | set(METRICS) | {"config", "key"}
    out = []
    for row in rows:
        best = oracle.get((row["world"], _stencil(row)))
        ratio = math.nan
        if best and row["reached"] and best["reached"] and best["length"] > 0:
            ratio = row["length"] / best["length"]
        extra = {k: v for k, v in row.items()
                 if k not in known and (v is None or isinstance(v, (bool, int, float, str)))}
        out.append({**{c: row[c] for c in WORLD_COLUMNS}, **{c: row["config"].get(c) for c in spec.columns},
                    **{m: row.get(m) for m in METRICS}, "ratio": ratio, **extra, "key": row["key"]})
    return out


def _stencil(row: dict) -> tuple:
    return tuple(row["config"][name] for name in STENCIL_FIELDS)


def summarise(spec: Spec, table: list[dict]) -> list[dict]:
    """Per world group, planner and configuration (the spec's fields): episodes, reached %, mean and max ratio
    (over the episodes reached), collisions, hits, wait ticks, detections, and the median of the episodes' median
    planner time per tick (ms)."""
    groups: dict[tuple, list[dict]] = {}
    for row in table:
        groups.setdefault(tuple(row[c] for c in ("group", "planner", *spec.columns)), []).append(row)
    out = []
    for coords, mine in groups.items():
        ratios = [r["ratio"] for r in mine if not math.isnan(r["ratio"])]
        out.append({**dict(zip(("group", "planner", *spec.columns), coords)), "episodes": len(mine),
                    "reached_pct": 100.0 * sum(r["reached"] for r in mine) / len(mine),
                    "mean_ratio": float(np.mean(ratios)) if ratios else math.nan,
                    "max_ratio": float(np.max(ratios)) if ratios else math.nan,
                    **{m: sum(r[m] for r in mine) for m in ("collisions", "hits", "waits", "detections")},
                    "ms_median": float(np.median([r["ms_median"] for r in mine]))})
    return out


def write_csv(records: list[dict], path: Path) -> Path:
    """``records`` as CSV (the union of their keys as columns, empty for None)."""
    columns = list(dict.fromkeys(k for r in records for k in r))
    with open(path, "w", newline="") as file:
        writer = csv.DictWriter(file, columns, restval="")
        writer.writeheader()
        writer.writerows({k: "" if v is None else v for k, v in r.items()} for r in records)
    return path


def write_parquet(records: list[dict], path: Path) -> Path | None:
    """``records`` as Parquet where pyarrow is installed (None where it is not)."""
    try:
        import pyarrow
        import pyarrow.parquet
    except ImportError:
        return None
    pyarrow.parquet.write_table(pyarrow.Table.from_pylist(records), path)
    return path


def swept(spec: Spec, table: list[dict]) -> list[str]:
    """The spec's fields that take more than one value in ``table``."""
    return [c for c in spec.columns if len({r[c] for r in table if r[c] is not None}) > 1]


def ratio_figure(spec: Spec, table: list[dict], path: Path) -> Path:
    """Mean ratio to the oracle against each swept field (one panel each; a planner without the field is a level
    line in its own style, its mean over all its episodes), a line per world group and planner; bars per group
    and planner when nothing is swept."""
    from ..plot import pyplot, save_figure

    plt = pyplot()
    fields = swept(spec, table) or [None]
    fig, axes = plt.subplots(1, len(fields), figsize=(5.2 * len(fields), 4), squeeze=False)
    groups = list(dict.fromkeys(r["group"] for r in table))
    planners = [p for p in dict.fromkeys(r["planner"] for r in table) if p != "oracle"]
    colours = dict(zip(groups, plt.cm.tab10(np.linspace(0, 1, 10))))
    styles = dict(zip(planners, ("o-", "s--", "^:", "d-.")))
    for ax, field in zip(axes[0], fields):
        for g, group in enumerate(groups):
            for p, planner in enumerate(planners):
                mine = [r for r in table if r["group"] == group and r["planner"] == planner
                        and not math.isnan(r["ratio"])]
                if not mine:
                    continue
                label = f"{group}, {planner}"
                if field is None:
                    ax.bar(g + p * 0.8 / len(planners), np.mean([r["ratio"] for r in mine]), 0.8 / len(planners),
                           color=colours[group], alpha=1 - 0.25 * p, label=label)
                elif mine[0][field] is None:
                    ax.axhline(np.mean([r["ratio"] for r in mine]), color=colours[group], ls=styles[planner][1:],
                               lw=1, alpha=0.7, label=f"{label} (all)")
                else:
                    values = sorted({r[field] for r in mine})
                    means = [np.mean([r["ratio"] for r in mine if r[field] == v]) for v in values]
                    ax.plot(values, means, styles[planner], color=colours[group], label=label)
        ax.set_xlabel(field or "world group")
        if field is None:
            ax.set_xticks(range(len(groups)))
            ax.set_xticklabels(groups, rotation=20, fontsize=8)
        ax.set_ylabel("mean path length / oracle")
        ax.grid(alpha=0.3)
        ax.legend(fontsize=6, loc="best")
    fig.suptitle(f"sweep {spec.name}: {len(table)} episodes", fontsize=10)
    return save_figure(fig, path)


def write_report(spec: Spec, rows: list[dict], out: Path) -> list[Path]:
    """Write episodes.csv (and .parquet where pyarrow exists), summary.csv and ratio.png into ``out``; the tables
    first, so that a figure that cannot be drawn loses nothing. Returns the paths written."""
    table = tidy(spec, rows)
    summary = summarise(spec, table)
    written = [write_csv(table, out / "episodes.csv"), write_parquet(table, out / "episodes.parquet"),
               write_csv(summary, out / "summary.csv")]
    if table:
        written.append(ratio_figure(spec, table, out / "ratio.png"))
    return [p for p in written if p is not None]
