"""Accelerating-node placement (paper 3.3, DESIGN 5.1) and the node graph (eq. 14)."""
from __future__ import annotations

import math
from typing import NamedTuple

import numpy as np


class Lattice(NamedTuple):
    """Placed nodes: ``cells`` (n, 2) int (row, col), the lattice ``spacing`` in cells."""

    cells: np.ndarray
    spacing: float


def spacing_for(shape: tuple[int, int], count: int) -> float:
    """The spacing s (cells) of a uniform lattice of about ``count`` nodes on a map of ``shape``."""
    if isinstance(count, bool) or not isinstance(count, int) or count < 1:
        raise ValueError(f"nodes must be a positive integer, got {count!r}")
    return math.sqrt(shape[0] * shape[1] / count)


def place_nodes(occupied: np.ndarray, *, count: int | None = None, spacing: float | None = None,
                nudge: bool = False) -> Lattice:
    """Uniform lattice of nodes at ((k + 1/2) s) in rows and columns (DESIGN 5.1).

    Give ``count`` (s follows from the map's area) or ``spacing`` s in cells. A node on an obstacle is dropped, as
    in the paper, or with ``nudge`` moved to the nearest free cell within s/4 (dropped if there is none).
    """
    if (count is None) == (spacing is None):
        raise ValueError("give exactly one of nodes (a count) or spacing")
    if spacing is None:
        spacing = spacing_for(occupied.shape, count)
    if isinstance(spacing, bool) or not isinstance(spacing, (int, float)) or not 1 <= spacing < math.inf:
        raise ValueError(f"spacing must be a number of cells >= 1, got {spacing!r}")
    rows = [int((k + 0.5) * spacing) for k in range(int(occupied.shape[0] / spacing + 0.5))]
    cols = [int((k + 0.5) * spacing) for k in range(int(occupied.shape[1] / spacing + 0.5))]
    cells = []
    for r in rows:
        for c in cols:
            if r >= occupied.shape[0] or c >= occupied.shape[1]:
                continue
            cell = (r, c) if not occupied[r, c] else (_nearest_free(occupied, (r, c), spacing / 4) if nudge else None)
            if cell is not None:
                cells.append(cell)
    return Lattice(np.array(cells, np.int32).reshape(-1, 2), float(spacing))


def _nearest_free(occupied: np.ndarray, cell: tuple[int, int], radius: float) -> tuple[int, int] | None:
    """The free cell nearest to ``cell`` within Euclidean ``radius`` (ties: row-major first), or None."""
    reach = int(radius)
    best, best_d = None, math.inf
    for r in range(cell[0] - reach, cell[0] + reach + 1):
        for c in range(cell[1] - reach, cell[1] + reach + 1):
            d = math.hypot(r - cell[0], c - cell[1])
            inside = 0 <= r < occupied.shape[0] and 0 <= c < occupied.shape[1]
            if inside and d <= radius and d < best_d and not occupied[r, c]:
                best, best_d = (r, c), d
    return best
