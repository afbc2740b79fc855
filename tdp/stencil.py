"""Neighbourhoods of the DP (paper eq. 4): moves, their lengths and the cells a move sweeps over.

A move is ``(dr, dc)`` from a cell V to its neighbour Z = V + (dr, dc), in cells. Its cost is its Euclidean
length (1, sqrt 2 or sqrt 5). ``crossed`` lists the offsets, relative to V, of the cells the move's segment passes
through besides V and Z; with the default rule (no corner cutting) they must be free for the move to be allowed
(ARCHITECTURE §4). The order of :func:`moves` is the fixed tie order of successors: straight, diagonal, knight.
"""
from __future__ import annotations

import heapq
import math
from typing import Callable, NamedTuple

import numpy as np

NEIGHBOURHOODS = (4, 8, 16)

_STRAIGHT = ((-1, 0), (0, 1), (1, 0), (0, -1))
_DIAGONAL = ((-1, 1), (1, 1), (1, -1), (-1, -1))
_KNIGHT = ((-1, 2), (1, 2), (2, 1), (2, -1), (1, -2), (-1, -2), (-2, -1), (-2, 1))

#: Largest |dr| or |dc| of any move: the padding, in cells, that the engine keeps around each array.
REACH = 2

#: Longest way out (cells) :func:`escape_move` looks for when an obstacle covers the robot.
ESCAPE_CELLS = 16.0


class Move(NamedTuple):
    """One move of the stencil: offset (dr, dc) in cells, its length, and the cells it crosses."""

    dr: int
    dc: int
    cost: float
    crossed: tuple[tuple[int, int], ...]


def chain_moves(chain, cost: np.ndarray | None = None) -> tuple[np.ndarray, np.ndarray]:
    """Each move of ``chain`` (cells, each one move from the last): its length L (cells) and its cost in the goal
    layer's units - L itself, or on a map with traversal costs ``cost`` (H, W) L x (cost[u] + cost[v]) / 2."""
    cells = np.asarray(chain)
    lengths = np.hypot(*np.diff(cells, axis=0).T)
    if cost is None:
        return lengths, lengths
    at = cost[tuple(cells.T)].astype(np.float64)
    return lengths, lengths * (at[:-1] + at[1:]) / 2


def _sign(x: int) -> int:
    return (x > 0) - (x < 0)


def _crossed_cells(dr: int, dc: int) -> tuple[tuple[int, int], ...]:
    """Cells (offsets from V) that the segment from V to V + (dr, dc) passes through (ARCHITECTURE §4)."""
    sr, sc = _sign(dr), _sign(dc)
    if abs(dr) + abs(dc) == 1:
        return ()
    if abs(dr) == 1 and abs(dc) == 1:
        return ((dr, 0), (0, dc))
    if abs(dc) == 2:
        return ((0, sc), (dr, sc))
    return ((sr, 0), (sr, dc))


def through_corner(move: Move) -> bool:
    """Whether ``move`` starts on, or crosses, a diagonal neighbour of the cell Z it ends on: when Z's four diagonal
    neighbours are all blocked, no such move reaches Z (a one-cell corridor's cells: the search skips them there)."""
    return _touches_corner([(-move.dr, -move.dc)] + [(r - move.dr, c - move.dc) for r, c in move.crossed])


def leaves_by_corner(move: Move) -> bool:
    """Whether ``move`` ends on, or crosses, a diagonal neighbour of the cell V it starts from: when V's four diagonal
    neighbours are all blocked, no such move leaves V (a one-cell corridor's cells: a mend's raise skips them
    there)."""
    return _touches_corner([(move.dr, move.dc), *move.crossed])


def _touches_corner(offsets: list[tuple[int, int]]) -> bool:
    """Whether any of ``offsets`` (from a cell) is one of its four diagonal neighbours."""
    return any(abs(r) == 1 and abs(c) == 1 for r, c in offsets)


def check_neighbourhood(neighbourhood: int) -> int:
    """Return ``neighbourhood`` if it is 4, 8 or 16, else raise ValueError naming it."""
    if isinstance(neighbourhood, bool) or neighbourhood not in NEIGHBOURHOODS:
        raise ValueError(f"neighbourhood must be one of {NEIGHBOURHOODS}, got {neighbourhood!r}")
    return int(neighbourhood)


