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


class NodeGraph:
    """The graph of eq. 14 over the nodes Q plus the robot R and the goal G, from the layers' values.

    ``samples`` is the engine's :meth:`~tdp.engine.Engine.sample` at the node cells then R then G: row k, column 0
    the goal layer at cell k, column 1 + j node j's layer at cell k. Vertex ids: nodes 0..n-1, R = n, G = n + 1.
    Pair weight D(Qa, Qb) = max(layer_b[Qa], layer_a[Qb]) (conservative while news travels); robot and goal edges
    are layer_j[R] and layer_j[G]; R-G is direct when layer_0[R] < DmaxQ. An edge exists where its weight < DmaxQ.
    Inactive nodes (covered by an obstacle) have no edges; ``blocked`` pairs (the monitor's verdict: their distance
    is still rising after a cut, so their weight is stale) have none either, and neither has the edge from R (or G)
    to a node j blocked from a node i that R (or G) reaches first: R's reading of j then most likely went through
    the cut, and the news has not reached R yet.
    """

    def __init__(self, samples: np.ndarray, vision: float, active: np.ndarray, blocked: np.ndarray | None = None):
        n = samples.shape[0] - 2
        self.n = n
        self.vision = float(vision)
        self.active = np.asarray(active, bool)
        node_rows = samples[:n, 1:].astype(np.float64)
        self.pairs = np.maximum(node_rows, node_rows.T)
        self.robot_readings = samples[n, 1:].astype(np.float64)  # layer_j[R] before any edge is dropped
        self.robot = self.robot_readings.copy()
        self.goal = samples[n + 1, 1:].astype(np.float64)
        self.robot_goal = float(samples[n, 0])
        if blocked is not None:
            self.pairs[blocked] = np.inf
            self.robot[self._cut_off(self.robot, blocked)] = np.inf
            self.goal[self._cut_off(self.goal, blocked)] = np.inf
        inactive = ~self.active
        self.pairs[inactive, :] = np.inf
        self.pairs[:, inactive] = np.inf
        self.robot[inactive] = np.inf
        self.goal[inactive] = np.inf

    @staticmethod
    def _cut_off(readings: np.ndarray, blocked: np.ndarray) -> np.ndarray:
        """Nodes j with a blocked pair (i, j) where readings[i] < readings[j]."""
        nearer = readings[:, None] < readings[None, :]
        return (blocked & nearer).any(axis=0)

    @property
    def robot_id(self) -> int:
        return self.n

    @property
    def goal_id(self) -> int:
        return self.n + 1

    def neighbours(self, vertex: int):
        """(neighbour, weight) pairs of ``vertex`` over the edges with weight < DmaxQ."""
        cap = self.vision
        if vertex == self.robot_id:
            weights = np.append(self.robot, [np.inf, self.robot_goal])
        elif vertex == self.goal_id:
            weights = np.append(self.goal, [self.robot_goal, np.inf])
        else:
            weights = np.append(self.pairs[vertex], [self.robot[vertex], self.goal[vertex]])
            weights[vertex] = np.inf
        for other in np.flatnonzero(weights < cap):
            yield int(other), float(weights[other])

    def edges(self) -> list[tuple[int, int, float]]:
        """Every node-node edge (a < b, weight) of the current graph."""
        a, b = np.nonzero(np.triu(self.pairs < self.vision, k=1))
        return [(int(i), int(j), float(self.pairs[i, j])) for i, j in zip(a, b)]
