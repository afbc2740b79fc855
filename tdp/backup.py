"""The backup rules of the accelerating-nodes planner (paper sections 4.2-4.3, ARCHITECTURE §5.5): when to search
the node graph for a backup route, which subgoal to follow, when to search again and when to switch back to the
goal layer.

The rules are pure functions over a frozen :class:`BackupState` and readings the caller hands in (whether a relevant
blockage was detected, a layer's value at the robot, a :class:`~tdp.nodes.NodeGraph`, the cost a layer really
drives along an edge), so a test can drive them with hand-built numbers. :class:`tdp.Navigator` reads the engine and
applies them once a tick.

Costs are in the goal layer's units: cells on a binary map; on a map with traversal costs, the moves' costs, while
node layers measure cells (connectivity, for the blockage test) and their readings are lower bounds of a cost until
an edge is driven (ARCHITECTURE §5.5).
"""
from __future__ import annotations

import math
from dataclasses import dataclass, field, replace
from enum import Enum
from typing import Callable

import numpy as np

from .nodes import NodeGraph, choose_subgoal
from .search import uniform_cost_search


class Follow(Enum):
    """Which layer the robot follows: the goal layer (``GOAL``), a backup subgoal's layer (``BACKUP``), or the goal
    layer while the last search found no route in the node graph (``NO_ROUTE``: the search is retried every tick)."""

    GOAL = "goal"
    BACKUP = "backup"
    NO_ROUTE = "no-route"


class Step(Enum):
    """What a tick does about the backup (:func:`next_step`).

    ``SEARCH``: a relevant blockage was detected - search, and count ||Path|| iterations from now.
    ``RETRY``: no route last time - search again, counting from the last detection.
    ``RESEARCH``: the robot is near its subgoal - search again, keeping the backup's ||Path||.
    ``SWITCH_BACK``: ||Path|| iterations have passed since the detection - follow the goal layer again.
    ``KEEP``: nothing to do.
    """

    SEARCH = "search"
    RETRY = "retry"
    RESEARCH = "research"
    SWITCH_BACK = "switch back"
    KEEP = "keep"


@dataclass(frozen=True)
class Backup:
    """A backup route found in the node graph: ``path`` the vertex ids R, Q1, ..., G; ``cost`` its length ||Path||
    (the goal layer's units); ``subgoal`` the vertex the robot heads for; ``cost_to_goal`` the cost from each vertex
    of the path to G along it."""

    path: tuple[int, ...]
    cost: float
    subgoal: int
    cost_to_goal: dict[int, float] = field(default_factory=dict)


@dataclass(frozen=True)
class BackupState:
    """What the backup rules remember between ticks: the layer followed, the backup route followed (None unless
    ``follow`` is BACKUP), ||Path|| of the last backup (DP iterations to wait before switching back; a cost is at
    least the path's cells, so on a map with costs the wait is longer than the news needs) and the DP iterations
    since the last relevant detection."""

    follow: Follow = Follow.GOAL
    route: Backup | None = None
    path_cost: float = 0.0
    since_detection: int = 0

    @property
    def subgoal(self) -> int | None:
        """The vertex the robot heads for while following a backup, else None."""
        return self.route.subgoal if self.follow is Follow.BACKUP else None


def next_step(state: BackupState, relevant_detection: bool, subgoal_at_robot: float, dmax_q: float) -> Step:
    """The paper's rules (section 4.3): a relevant detection starts a search; following a backup, switch back after
    ||Path|| iterations, or search again once the subgoal's layer at R is under DmaxQ / 2 (cells; the robot is
    near its subgoal); with no route, search every tick."""
    if relevant_detection:
        return Step.SEARCH
    if state.follow is Follow.NO_ROUTE:
        return Step.RETRY
    if state.follow is not Follow.BACKUP:
        return Step.KEEP
    if state.since_detection >= state.path_cost:
        return Step.SWITCH_BACK
    return Step.RESEARCH if subgoal_at_robot < dmax_q / 2 else Step.KEEP


def after_search(state: BackupState, found: Backup | None, step: Step) -> BackupState:
    """The state after a search made for ``step`` (SEARCH, RETRY or RESEARCH) found ``found`` (None: no route)."""
    if step is Step.SEARCH:
        state = replace(state, since_detection=0)
    if found is None:
        return replace(state, follow=Follow.NO_ROUTE, route=None)
    path_cost = state.path_cost if step is Step.RESEARCH else found.cost
    return replace(state, follow=Follow.BACKUP, route=found, path_cost=path_cost)