def moves(neighbourhood: int = 16, corner_cutting: bool = False) -> tuple[Move, ...]:
    """The moves of a 4-, 8- or 16-neighbourhood in tie order (straight, diagonal, knight).

    With ``corner_cutting=True`` no move needs its crossed cells free (the paper's literal eq. 4).
    """
    offsets = {4: _STRAIGHT, 8: _STRAIGHT + _DIAGONAL, 16: _STRAIGHT + _DIAGONAL + _KNIGHT}
    return tuple(
        Move(dr, dc, math.hypot(dr, dc), () if corner_cutting else _crossed_cells(dr, dc))
        for dr, dc in offsets[check_neighbourhood(neighbourhood)]
    )


def legal_moves(occupied: np.ndarray, cell: tuple[int, int], allowed: tuple[Move, ...]):
    """(neighbour, length) of each of the ``allowed`` moves from ``cell`` into a free cell of the bool map
    ``occupied`` (True = obstacle), crossing only free cells; cells outside the map count as occupied."""
    for there, m in _moves_clear_of(occupied, cell, allowed):
        yield there, m.cost


def escape_move(occupied: np.ndarray, cell: tuple[int, int], allowed: tuple[Move, ...],
                distances_at: Callable[[list], np.ndarray], walls: np.ndarray | None = None,
                max_length: float = ESCAPE_CELLS) -> tuple[int, int] | None:
    """The first move out of an obstacle that covers ``cell`` (a door closed on the robot, a box parked over it):
    the shortest walk of ``allowed`` moves through occupied cells, at most ``max_length`` cells long and never
    deeper into the obstacle (each cell walked through is no further from a free cell than the one before), to the
    free cell that minimises walk length + its distance to the goal (``distances_at(cells)``, inf where the goal
    cannot be reached). So a robot in a doorway when its door closes leaves by the side towards the goal, and one
    under a box that parked backs out by the nearest side, not through the box. ``walls`` (a mask like
    ``occupied``; None: none) are the map's own obstacles: the walk never enters or crosses them, while the
    occupied cells it walks through may be crossed (the robot is inside them already); a robot on a wall, or under
    an obstacle with no way out within reach, may walk through any occupied cell that is not a wall. None when no
    such free cell has a finite distance."""
    walls = np.zeros_like(occupied) if walls is None else walls
    depth = _depths(occupied, walls, cell, allowed, math.ceil(max_length))
    reached = {cell: 0.0}
    heap = [(0.0, cell, cell)]
    exits: dict[tuple[int, int], tuple[float, tuple[int, int]]] = {}
    while heap:
        length, here, first = heapq.heappop(heap)
        if length > reached[here]:
            continue
        for there, m in _moves_clear_of(walls, here, allowed):
            walked, step = length + m.cost, there if here == cell else first
            if walked > max_length:
                continue
            if not occupied[there]:
                if walked < exits.get(there, (math.inf,))[0]:
                    exits[there] = (walked, step)
            elif walked < reached.get(there, math.inf) and all(
                    depth.get(c, math.inf) <= depth.get(here, math.inf) for c in _passed(here, m) if occupied[c]):
                reached[there] = walked
                heapq.heappush(heap, (walked, there, step))
    if not exits:
        return None
    cells = list(exits)
    totals = [exits[c][0] + float(d) for c, d in zip(cells, distances_at(cells))]
    best = int(np.argmin(totals))
    return exits[cells[best]][1] if math.isfinite(totals[best]) else None


class RobotMoves:
    """The moves a planner may offer the robot on a changing map: the stencil's legal moves from its cell, and the
    way out when an obstacle covers it (:func:`escape_move`), never through the map's own walls - the cells occupied
    in the map the planner was given and never freed since (a box that stood somewhere at the start and drove off
    is no wall). Values at or above ``d_max`` (a layer's cap, cells) count as unreachable."""

    def __init__(self, occupied: np.ndarray, neighbourhood: int, corner_cutting: bool, d_max: float):
        self.walls = np.array(occupied, bool)
        self.allowed = moves(neighbourhood, corner_cutting)
        self.d_max = d_max

    def freed(self, cells: np.ndarray, occupied: np.ndarray) -> None:
        """A map update: ``cells`` (n, 2) whose new state is ``occupied`` (bool per cell); freed cells are no walls."""
        freed = cells[~occupied]
        self.walls[freed[:, 0], freed[:, 1]] = False

    def legal(self, occupied: np.ndarray, cell: tuple[int, int]) -> list[tuple[tuple[int, int], float]]:
        """(neighbour, length) of every stencil move from ``cell`` into a free cell, crossing only free cells."""
        return list(legal_moves(occupied, cell, self.allowed))

    def escape(self, occupied: np.ndarray, cell: tuple[int, int],
               values_at: Callable[[list], np.ndarray]) -> tuple[int, int] | None:
        """The first move out of the obstacle that covers ``cell`` towards the target of the layer whose values
        at given cells ``values_at`` reads (:func:`escape_move`); None when no way out reaches a finite value."""
        def distances(cells: list) -> np.ndarray:
            values = np.asarray(values_at(cells), np.float64)
            return np.where(values >= self.d_max, np.inf, values)

        return escape_move(occupied, cell, self.allowed, distances, walls=self.walls)


