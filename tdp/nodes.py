"""Accelerating-node placement (paper 3.3, ARCHITECTURE §5.1) and the node graph (eq. 14)."""
from __future__ import annotations

import math
from typing import NamedTuple

import numpy as np

from . import checks


class Lattice(NamedTuple):
    """Placed nodes: ``cells`` (n, 2) int (row, col), the lattice ``spacing`` in cells."""

    cells: np.ndarray
    spacing: float


def spacing_for(shape: tuple[int, int], count: int) -> float:
    """The spacing s (cells) of a uniform lattice of about ``count`` nodes on a map of ``shape``."""
    if isinstance(count, bool) or not isinstance(count, int) or count < 1:
        raise ValueError(f"nodes must be a positive integer, got {count!r}")
    if count > shape[0] * shape[1]:
        raise ValueError(f"nodes={count} is more than the {shape[0]} x {shape[1]} map's cells: a lattice spacing needs "
                         f"at least one cell (at most {shape[0] * shape[1]} nodes)")
    return math.sqrt(shape[0] * shape[1] / count)


#: Placement rules: "free" (the free cell nearest each lattice cell's centre, inside that cell), "drop" (the paper:
#: a centre on an obstacle loses its node) and "nudge" (a centre on an obstacle moves to a free cell within s/4).
PLACEMENTS = ("free", "drop", "nudge")


def place_nodes(occupied: np.ndarray, *, count: int | None = None, spacing: float | None = None,
                rule: str = "free") -> Lattice:
    """Nodes of a uniform lattice of spacing s: one per s x s lattice cell, centred at ((k + 1/2) s) in rows and
    columns (ARCHITECTURE §5.1).

    Give ``count`` (s follows from the map's area) or ``spacing`` s in cells. ``rule`` says what happens where the
    centre is on an obstacle: "free" takes the free cell of the lattice cell nearest its centre (so a corridor or a
    side route through a lattice cell gets a node; a lattice cell with no free cell gets none), "drop" leaves the
    node out (the paper), "nudge" takes the nearest free cell within s/4 (dropped if there is none). At most one
    node per lattice cell in every rule, so the windows' total area stays bounded.
    """
    if (count is None) == (spacing is None):
        raise ValueError("give exactly one of nodes (a count) or spacing")
    if rule not in PLACEMENTS:
        raise ValueError(f"placement must be one of {PLACEMENTS}, got {rule!r}")
    if spacing is None:
        spacing = spacing_for(occupied.shape, count)
    spacing = checks.number(spacing, "spacing (cells)", 1.0)
    rows = range(int(occupied.shape[0] / spacing + 0.5))
    cols = range(int(occupied.shape[1] / spacing + 0.5))
    cells = []
    for a in rows:
        for b in cols:
            centre = (int((a + 0.5) * spacing), int((b + 0.5) * spacing))
            if centre[0] >= occupied.shape[0] or centre[1] >= occupied.shape[1]:
                continue
            if not occupied[centre]:
                cell = centre
            elif rule == "free":
                lattice_cell = (int(a * spacing), int(b * spacing), int((a + 1) * spacing), int((b + 1) * spacing))
                cell = _nearest_free(occupied, centre, math.inf, lattice_cell)
            elif rule == "nudge":
                cell = _nearest_free(occupied, centre, spacing / 4)
            else:
                cell = None
            if cell is not None:
                cells.append(cell)
    return Lattice(np.array(cells, np.int32).reshape(-1, 2), float(spacing))


