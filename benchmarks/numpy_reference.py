"""A vectorised numpy implementation of the same all-layer update as tdp's engine: the benchmarks' reference.

Same layers, same windows, same padding and penalty trick (ARCHITECTURE §4); one array per layer kind, every move a
shifted-slice operation over all layers at once.
"""
from __future__ import annotations

import numpy as np

from tdp import stencil

PAD = stencil.REACH


class NumpyDP:
    """Goal layer (H, W) and node windows (n, side, side), relaxed by eqs. 5 and 10 with numpy."""

    def __init__(self, occupied: np.ndarray, goal: tuple[int, int], nodes: np.ndarray, node_cap: float,
                 neighbourhood: int = 16, corner_cutting: bool = False):
        self.moves = stencil.moves(neighbourhood, corner_cutting)
        rows, cols = occupied.shape
        grid_pen = np.full((rows + 2 * PAD, cols + 2 * PAD), np.inf, np.float32)
        grid_pen[PAD:-PAD, PAD:-PAD] = np.where(occupied, np.inf, 0.0)
        self.layers = [self._layer(grid_pen[None], (goal[0] + PAD, goal[1] + PAD), np.float32(np.inf))]
        if len(nodes):
            radius = int(np.ceil(node_cap))
            side = 2 * radius + 1
            big = np.full((rows + 2 * radius + 2 * PAD, cols + 2 * radius + 2 * PAD), np.inf, np.float32)
            big[radius:radius + rows + 2 * PAD, radius:radius + cols + 2 * PAD] = grid_pen
            pen = np.full((len(nodes), side + 2 * PAD, side + 2 * PAD), np.inf, np.float32)
            for k, (r, c) in enumerate(nodes):
                pen[k, PAD:-PAD, PAD:-PAD] = big[r + PAD:r + PAD + side, c + PAD:c + PAD + side]
            self.layers.append(self._layer(pen, (radius + PAD, radius + PAD), np.float32(node_cap)))

    @staticmethod
    def _layer(pen: np.ndarray, source: tuple[int, int], cap: np.float32) -> dict:
        values = np.full(pen.shape, cap, np.float32)
        values[:, source[0], source[1]] = np.where(pen[:, source[0], source[1]] > 0, cap, 0)
        return {"pen": pen, "values": values, "source": source, "cap": cap}

    def step(self) -> None:
        """One synchronous iteration of every layer."""
        for layer in self.layers:
            layer["values"] = self._relaxed(layer)

    def _relaxed(self, layer: dict) -> np.ndarray:
        values, pen, cap = layer["values"], layer["pen"], layer["cap"]
        _, rows, cols = values.shape
        inner = (slice(None), slice(PAD, rows - PAD), slice(PAD, cols - PAD))

        def shifted(array: np.ndarray, dr: int, dc: int) -> np.ndarray:
            return array[:, PAD + dr:rows - PAD + dr, PAD + dc:cols - PAD + dc]

        best = np.full(values[inner].shape, cap, np.float32)
        for m in self.moves:
            cand = shifted(values, m.dr, m.dc) + np.float32(m.cost) + shifted(pen, m.dr, m.dc)
            for cr, cc in m.crossed:
                cand += shifted(pen, cr, cc)
            np.minimum(best, cand, out=best)
        new = values.copy()
        new[inner] = np.where(pen[inner] > 0, cap, best)
        sr, sc = layer["source"]
        new[:, sr, sc] = np.where(pen[:, sr, sc] > 0, cap, 0)
        return new

    def goal_distances(self) -> np.ndarray:
        return self.layers[0]["values"][0, PAD:-PAD, PAD:-PAD]