def _moves_clear_of(blocked: np.ndarray, here: tuple[int, int], allowed: tuple[Move, ...]):
    """(cell, move) of each of ``allowed`` moves from ``here`` that stays on the map and enters or crosses no cell
    of the bool map ``blocked`` (the cells a move crosses lie between its ends, so on the map too)."""
    rows, cols = blocked.shape
    for m in allowed:
        there = (here[0] + m.dr, here[1] + m.dc)
        if 0 <= there[0] < rows and 0 <= there[1] < cols and not any(blocked[c] for c in _passed(here, m)):
            yield there, m


def _passed(here: tuple[int, int], m: Move) -> list[tuple[int, int]]:
    """The cells move ``m`` from ``here`` enters or crosses."""
    return [(here[0] + dr, here[1] + dc) for dr, dc in ((m.dr, m.dc),) + m.crossed]


def _depths(occupied: np.ndarray, walls: np.ndarray, cell: tuple[int, int], allowed: tuple[Move, ...],
            radius: int) -> dict[tuple[int, int], float]:
    """For each occupied cell that is not a wall within ``radius`` cells of ``cell`` (rows and columns), the length
    of the shortest walk of ``allowed`` moves through such cells to a free cell (moves are symmetric: a search
    from all the free cells at once), on the window's arrays: the moves clear of walls from every cell at once, then
    relaxed until nothing falls (a Python Dijkstra over the cells took up to 34 ms a tick under a box in a corridor
    world)."""
    rows, cols = occupied.shape
    r0, c0 = max(0, cell[0] - radius), max(0, cell[1] - radius)
    r1, c1 = min(rows, cell[0] + radius + 1), min(cols, cell[1] + radius + 1)
    walled, covered = _around(walls, r0, r1, c0, c1), _around(occupied, r0, r1, c0, c1)
    shape = (r1 - r0, c1 - c0)

    def shifted(grid: np.ndarray, dr: int, dc: int) -> np.ndarray:
        return grid[REACH + dr:REACH + dr + shape[0], REACH + dc:REACH + dc + shape[1]]

    inside = shifted(covered, 0, 0) & ~shifted(walled, 0, 0)
    depth = np.full(shape, math.inf)
    steps = []  # (move, where it is clear of walls from)
    for m in allowed:
        clear = ~shifted(walled, m.dr, m.dc)
        for dr, dc in m.crossed:
            clear &= ~shifted(walled, dr, dc)
        out = inside & clear & ~shifted(covered, m.dr, m.dc)
        depth[out] = np.minimum(depth[out], m.cost)
        steps.append((m, inside & clear))
    offered = np.full((shape[0] + 2 * REACH, shape[1] + 2 * REACH), math.inf)
    while True:
        before = depth.copy()
        for m, clear in steps:  # a cell inside takes what the cell a move behind it offers
            offered[REACH:-REACH, REACH:-REACH] = np.where(clear, depth + m.cost, math.inf)
            np.minimum(depth, np.where(inside, shifted(offered, -m.dr, -m.dc), math.inf), out=depth)
        if np.array_equal(before, depth):
            return {(int(r) + r0, int(c) + c0): float(depth[r, c]) for r, c in np.argwhere(np.isfinite(depth))}


def _around(grid: np.ndarray, r0: int, r1: int, c0: int, c1: int) -> np.ndarray:
    """Rows r0:r1 and columns c0:c1 of the bool map ``grid`` and REACH cells round them, True off the map."""
    rows, cols = grid.shape
    out = np.ones((r1 - r0 + 2 * REACH, c1 - c0 + 2 * REACH), bool)
    e0, e1, f0, f1 = max(0, r0 - REACH), min(rows, r1 + REACH), max(0, c0 - REACH), min(cols, c1 + REACH)
    out[e0 - r0 + REACH:e1 - r0 + REACH, f0 - c0 + REACH:f1 - c0 + REACH] = grid[e0:e1, f0:f1]
    return out
