"""D* Lite (Koenig and Likhachev, "D* Lite", AAAI 2002; the optimised version of their Fig. 4) on tdp's grid
graph: the same 4/8/16-neighbour moves, lengths and corner rule. Plain Python, a baseline for sweeps and benchmarks.

The search runs from the goal back to the robot with the Euclidean heuristic (consistent: every move costs its
Euclidean length, or on a map with traversal costs at least that: L x (cost[u] + cost[v]) / 2 with costs >= 1).
Map edits update the vertices whose edges they touch and repair the search; a moved goal starts a new search, as
D* Lite has no notion of a moving goal.
"""
from __future__ import annotations

import heapq
import math
import time

import numpy as np

from . import checks, stencil
from .contract import Mode, TickResult

INF = math.inf
#: Keys whose first components differ by less than this are ties (broken by the second component): both are sums
#: of Euclidean lengths in different orders, so a tie in exact arithmetic can come out one rounding apart, and
#: stopping on that rounding leaves the robot's distance stale.
KEY_TOLERANCE = 1e-9


def _before(key: tuple[float, float], other: tuple[float, float]) -> bool:
    """Whether ``key`` orders before ``other``, with ties in the first component taken within KEY_TOLERANCE."""
    if abs(key[0] - other[0]) > KEY_TOLERANCE * max(1.0, abs(other[0])):
        return key[0] < other[0]
    return key[1] < other[1]


class DStarLite:
    """A :class:`tdp.contract.Planner`: update_map, set_goal, move_robot, tick."""

    def __init__(self, occupied: np.ndarray, start: tuple[int, int], goal: tuple[int, int], neighbourhood: int = 16,
                 corner_cutting: bool = False, cost: np.ndarray | None = None):
        self.occupied = np.array(occupied, bool)
        self.cost = None if cost is None else np.asarray(cost, np.float64)  # a GridMap's costs, or None
        self.rows, self.cols = self.occupied.shape
        self.moves = stencil.moves(neighbourhood, corner_cutting)
        self.start = self.last = tuple(start)
        self.expanded = 0
        self._initialise(tuple(goal))

    def _initialise(self, goal: tuple[int, int]) -> None:
        self.goal = goal
        self.g: dict[tuple[int, int], float] = {}
        self.rhs: dict[tuple[int, int], float] = {goal: 0.0}
        self.km = 0.0
        self.queue: list = []
        self.queued: dict[tuple[int, int], tuple[float, float]] = {}
        self._push(goal)
        self._compute()

    # -- graph ---------------------------------------------------------------------------------------------------
    def _free(self, r: int, c: int) -> bool:
        return 0 <= r < self.rows and 0 <= c < self.cols and not self.occupied[r, c]

    def _edges(self, cell):
        """(neighbour, cost) over the allowed moves from ``cell`` (the graph is symmetric)."""
        if not self._free(*cell):
            return
        for neighbour, length in stencil.legal_moves(self.occupied, cell, self.moves):
            yield neighbour, length if self.cost is None else length * (self.cost[cell] + self.cost[neighbour]) / 2

    # -- D* Lite -------------------------------------------------------------------------------------------------
    def _h(self, a, b) -> float:
        return math.dist(a, b)

    def _key(self, cell) -> tuple[float, float]:
        best = min(self.g.get(cell, INF), self.rhs.get(cell, INF))
        return best + self._h(self.start, cell) + self.km, best

    def _push(self, cell) -> None:
        key = self._key(cell)
        self.queued[cell] = key
        heapq.heappush(self.queue, (key, cell))

    def _top(self):
        while self.queue and self.queued.get(self.queue[0][1]) != self.queue[0][0]:
            heapq.heappop(self.queue)
        return self.queue[0] if self.queue else ((INF, INF), None)

    def _update(self, cell) -> None:
        if cell != self.goal:
            self.rhs[cell] = min((cost + self.g.get(nb, INF) for nb, cost in self._edges(cell)), default=INF)
        self.queued.pop(cell, None)
        if self.g.get(cell, INF) != self.rhs.get(cell, INF):
            self._push(cell)

    def _compute(self) -> None:
        while True:
            key, cell = self._top()
            if cell is None or (not _before(key, self._key(self.start))
                                and self.rhs.get(self.start, INF) == self.g.get(self.start, INF)):
                return
            self.expanded += 1
            new_key = self._key(cell)
            if key < new_key:
                self._push(cell)
            elif self.g.get(cell, INF) > self.rhs.get(cell, INF):
                self.g[cell] = self.rhs[cell]
                self.queued.pop(cell, None)
                for nb, _ in self._edges(cell):
                    self._update(nb)
            else:
                self.g[cell] = INF
                self._update(cell)
                for nb, _ in self._edges(cell):
                    self._update(nb)

    # -- planner interface ---------------------------------------------------------------------------------------
    def distance(self) -> float:
        """The current shortest distance from the robot to the goal."""
        return self.g.get(self.start, INF)

    def update_map(self, cells: np.ndarray, occupied) -> None:
        """Cells change state; repair the search (edges within the stencil's reach of each cell change)."""
        occupied = checks.flags(occupied, len(cells), "occupied")
        self.occupied[cells[:, 0], cells[:, 1]] = occupied
        self.km += self._h(self.last, self.start)
        self.last = self.start
        reach = stencil.REACH
        touched = {(r + dr, c + dc) for r, c in cells for dr in range(-reach, reach + 1)
                   for dc in range(-reach, reach + 1) if 0 <= r + dr < self.rows and 0 <= c + dc < self.cols}
        for cell in touched:
            if self.occupied[cell]:
                self.g[cell] = INF  # an occupied cell has no edges: it can no longer relay distances
            self._update(cell)
        self._compute()

    def set_goal(self, goal: tuple[int, int]) -> None:
        self._initialise(tuple(goal))

    def move_robot(self, cell) -> None:
        self.start = tuple(cell)

    def tick(self) -> TickResult:
        """The move to the neighbour minimising c(R, s') + g(s') (ties in the stencil's order)."""
        began = time.perf_counter()
        self._compute()
        best, target = INF, None
        for nb, cost in self._edges(self.start):
            value = cost + self.g.get(nb, INF)
            if value < best:
                best, target = value, nb
        if self.start == self.goal:
            target = None
        result = TickResult(mode=Mode.DSTAR if target else Mode.WAIT, next_cell=target)
        result.timings = {"search": time.perf_counter() - began}
        return result
