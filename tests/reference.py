"""Independent reference: the grid graph built straight from ARCHITECTURE §4's text, solved by scipy's Dijkstra.

Deliberately shares no code with tdp: the offsets, weights and corner rule are written out again here.
"""
from __future__ import annotations

import math

import numpy as np
from scipy.sparse import coo_matrix
from scipy.sparse.csgraph import dijkstra

STRAIGHT = [(-1, 0), (1, 0), (0, -1), (0, 1)]
DIAGONAL = [(-1, -1), (-1, 1), (1, -1), (1, 1)]
KNIGHT = [(1, 2), (2, 1), (-1, 2), (-2, 1), (1, -2), (2, -1), (-1, -2), (-2, -1)]


def offsets(neighbourhood: int):
    return {4: STRAIGHT, 8: STRAIGHT + DIAGONAL, 16: STRAIGHT + DIAGONAL + KNIGHT}[neighbourhood]


def move_allowed(free: np.ndarray, r: int, c: int, dr: int, dc: int, corner_cutting: bool) -> bool:
    rows, cols = free.shape

    def ok(y, x):
        return 0 <= y < rows and 0 <= x < cols and free[y, x]

    if not ok(r + dr, c + dc):
        return False
    if corner_cutting or abs(dr) + abs(dc) == 1:
        return True
    sr = 1 if dr > 0 else -1
    sc = 1 if dc > 0 else -1
    if abs(dr) == 1 and abs(dc) == 1:
        return ok(r + dr, c) and ok(r, c + dc)
    if abs(dc) == 2:
        return ok(r, c + sc) and ok(r + dr, c + sc)
    return ok(r + sr, c) and ok(r + sr, c + dc)


def graph(occupied: np.ndarray, neighbourhood: int, corner_cutting: bool, cost: np.ndarray | None = None):
    """Directed sparse graph V -> Z with weight |V - Z| for every allowed move between free cells; with ``cost``,
    |V - Z| x (cost[V] + cost[Z]) / 2 in float64."""
    free = ~occupied
    rows, cols = free.shape
    src, dst, weight = [], [], []
    for r, c in zip(*np.nonzero(free)):
        for dr, dc in offsets(neighbourhood):
            if move_allowed(free, r, c, dr, dc, corner_cutting):
                src.append(r * cols + c)
                dst.append((r + dr) * cols + c + dc)
                mean = 1.0 if cost is None else (float(cost[r, c]) + float(cost[r + dr, c + dc])) / 2
                weight.append(math.hypot(dr, dc) * mean)
    n = rows * cols
    return coo_matrix((weight, (src, dst)), shape=(n, n)).tocsr()


def distances_to(occupied: np.ndarray, goal, neighbourhood: int = 16, corner_cutting: bool = False,
                 hops: bool = False, cost: np.ndarray | None = None) -> np.ndarray:
    """Shortest distance from every cell to ``goal`` (inf where unreachable or occupied); move counts if hops."""
    g = graph(occupied, neighbourhood, corner_cutting, cost)
    rows, cols = occupied.shape
    d = dijkstra(g.T, indices=goal[0] * cols + goal[1], unweighted=hops)
    return d.reshape(rows, cols)


def assert_distances_match(ours: np.ndarray, expected: np.ndarray, rtol: float) -> None:
    """``ours`` (float32, no NaN) is inf exactly where ``expected`` is, and within ``rtol`` elsewhere."""
    assert ours.dtype == np.float32
    assert not np.isnan(ours).any()
    np.testing.assert_array_equal(np.isinf(ours), np.isinf(expected))
    finite = np.isfinite(expected)
    np.testing.assert_allclose(ours[finite], expected[finite], rtol=rtol, atol=1e-5)
