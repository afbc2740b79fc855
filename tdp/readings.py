"""What the accelerating-nodes planner reads from the node layers: which nodes are active, the blockage monitor's
view of the pair distances, and the node graph of eq. 14 (ARCHITECTURE §5.1-5.5)."""
from __future__ import annotations

import math

import numpy as np

from .blockage import BlockageMonitor
from .checks import Cell
from .engine import Engine
from .nodes import NodeGraph, Vertices, pair_distances
from .stencil import chain_moves



class NodeReadings:
    """The node layers as the planner sees them, for ``engine``'s nodes (``vertices.nodes``) with vision DmaxQ
    ``dmax_q`` (cells) and the blockage test's window J and rise U; ``predicted`` is the (H, W) mask of cells a box
    is predicted to sweep over (updated in place by the caller), which no route counted as real may cross.

    A node is active from the DP iteration its layer can be trusted: never while an obstacle (or a predicted box)
    covers it, and once uncovered, after long enough for its layer to settle (phantom values rise at least a cell per
    iteration, true ones arrive within DmaxQ + U). The graph's readings are cached per state (iteration, R, G and
    the count of edits); every edit that changes the layers between iterations must call :meth:`edited`.
    """

    def __init__(self, engine: Engine, vertices: Vertices, dmax_q: float, window: int, rise: float,
                 predicted: np.ndarray):
        self.engine = engine
        self.predicted = predicted
        self.vertices = vertices
        self.dmax_q = dmax_q
        self.monitor = BlockageMonitor(dmax_q, window, rise)
        self._active_from = np.zeros(len(vertices.nodes))
        self._settling = math.ceil(dmax_q + rise) + 1
        self._readings: tuple[tuple, np.ndarray] | None = None  # (state, every layer at the graph's cells)
        self._edits = 0

    def edited(self) -> None:
        """The layers changed between iterations (a map edit, a setup, a prediction): readings are stale."""
        self._edits += 1

    def cover(self) -> None:
        """Nodes on an occupied or predicted cell leave the graph; uncovered ones return once settled."""
        rows, cols = self.vertices.nodes[:, 0], self.vertices.nodes[:, 1]
        covered = self.engine.occupied[rows, cols] | self.predicted[rows, cols]
        uncovered = ~covered & np.isinf(self._active_from)
        self._active_from[covered] = np.inf
        self._active_from[uncovered] = self.engine.iterations + self._settling

    def active(self, iteration: int | np.ndarray | None = None) -> np.ndarray:
        """Nodes active at DP iteration ``iteration`` (default: the last; a column of iterations gives a row per
        iteration)."""
        return self._active_from <= (self.engine.iterations if iteration is None else iteration)

    def observe(self, samples: np.ndarray) -> list[tuple[int, tuple[int, int]]]:
        """Feed the monitor the pair distances of the iterations ``samples`` holds (the engine's samples at the
        nodes' cells, or at the graph's, one per iteration, the last iteration's last); the pairs newly blocked,
        with their iteration."""
        first = self.engine.iterations - len(samples) + 1
        active = self.active(first + np.arange(len(samples))[:, None])  # (iterations, nodes)
        found = self.monitor.observe_iterations(pair_distances(samples, active))
        return [(first + step, pair) for step, pair in found]

    def remember(self, robot: tuple[int, int], goal: tuple[int, int], values: np.ndarray) -> None:
        """Keep ``values``, every layer at the graph's cells after the last iteration, as the graph's readings."""
        self._readings = (self._state(robot, goal), values)

    def graph(self, robot: tuple[int, int], goal: tuple[int, int], blocked: bool = False,
              direct_goal: bool = True) -> NodeGraph:
        """The node graph of eq. 14 now; with ``blocked``, without the pairs the monitor holds blocked;
        ``direct_goal``: whether the goal layer's value at R may stand for a direct R-G edge (see NodeGraph)."""
        if self._readings is None or self._readings[0] != self._state(robot, goal):
            self.remember(robot, goal, self.engine.sample(self.vertices.cells(robot, goal)))
        unreliable = self.monitor.blocked if blocked else None
        return NodeGraph(self._readings[1], self.dmax_q, self.active(), unreliable, direct_goal)

    def real_chain(self, start: Cell, vertex: int, max_steps: int, robot: Cell, goal: Cell) -> list[Cell] | None:
        """The successors of graph vertex ``vertex``'s layer from ``start`` (robot and goal at ``robot`` and
        ``goal``) when they reach its cell within ``max_steps`` moves through no predicted cell - a real route on
        the map as it is, not about to close - ``start`` first; else None. The successors only ever make legal
        moves on the current map; while the news of a cut is still travelling, they run into the cut."""
        chain = [start] + self.engine.trace(self.vertices.layer(vertex), start, max_steps)
        if chain[-1] != self.vertices.cell(vertex, robot, goal) or self.predicted[tuple(np.array(chain).T)].any():
            return None
        return chain

    def driven_length(self, a: int, b: int, robot: Cell, goal: Cell) -> float:
        """The cost of the way from graph vertex ``a`` to ``b`` that b's layer really drives - its successors from
        a's cell, if they reach b in less than DmaxQ cells (b's vision); else inf - in the goal layer's units (cells;
        on a map with traversal costs, the moves' costs)."""
        chain = self.real_chain(self.vertices.cell(a, robot, goal), b, math.ceil(self.dmax_q) + 1, robot, goal)
        if chain is None:
            return math.inf
        lengths, costs = chain_moves(chain, self.engine.cost)
        return math.inf if lengths.sum() >= self.dmax_q else float(costs.sum())

    def _state(self, robot: tuple[int, int], goal: tuple[int, int]) -> tuple:
        """What the layers read at the graph's cells depend on: the iteration, R, G and the edits so far."""
        return self.engine.iterations, robot, goal, self._edits