def _nearest_free(occupied: np.ndarray, cell: tuple[int, int], radius: float,
                  within: tuple[int, int, int, int] | None = None) -> tuple[int, int] | None:
    """The free cell nearest to ``cell`` within Euclidean ``radius`` and inside the rows r0..r1-1 and columns
    c0..c1-1 of ``within`` = (r0, c0, r1, c1) if given (ties: row-major first), or None."""
    reach = min(int(radius), max(occupied.shape)) if math.isfinite(radius) else max(occupied.shape)
    r0, c0, r1, c1 = within or (cell[0] - reach, cell[1] - reach, cell[0] + reach + 1, cell[1] + reach + 1)
    r0, c0 = max(r0, 0, cell[0] - reach), max(c0, 0, cell[1] - reach)
    r1, c1 = min(r1, occupied.shape[0], cell[0] + reach + 1), min(c1, occupied.shape[1], cell[1] + reach + 1)
    rows, cols = np.mgrid[r0:r1, c0:c1]
    distance = np.hypot(rows - cell[0], cols - cell[1])
    distance[occupied[r0:r1, c0:c1] | (distance > radius)] = np.inf
    if not np.isfinite(distance).any():
        return None
    k = int(np.argmin(distance))
    return int(rows.flat[k]), int(cols.flat[k])


def pair_distances(samples: np.ndarray, active: np.ndarray) -> np.ndarray:
    """The pair weights D(Qa, Qb) = max(layer_b[Qa], layer_a[Qb]) of eq. 14 (cells), inf where either node is
    inactive, from ``samples`` (rows: the nodes' cells first; columns: the goal layer, then each node's, 1 + n) and
    ``active`` (n,) bool; or from k iterations' at once, (k, rows, 1 + n) and (k, n), into (k, n, n)."""
    n = samples.shape[-1] - 1
    rows = samples[..., :n, 1:].astype(np.float64)
    pairs = np.maximum(rows, np.swapaxes(rows, -1, -2))
    inactive = ~np.asarray(active, bool)
    pairs[inactive[..., :, None] | inactive[..., None, :]] = np.inf
    return pairs


class NodeGraph:
    """The graph of eq. 14 over the nodes Q plus the robot R and the goal G, from the layers' values.

    ``samples`` is the engine's :meth:`~tdp.engine.Engine.sample` at the node cells then R then G: row k, column 0
    the goal layer at cell k, column 1 + j node j's layer at cell k. Vertex ids: nodes 0..n-1, R = n, G = n + 1.
    Pair weight D(Qa, Qb) = max(layer_b[Qa], layer_a[Qb]) (conservative while news travels); robot and goal edges
    are layer_j[R] and layer_j[G]; R-G is direct when layer_0[R] < DmaxQ and ``direct_goal`` (the caller vouches
    that the goal layer's value at R is a real route, not stale). An edge exists where its reading < DmaxQ (the
    vision; node layers measure cells even on a map with traversal costs, the goal layer the costs), and keeps the
    weight :meth:`reweight` gives it (the cost a layer really drives, which costs may raise past DmaxQ).
    Inactive nodes (covered by an obstacle) have no edges; ``blocked`` pairs (the monitor's verdict: their distance
    is still rising after a cut, so their weight is stale) have none either, and neither has the edge from R (or G)
    to a node j blocked from a node i that R (or G) reaches first: R's reading of j then most likely went through
    the cut, and the news has not reached R yet.
    """

    def __init__(self, samples: np.ndarray, dmax_q: float, active: np.ndarray, blocked: np.ndarray | None = None,
                 direct_goal: bool = True):
        n = samples.shape[0] - 2
        self.n = n
        self.dmax_q = float(dmax_q)
        self.active = np.asarray(active, bool)
        self.pairs = pair_distances(samples, self.active)
        self.robot_readings = samples[n, 1:].astype(np.float64)  # layer_j[R] before any edge is dropped
        self.robot = self.robot_readings.copy()
        self.goal = samples[n + 1, 1:].astype(np.float64)
        self.robot_goal = float(samples[n, 0]) if direct_goal else np.inf
        if blocked is not None:
            self.pairs[blocked] = np.inf
            self.robot[self._cut_off(self.robot, blocked)] = np.inf
            self.goal[self._cut_off(self.goal, blocked)] = np.inf
        inactive = ~self.active
        self.robot[inactive] = np.inf
        self.goal[inactive] = np.inf
        for weights in (self.pairs, self.robot, self.goal):  # eq. 14: an edge only within vision
            weights[weights >= self.dmax_q] = np.inf
        if self.robot_goal >= self.dmax_q:
            self.robot_goal = np.inf

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

    def _weights(self, vertex: int) -> np.ndarray:
        """Weights from ``vertex`` to every vertex (nodes, then R, then G); inf where there is no edge."""
        if vertex == self.robot_id:
            return np.append(self.robot, [np.inf, self.robot_goal])
        if vertex == self.goal_id:
            return np.append(self.goal, [self.robot_goal, np.inf])
        weights = np.append(self.pairs[vertex], [self.robot[vertex], self.goal[vertex]])
        weights[vertex] = np.inf
        return weights

    def neighbours(self, vertex: int):
        """(neighbour, weight) pairs of ``vertex`` over its edges."""
        weights = self._weights(vertex)
        for other in np.flatnonzero(np.isfinite(weights)):
            yield int(other), float(weights[other])

    def at_robot(self, vertex: int) -> float:
        """The value at R of the layer of ``vertex`` (a node, or G for the goal layer), before any edge is dropped."""
        return self.robot_goal if vertex == self.goal_id else float(self.robot_readings[vertex])

    def weight(self, a: int, b: int) -> float:
        """The weight of edge a-b (vertex ids), inf if there is none."""
        return float(self._weights(a)[b])

    def reweight(self, a: int, b: int, weight: float) -> None:
        """Set the weight of edge a-b (vertex ids, either order; the goal layer's units, which may exceed DmaxQ on
        a map with traversal costs); inf drops the edge."""
        r, g = self.robot_id, self.goal_id
        if {a, b} == {r, g}:
            self.robot_goal = weight
        elif r in (a, b):
            self.robot[a + b - r] = weight
        elif g in (a, b):
            self.goal[a + b - g] = weight
        else:
            self.pairs[a, b] = self.pairs[b, a] = weight

    def edges(self) -> list[tuple[int, int, float]]:
        """Every node-node edge (a < b, weight) of the current graph."""
        a, b = np.nonzero(np.triu(np.isfinite(self.pairs), k=1))
        return [(int(i), int(j), float(self.pairs[i, j])) for i, j in zip(a, b)]


