"""Animations of episodes (GIF, and MP4 where ffmpeg exists); needs matplotlib (``pip install tdp[plot]``).

Each frame is one tick: the map, the boxes where they are, the robot's trail coloured by mode, the nodes, the node
pairs detected blocked in the last few ticks (red), the backup route the robot follows (orange), the target.
Several episodes of one scenario play side by side, so that planners can be compared tick by tick.
"""
from __future__ import annotations

import shutil
import sys
from pathlib import Path

import numpy as np

from .config import planner_label
from .contract import Mode
from .plot import MODE_COLOURS, draw_map, pyplot
from .simulate import Episode
from .world import Scenario

#: Ticks a blocked pair stays drawn after its detection.
BLOCKED_TICKS = 10


#: Frames an animation has at most: longer episodes show every second (third, ...) tick.
MAX_FRAMES = 150


def save_episode_animation(scenario: Scenario, episodes: list[Episode], out: str | Path, fps: int = 15,
                           progress: bool = False) -> list[Path]:
    """Write an animated GIF at ``out`` (and an MP4 beside it where ffmpeg exists) of ``episodes`` side by side,
    a frame per tick (every n-th tick beyond MAX_FRAMES, and always the last); returns the files written."""
    plt = pyplot()
    from matplotlib.animation import FFMpegWriter, PillowWriter

    out = Path(out)
    out.parent.mkdir(parents=True, exist_ok=True)
    ticks = max(e.ticks for e in episodes)
    width = 4.2 * len(episodes)
    fig, axes = plt.subplots(1, len(episodes), figsize=(width, 4.6), squeeze=False)
    panels = [_Panel(ax, scenario, episode) for ax, episode in zip(axes[0], episodes)]
    fig.tight_layout()
    fig.set_layout_engine(None)  # laid out once: with tight_layout's engine left set, each frame drew twice

    def frame(tick: int):
        if progress and tick % 100 == 0:
            print(f"  animation: frame {tick}/{ticks}", file=sys.stderr, flush=True)
        return [artist for panel in panels for artist in panel.show(tick)]

    step = -(-(ticks + 1) // MAX_FRAMES)
    frames = sorted(set(range(0, ticks + 1, step)) | {ticks})
    written = [out]
    _record(fig, frames, frame, PillowWriter(fps=fps), out, dpi=80)
    if shutil.which("ffmpeg"):
        _record(fig, frames, frame, FFMpegWriter(fps=fps), out.with_suffix(".mp4"), dpi=100)
        written.append(out.with_suffix(".mp4"))
    plt.close(fig)
    return written


def _record(fig, frames: list[int], show, writer, path: Path, dpi: int) -> None:
    """Each of ``frames`` shown by ``show(tick)`` and grabbed by ``writer`` into ``path``: one drawing of the
    figure a frame (matplotlib's FuncAnimation drew each frame twice more, for a screen there is none of)."""
    with writer.saving(fig, path, dpi):
        for tick in frames:
            show(tick)
            writer.grab_frame()


class _Panel:
    """One episode's axes and the artists that change from frame to frame."""

    def __init__(self, ax, scenario: Scenario, episode: Episode):
        self.scenario, self.episode = scenario, episode
        self.nodes = np.array(episode.nodes, float).reshape(-1, 2)
        self.trajectory = np.array(episode.trajectory, float)
        self.modes = list(episode.modes)
        self.target = [tuple(t) for t in _target_path(scenario, episode)]
        draw_map(ax, scenario.grid.occupied, scenario.grid.cost)
        ax.set_title(planner_label(episode.config), fontsize=9)
        if len(self.nodes):
            ax.plot(self.nodes[:, 1], self.nodes[:, 0], "o", mfc="none", mec="tab:purple", ms=4)
        self.boxes = ax.imshow(np.ma.masked_all(scenario.grid.shape), cmap="Oranges", vmin=0, vmax=1.2,
                               interpolation="nearest")
        self.trails = {mode: ax.plot([], [], ".", color=colour, ms=2.5)[0] for mode, colour in MODE_COLOURS.items()}
        self.blocked = ax.plot([], [], "-", color="tab:red", lw=1.6)[0]
        self.backup = ax.plot([], [], "--", color="tab:orange", lw=1.2)[0]
        self.robot = ax.plot([], [], "o", color="black", ms=5)[0]
        self.goal = ax.plot([], [], "*", color="tab:red", ms=11)[0]
        self.label = ax.text(0.02, 0.02, "", transform=ax.transAxes, fontsize=8,
                             bbox={"facecolor": "white", "alpha": 0.8, "lw": 0})

    def show(self, tick: int) -> list:
        episode = self.episode
        t = min(tick, episode.ticks)
        boxes = self.scenario.occupancy(t) & ~self.scenario.grid.occupied
        self.boxes.set_data(np.ma.masked_array(np.ones(boxes.shape), mask=~boxes))
        for mode, trail in self.trails.items():
            cells = self.trajectory[1:t + 1][[m is mode for m in self.modes[:t]]] if t else np.zeros((0, 2))
            trail.set_data(cells[:, 1], cells[:, 0])
        robot = self.trajectory[t]
        self.robot.set_data([robot[1]], [robot[0]])
        goal = self.target[min(t, len(self.target) - 1)]
        self.goal.set_data([goal[1]], [goal[0]])
        self.blocked.set_data(*_segments(self.nodes, [d["pair"] for d in episode.detections
                                                      if t - BLOCKED_TICKS < d["tick"] <= t]))
        self.backup.set_data(*self._backup_route(t, robot, goal))
        mode = self.modes[t - 1] if 0 < t <= len(self.modes) else Mode.DP
        self.label.set_text(f"tick {t}  {mode}")
        return [self.boxes, self.blocked, self.backup, self.robot, self.goal, self.label, *self.trails.values()]

    def _backup_route(self, tick: int, robot, goal) -> tuple[list, list]:
        """The last backup path found up to ``tick``, while the robot is following it."""
        if not (0 < tick <= len(self.modes)) or self.modes[tick - 1] is not Mode.BACKUP:
            return [], []
        found = [b for b in self.episode.backups if b["tick"] <= tick]
        if not found:
            return [], []
        n = len(self.nodes)
        points = [robot if v == n else goal if v == n + 1 else self.nodes[v] for v in found[-1]["path"]]
        points = np.array(points, float)
        return list(points[:, 1]), list(points[:, 0])


def _segments(nodes: np.ndarray, pairs: list) -> tuple[list, list]:
    """x and y lists drawing each pair of nodes as a segment (separated by NaN)."""
    xs, ys = [], []
    for a, b in pairs:
        xs += [nodes[a, 1], nodes[b, 1], np.nan]
        ys += [nodes[a, 0], nodes[b, 0], np.nan]
    return xs, ys


def _target_path(scenario: Scenario, episode: Episode) -> list:
    """The target's cell at every tick of the episode."""
    return [scenario.target(t) for t in range(episode.ticks + 1)]