def switched_back(state: BackupState) -> BackupState:
    """The state once the robot follows the goal layer again."""
    return replace(state, follow=Follow.GOAL, route=None)


def without_route(state: BackupState) -> BackupState:
    """The state when no node layer offers the robot a move: the goal layer's, searching again next tick."""
    return replace(state, follow=Follow.NO_ROUTE, route=None)


def iterated(state: BackupState, iterations: int) -> BackupState:
    """The state after ``iterations`` more DP iterations."""
    return replace(state, since_detection=state.since_detection + iterations)


def cost_from_robot(state: BackupState, subgoal_at_robot: float) -> float:
    """The backup's estimated cost from R: the subgoal's layer at R plus the rest of the path (inf unless a backup
    is followed). A node subgoal's layer measures cells: on a map with costs the first leg is a lower bound."""
    if state.follow is not Follow.BACKUP:
        return math.inf
    return subgoal_at_robot + state.route.cost_to_goal[state.route.subgoal]


def plan_backup(graph: NodeGraph, driven_length: Callable[[int, int], float]) -> Backup | None:
    """The backup route R -> G over ``graph`` (:func:`driven_search`), its subgoal (:func:`tdp.nodes.choose_subgoal`;
    Q1 when Q2's layer does not yet drive R there, ``driven_length`` inf) and its costs to G; None when there is no
    route."""
    found = driven_search(graph, driven_length)
    if found is None:
        return None
    path, cost = found
    subgoal = choose_subgoal(path, graph)
    if subgoal not in path[:2] and math.isinf(driven_length(graph.robot_id, subgoal)):
        subgoal = path[1]
    remaining, cost_to_goal = 0.0, {path[-1]: 0.0}
    for a, b in zip(path[-2::-1], path[:0:-1]):
        remaining += graph.weight(a, b)
        cost_to_goal[a] = remaining
    return Backup(tuple(path), cost, subgoal, cost_to_goal)


def driven_search(graph: NodeGraph, driven_length: Callable[[int, int], float]) -> tuple[list[int], float] | None:
    """Uniform-cost search R -> G over edges the layers really drive (lazily, ARCHITECTURE §5.5): each edge a-b of a
    found path is reweighted once to ``max(weight, driven_length(a, b))`` (inf drops it: b's layer does not lead
    from a's cell to b yet; readings are lower bounds of driven costs, so the last path is the cheapest driven one),
    and the search runs again until every edge of its path has been driven. Returns (path, cost) or None. Reweights
    ``graph`` in place."""
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
            graph.reweight(a, b, max(graph.weight(a, b), driven_length(a, b)))


def cells_near(steps: np.ndarray, spacing: float) -> int:
    """How many moves of a chain (``steps``: each move's length, cells) it takes to go ``spacing`` cells."""
    return int(np.searchsorted(np.cumsum(steps), spacing)) + 1


def goal_route_wins(steps: np.ndarray, values: np.ndarray, budget: float, settled_route: bool, rise: float,
                    settled_cells: float) -> bool:
    """Whether the goal layer's route from R (a chain of successors that reaches G; ``steps`` its moves' costs in
    the goal layer's units) beats a backup whose estimated cost from R, with the slack, is ``budget`` - the
    evidence test of ``switch_back="evidence"``.

    ``values`` is the goal layer along the chain's first :func:`cells_near` moves, R first. The route must be no
    longer than ``budget`` and settled near the robot: each value equal to its successor's plus the move within
    ``settled_cells``, i.e. no change still arriving where the robot is about to drive. With ``settled_route``
    (leaving a backup the robot already follows) it must also be settled as a whole: its length at most ``rise``
    (U) above the value at R. A larger gap is a rise still on its way to R or detours round boxes that moved far
    ahead; the two cannot be told apart, so the test holds only once the robot has turned to a detour, where leaving
    on a rise in transit costs most."""
    length = float(np.sum(steps))
    if length > budget or (settled_route and length - values[0] > rise):
        return False
    near = len(values) - 1
    return bool((values[1:] + steps[:near] - values[:-1] <= settled_cells).all())
