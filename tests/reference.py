"""Independent reference: the grid graph built straight from ARCHITECTURE §4's text, solved by scipy's Dijkstra.

Deliberately shares no code with tdp: the offsets, weights and corner rule are written out again here.
"""
from __future__ import annotations

import heapq
import math

import numpy as np
from scipy.sparse import coo_matrix
from scipy.sparse.csgraph import dijkstra

STRAIGHT = [(-1, 0), (1, 0), (0, -1), (0, 1)]
DIAGONAL = [(-1, -1), (-1, 1), (1, -1), (1, 1)]
KNIGHT = [(1, 2), (2, 1), (-1, 2), (-2, 1), (1, -2), (2, -1), (-1, -2), (-2, -1)]


def offsets(neighbourhood: int):
    return {4: STRAIGHT, 8: STRAIGHT + DIAGONAL, 16: STRAIGHT + DIAGONAL + KNIGHT}[neighbourhood]


def crossed(dr: int, dc: int, corner_cutting: bool) -> list[tuple[int, int]]:
    """The cells besides its target that move (dr, dc) must find free, as offsets from the cell it leaves: none
    for a straight move or with corner cutting; a diagonal's two side cells; a knight move's two cells beside the
    straight line to its target (for (1, 2): (0, 1) and (1, 1))."""
    if corner_cutting or abs(dr) + abs(dc) == 1:
        return []
    sr = 1 if dr > 0 else -1
    sc = 1 if dc > 0 else -1
    if abs(dr) == 1 and abs(dc) == 1:
        return [(dr, 0), (0, dc)]
    if abs(dc) == 2:
        return [(0, sc), (dr, sc)]
    return [(sr, 0), (sr, dc)]


def graph(occupied: np.ndarray, neighbourhood: int, corner_cutting: bool, cost: np.ndarray | None = None):
    """Directed sparse graph V -> Z with weight |V - Z| for every allowed move between free cells; with ``cost``,
    |V - Z| x (cost[V] + cost[Z]) / 2 in float64."""
    rows, cols = occupied.shape
    free = np.zeros((rows + 4, cols + 4), bool)  # two cells of blocked border: every move's cells fall inside
    free[2:-2, 2:-2] = ~occupied

    def free_at(dr: int, dc: int) -> np.ndarray:
        """For every cell (r, c) of the map: whether cell (r + dr, c + dc) is on the map and free."""
        return free[2 + dr:2 + dr + rows, 2 + dc:2 + dc + cols]

    index = np.arange(rows * cols).reshape(rows, cols)
    src, dst, weight = [], [], []
    for dr, dc in offsets(neighbourhood):
        allowed = free_at(0, 0) & free_at(dr, dc)
        for y, x in crossed(dr, dc, corner_cutting):
            allowed &= free_at(y, x)
        r, c = np.nonzero(allowed)
        src.append(index[r, c])
        dst.append(index[r + dr, c + dc])
        mean = 1.0 if cost is None else (cost[r, c].astype(np.float64) + cost[r + dr, c + dc].astype(np.float64)) / 2
        weight.append(np.full(len(r), math.hypot(dr, dc)) * mean)
    n = rows * cols
    return coo_matrix((np.concatenate(weight), (np.concatenate(src), np.concatenate(dst))), shape=(n, n)).tocsr()


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


def escape_depths(occupied: np.ndarray, walls: np.ndarray, cell, radius: int, neighbourhood: int,
                  corner_cutting: bool) -> np.ndarray:
    """For each occupied cell that is not a wall within ``radius`` rows and columns of ``cell``: the shortest walk
    through such cells, each move clear of walls, to a free cell (inf elsewhere) - from every free cell at once on
    the graph of the cells that are not walls, its walks going on from those cells only."""
    rows, cols = occupied.shape
    near = np.zeros_like(occupied)
    near[max(0, cell[0] - radius):cell[0] + radius + 1, max(0, cell[1] - radius):cell[1] + radius + 1] = True
    inside = (occupied & ~walls & near).ravel()
    walks = graph(walls, neighbourhood, corner_cutting).tocoo()
    kept = inside[walks.row]
    through = coo_matrix((walks.data[kept], (walks.row[kept], walks.col[kept])), shape=walks.shape)
    free = np.flatnonzero(~occupied.ravel())
    depth = (np.full(rows * cols, np.inf) if not len(free)
             else dijkstra(through.T.tocsr(), indices=free, min_only=True))
    return np.where(inside, depth, np.inf).reshape(rows, cols)


def escape_totals(occupied: np.ndarray, walls: np.ndarray, cell, neighbourhood: int, corner_cutting: bool,
                  distance, max_length: float) -> dict:
    """For each first move out of ``cell`` (an escape from under an obstacle, ARCHITECTURE §5.5): the least walk
    length + ``distance(free cell)`` over the walks that start with it and end on a free cell within
    ``max_length`` - walks of moves clear of walls through occupied cells, each move's occupied cells no deeper
    (:func:`escape_depths`, within ceil(max_length) of ``cell``) than the cell it leaves. A plain Dijkstra."""
    rows, cols = occupied.shape
    depth = escape_depths(occupied, walls, cell, math.ceil(max_length), neighbourhood, corner_cutting)

    def moves(here):
        for dr, dc in offsets(neighbourhood):
            there = (here[0] + dr, here[1] + dc)
            passed = [there] + [(here[0] + y, here[1] + x) for y, x in crossed(dr, dc, corner_cutting)]
            if all(0 <= r < rows and 0 <= c < cols and not walls[r, c] for r, c in passed) and (
                    not occupied[there] or all(depth[p] <= depth[here] for p in passed if occupied[p])):
                yield there, math.hypot(dr, dc)

    totals = {}
    for first, length in moves(cell):
        walked, heap, best = {first: length}, [(length, first)], math.inf
        while heap:
            here_length, here = heapq.heappop(heap)
            if here_length > walked[here] or here_length > max_length:
                continue
            if not occupied[here]:
                best = min(best, here_length + distance(here))
                continue
            for there, step in moves(here):
                if here_length + step < walked.get(there, math.inf):
                    walked[there] = here_length + step
                    heapq.heappush(heap, (here_length + step, there))
        totals[first] = best
    return totals
