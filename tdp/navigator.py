"""The navigator: the loop of the paper's Fig. 4 (sections 4.1-4.3, ARCHITECTURE §5.4-5.6).

Setup (``converge``), then per tick: K DP iterations with the blockage monitor after each, the relevance test of
new blockages against the robot's current path, a backup path by uniform-cost search over the node graph, subgoal
following with re-search, the switch back to the DP after ||Path|| iterations, and waiting while no route exists.
"""
from __future__ import annotations

import math
import time
from dataclasses import asdict, dataclass

import numpy as np

from . import checks
from .blockage import BlockageMonitor, segment_near_path
from .contract import Detection, Mode, TickResult
from .engine import Engine
from .field import cells_from, check_cap
from .grid import GridMap
from .nodes import PLACEMENTS, NodeGraph, choose_subgoal, pair_distances, place_nodes
from .predict import MotionPredictor
from .search import uniform_cost_search
from .stencil import check_neighbourhood, escape_move, legal_moves, moves

#: The planners a config can name: exact replanning every tick (tdp.ExactPlanner), the paper's accelerating nodes and
#: its plain DP baseline (tdp.Navigator).
PLANNERS = ("exact", "accelerating", "plain-dp")
#: What each planner is called in messages and figures.
PLANNER_NAMES = {"exact": "exact replanning", "accelerating": "accelerating nodes", "plain-dp": "plain DP"}
#: How a backup ends: "evidence" (as soon as the goal layer shows a route to G no longer than the backup's, or
#: after ||Path|| iterations) or "paper" (after ||Path|| iterations only, section 4.3).
SWITCH_BACK = ("evidence", "paper")
#: With switch_back="evidence", the goal layer's route wins when it is at most this fraction longer than the
#: backup's estimate: the estimate reads node layers that are at most the true lengths while they rise, while the
#: route's length counts every detour the goal layer still holds around boxes that are moving far ahead.
EVIDENCE_SLACK = 0.1
#: How far (cells) a value of the goal layer may sit below its successor's plus the move and still count as
#: settled: float rounding only; a value still rising after a change is short by about a cell or more.
SETTLED_CELLS = 0.25
#: With avoid_boxes, a step aside prefers cells no box is predicted to enter within this many ticks.
AVOID_TICKS = 2
#: With avoid_boxes, how many of the robot's next moves are checked against the arrivals of boxes crossing its way.
MEET_TICKS = 8


