"""The navigator: the loop of the paper's Fig. 4 (sections 4.1-4.3, ARCHITECTURE §5.4-5.6).

Setup (``converge``), then per tick: observe (K DP iterations with the blockage monitor after each, the relevance
test of new blockages against the robot's current route), decide (the backup rules of :mod:`tdp.backup`: a backup
path by uniform-cost search over the node graph, subgoal following with re-search, the switch back to the DP) and
move (the followed layer's successor, an escape from a cell an obstacle covers, waiting while no route exists).
"""
from __future__ import annotations

import math
import time
from functools import partial
from typing import Callable

import numpy as np

from . import checks
from .backup import (BackupState, Follow, Step, after_search, cells_near, cost_from_robot, goal_route_wins, iterated,
                     next_step, plan_backup, switched_back, without_route)
from .blockage import polyline_cells, segment_near_path
from .checks import Cell
from .config import NavigatorConfig
from .contract import Detection, Mode, PhaseClock, TickResult
from .engine import Engine
from .field import cells_from
from .grid import GridMap
from .lookout import BoxLookout
from .nodes import Vertices, place_nodes
from .readings import NodeReadings
from .stencil import RobotMoves, chain_moves

MOST_PER_CALL = 1024  # DP iterations a call of the tick's iterate runs at most (iterations_within)


