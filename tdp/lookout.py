"""Obstacle prediction (ARCHITECTURE §5.7): moving boxes tracked from the map's updates, the cells they are about to
sweep over held occupied in the node layers (the DP planners), and the robot kept out of their way (every planner)."""
from __future__ import annotations

import math
from typing import Callable

import numpy as np

from .checks import Cell
from .config import NavigatorConfig
from .engine import Engine
from .predict import MotionPredictor
from .stencil import REACH


def step_aside(cells: list[Cell], costs: np.ndarray, arrivals: list[float], gaps: np.ndarray, avoid_ticks: int,
               entered: bool) -> Cell | None:
    """Where the robot steps aside to (a pure rule of :meth:`BoxLookout.clear_move`), among ``cells`` no box enters
    at the next tick, each with its ``costs`` (the followed layer's value there plus the move's length), the tick a
    box may first enter it (``arrivals``, 1 = the next; inf: none) and how far it lies from a moving box (``gaps``,
    cells: :meth:`MotionPredictor.box_gaps`). A cell is clear where no box enters it within ``avoid_ticks`` and it
    lies next to none (gap over 1); clear cells first. A robot a box is about to drive onto (``entered``) takes the
    least cost among them; one that a box only came beside takes the cell furthest from the boxes, then the least
    cost - toward the goal, it kept just ahead of a box shuttling diagonally across its way and escorted it for 250
    ticks (crossing-60-418 of the held-out seeds) - or stays (None) where no cell is clear."""
    clear = [arrival > avoid_ticks and gap > 1 for arrival, gap in zip(arrivals, gaps)]
    if not entered and not any(clear):
        return None
    away = [0] * len(cells) if entered else list(gaps)
    best = max(range(len(cells)), key=lambda i: (clear[i], away[i], -costs[i]))
    return cells[best]