@dataclass(frozen=True)
class NavigatorConfig:
    """Every parameter of the planner.

    planner: "exact" (default: the goal layer repaired exactly every tick, :class:`tdp.ExactPlanner`; RESULTS.md's
    equal-time benchmark finds it the best for a user who does not choose), "accelerating" (the paper's accelerating
    nodes, :class:`tdp.Navigator`) or "plain-dp" (the paper's baseline: K synchronous DP iterations per move). The
    exact planner reads the stencil, ``d_max`` and ``budget_ms`` (then its repair is anytime: see ExactPlanner);
    ``accelerating=False`` of earlier versions is ``planner="plain-dp"``.
    nodes: number of nodes of the uniform lattice (its spacing s follows from the map's area);
    spacing: lattice spacing s in cells, overriding ``nodes`` when given.
    vision: DmaxQ / s (ARCHITECTURE §5.2). updates_per_move: K, DP iterations per robot move.
    budget_ms: a time budget per tick in milliseconds instead of a fixed K: each tick runs as many DP iterations
    as fit in it, the monitor included (at least one; the number depends on the machine, so runs do too); for the
    exact planner, how long its repair may run before the robot moves on the layer as far as it got.
    detect_window, detect_rise: J and U of the blockage test (U defaults to J - 1).
    d_max: cap of the goal layer (eq. 5). neighbourhood, corner_cutting: the stencil (ARCHITECTURE §4).
    placement: where a lattice node whose centre is on an obstacle goes: "free" (the free cell of its lattice cell
    nearest the centre), "drop" (left out, the paper) or "nudge" (a free cell within s/4); see
    :func:`tdp.nodes.place_nodes`.
    switch_back: "evidence" (leave a backup as soon as the goal layer's successors reach G by a route no longer
    than the backup's estimate, and never start one that the goal layer already beats) or "paper" (only after
    ||Path|| DP iterations, section 4.3).
    predict_ticks: obstacle prediction's horizon H in ticks (0: off; ARCHITECTURE §5.7): moving boxes are tracked
    from the map updates and the node layers (not the goal layer) see the cells they are predicted to sweep over
    in the next H ticks, so the monitor flags a passage a box is about to close.
    avoid_boxes: with the same tracking, the robot does not step into a cell a box is predicted to enter at the next
    tick: it yields (stays) or, if a box is about to enter its own cell, steps aside.
    """

    planner: str = "exact"
    nodes: int = 25
    vision: float = 2.5
    updates_per_move: int = 4
    detect_window: int = 6
    detect_rise: float | None = None
    d_max: float = math.inf
    neighbourhood: int = 16
    corner_cutting: bool = False
    spacing: float | None = None
    budget_ms: float | None = None
    placement: str = "free"
    switch_back: str = "evidence"
    predict_ticks: int = 0
    avoid_boxes: bool = False

    def __post_init__(self):
        def normalised(name: str, value) -> None:  # the checked value, as a plain Python int, float or bool
            object.__setattr__(self, name, value)

        if self.planner not in PLANNERS:
            raise ValueError(f"planner must be one of {PLANNERS}, got {self.planner!r}")
        normalised("nodes", checks.integer(self.nodes, "nodes", 1))
        if self.spacing is not None:
            normalised("spacing", checks.number(self.spacing, "spacing", 1.0))
        normalised("vision", checks.number(self.vision, "vision", 0.0, inclusive=False))
        normalised("updates_per_move", checks.integer(self.updates_per_move, "updates_per_move", 1))
        if self.budget_ms is not None:
            normalised("budget_ms", checks.number(self.budget_ms, "budget_ms", 0.0, inclusive=False))
        normalised("detect_window", checks.integer(self.detect_window, "detect_window", 1))
        if self.detect_rise is not None:
            normalised("detect_rise", checks.number(self.detect_rise, "detect_rise", 0.0, inclusive=False))
        check_cap(self.d_max, "d_max")
        check_neighbourhood(self.neighbourhood)
        normalised("corner_cutting", checks.flag(self.corner_cutting, "corner_cutting"))
        if self.placement not in PLACEMENTS:
            raise ValueError(f"placement must be one of {PLACEMENTS}, got {self.placement!r}")
        if self.switch_back not in SWITCH_BACK:
            raise ValueError(f"switch_back must be one of {SWITCH_BACK}, got {self.switch_back!r}")
        normalised("predict_ticks", checks.integer(self.predict_ticks, "predict_ticks", 0))
        normalised("avoid_boxes", checks.flag(self.avoid_boxes, "avoid_boxes"))
        if self.planner == "exact" and (self.predict_ticks or self.avoid_boxes):
            raise ValueError("predict_ticks and avoid_boxes track boxes for the DP planners: they need planner "
                             "'accelerating' or 'plain-dp', not 'exact'")

    @property
    def accelerating(self) -> bool:
        """Whether the planner is the paper's accelerating nodes."""
        return self.planner == "accelerating"

    @property
    def rise(self) -> float:
        """U: the rise over J iterations that signals a blockage."""
        return float(self.detect_window - 1) if self.detect_rise is None else float(self.detect_rise)

    def to_dict(self) -> dict:
        return asdict(self)

    def label(self) -> str:
        """The planner's name with what bounds its work per tick: K for the DP planners, or the budget."""
        return planner_label(self.to_dict())


def planner_label(config: dict) -> str:
    """:meth:`NavigatorConfig.label` of a config written as a dict (an episode's, a run's metrics)."""
    if config.get("budget_ms") is not None:
        return f"{PLANNER_NAMES[config['planner']]}, {config['budget_ms']:g} ms"
    return PLANNER_NAMES[config["planner"]] + ("" if config["planner"] == "exact" else
                                               f", K = {config['updates_per_move']}")