class Navigator:
    """Plans a robot's moves on a changing grid with the paper's DP: accelerating nodes (``planner="accelerating"``)
    or plain DP (``"plain-dp"``), K synchronous iterations (or a time budget's worth) per move.

    Cells are (row, col); the navigator never moves the robot itself: :meth:`tick` says where to go and the caller
    reports the robot's position with :meth:`move_robot`. Map edits (:meth:`update_map`) and goal moves
    (:meth:`set_goal`) take effect at the next DP iteration.

    Raises:
        ValueError: ``grid`` is not a GridMap, ``config`` not a NavigatorConfig or names planner "exact", start or
            goal not a free cell.
    """

    def __init__(self, grid: GridMap, start: Cell, goal: Cell,
                 config: NavigatorConfig = NavigatorConfig(planner="accelerating")):
        _check(grid, config)
        self.grid = grid
        self.config = config
        self.robot = grid.check_free_cell(start, "start")
        goal = grid.check_free_cell(goal, "goal")
        self.moves = RobotMoves(grid.occupied, config.neighbourhood, config.corner_cutting, config.d_max)
        self.nodes, self.spacing = _lattice(grid, config)
        self.dmax_q = config.vision * self.spacing  # DmaxQ, in cells
        self.engine = Engine(grid.occupied, goal, goal_cap=config.d_max, nodes=self.nodes,
                             node_cap=self.dmax_q + config.rise, neighbourhood=config.neighbourhood,
                             corner_cutting=config.corner_cutting, cost=grid.cost)
        self.vertices = Vertices(self.nodes)
        self.lookout = BoxLookout(self.engine, config) if config.predict_ticks or config.avoid_boxes else None
        predicted = self.lookout.predicted if self.lookout else np.zeros(grid.shape, bool)
        self.readings = NodeReadings(self.engine, self.vertices, self.dmax_q, config.detect_window, config.rise,
                                     predicted)
        self.backup = BackupState()

    # -- inputs ------------------------------------------------------------------------------------------------
    @property
    def goal(self) -> Cell:
        return self.engine.goal

    def setup(self) -> int:
        """The setup phase (robot stationary): compile the engine's kernels, converge every layer; returns the
        rounds converging took."""
        self.readings.edited()
        self.engine.warm_up()
        return self.engine.converge()

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
        if not self.engine.set_cells(cells, flags):
            return
        if self.lookout:
            self.lookout.hold(cells)
        self.readings.edited()
        self.readings.cover()

    def update_costs(self, cells, costs) -> None:
        """Set the goal layer's traversal costs of ``cells`` (a mask or cells) to ``costs`` (node layers: cells)."""
        if self.engine.set_costs(cells_from(self.grid.shape, cells, "update_costs"), costs):
            self.readings.edited()

    def set_goal(self, goal: Cell) -> None:
        """Move the target (moving-target scenarios). The goal may be on an obstacle (a moving target may cross
        one): while it is, the goal layer has no source, its values rise, and the robot keeps to the last route
        the layer knew until the target is on free ground again."""
        self.engine.set_goal(checks.cell(goal, self.grid.shape, "goal"))

    def move_robot(self, cell: Cell) -> None:
        """Tell the navigator where the robot is now (a cell inside the map; it may be on an obstacle that drove
        onto it)."""
        self.robot = checks.cell(cell, self.grid.shape, "robot cell")

    # -- the tick ----------------------------------------------------------------------------------------------
    def tick(self) -> TickResult:
        """Observe (K DP iterations with the monitor after each), decide (the backup rules), move; returns where to
        move and the seconds each phase took. The mode is DP or BACKUP while the robot moves, WAIT while it has
        nowhere to go: with no route in the node graph the robot follows the goal layer (searching again every tick)
        and waits only when neither offers a move (ARCHITECTURE §5.5); YIELD when it stays for a box's way."""
        clock = PhaseClock("dp", "monitor", "search")
        result = self._observe(clock)
        with clock("search"):
            self._decide(result)
            result.next_cell = self._next_move(result)
        self._move(result, clock)
        result.timings = clock.seconds
        return result

    def _observe(self, clock: PhaseClock) -> TickResult:
        """The tick's observations: predicted boxes, the DP iterations with the monitor, the detections."""
        if self.lookout:
            with clock("predict"):
                if self.lookout.predict():
                    self.readings.edited()
                self.readings.cover()
        new_pairs, iterations = self._iterate(clock)
        with clock("monitor"):
            return TickResult(mode=Mode.DP, next_cell=None, detections=self._classify(new_pairs),
                              iterations=iterations)

    def _iterate(self, clock: PhaseClock) -> tuple[list[tuple[int, Cell]], int]:
        """The tick's DP iterations (:func:`iterations_within` the budget, if any) with the monitor observing the
        pair distances after each (the engine samples them as it iterates). Returns the newly blocked pairs with
        their iteration, and the iterations run."""
        new_pairs = []
        # The monitor reads the nodes' cells; R and G too only when this tick reads the graph anyway (following a
        # backup, or searching): a layer kind with nothing to iterate then launches no kernel in most ticks.
        reads_graph = self.backup.follow is not Follow.GOAL
        cells = self.vertices.cells(self.robot, self.goal) if reads_graph else self.nodes

        def iterate(k: int) -> None:
            with clock("dp"):
                samples = self.engine.advance(k, cells) if self.config.accelerating else self.engine.step(k)
            with clock("monitor"):
                if self.config.accelerating:
                    if reads_graph:
                        self.readings.remember(self.robot, self.goal, samples[-1])
                    new_pairs.extend(self.readings.observe(samples))

        done = iterations_within(iterate, self.config.updates_per_move, self.config.budget_ms)
        self.backup = iterated(self.backup, done)
        return new_pairs, done

    def _decide(self, result: TickResult) -> None:
        """Apply the backup rules (:func:`tdp.backup.next_step`); with ``switch_back="evidence"``, follow the goal
        layer again as soon as it is trusted (:meth:`_goal_layer_beats_backup`)."""
        following_backup = self.backup.follow is Follow.BACKUP
        relevant = any(d.relevant for d in result.detections)
        step = next_step(self.backup, relevant, self._subgoal_at_robot(), self.dmax_q)
        if step is Step.SWITCH_BACK:
            self.backup = switched_back(self.backup)
            result.switched_back = True
        elif step is not Step.KEEP:
            self._search(result, step)
        evidence = self.backup.follow is not Follow.GOAL and self.config.switch_back == "evidence"
        if evidence and self._goal_layer_beats_backup(settled_route=following_backup):
            result.switched_back = following_backup
            self.backup = switched_back(self.backup)

    def _next_move(self, result: TickResult) -> Cell | None:
        """The followed layer's successor; following a backup whose layer does not reach R, search again, and with
        no node layer offering a move, the goal layer's; out of a cell an obstacle covers, the way out."""
        cell = self._successor()
        if cell is None and self.backup.follow is Follow.BACKUP:
            self._search(result, Step.RESEARCH)
            cell = self._successor()
        if cell is None and self.backup.follow is Follow.BACKUP:
            self.backup = without_route(self.backup)
            cell = self._successor()
        if self.engine.occupied[self.robot]:  # a door closed on it, a box parked over it: the way out
            cell = self.moves.escape(self.engine.occupied, self.robot, self._followed_values) or cell
        return cell

    def _move(self, result: TickResult, clock: PhaseClock) -> None:
        """The tick's mode and, with ``avoid_boxes``, the move vetted against the boxes' predicted arrivals."""
        moving = result.next_cell is not None or self.robot == self.goal
        following = Mode.BACKUP if self.backup.follow is Follow.BACKUP else Mode.DP
        result.mode = following if moving else Mode.WAIT
        result.subgoal = self.backup.subgoal
        if self.config.avoid_boxes and self.robot != self.goal:
            with clock("predict"):
                legal_moves = partial(self.moves.legal, self.engine.occupied, self.robot)
                cleared = self.lookout.clear_move(self.robot, result.next_cell, self.route, legal_moves,
                                                  self._followed_values)
                if (cleared is None) != (result.next_cell is None):  # held back, or stepped aside from a wait
                    result.mode = Mode.YIELD
                result.next_cell = cleared

    def _search(self, result: TickResult, step: Step) -> None:
        """Search the node graph R -> G for a backup (:func:`tdp.backup.plan_backup`) and follow it; with none,
        follow the goal layer and search again next tick."""
        direct = self._goal_chain(math.ceil(self.dmax_q) + 1) is not None
        graph = self.readings.graph(self.robot, self.goal, blocked=True, direct_goal=direct)
        found = plan_backup(graph, lambda a, b: self.readings.driven_length(a, b, self.robot, self.goal))
        self.backup = after_search(self.backup, found, step)
        if found is not None:
            result.backup_path, result.backup_cost = list(found.path), found.cost

    def _goal_layer_beats_backup(self, settled_route: bool) -> bool:
        """Whether the goal layer can be trusted again and knows a route no longer than the backup's (more than
        ``evidence_slack`` longer than its estimate from R loses; :func:`tdp.backup.goal_route_wins`)."""
        budget = cost_from_robot(self.backup, self._subgoal_at_robot()) * (1 + self.config.evidence_slack)
        max_steps = 4 * sum(self.grid.shape) if math.isinf(budget) else math.floor(budget) + 1
        chain = self._goal_chain(max_steps)
        if chain is None:
            return False
        lengths, costs = chain_moves(chain, self.engine.cost)
        if costs.sum() > budget:  # the cost alone decides: no sample of the values (a kernel launch)
            return False
        values = self.engine.sample(chain[:cells_near(lengths, self.spacing) + 1])[:, 0].astype(np.float64)
        return goal_route_wins(costs, values, budget, settled_route, self.config.rise, self.config.settled_cells)

    def _subgoal_at_robot(self) -> float:
        """The subgoal's layer at R while a backup is followed (inf otherwise)."""
        if self.backup.follow is not Follow.BACKUP:
            return math.inf
        return self.readings.graph(self.robot, self.goal).at_robot(self.backup.subgoal)

    def _goal_chain(self, max_steps: int) -> list[Cell] | None:
        """The goal layer's successors from R if they are a real route to G (:meth:`NodeReadings.real_chain`)."""
        return self.readings.real_chain(self.robot, self.vertices.goal, max_steps, self.robot, self.goal)

    def _classify(self, new_pairs: list[tuple[int, tuple[int, int]]]) -> list[Detection]:
        """Mark each newly blocked pair relevant if its segment passes within s cells of the route the robot
        follows (:meth:`_followed_route`)."""
        if not new_pairs:
            return []
        path = self._followed_route()
        return [Detection(iteration, pair, segment_near_path(self.nodes[pair[0]], self.nodes[pair[1]], path,
                                                              self.spacing))
                for iteration, pair in new_pairs]

    def _followed_route(self) -> np.ndarray:
        """Cells (m, 2) of the way the robot is going: its current DP path and, following a backup, the subgoal
        layer's successors from R and the straight legs through the rest of the backup path to G - a cut on the
        detour matters as much as one on the DP's route."""
        cells = self.current_path()
        if self.backup.follow is Follow.BACKUP:
            cells += self.route(max(1, int(4 * self.dmax_q)))
            path = self.backup.route.path
            legs = path[path.index(self.backup.subgoal):]
            cells += polyline_cells([self.vertices.cell(v, self.robot, self.goal) for v in legs])
        return np.array(cells)

    def _followed_values(self, cells: list[Cell]) -> np.ndarray:
        """The followed layer's values at ``cells``."""
        return self.engine.sample(cells)[:, self._followed_layer()]

    # -- reading the plan ----------------------------------------------------------------------------------------
    def node_edges(self) -> list[tuple[int, int]]:
        """The node pairs (a < b) connected in the node graph now (eq. 14), e.g. for a figure."""
        if not self.config.accelerating:
            return []
        return [(a, b) for a, b, _ in self.readings.graph(self.robot, self.goal).edges()]

    def current_path(self) -> list[Cell]:
        """The robot's current DP path: successors of the goal layer from R, up to the goal or 4 DmaxQ cells."""
        limit = max(1, int(4 * self.dmax_q)) if self.config.accelerating else self.grid.shape[0] * self.grid.shape[1]
        return [self.robot] + self.engine.trace(0, self.robot, limit)

    def route(self, steps: int) -> list[Cell]:
        """Up to ``steps`` cells the robot would follow from R now: successors of the goal layer, or in backup mode
        of the subgoal's layer (for a controller's look-ahead). Empty at the goal or where the layer gives no move."""
        return [] if self.robot == self.goal else self.engine.trace(self._followed_layer(), self.robot, steps)

    def _followed_layer(self) -> int:
        """The layer the robot follows: the subgoal's in backup mode, else 0 (the goal layer)."""
        subgoal = self.backup.subgoal
        return 0 if subgoal is None else self.vertices.layer(subgoal)

    def _successor(self) -> Cell | None:
        return next(iter(self.route(1)), None)