class BoxLookout:
    """Tracks moving boxes for a :class:`tdp.Navigator` with ``predict_ticks`` or ``avoid_boxes``, or an
    :class:`tdp.ExactPlanner` with ``avoid_boxes`` (``predict_ticks`` 0: no node layer is written).

    ``predicted`` is the (H, W) mask of cells the node layers hold occupied on prediction alone (updated in place).
    Each map update goes through :meth:`note_update` before the engine takes it and :meth:`hold` after; each tick
    starts with :meth:`predict`; :meth:`clear_move` vets the robot's move.
    """

    def __init__(self, engine: Engine, config: NavigatorConfig):
        self.engine = engine
        self.config = config
        self.predictor = MotionPredictor(engine.occupied.shape)
        self.ticks = 0
        self.predicted = np.zeros(engine.occupied.shape, bool)
        self._became_occupied: list[np.ndarray] = []
        self._predicted_cells = np.zeros((0, 2), np.int64)

    def note_update(self, cells: np.ndarray, occupied: np.ndarray) -> None:
        """Before the engine takes a map update: remember the cells (n, 2) that become occupied."""
        was = self.engine.occupied[cells[:, 0], cells[:, 1]]
        self._became_occupied.append(cells[occupied & ~was])

    def hold(self, cells: np.ndarray) -> None:
        """After the engine took a map update of ``cells``: the node layers keep the predicted ones occupied."""
        self.engine.set_node_cells(cells[self.predicted[cells[:, 0], cells[:, 1]]], True)

    def predict(self) -> bool:
        """A new tick: feed the tracker the cells that became occupied since the last, and hold the cells the boxes
        are predicted to sweep over in the next ``predict_ticks`` ticks occupied in the node layers. Returns whether
        the node layers changed."""
        self.ticks += 1
        became = np.vstack(self._became_occupied) if self._became_occupied else np.zeros((0, 2), np.int64)
        self._became_occupied = []
        self.predictor.observe(self.ticks, became)
        if not self.config.predict_ticks:
            return False  # avoid_boxes alone: nothing is held
        cells = self.predictor.entering(self.ticks, self.config.predict_ticks)
        occupied = self.engine.occupied
        cells = cells[~occupied[cells[:, 0], cells[:, 1]]]
        old = self._predicted_cells
        already = self.predicted[cells[:, 0], cells[:, 1]]
        self.predicted[old[:, 0], old[:, 1]] = False
        self.predicted[cells[:, 0], cells[:, 1]] = True
        freed = old[~self.predicted[old[:, 0], old[:, 1]] & ~occupied[old[:, 0], old[:, 1]]]
        self.engine.set_node_cells(freed, False)
        self.engine.set_node_cells(cells[~already], True)
        self._predicted_cells = cells
        return bool(len(freed) or not already.all())

    def clear_move(self, robot: Cell, wanted: Cell | None, route: Callable[[int], list[Cell]],
                   legal_moves: Callable[[], list[tuple[Cell, float]]],
                   values: Callable[[list[Cell]], np.ndarray]) -> Cell | None:
        """The move to make given the cells the tracked boxes are predicted to enter (and at the next tick those right
        behind a moving box, which it enters if it turns back: :meth:`MotionPredictor.behind`): ``wanted`` if the
        robot meets no box on its next ``meet_ticks`` moves (:meth:`_meets_a_box`; ``route(k)``: the robot's next k
        cells) and ``wanted`` lies next to no moving box (:meth:`MotionPredictor.box_gaps`: a box turning at any
        angle drives onto a robot next to it before its edges show the turn); else stay (yield: None) if no box
        enters the robot's cell at the next tick and none lies next to it; else step aside to one of the
        ``legal_moves()`` (cell, length; asked for only then) that no box enters at the next tick, as
        :func:`step_aside` chooses (``values``: the followed layer's values of cells); ``wanted`` when every move is
        entered at the next tick and a box enters the robot's cell, else stay."""
        arrivals = self.predictor.arrivals(self.ticks, self.config.avoid_ticks, near=(robot, REACH))
        behind = self.predictor.behind(self.ticks, self.engine.occupied, near=(robot, REACH))
        arrivals.update((cell, 1) for cell in map(tuple, behind.tolist()))  # a box may turn back into them
        if (wanted is not None and self._box_gaps([wanted])[0] > 1
                and not self._meets_a_box(robot, wanted, arrivals, route)):
            return wanted
        entered = arrivals.get(robot, math.inf) <= 1
        if not entered and self._box_gaps([robot])[0] > 1:
            return None
        options = [(cell, cost) for cell, cost in legal_moves() if arrivals.get(cell, math.inf) > 1]
        if not options:
            return wanted if entered else None
        cells = [cell for cell, _ in options]
        ahead = [arrivals.get(cell, math.inf) for cell in cells]
        layer = values(cells)
        costs = layer + np.array([cost for _, cost in options], layer.dtype)  # summed as the layer's values are
        return step_aside(cells, costs, ahead, self._box_gaps(cells), self.config.avoid_ticks, entered)

    def _box_gaps(self, cells: list[Cell]) -> np.ndarray:
        """How far each of ``cells`` lies from a moving box (:meth:`MotionPredictor.box_gaps`; 1: next to it)."""
        return self.predictor.box_gaps(self.ticks, self.engine.occupied, cells)

    def _meets_a_box(self, robot: Cell, wanted: Cell, arrivals: dict[Cell, int],
                     route: Callable[[int], list[Cell]]) -> bool:
        """Whether a box is predicted to enter ``wanted`` at the next tick, or a box moving across the robot's way
        to enter one of its next ``meet_ticks`` cells (``wanted``, then the followed layer's successors) no later
        than the robot would get there, a move per tick. The next cell alone let the robot escort a box that drove
        across its way: it stepped along the box's front, one cell per yield, for as long as the box drove. A box
        moving along the robot's way is left to the next-cell test: waiting for it does not clear the way."""
        if arrivals.get(wanted, math.inf) <= 1:
            return True
        reach = REACH * self.config.meet_ticks  # the robot's next meet_ticks cells lie within it
        if not self.predictor.may_reach(self.ticks, self.config.meet_ticks, robot, reach):
            return False  # no box can meet the robot: its route is not traced (a kernel launch)
        ahead = route(self.config.meet_ticks)
        if not ahead or ahead[0] != wanted:
            return False
        heading = np.subtract(ahead[-1], robot)
        across = self.predictor.arrivals(self.ticks, self.config.meet_ticks, across=heading, near=(robot, reach))
        return any(across.get(cell, math.inf) <= moves_there for moves_there, cell in enumerate(ahead, start=1))
