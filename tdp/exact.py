"""Exact replanning every tick: the goal layer repaired to its fixed point where the robot's route needs it.

Each tick takes the map's and the goal's edits, repairs the goal layer with a converge focused on the robot's cell
(D* Lite's stop rule, ARCHITECTURE §7: the value there and the successors from there to the goal are those of a
full converge, exactly; work that cannot change them waits for a tick that needs it) and moves to the successor.
With a time budget the repair is anytime: it stops at the budget and goes on at the next tick with the new edits
merged, and the robot follows the partly repaired layer meanwhile (see :class:`ExactPlanner`).
"""
from __future__ import annotations

import time
from functools import partial

import numpy as np

from . import checks
from .contract import Mode, TickResult
from .engine import SLICE_GROWTH, Engine, sweeps_fitting
from .field import cells_from
from .grid import GridMap
from .config import NavigatorConfig
from .lookout import BoxLookout
from .stencil import RobotMoves

#: With a budget, a slice of a tick's repair makes at least this many sweeps (a pass over an 8 x 8 tile, about
#: 0.5-1.5 µs on the 2-core VM; settling a tile takes 1 to 32 of them), and as many more as the rate measured so far
#: says fit in what is left after a slice's fixed cost. Counted in tiles settled, slices overran: tiles cost 0.2-25
#: µs, and a rate measured on cheap ones opened the way to thousands of dear ones.
FIRST_SWEEPS = 64


def holds_goal(budgeted: bool, settled: bool, waited_ticks: int, since_ticks: int) -> bool:
    """Whether a planner holds a target's move back, the goal layer kept at the goal it last took: with a budget,
    while the repair that move started has cost ticks (``waited_ticks``) and not yet reached the robot (not
    ``settled``) - a new move would throw that work away, and a target that moved more often than a repair took would
    keep the robot waiting for ever -, and once it has, for as many ticks again (``since_ticks``, counted from then),
    so that the robot drives at least as long as it waited. Unbudgeted, or before a tick was spent on the last move,
    never: every move is taken at once."""
    if not budgeted or waited_ticks == 0:
        return False
    return not settled or since_ticks < waited_ticks


