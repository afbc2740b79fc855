"""The exact planner's reference: a goal field converged fully (no focus) at every tick, its successor, and the
same way out of an obstacle - the oracle as it was before the focused exact planner. Tests and benchmarks check
that :class:`tdp.ExactPlanner` drives its trajectory tick for tick."""
from __future__ import annotations

import numpy as np

import tdp
from tdp.contract import Mode, TickResult
from tdp.stencil import escape_move, moves


class FullConverge:
    """A :class:`tdp.contract.Planner` on ``grid`` from ``start`` to ``goal`` reading the stencil of ``config``."""

    def __init__(self, grid: tdp.GridMap, start: tuple[int, int], goal: tuple[int, int], config: tdp.NavigatorConfig):
        self.field = tdp.DistanceField(grid, goal, config.neighbourhood, config.corner_cutting, config.d_max)
        self.moves = moves(config.neighbourhood, config.corner_cutting)
        self.walls = grid.occupied.copy()  # the map's own obstacles: occupied at the start and never freed since
        self.robot = start

    def update_map(self, cells: np.ndarray, occupied: np.ndarray) -> None:
        for value in (True, False):
            self.field.set_occupied(cells[occupied == value], value)
        self.walls[cells[~occupied, 0], cells[~occupied, 1]] = False

    def set_goal(self, goal: tuple[int, int]) -> None:
        self.field.set_goal(goal)

    def move_robot(self, cell: tuple[int, int]) -> None:
        self.robot = cell

    def tick(self) -> TickResult:
        self.field.converge()
        step = self.field.successor(self.robot)
        if self.field.occupied[self.robot]:
            step = escape_move(self.field.occupied, self.robot, self.moves, self._distances, self.walls) or step
        return TickResult(mode=Mode.EXACT, next_cell=step)

    def _distances(self, cells: list) -> np.ndarray:
        values = np.array([self.field.distance(cell) for cell in cells])
        return np.where(values >= self.field.d_max, np.inf, values)
