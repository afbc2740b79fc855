"""The DP's grid graph as a scipy sparse matrix, built with vectorised numpy (for the benchmarks' Dijkstra)."""
from __future__ import annotations

import numpy as np
from scipy.sparse import coo_matrix

from tdp import stencil


def grid_graph(occupied: np.ndarray, neighbourhood: int = 16, corner_cutting: bool = False,
               cost: np.ndarray | None = None):
    """CSR matrix with an edge V -> V + (dr, dc) of weight |move| for every move allowed by ARCHITECTURE §4; with
    ``cost`` (H, W), |move| x (cost[V] + cost[V + move]) / 2, in float64."""
    rows, cols = occupied.shape
    reach = stencil.REACH
    free = np.zeros((rows + 2 * reach, cols + 2 * reach), bool)
    free[reach:-reach, reach:-reach] = ~occupied
    index = np.arange(rows * cols).reshape(rows, cols)
    sources, targets, weights = [], [], []

    def shifted(dr: int, dc: int) -> np.ndarray:
        return free[reach + dr:reach + dr + rows, reach + dc:reach + dc + cols]

    for move in stencil.moves(neighbourhood, corner_cutting):
        allowed = shifted(0, 0) & shifted(move.dr, move.dc)
        for dr, dc in move.crossed:
            allowed &= shifted(dr, dc)
        r, c = np.nonzero(allowed)
        sources.append(index[r, c])
        targets.append(index[r + move.dr, c + move.dc])
        mean = 1.0 if cost is None else (cost[r, c].astype(np.float64) + cost[r + move.dr, c + move.dc]) / 2
        weights.append(np.full(len(r), move.cost) * mean)
    n = rows * cols
    return coo_matrix((np.concatenate(weights), (np.concatenate(sources), np.concatenate(targets))),
                      shape=(n, n)).tocsr()
