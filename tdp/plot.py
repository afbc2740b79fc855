"""Figures (PNG) of maps and paths; needs matplotlib (``pip install tdp[plot]``)."""
from __future__ import annotations

from pathlib import Path

import numpy as np

from .grid import GridMap


def _pyplot():
    try:
        import matplotlib
    except ImportError:
        raise ValueError("figures need matplotlib: pip install 'tdp[plot]'") from None
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    return plt


def draw_map(ax, occupied: np.ndarray) -> None:
    """Obstacles black on white, cell (r, c) centred at x = c, y = r, row 0 at the top."""
    ax.imshow(occupied, cmap="gray_r", vmin=0, vmax=1.6, interpolation="nearest")
    ax.set_xlim(-0.5, occupied.shape[1] - 0.5)
    ax.set_ylim(occupied.shape[0] - 0.5, -0.5)
    ax.set_xticks([])
    ax.set_yticks([])


def save_path_figure(grid: GridMap, path: list[tuple[int, int]], out: str | Path, title: str = "",
                     distances: np.ndarray | None = None) -> Path:
    """Write a PNG of the map, the distance field (if given) and the path; returns the file written."""
    plt = _pyplot()
    fig, ax = plt.subplots(figsize=(6, 6 * grid.shape[0] / grid.shape[1] + 0.4))
    if distances is not None:
        shown = np.where(np.isfinite(distances) & ~grid.occupied, distances, np.nan)
        ax.imshow(shown, cmap="viridis", interpolation="nearest", alpha=0.45)
    draw_map(ax, np.where(grid.occupied, 1.0, np.nan))
    if path:
        rows, cols = np.array(path).T
        ax.plot(cols, rows, "-", color="tab:red", lw=2)
        ax.plot(cols[0], rows[0], "o", color="tab:green", ms=8, label="start")
        ax.plot(cols[-1], rows[-1], "*", color="tab:red", ms=14, label="goal")
        ax.legend(loc="upper right", fontsize=8)
    ax.set_title(title, fontsize=9)
    out = Path(out)
    out.parent.mkdir(parents=True, exist_ok=True)
    fig.tight_layout()
    fig.savefig(out, dpi=120)
    plt.close(fig)
    return out
