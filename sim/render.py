"""Top-down figure of a PyBullet episode: map, nodes, the robot's trace coloured by mode, obstacles' traces."""
from __future__ import annotations

from dataclasses import fields
from pathlib import Path

import numpy as np

import tdp
from tdp.config import planner_label
from tdp.plot import MODE_COLOURS, box_patch, cost_bar, draw_map, pyplot, save_figure

from .episode import SimConfig


def _static_costs(scenario: tdp.Scenario, settings: dict) -> np.ndarray | None:
    """The traversal costs the planner saw on the static map (the world's, raised by the run's inflation cost round
    the grown walls, which show at the dearest cost; the boxes' moved with them), or None on a binary run."""
    sim = SimConfig(**{field.name: settings[field.name] for field in fields(SimConfig)})
    grown = scenario.grid.inflate(sim.inflate_m / settings["cell_m"]).occupied
    cost = sim.costs(grown, settings["cell_m"], scenario.grid.cost)
    return None if cost is None else np.where(grown, cost.max(), cost)


def oracle_text(metrics: dict) -> str:
    """The oracle's length in a run's metrics (from :func:`sim.episode.run_episode`) as tables and titles show it:
    metres, "not reached" where the oracle found no way for the robot, "-" where the episode has no oracle."""
    if metrics["oracle_reached"] is False:
        return "not reached"
    return "-" if metrics["oracle_length_m"] is None else f"{metrics['oracle_length_m']:.2f} m"


def save_trace_figure(scenario: tdp.Scenario, metrics: dict, out: str | Path) -> Path:
    """Write a PNG of the run in ``metrics`` (from :func:`sim.episode.run_episode`); returns the file written."""
    plt = pyplot()
    cell, rows = metrics["sim"]["cell_m"], scenario.grid.shape[0]

    def to_cells(x, y):
        return np.asarray(x) / cell - 0.5, rows - np.asarray(y) / cell - 0.5

    fig, ax = plt.subplots(figsize=(7, 7.4))
    cost_bar(fig, ax, draw_map(ax, scenario.grid.occupied, _static_costs(scenario, metrics["sim"])))
    nodes = np.array(metrics["nodes"]).reshape(-1, 2)
    if len(nodes):
        ax.plot(nodes[:, 1], nodes[:, 0], "o", mfc="none", mec="tab:purple", ms=6, label="accelerating nodes")
    for obstacle in scenario.obstacles:
        ticks = range(obstacle.appear_at or 0, min(metrics["ticks"], obstacle.vanish_at or metrics["ticks"]) + 1)
        corners = np.array([obstacle.corner(t) for t in ticks])
        r0, c0, r1, c1 = obstacle.box
        ax.plot(corners[:, 1] + (c1 - c0) / 2 - 0.5, corners[:, 0] + (r1 - r0) / 2 - 0.5, "-", color="tab:brown",
                lw=1, alpha=0.7)
        ax.add_patch(box_patch(plt, obstacle.footprint(ticks[0]), fill=False, ec="tab:brown", ls="--"))
        ax.add_patch(box_patch(plt, obstacle.footprint(ticks[-1]), color="tab:brown", alpha=0.6))
    oracle = np.array(metrics["oracle_trajectory"]).reshape(-1, 2)
    ax.plot(oracle[:, 1], oracle[:, 0], ":", color="0.35", lw=1.3, label="oracle (grid)")
    trace = metrics["trace"]
    for (x0, y0, _), (x1, y1, mode) in zip(trace, trace[1:]):
        cols, rows_ = to_cells([x0, x1], [y0, y1])
        ax.plot(cols, rows_, "-", color=MODE_COLOURS[mode], lw=2.2)
    for mode in dict.fromkeys(metrics["modes"]):
        ax.plot([], [], "-", color=MODE_COLOURS[mode], lw=2.2, label=f"robot: {mode}")
    for name in ("turn_point", "switch_back_point"):
        if metrics[name] is not None:
            c, r = to_cells(*metrics[name])
            ax.plot(c, r, "kx", ms=9, mew=2)
            ax.annotate("A" if name == "turn_point" else "B", (c, r), xytext=(6, -6), textcoords="offset points",
                        fontsize=13, weight="bold")
    ax.set_title(f"PyBullet {metrics['scenario']}, {planner_label(metrics['config'])}: "
                 f"{metrics['path_length_m']:.2f} m (oracle {oracle_text(metrics)}), "
                 f"contacts {metrics['contacts']}", fontsize=9)
    ax.legend(loc="lower left", fontsize=7, framealpha=0.85)
    return save_figure(fig, out)


def save_frames_animation(films: list[tuple[str, list]], out: str | Path, fps: int = 10) -> Path:
    """An animated GIF of camera pictures, one film per column with its title above (films may differ in length:
    a finished one holds its last picture). Returns the file written."""
    from PIL import Image, ImageDraw

    out = Path(out)
    out.parent.mkdir(parents=True, exist_ok=True)
    height, width = films[0][1][0].shape[:2]
    pictures = []
    for k in range(max(len(frames) for _, frames in films)):
        canvas = Image.new("RGB", (width * len(films), height + 18), "white")
        draw = ImageDraw.Draw(canvas)
        for column, (title, frames) in enumerate(films):
            canvas.paste(Image.fromarray(frames[min(k, len(frames) - 1)]), (column * width, 18))
            draw.text((column * width + 6, 3), title, fill="black")
        pictures.append(canvas)
    pictures[0].save(out, save_all=True, append_images=pictures[1:], duration=int(1000 / fps), loop=0)
    return out
