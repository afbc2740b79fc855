"""Figures (PNG) of maps and paths; needs matplotlib (``pip install tdp[plot]``)."""
from __future__ import annotations

from pathlib import Path

import numpy as np

from .config import planner_label
from .contract import Mode
from .grid import GridMap


def pyplot():
    """matplotlib.pyplot on the headless Agg backend; a clear error if matplotlib is missing."""
    try:
        import matplotlib
    except ImportError:
        raise ValueError("figures need matplotlib: pip install 'tdp-planner[plot]'") from None
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    return plt


def save_figure(fig, out: str | Path) -> Path:
    """Write ``fig`` as a PNG at ``out`` (creating its folder), close it, and return the path."""
    out = Path(out)
    out.parent.mkdir(parents=True, exist_ok=True)
    fig.tight_layout()
    fig.savefig(out, dpi=120)
    pyplot().close(fig)
    return out


def draw_map(ax, occupied: np.ndarray, cost: np.ndarray | None = None):
    """Obstacles black on white, cell (r, c) centred at x = c, y = r, row 0 at the top; with ``cost`` (a map's
    traversal costs) the free cells above 1 shaded yellow to red. Returns the cost shading's image (for a colour
    bar), or None."""
    ax.imshow(occupied, cmap="gray_r", vmin=0, vmax=1.6, interpolation="nearest")
    shading = None
    if cost is not None:
        shading = ax.imshow(np.ma.masked_where(occupied | (cost <= 1), cost), cmap="YlOrRd", vmin=1,
                            vmax=max(float(cost[~occupied].max(initial=1.0)), 1.0 + 1e-6), interpolation="nearest",
                            alpha=0.8)
    ax.set_xlim(-0.5, occupied.shape[1] - 0.5)
    ax.set_ylim(occupied.shape[0] - 0.5, -0.5)
    ax.set_xticks([])
    ax.set_yticks([])
    return shading


def cost_bar(fig, ax, shading) -> None:
    """A colour bar for :func:`draw_map`'s cost shading, if there is one."""
    if shading is not None:
        fig.colorbar(shading, ax=ax, fraction=0.046, label="traversal cost (1: open ground)")


def map_figsize(shape: tuple[int, int], longest_in: float = 6.0, shortest_in: float = 2.0) -> tuple[float, float]:
    """A figure's (width, height) in inches for a map of ``shape`` (rows, cols) cells: its longer side
    ``longest_in``, the other in the map's proportion but at least ``shortest_in``, and 0.4 more in height for a
    title. Sized by the map's proportion alone, a map of 3,000 x 2 cells asked for a figure 9,000 inches tall
    (matplotlib took 23 GB and was killed)."""
    rows, cols = shape
    short = max(longest_in * min(rows, cols) / max(rows, cols), shortest_in)
    width, height = (longest_in, short) if cols >= rows else (short, longest_in)
    return width, height + 0.4


def save_path_figure(grid: GridMap, path: list[tuple[int, int]], out: str | Path, title: str = "",
                     distances: np.ndarray | None = None) -> Path:
    """Write a PNG of the map, its costs or else the distance field (if given), and the path; returns the file
    written."""
    plt = pyplot()
    fig, ax = plt.subplots(figsize=map_figsize(grid.shape))
    if distances is not None and grid.cost is None:
        shown = np.where(np.isfinite(distances) & ~grid.occupied, distances, np.nan)
        ax.imshow(shown, cmap="viridis", interpolation="nearest", alpha=0.45)
        draw_map(ax, np.where(grid.occupied, 1.0, np.nan))
    else:
        cost_bar(fig, ax, draw_map(ax, grid.occupied, grid.cost))
    if path:
        rows, cols = np.array(path).T
        ax.plot(cols, rows, "-", color="tab:red", lw=2)
        ax.plot(cols[0], rows[0], "o", color="tab:green", ms=8, label="start")
        ax.plot(cols[-1], rows[-1], "*", color="tab:red", ms=14, label="goal")
        ax.legend(loc="upper right", fontsize=8)
    ax.set_title(title, fontsize=9)
    return save_figure(fig, out)