def _check(grid: GridMap, config: NavigatorConfig) -> None:
    """A Navigator's grid and config, or a ValueError naming what is wrong."""
    if not isinstance(config, NavigatorConfig):
        raise ValueError(f"config must be a tdp.NavigatorConfig, got {type(config).__name__}")
    if config.planner == "exact":
        raise ValueError("Navigator runs the planners 'accelerating' and 'plain-dp'; for planner 'exact' use "
                         "tdp.ExactPlanner, or tdp.make_planner for whichever the config names")
    if not isinstance(grid, GridMap):
        raise ValueError(f"grid must be a tdp.GridMap, got {type(grid).__name__}")


def _lattice(grid: GridMap, config: NavigatorConfig) -> tuple[np.ndarray, float]:
    """The accelerating nodes' cells (n, 2) and the lattice spacing s (cells); none for plain DP."""
    if not config.accelerating:
        return np.zeros((0, 2), np.int32), 0.0
    count = None if config.spacing is not None else config.nodes
    lattice = place_nodes(grid.occupied, count=count, spacing=config.spacing, rule=config.placement)
    return lattice.cells, lattice.spacing


def iterations_within(iterate: Callable[[int], None], k: int, budget_ms: float | None) -> int:
    """Run ``iterate(k)`` (K iterations) without a budget; with ``budget_ms`` one iteration, then as many more as the
    rate so far says fit in what is left (at most twice the last call's) until no more fit. At most
    MOST_PER_CALL iterations a call: each call's samples and pair distances are held at once (an idle layer's
    iterations cost next to nothing: a budget of a second ran calls of 8,192, 40 MB at 25 nodes, a K of a million
    one of 4.7 GB). Returns the iterations run."""
    if budget_ms is None:
        for done in range(0, k, MOST_PER_CALL):
            iterate(min(MOST_PER_CALL, k - done))
        return k
    began, done, k = time.perf_counter(), 0, 1
    while True:
        iterate(k)
        done += k
        spent = time.perf_counter() - began
        left = budget_ms / 1e3 - spent
        if left < spent / done:  # not enough left for one more iteration at the rate so far
            return done
        k = max(1, min(int(left / (spent / done)), 2 * k, MOST_PER_CALL))