class Vertices:
    """The node graph's id space and its conversions, in one place: vertex j < n is node j, whose layer is engine
    layer 1 + j (column 1 + j of :meth:`~tdp.engine.Engine.sample`); R is vertex n; G is vertex n + 1, whose layer
    is the goal layer (layer 0). ``nodes`` (n, 2) are the nodes' cells."""

    def __init__(self, nodes: np.ndarray):
        self.nodes = nodes
        self.robot = len(nodes)
        self.goal = len(nodes) + 1

    def layer(self, vertex: int) -> int:
        """The engine layer of ``vertex``: 1 + j for node j, 0 (the goal layer) for G."""
        return 1 + vertex if vertex < self.robot else 0

    def cell(self, vertex: int, robot: tuple[int, int], goal: tuple[int, int]) -> tuple[int, int]:
        """The cell of ``vertex`` while the robot is at ``robot`` and the goal at ``goal``."""
        if vertex < self.robot:
            return tuple(int(v) for v in self.nodes[vertex])
        return robot if vertex == self.robot else goal

    def cells(self, robot: tuple[int, int], goal: tuple[int, int]) -> np.ndarray:
        """Every vertex's cell in id order (the nodes, R, G): where :class:`NodeGraph` reads the layers."""
        return np.vstack([self.nodes, [robot], [goal]])


def choose_subgoal(path: list[int], graph: NodeGraph) -> int:
    """The vertex a backup heads for on ``path`` = <R, Q1, Q2, ..., G> (paper 4.2, ARCHITECTURE §5.5): Q2, or Q1
    when R is outside Q2's vision (its layer at R >= DmaxQ), or the last point when the path is shorter. Q2 may be G
    itself (path <R, Q1, G>): then "outside its vision" means layer_0[R] >= DmaxQ, and the robot heads for Q1 rather
    than follow a goal layer that may still be stale. A node the robot already stands on is skipped."""
    if len(path) > 2 and graph.at_robot(path[1]) == 0:
        path = path[:1] + path[2:]
    index = min(2, len(path) - 1)
    if index == 2 and graph.at_robot(path[2]) >= graph.dmax_q:
        index = 1
    return path[index]