class ExactPlanner:
    """The planner of ``NavigatorConfig(planner="exact")``: optimal on the map as it is at every tick.

    Cells are (row, col), distances in cells. The same contract as :class:`tdp.Navigator` (:meth:`setup`, then each
    tick :meth:`update_map`, :meth:`set_goal`, :meth:`tick`, :meth:`move_robot`), the same escape rule when an
    obstacle covers the robot's cell (:func:`tdp.stencil.escape_move`), no node layers. It reads the stencil,
    ``d_max``, ``budget_ms`` and ``avoid_boxes`` (with ``avoid_ticks`` and ``meet_ticks``) of the config: with
    ``avoid_boxes`` the tick's move is vetted against the boxes tracked from the map's updates
    (:class:`tdp.lookout.BoxLookout`) and the robot yields (mode ``yield``) or steps aside where one may meet it.

    Unbudgeted, every tick's move is the successor of a full converge on that tick's map (mode ``exact``). With
    ``budget_ms`` a tick repairs for at most about that long (its work in 8 x 8 tiles, plus a launch: RESULTS.md §0);
    when the budget runs out before the robot's route is settled, the robot follows the layer as far as the
    repair got (mode ``behind``): the successors only make legal moves down the values, never into an obstacle;
    where the repair has been, every finite value is the length of a real route on the current map, so the robot
    heads along a real route, perhaps not the shortest; values it has not reached (lifts still waiting) may lead
    towards a passage that has closed. The repair catches up at a later tick and the route is exact again. A goal
    move restarts the layer, so with a budget a move may wait (:meth:`set_goal`, ``holds_goal``): the robot then
    drives towards where the target was (mode ``behind``).

    Raises:
        ValueError: ``grid`` is not a GridMap, ``config`` not a NavigatorConfig, start or goal not a free cell.

    Examples:
        >>> import numpy as np, tdp
        >>> planner = tdp.ExactPlanner(tdp.GridMap(np.zeros((20, 20), bool)), (0, 0), (19, 19))
        >>> planner.setup() > 0
        True
        >>> planner.tick().next_cell
        (1, 1)
    """

    def __init__(self, grid: GridMap, start: tuple[int, int], goal: tuple[int, int],
                 config: NavigatorConfig = NavigatorConfig(planner="exact")):
        if not isinstance(grid, GridMap):
            raise ValueError(f"grid must be a tdp.GridMap, got {type(grid).__name__}")
        if not isinstance(config, NavigatorConfig):
            raise ValueError(f"config must be a tdp.NavigatorConfig, got {type(config).__name__}")
        self.grid, self.config = grid, config
        self.robot = grid.check_free_cell(start, "start")
        self.engine = Engine(grid.occupied, grid.check_free_cell(goal, "goal"), goal_cap=config.d_max,
                             neighbourhood=config.neighbourhood, corner_cutting=config.corner_cutting, cost=grid.cost)
        self.nodes = np.zeros((0, 2), np.int32)
        self.moves = RobotMoves(grid.occupied, config.neighbourhood, config.corner_cutting, config.d_max)
        self.lookout = BoxLookout(self.engine, config) if config.avoid_boxes else None
        self._sweep_s = 0.0  # seconds per sweep, beyond the fixed cost, in the last slice that made any
        self._last_sweeps = FIRST_SWEEPS  # the sweeps the last slice made
        self._slice_s = 0.0  # the fixed cost of a slice (a converge launch with nothing to settle), from setup()
        # The cells whose route to the goal the last repair left exact (the robot's cell and its next step), or
        # none since an edit or a goal move: a tick that finds the robot on one of them has nothing to repair.
        self._exact_from: tuple[tuple[int, int], ...] = ()
        # The target's cell as set_goal last gave it (the goal layer's may lag: ``holds_goal``), the ticks the repair
        # after the goal layer's last move has taken, whether it reached the robot, and the ticks since it did.
        self._target = self.engine.goal
        self._waited_ticks, self._settled, self._since_ticks = 0, False, 0

    @property
    def goal(self) -> tuple[int, int]:
        """The target's cell (the goal layer's goal may lag behind it with a budget: :meth:`set_goal`)."""
        return self._target

    def setup(self) -> int:
        """Compile the engine's kernels and converge the goal layer focused on the start, as D* Lite's first search
        (the engine's search in A*'s order, ARCHITECTURE §7); returns the buckets it emptied. It settles what can
        be on the start's route or beat it and leaves the rest of the map pending (:meth:`Engine.pending`) until a
        tick's repair needs it; ``planner.engine.converge()`` completes the layer when a whole field is wanted."""
        self.engine.warm_up()
        rounds = self.engine.converge(focus=self._focus())
        idle = []
        for _ in range(3):  # a converge with nothing to do: what every slice of a budgeted repair costs at least
            began = time.perf_counter()
            self.engine.converge(focus=self._focus(), max_sweeps=FIRST_SWEEPS)
            idle.append(time.perf_counter() - began)
        self._slice_s = min(idle)
        return rounds

    def update_map(self, cells_or_mask, occupied: bool | np.ndarray = True) -> None:
        """Set cells (a mask or (row, col) cells) occupied or free; ``occupied`` may give one value per cell.

        Raises:
            ValueError: a cell outside the map, or ``occupied`` not True, False or one bool per cell.
        """
        cells = cells_from(self.grid.shape, cells_or_mask, "update_map")
        flags = checks.flags(occupied, len(cells), "occupied")
        self.moves.freed(cells, flags)
        if self.lookout:
            self.lookout.note_update(cells, flags)
        if self.engine.set_cells(cells, flags):
            self._exact_from = ()

    def update_costs(self, cells, costs) -> None:
        """Set the traversal costs of ``cells`` (a mask or (row, col) cells) to ``costs`` (a number or one per cell)
        on a map with costs (:meth:`tdp.engine.Engine.set_costs`)."""
        if self.engine.set_costs(cells_from(self.grid.shape, cells, "update_costs"), costs):
            self._exact_from = ()

    def set_goal(self, goal: tuple[int, int]) -> None:
        """Move the target; it may stand on an obstacle (then no cell reaches it until it leaves). With a budget, a
        move that arrives while the repair after the last one is still on its way to the robot waits, and so does one
        that arrives before the robot has driven as many ticks as that repair took (``holds_goal``): the robot drives
        towards where the target was (mode ``behind``) and the goal layer takes the target's latest cell then, or
        once the robot reaches the goal it has."""
        self._target = checks.cell(goal, self.grid.shape, "goal")
        if not self._holding():
            self._take_target()

    def _holding(self) -> bool:
        """Whether a move of the target waits now (``holds_goal``)."""
        return holds_goal(self.config.budget_ms is not None, self._settled, self._waited_ticks, self._since_ticks)

    def _take_target(self) -> None:
        """Move the goal layer's goal to the target's cell, if it is elsewhere."""
        if self._target != self.engine.goal:
            self.engine.set_goal(self._target)
            self._exact_from = ()
            self._waited_ticks, self._settled, self._since_ticks = 0, False, 0

    def move_robot(self, cell: tuple[int, int]) -> None:
        """The robot is now at ``cell`` (inside the map; an obstacle may have driven onto it)."""
        self.robot = checks.cell(cell, self.grid.shape, "robot cell")

    def tick(self) -> TickResult:
        """Repair (focused on the robot; within the budget, if any), then the successor or the way out of an
        obstacle. Mode ``exact``, ``behind`` (the budget ran out first, or the target's last move waits: the move,
        if any, is as far as the repair got, and no move means stay this tick while the repair catches up),
        ``wait`` (no move on the map as it is) or, with ``avoid_boxes``, ``yield`` (a box may meet the move)."""
        began = time.perf_counter()
        if self.robot == self.engine.goal or not self._holding():
            self._take_target()
        exact = self.robot in self._exact_from or self._repair(began)
        self._count_tick(exact)
        repaired = time.perf_counter()
        step = None if self.robot == self.engine.goal else self.engine.focus_successor(self.robot)
        self._exact_from = (self.robot,) + ((step,) if step else ()) if exact else ()
        if self.engine.occupied[self.robot]:
            step = self.moves.escape(self.engine.occupied, self.robot, self._goal_values) or step
        moving = step is not None or self.robot == self.engine.goal
        on_target = exact and self._target == self.engine.goal
        mode = (Mode.EXACT if moving else Mode.WAIT) if on_target else Mode.BEHIND
        searched = time.perf_counter()
        timings = {"converge": repaired - began, "search": searched - repaired}
        if self.lookout:
            cleared = self._clear(step)
            mode, step = (Mode.YIELD if (step is None) != (cleared is None) else mode), cleared
            timings["predict"] = time.perf_counter() - searched
        return TickResult(mode=mode, next_cell=step, timings=timings)

    def _clear(self, step: tuple[int, int] | None) -> tuple[int, int] | None:
        """With ``avoid_boxes``: the tick's move vetted against the tracked boxes' predicted arrivals
        (:meth:`tdp.lookout.BoxLookout.clear_move`: the move, none to yield, or a step aside), and on a tick that
        gives no move (a budgeted repair not yet at the robot, no way on the map) a step aside from a box about to
        drive onto the robot."""
        self.lookout.predict()
        if self.robot == self.engine.goal:
            return step
        legal_moves = partial(self.moves.legal, self.engine.occupied, self.robot)
        return self.lookout.clear_move(self.robot, step, self.route, legal_moves, self._goal_values)

    def _count_tick(self, exact: bool) -> None:
        """Count a tick for ``holds_goal``: one the repair after the last goal move took, or one since it reached the
        robot."""
        if self._settled:
            self._since_ticks += 1
        elif exact:
            self._settled = True
        else:
            self._waited_ticks += 1

    def _repair(self, began: float) -> bool:
        """Converge focused on the robot, in one go or, with a budget, in slices of sweeps until it is through
        or the budget is spent; returns whether the robot's route is exact. Not called when the robot stands on the
        route the last repair left exact and nothing changed since: stepping along an exact route, every pending
        tile's priority falls by at most the step, and so does the robot's value (the focus test still holds)."""
        focus = self._focus()
        if self.config.budget_ms is None:
            self.engine.converge(focus=focus)
            return True
        deadline = began + self.config.budget_ms / 1e3
        while True:
            sliced = time.perf_counter()
            self.engine.converge(focus=focus, max_sweeps=self._sweeps_fitting(deadline - sliced))
            now = time.perf_counter()
            if not self.engine.cut_short():
                return True
            if self.engine.swept():
                self._sweep_s = max(now - sliced - self._slice_s, 0.0) / self.engine.swept()
                self._last_sweeps = self.engine.swept()
            if deadline - now <= self._slice_s + FIRST_SWEEPS * self._sweep_s:
                return False

    def _focus(self) -> tuple[int, int] | None:
        """The cell a repair focuses on: the robot's, or none (a full converge) while an obstacle covers it, since
        escaping reads the values of its whole neighbourhood."""
        return None if self.engine.occupied[self.robot] else self.robot

    def _sweeps_fitting(self, left_s: float) -> int:
        """How many sweeps a slice may make in ``left_s`` seconds, less a slice's fixed cost, at the rate measured
        so far (``sweeps_fitting``: FIRST_SWEEPS at least, and while nothing is measured; SLICE_GROWTH times the last
        slice's at most)."""
        if self._sweep_s <= 0:
            return FIRST_SWEEPS
        return sweeps_fitting(left_s - self._slice_s, self._sweep_s, FIRST_SWEEPS,
                              SLICE_GROWTH * max(self._last_sweeps, FIRST_SWEEPS))

    def _goal_values(self, cells: list) -> np.ndarray:
        """The goal layer at ``cells`` (for the way out of an obstacle)."""
        return self.engine.sample(cells)[:, 0]

    def route(self, steps: int) -> list[tuple[int, int]]:
        """Up to ``steps`` cells the robot would follow from its cell now (the goal layer's successors); empty at
        the goal or where the layer gives no move."""
        if self.robot == self.engine.goal:
            return []
        return self.engine.trace(0, self.robot, steps)

    def node_edges(self) -> list[tuple[int, int]]:
        """No node graph: an empty list (figures draw the node graph of planners that have one)."""
        return []