class Navigator:
    """Plans a robot's moves on a changing grid with the paper's DP: accelerating nodes (``planner="accelerating"``)
    or plain DP (``"plain-dp"``), K synchronous iterations (or a time budget's worth) per move.

    Cells are (row, col); the navigator never moves the robot itself: :meth:`tick` says where to go and the caller
    reports the robot's position with :meth:`move_robot`. Map edits (:meth:`update_map`) and goal moves
    (:meth:`set_goal`) take effect at the next DP iteration.
    """

    def __init__(self, grid: GridMap, start: tuple[int, int], goal: tuple[int, int],
                 config: NavigatorConfig = NavigatorConfig(planner="accelerating")):
        if not isinstance(config, NavigatorConfig):
            raise ValueError(f"config must be a tdp.NavigatorConfig, got {type(config).__name__}")
        if config.planner == "exact":
            raise ValueError("Navigator runs the planners 'accelerating' and 'plain-dp'; for planner 'exact' use "
                             "tdp.ExactPlanner, or tdp.make_planner for whichever the config names")
        if not isinstance(grid, GridMap):
            raise ValueError(f"grid must be a tdp.GridMap, got {type(grid).__name__}")
        self.grid = grid
        self.config = config
        self.robot = grid.check_free_cell(start, "start")
        self._walls = grid.occupied.copy()  # the map's own obstacles: occupied in ``grid`` and never freed since
        goal = grid.check_free_cell(goal, "goal")
        if config.accelerating:
            count = None if config.spacing is not None else config.nodes
            lattice = place_nodes(grid.occupied, count=count, spacing=config.spacing, rule=config.placement)
            self.nodes, self.spacing = lattice.cells, lattice.spacing
        else:
            self.nodes, self.spacing = np.zeros((0, 2), np.int32), 0.0
        self.dmax_q = config.vision * self.spacing  # DmaxQ, in cells
        self.engine = Engine(grid.occupied, goal, goal_cap=config.d_max, nodes=self.nodes,
                             node_cap=self.dmax_q + config.rise, neighbourhood=config.neighbourhood,
                             corner_cutting=config.corner_cutting)
        self.monitor = BlockageMonitor(self.dmax_q, config.detect_window, config.rise)
        # What the robot follows: "dp" (S(., G)), "backup" (S(., subgoal)), or "no-route": S(., G) while the last
        # search found no route in the node graph, searching again every tick.
        self.state = "dp"
        self._path_cost = 0.0
        self._since_detection = 0
        self._subgoal: int | None = None
        self._cost_to_goal: dict[int, float] = {}  # along the last backup path: cost from each vertex to G
        self._backup_path: list[int] = []  # the last backup path's vertices, R first
        # Iteration from which each node is active: inf while covered, and after it is uncovered, long enough for
        # its layer to settle (phantom values rise at least a cell per iteration, true ones arrive within DmaxQ).
        self._active_from = np.zeros(len(self.nodes))
        self._settling = math.ceil(self.dmax_q + config.rise) + 1
        # Every layer at the graph cells, with the state it was read in: (iteration, R, G, edits), values.
        self._readings: tuple[tuple, np.ndarray] | None = None
        self._edits = 0  # map edits and setups so far: they change the layers between iterations
        self.last_iterations = 0  # DP iterations the last tick ran
        # Obstacle prediction (predict_ticks > 0): the tracker, the ticks so far, the cells that became occupied
        # since the last tick, and the cells the node layers hold occupied on prediction alone.
        self.predictor = MotionPredictor(grid.shape) if config.predict_ticks or config.avoid_boxes else None
        self._ticks = 0
        self._became_occupied: list[np.ndarray] = []
        self._predicted = np.zeros(grid.shape, bool)
        self._predicted_cells = np.zeros((0, 2), np.int64)

    # -- inputs ------------------------------------------------------------------------------------------------
    @property
    def goal(self) -> tuple[int, int]:
        return self.engine.goal

    def setup(self) -> int:
        """The setup phase (robot stationary): compile the engine's kernels, converge every layer; returns the
        rounds converging took."""
        self._edits += 1
        self.engine.warm_up()
        return self.engine.converge()

    def update_map(self, cells_or_mask, occupied: bool | np.ndarray = True) -> None:
        """Set cells (a mask or (row, col) cells) occupied or free; ``occupied`` may give one value per cell."""
        cells = cells_from(self.grid.shape, cells_or_mask, "update_map")
        flags = np.broadcast_to(np.asarray(occupied, bool), (len(cells),))
        self._walls[cells[~flags, 0], cells[~flags, 1]] = False
        if self.predictor is not None:
            self._became_occupied.append(cells[flags & ~self.engine.occupied[cells[:, 0], cells[:, 1]]])
        self.engine.set_cells(cells, flags)
        if self.predictor is not None:  # the node layers keep the predicted cells occupied
            self.engine.set_node_cells(cells[self._predicted[cells[:, 0], cells[:, 1]]], True)
        self._edits += 1
        self._update_cover()

    def _update_cover(self) -> None:
        """Nodes on an occupied (or predicted) cell leave the graph; uncovered ones return once settled."""
        rows, cols = self.nodes[:, 0], self.nodes[:, 1]
        covered = self.engine.occupied[rows, cols] | self._predicted[rows, cols]
        uncovered = ~covered & np.isinf(self._active_from)
        self._active_from[covered] = np.inf
        self._active_from[uncovered] = self.engine.iterations + self._settling

    def set_goal(self, goal: tuple[int, int]) -> None:
        """Move the target (moving-target scenarios). The goal may be on an obstacle (a moving target may cross
        one): while it is, the goal layer has no source, its values rise, and the robot keeps to the last route
        the layer knew until the target is on free ground again."""
        self.engine.set_goal(checks.cell(goal, self.grid.shape, "goal"))

    def move_robot(self, cell: tuple[int, int]) -> None:
        """Tell the navigator where the robot is now (a cell inside the map; it may be on an obstacle that drove
        onto it)."""
        self.robot = checks.cell(cell, self.grid.shape, "robot cell")

    # -- the tick ----------------------------------------------------------------------------------------------
    def tick(self) -> TickResult:
        """K DP iterations with the monitor after each, then the mode logic; returns where to move.

        The mode is "dp" or "backup" while the robot moves, "wait" while it has nowhere to go: the robot follows
        the goal layer when the node graph has no route (the search is retried every tick) and waits only when
        neither offers a move (ARCHITECTURE §5.5).
        """
        began = time.perf_counter()
        if self.predictor is not None:
            self._predict()
        predict_s = time.perf_counter() - began
        new_pairs, dp_s, monitor_s = self._run_iterations()
        began = time.perf_counter()
        result = TickResult(mode=Mode.DP, next_cell=None, detections=self._classify(new_pairs))
        monitor_s += time.perf_counter() - began

        began = time.perf_counter()
        self._update_state(result)
        result.next_cell = self._next_cell()
        if result.next_cell is None and self.state == "backup":
            self._search(result, keep_count=True)  # the subgoal's layer does not reach R: look again
            result.next_cell = self._next_cell()
        if result.next_cell is None and self.state == "backup":
            self.state, self._subgoal = "no-route", None  # no node layer offers a move: the goal layer's
            result.next_cell = self._next_cell()
        if self.engine.occupied[self.robot]:
            result.next_cell = self._escape() or result.next_cell
        search_s = time.perf_counter() - began
        moving = result.next_cell is not None or self.robot == self.goal
        result.mode = (Mode.BACKUP if self.state == "backup" else Mode.DP) if moving else Mode.WAIT
        if self.config.avoid_boxes and moving:
            began = time.perf_counter()
            result.next_cell = self._clear_of_boxes(result.next_cell)
            if result.next_cell is None and self.robot != self.goal:
                result.mode = Mode.YIELD
            predict_s += time.perf_counter() - began
        result.subgoal = self._subgoal if self.state == "backup" else None
        result.timings = {"dp": dp_s, "monitor": monitor_s, "search": search_s}
        if self.predictor is not None:
            result.timings["predict"] = predict_s
        result.iterations = self.last_iterations
        return result

    def _predict(self) -> None:
        """Feed the tracker this tick's newly occupied cells and hold the cells the boxes are predicted to sweep over
        in the next ``predict_ticks`` ticks occupied in the node layers (ARCHITECTURE §5.7)."""
        self._ticks += 1
        became = np.vstack(self._became_occupied) if self._became_occupied else np.zeros((0, 2), np.int64)
        self._became_occupied = []
        self.predictor.observe(self._ticks, became)
        cells = self.predictor.entering(self._ticks, self.config.predict_ticks)
        cells = cells[~self.engine.occupied[cells[:, 0], cells[:, 1]]]
        old = self._predicted_cells
        already = self._predicted[cells[:, 0], cells[:, 1]]
        self._predicted[old[:, 0], old[:, 1]] = False
        self._predicted[cells[:, 0], cells[:, 1]] = True
        freed = old[~self._predicted[old[:, 0], old[:, 1]] & ~self.engine.occupied[old[:, 0], old[:, 1]]]
        self.engine.set_node_cells(freed, False)
        self.engine.set_node_cells(cells[~already], True)
        if len(freed) or not already.all():
            self._edits += 1
        self._predicted_cells = cells
        self._update_cover()

    def _clear_of_boxes(self, wanted: tuple[int, int] | None) -> tuple[int, int] | None:
        """The move to make given the cells the tracked boxes are predicted to enter (ARCHITECTURE §5.7): ``wanted``
        if the robot meets no box on its next MEET_TICKS moves (:meth:`_meets_a_box`); else stay (yield) if none
        enters the robot's cell at the next tick; else step aside to a legal move that no box enters at the next
        tick - one that none enters within AVOID_TICKS if there is such, the lowest value of the followed layer plus
        the move's length among them; ``wanted`` when every move is entered at the next tick."""
        arrivals = self.predictor.arrivals(self._ticks, AVOID_TICKS)
        if wanted is not None and not self._meets_a_box(wanted, arrivals):
            return wanted
        if arrivals.get(self.robot, math.inf) > 1:
            return None
        options = [(cell, cost) for cell, cost in self._legal_moves() if arrivals.get(cell, math.inf) > 1]
        if not options:
            return wanted
        values = self.engine.sample([cell for cell, _ in options])[:, self._followed_layer()]
        clear = [arrivals.get(cell, math.inf) > AVOID_TICKS for cell, _ in options]
        best = max(range(len(options)), key=lambda i: (clear[i], -(values[i] + options[i][1])))
        return options[best][0]

    def _meets_a_box(self, wanted: tuple[int, int], arrivals: dict[tuple[int, int], int]) -> bool:
        """Whether a box is predicted to enter ``wanted`` at the next tick, or a box moving across the robot's way
        to enter one of its next MEET_TICKS cells (``wanted``, then the followed layer's successors) no later than
        the robot would get there, a move per tick. The next cell alone let the robot escort a box that drove across
        its way: it stepped along the box's front, one cell per yield, for as long as the box drove. A box moving
        along the robot's way is left to the next-cell test: waiting for it does not clear the way."""
        if arrivals.get(wanted, math.inf) <= 1:
            return True
        ahead = self.route(MEET_TICKS)
        if not ahead or ahead[0] != wanted:
            return False
        heading = np.subtract(ahead[-1], self.robot)
        across = self.predictor.arrivals(self._ticks, MEET_TICKS, across=heading)
        return any(across.get(cell, math.inf) <= moves_there for moves_there, cell in enumerate(ahead, start=1))

    def _escape(self) -> tuple[int, int] | None:
        """The robot's cell is occupied (a door closed on it, a box parked over it): the first move of the shortest
        way out, through the obstacles (never its walls: the cells occupied in the map it was given and never freed
        since, so a box that stood there at the start and drove off is no wall), towards the followed
        layer's target (:func:`~tdp.stencil.escape_move`); None when no way out within ESCAPE_CELLS reaches a
        finite value. The layer's own successor is one of the ways out; a door that closed on the robot in its
        doorway may have its shorter way out on the far side."""
        layer = self._followed_layer()

        def layer_distances(cells):
            values = self.engine.sample(cells)[:, layer].astype(np.float64)
            return np.where(values >= self.config.d_max, np.inf, values)

        allowed = moves(self.config.neighbourhood, self.config.corner_cutting)
        return escape_move(self.engine.occupied, self.robot, allowed, layer_distances, walls=self._walls)

    def _legal_moves(self) -> list[tuple[tuple[int, int], float]]:
        """(cell, cost) of every stencil move from R into a free cell, crossing only free cells."""
        allowed = moves(self.config.neighbourhood, self.config.corner_cutting)
        return list(legal_moves(self.engine.occupied, self.robot, allowed))

    def _run_iterations(self) -> tuple[list[tuple[int, tuple[int, int]]], float, float]:
        """The tick's DP iterations - K, or with ``budget_ms`` as many as fit in the budget (at least one) - with
        the monitor observing the pair distances after each (the engine samples them as it iterates). Returns the
        newly blocked pairs with their iteration, and the seconds spent in DP and monitor."""
        budget_s = None if self.config.budget_ms is None else self.config.budget_ms / 1e3
        began = time.perf_counter()
        k = self.config.updates_per_move if budget_s is None else 1
        done, dp_s, monitor_s, new_pairs = 0, 0.0, 0.0, []
        # The monitor reads the nodes' cells; R and G too only when this tick reads the graph anyway (following a
        # backup, or searching): a layer kind with nothing to iterate then launches no kernel in most ticks.
        reads_graph = self.state != "dp"
        cells = self._graph_cells() if reads_graph else self.nodes
        while True:
            dp_began = time.perf_counter()
            if self.config.accelerating:
                samples = self.engine.advance(k, cells)
                if reads_graph:
                    self._readings = (self._reading_state(), samples[-1])
            else:
                self.engine.step(k)
            monitor_began = time.perf_counter()
            dp_s += monitor_began - dp_began
            if self.config.accelerating:
                new_pairs += self._observe(samples)
            monitor_s += time.perf_counter() - monitor_began
            done += k
            if budget_s is None:
                break
            spent = time.perf_counter() - began
            left = budget_s - spent
            if left < spent / done:  # not enough left for one more iteration at the rate so far
                break
            k = max(1, min(int(left / (spent / done)), 2 * k))
        self._since_detection += done
        self.last_iterations = done
        return new_pairs, dp_s, monitor_s

    def _observe(self, samples: np.ndarray) -> list[tuple[int, tuple[int, int]]]:
        """Feed the monitor the pair distances of the iterations ``samples`` holds, in one call; the pairs newly
        blocked, with their iteration."""
        first = self.engine.iterations - len(samples) + 1
        active = self._active_nodes(first + np.arange(len(samples))[:, None])  # (iterations, nodes)
        found = self.monitor.observe_iterations(pair_distances(samples, active))
        return [(first + step, pair) for step, pair in found]

    def _graph_cells(self) -> np.ndarray:
        """The cells the node graph reads every layer at: the nodes, then R, then G."""
        return np.vstack([self.nodes, [self.robot], [self.goal]])

    def _active_nodes(self, iteration: int | np.ndarray | None = None) -> np.ndarray:
        """Nodes active at DP iteration ``iteration`` (default: the last; a column of iterations gives a row per
        iteration): not covered by an obstacle, and settled since they were last uncovered (ARCHITECTURE §5.1)."""
        return self._active_from <= (self.engine.iterations if iteration is None else iteration)

    def _graph(self, without_blocked: bool = False) -> NodeGraph:
        """The node graph of eq. 14 now; for a search, without the pairs the monitor holds blocked, and with the
        direct R-G edge only where the goal layer's successors really reach G (while news of a cut travels, its
        value at R can be under DmaxQ and stale)."""
        if self._readings is None or self._readings[0] != self._reading_state():
            self._readings = (self._reading_state(), self.engine.sample(self._graph_cells()))
        unreliable, direct = None, True
        if without_blocked:
            unreliable = self.monitor.blocked
            direct = self._real_goal_route(math.ceil(self.dmax_q) + 1) is not None
        return NodeGraph(self._readings[1], self.dmax_q, self._active_nodes(), unreliable, direct)

    def _reading_state(self) -> tuple:
        """What the layers read at the graph cells depend on: the iteration, R, G and the edits so far."""
        return self.engine.iterations, self.robot, self.goal, self._edits

    def node_edges(self) -> list[tuple[int, int]]:
        """The node pairs (a < b) connected in the node graph now (eq. 14), e.g. for a figure."""
        if not self.config.accelerating:
            return []
        return [(a, b) for a, b, _ in self._graph().edges()]

    def current_path(self) -> list[tuple[int, int]]:
        """The robot's current DP path: successors of the goal layer from R, up to the goal or 4 DmaxQ cells."""
        limit = max(1, int(4 * self.dmax_q)) if self.config.accelerating else self.grid.shape[0] * self.grid.shape[1]
        return [self.robot] + self.engine.trace(0, self.robot, limit)

    def _classify(self, new_pairs) -> list[Detection]:
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
        if self.state == "backup":
            cells += self.route(max(1, int(4 * self.dmax_q)))
            corners = [self._vertex_cell(v) for v in self._backup_path[self._backup_path.index(self._subgoal):]]
            for a, b in zip(corners, corners[1:]):
                steps = int(max(abs(b[0] - a[0]), abs(b[1] - a[1]))) + 1
                cells += [tuple(cell) for cell in np.rint(np.linspace(a, b, steps)).astype(int)]
        return np.array(cells)

    def _vertex_cell(self, vertex: int) -> tuple[int, int]:
        """The cell of a graph vertex: node j, R (n) or G (n + 1)."""
        if vertex < len(self.nodes):
            return tuple(int(v) for v in self.nodes[vertex])
        return self.robot if vertex == len(self.nodes) else self.goal

    def _update_state(self, result: TickResult) -> None:
        """Start a backup on a relevant blockage, re-search near the subgoal, switch back after ||Path|| or, with
        ``switch_back="evidence"``, as soon as the goal layer is trusted again."""
        following_backup = self.state == "backup"
        if any(d.relevant for d in result.detections):
            self._since_detection = 0
            self._search(result, keep_count=False)
        elif self.state == "backup":
            if self._since_detection >= self._path_cost:
                self.state, self._subgoal = "dp", None
                result.switched_back = True
            elif self._layer_at_robot(self._subgoal) < self.dmax_q / 2:
                self._search(result, keep_count=True)
        elif self.state == "no-route":
            self._search(result, keep_count=False)
        if self.state != "dp" and self.config.switch_back == "evidence" and self._goal_layer_beats_backup(
                settled_route=following_backup):
            result.switched_back = following_backup
            self.state, self._subgoal = "dp", None

    def _goal_layer_beats_backup(self, settled_route: bool) -> bool:
        """Whether the goal layer can be trusted again and knows a route no longer than the backup's.

        The successors only ever make legal moves on the current map, so a chain from R that reaches G is a real
        route; while the news of a cut is still travelling, the chain runs into the cut and does not reach G. The
        route must be at most EVIDENCE_SLACK longer than the backup's estimate from R, and settled near the robot:
        along its first s cells each value equal to its successor's plus the move (within SETTLED_CELLS), i.e. no
        change is still arriving where the robot is about to drive. With ``settled_route`` (leaving a backup the
        robot already follows) it must also be settled as a whole: its length at most U above the goal layer's
        value at R. A larger gap is a rise still on its way to R (the successors turn once it arrives) or detours
        round boxes that moved far ahead; the two cannot be told apart here, so the test holds only once the robot
        has turned to a detour (not deciding whether to start one), where leaving on a rise in transit costs most."""
        budget = self._backup_cost_from_robot() * (1 + EVIDENCE_SLACK)
        chain = self._real_goal_route(4 * sum(self.grid.shape) if math.isinf(budget) else math.floor(budget) + 1)
        if chain is None:
            return False
        steps = np.hypot(*np.diff(np.array(chain), axis=0).T)
        if steps.sum() > budget:
            return False
        near = int(np.searchsorted(np.cumsum(steps), self.spacing)) + 1
        values = self.engine.sample(chain[:near + 1])[:, 0].astype(np.float64)
        if settled_route and steps.sum() - values[0] > self.config.rise:
            return False
        return bool((values[1:] + steps[:near] - values[:-1] <= SETTLED_CELLS).all())

    def _real_goal_route(self, max_steps: int) -> list[tuple[int, int]] | None:
        """The goal layer's successors from R when they reach G within ``max_steps`` moves through no predicted
        cell - a real route on the map as it is, not about to close - else None."""
        return self._real_chain(self.robot, len(self.nodes) + 1, max_steps)

    def _real_chain(self, start: tuple[int, int], vertex: int, max_steps: int) -> list[tuple[int, int]] | None:
        """The successors of graph vertex ``vertex``'s layer from ``start`` when they reach its cell within
        ``max_steps`` moves through no predicted cell, ``start`` first; else None."""
        chain = [start] + self.engine.trace(self._layer_of(vertex), start, max_steps)
        if chain[-1] != self._vertex_cell(vertex) or self._predicted[tuple(np.array(chain).T)].any():
            return None
        return chain

    def _driven_length(self, a: int, b: int) -> float:
        """The length (cells) of the way from graph vertex ``a`` to ``b`` that b's layer really drives: its
        successors from a's cell, if they reach b within DmaxQ; else inf."""
        chain = self._real_chain(self._vertex_cell(a), b, math.ceil(self.dmax_q) + 1)
        return math.inf if chain is None else _length(chain)

    def _backup_cost_from_robot(self) -> float:
        """The backup's estimated cost from R: the subgoal's layer at R plus the rest of the last path (inf when the
        last search found no route)."""
        if self.state != "backup":
            return math.inf
        return self._layer_at_robot(self._subgoal) + self._cost_to_goal[self._subgoal]

    def _search(self, result: TickResult, keep_count: bool) -> None:
        """Uniform-cost search R -> G; on success follow the subgoal (ARCHITECTURE §5.5), else follow the goal
        layer and search again next tick."""
        graph = self._graph(without_blocked=True)
        found = self._driven_search(graph)
        if found is None:
            self.state, self._subgoal = "no-route", None
            return
        path, cost = found
        if not keep_count:
            self._path_cost = cost
        result.backup_path, result.backup_cost = path, cost
        self.state = "backup"
        self._subgoal = choose_subgoal(path, graph)
        if self._subgoal not in path[:2] and math.isinf(self._driven_length(graph.robot_id, self._subgoal)):
            self._subgoal = path[1]  # Q2's own layer does not drive R there yet: head for Q1, which it does
        self._backup_path = path
        remaining = 0.0
        self._cost_to_goal = {path[-1]: 0.0}
        for a, b in zip(path[-2::-1], path[:0:-1]):
            remaining += graph.weight(a, b)
            self._cost_to_goal[a] = remaining

    def _driven_search(self, graph: NodeGraph) -> tuple[list[int], float] | None:
        """Uniform-cost search R -> G over edges the layers really drive (lazily, ARCHITECTURE §5.5): each edge
        of a found path is traced once along its target's layer and reweighted by the length of that chain, or
        dropped where the chain does not reach (the layer is still stale after a cut); search again until every
        edge of the path has been driven. Returns (path, cost) or None."""
        driven: set[tuple[int, int]] = set()
        while True:
            found = uniform_cost_search(graph.neighbours, graph.robot_id, graph.goal_id)
            if found is None:
                return None
            legs = [(a, b) for a, b in zip(found[0], found[0][1:]) if (a, b) not in driven]
            if not legs:
                return found
            for a, b in legs:
                driven.add((a, b))
                graph.reweight(a, b, max(graph.weight(a, b), self._driven_length(a, b)))

    def _layer_at_robot(self, vertex: int, graph: NodeGraph | None = None) -> float:
        """The value at R of the layer of graph vertex ``vertex`` (a node, or G for the goal layer)."""
        return (graph or self._graph()).at_robot(vertex)

    def route(self, steps: int) -> list[tuple[int, int]]:
        """Up to ``steps`` cells the robot would follow from R now: successors of the goal layer, or in backup mode
        of the subgoal's layer (for a controller's look-ahead). Empty at the goal or where the layer gives no move."""
        if self.robot == self.goal:
            return []
        return self.engine.trace(self._followed_layer(), self.robot, steps)

    def _followed_layer(self) -> int:
        """The layer the robot follows: the subgoal's in backup mode, else 0 (the goal layer)."""
        return self._layer_of(self._subgoal) if self.state == "backup" else 0

    def _layer_of(self, vertex: int) -> int:
        """The engine layer of graph vertex ``vertex``: 1 + j for node j, 0 (the goal layer) for G."""
        return 1 + vertex if vertex < len(self.nodes) else 0

    def _next_cell(self) -> tuple[int, int] | None:
        step = self.route(1)
        return step[0] if step else None


def _length(chain: list[tuple[int, int]]) -> float:
    """Length (cells) of a chain of cells, each move counted by its Euclidean length."""
    return float(np.hypot(*np.diff(np.array(chain), axis=0).T).sum())