MODE_COLOURS = {Mode.DP: "tab:blue", Mode.BACKUP: "tab:orange", Mode.WAIT: "tab:red", Mode.YIELD: "tab:purple",
                Mode.EXACT: "tab:green", Mode.BEHIND: "tab:olive", Mode.DSTAR: "tab:cyan"}


def box_patch(plt, box, **style):
    """A matplotlib rectangle covering the cells of ``box`` = (r0, c0, r1, c1) in a :func:`draw_map` axes."""
    r0, c0, r1, c1 = box
    return plt.Rectangle((c0 - 0.5, r0 - 0.5), c1 - c0, r1 - r0, **style)


def oracle_text(episode) -> str:
    """An Episode's oracle length (cells, one decimal) as titles and summaries show it; "not reached" where the
    oracle found no way."""
    return f"{episode.oracle_length:.1f}" if episode.oracle_reached else "not reached"


def save_episode_figure(scenario, episode, out: str | Path) -> Path:
    """A top-down figure like the paper's: map, nodes and their edges, the trajectory coloured by mode, the
    oracle's path, obstacles' first (outline) and last (filled) positions, the target path, the turn point A and
    the switch-back point B."""
    plt = pyplot()
    fig, ax = plt.subplots(figsize=(7, 7.4))
    cost_bar(fig, ax, draw_map(ax, scenario.grid.occupied, scenario.grid.cost))
    nodes = np.array(episode.nodes).reshape(-1, 2)
    for a, b in episode.edges:
        ax.plot(nodes[[a, b], 1], nodes[[a, b], 0], "-", color="0.8", lw=0.6, zorder=1)
    if len(nodes):
        ax.plot(nodes[:, 1], nodes[:, 0], "o", mfc="none", mec="tab:purple", ms=6, label="accelerating nodes")
    last = episode.ticks
    for obstacle in scenario.obstacles:
        first = obstacle.appear_at or 0
        ax.add_patch(box_patch(plt, obstacle.footprint(first), fill=False, ec="tab:brown", lw=1.2, ls="--"))
        end = min(last, (obstacle.vanish_at - 1) if obstacle.vanish_at else last)
        if obstacle.present(end):
            ax.add_patch(box_patch(plt, obstacle.footprint(end), color="tab:brown", alpha=0.6))
    oracle = np.array(episode.oracle_trajectory)
    ax.plot(oracle[:, 1], oracle[:, 0], ":", color="0.35", lw=1.3, label="oracle")
    trajectory = np.array(episode.trajectory)
    for k, mode in enumerate(episode.modes):
        ax.plot(trajectory[k:k + 2, 1], trajectory[k:k + 2, 0], "-", color=MODE_COLOURS[mode], lw=2.2)
    for mode, colour in MODE_COLOURS.items():
        if mode in episode.modes:
            ax.plot([], [], "-", color=colour, lw=2.2, label=f"robot: {mode}")
    target = np.array(episode.target_path)
    if len(target) > 1:
        ax.plot(target[:, 1], target[:, 0], "--", color="tab:green", lw=1.5, label="target path")
    ax.plot(trajectory[0, 1], trajectory[0, 0], "s", color="tab:green", ms=8)
    ax.plot(target[-1, 1], target[-1, 0], "*", color="tab:red", ms=14)
    for name, point in (("A", episode.turn_point), ("B", episode.switch_back_point)):
        if point is not None:
            ax.annotate(name, (point[1], point[0]), xytext=(6, -6), textcoords="offset points", fontsize=13,
                        weight="bold", color="black")
            ax.plot(point[1], point[0], "kx", ms=9, mew=2)
    ax.set_title(f"{episode.scenario}, {planner_label(episode.config)}: "
                 f"length {episode.length:.1f} (oracle {oracle_text(episode)}, ratio {episode.ratio:.3f})",
                 fontsize=9)
    ax.legend(loc="lower left", fontsize=7, framealpha=0.85)
    return save_figure(fig, out)
