"""Neighbourhoods of the DP (paper eq. 4): moves, their lengths and the cells a move sweeps over.

A move is ``(dr, dc)`` from a cell V to its neighbour Z = V + (dr, dc), in cells. Its cost is its Euclidean
length (1, sqrt 2 or sqrt 5). ``crossed`` lists the offsets, relative to V, of the cells the move's segment passes
through besides V and Z; with the default rule (no corner cutting) they must be free for the move to be allowed
(ARCHITECTURE §4). The order of :func:`moves` is the fixed tie order of successors: straight, diagonal, knight.
"""
from __future__ import annotations

import math
import numbers
from typing import Callable, NamedTuple

import numpy as np
from scipy.sparse import csr_matrix
from scipy.sparse.csgraph import dijkstra

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
    if isinstance(neighbourhood, bool) or not isinstance(neighbourhood, numbers.Integral) or (
            neighbourhood not in NEIGHBOURHOODS):
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
    window = _Window.around(occupied, walls, cell, math.ceil(max_length))
    legs = _Legs.of(window, allowed)
    start = window.flat(cell)
    walked, before = dijkstra(_walks(window, legs, start), indices=start, return_predecessors=True)
    exits = np.flatnonzero(~window.covered & (walked <= max_length))
    exits = exits[exits != start]
    if not len(exits):
        return None
    totals = walked[exits] + np.asarray(distances_at(window.cells(exits)), np.float64)
    best = int(np.argmin(totals))
    if not math.isfinite(totals[best]):
        return None
    step = exits[best]
    while before[step] != start:
        step = before[step]
    return window.cells(np.array([step]))[0]


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


class _Window(NamedTuple):
    """The cells within a radius of a cell (rows and columns) and REACH cells round them, flattened row by row:
    ``walled`` and ``covered`` (True off the map) from the walls and occupied maps, ``inner`` the cells within the
    radius; the flat index of map cell (r, c) is (r - top) x width + (c - left)."""

    walled: np.ndarray
    covered: np.ndarray
    inner: np.ndarray
    top: int
    left: int
    width: int

    @classmethod
    def around(cls, occupied: np.ndarray, walls: np.ndarray, cell: tuple[int, int], radius: int) -> "_Window":
        rows, cols = occupied.shape
        r0, c0 = max(0, cell[0] - radius), max(0, cell[1] - radius)
        r1, c1 = min(rows, cell[0] + radius + 1), min(cols, cell[1] + radius + 1)
        inner = np.zeros((r1 - r0 + 2 * REACH, c1 - c0 + 2 * REACH), bool)
        inner[REACH:-REACH, REACH:-REACH] = True
        return cls(_around(walls, r0, r1, c0, c1).ravel(), _around(occupied, r0, r1, c0, c1).ravel(), inner.ravel(),
                   r0 - REACH, c0 - REACH, inner.shape[1])

    def flat(self, cell: tuple[int, int]) -> int:
        """The flat index of map cell ``cell``."""
        return (cell[0] - self.top) * self.width + cell[1] - self.left

    def walked_through(self) -> np.ndarray:
        """The flat indices of the inner cells an escape's walk may go through: occupied, not walls."""
        return np.flatnonzero(self.inner & self.covered & ~self.walled)

    def cells(self, flat: np.ndarray) -> list[tuple[int, int]]:
        """The map cells at the flat indices ``flat``."""
        rows, cols = np.divmod(flat, self.width)
        return list(zip((rows + self.top).tolist(), (cols + self.left).tolist()))


class _Legs(NamedTuple):
    """The ``allowed`` moves as flat offsets in a :class:`_Window`: where each ends (``ahead``), the cells it
    crosses (``crossed``, two a move, padded with its end) and its length (``costs``, a column)."""

    ahead: np.ndarray
    crossed: np.ndarray
    costs: np.ndarray

    @classmethod
    def of(cls, window: _Window, allowed: tuple[Move, ...]) -> "_Legs":
        ahead = np.array([m.dr * window.width + m.dc for m in allowed])
        crossed = [[dr * window.width + dc for dr, dc in m.crossed] for m in allowed]
        crossed = np.array([c + [a] * (2 - len(c)) for c, a in zip(crossed, ahead)])
        return cls(ahead[:, None], crossed, np.array([m.cost for m in allowed])[:, None])

    def clear(self, window: _Window, cells: np.ndarray) -> np.ndarray:
        """(moves, cells): whether each move from each of the flat ``cells`` enters and crosses no wall."""
        crossed = self.crossed[:, :, None] + cells
        return ~(window.walled[self.ahead + cells] | window.walled[crossed[:, 0]] | window.walled[crossed[:, 1]])


def _depths(window: _Window, legs: _Legs) -> np.ndarray:
    """For each occupied cell of the ``window``'s inner cells that is not a wall, the length of the shortest walk of
    the ``legs``' moves through such cells to a free cell (inf elsewhere, flat): scipy's Dijkstra on their graph,
    from a source one move from each cell with a move out (moves are symmetric: a search from all the free cells at
    once), its edges gathered for all the cells at once."""
    at = window.walked_through()
    index = np.full(len(window.covered), -1)
    index[at] = np.arange(len(at))
    ahead, clear = legs.ahead + at, legs.clear(window, at)
    out = np.where(clear & ~window.covered[ahead], legs.costs, math.inf).min(axis=0, initial=math.inf)
    walk = clear & (index[ahead] >= 0)  # edges: from the cell a move ends on to the one it leaves
    leaving, source = np.flatnonzero(np.isfinite(out)), len(at)
    tails = np.concatenate([index[ahead[walk]], np.full(len(leaving), source)])
    heads = np.concatenate([np.nonzero(walk)[1], leaving])
    lengths = np.concatenate([np.broadcast_to(legs.costs, walk.shape)[walk], out[leaving]])
    graph = csr_matrix((lengths, (tails, heads)), shape=(source + 1, source + 1))
    depth = np.full(len(window.covered), math.inf)
    depth[at] = dijkstra(graph, indices=source)[:source]
    return depth


def _walks(window: _Window, legs: _Legs, start: int) -> csr_matrix:
    """The graph of :func:`escape_move`'s walks in the ``window``: each move of the ``legs`` from ``start`` or from
    an occupied cell that is not a wall, clear of walls, into a free cell or into occupied cells no deeper than the
    one it leaves (:func:`_depths`)."""
    depth = _depths(window, legs)
    at = np.union1d(window.walked_through(), [start])
    ahead, crossed = legs.ahead + at, legs.crossed[:, :, None] + at
    shallow = np.ones(ahead.shape, bool)
    for passed in (ahead, crossed[:, 0], crossed[:, 1]):
        shallow &= ~window.covered[passed] | (depth[passed] <= depth[at])
    move = legs.clear(window, at) & (~window.covered[ahead] | shallow)
    lengths = np.broadcast_to(legs.costs, move.shape)[move]
    size = len(window.covered)
    return csr_matrix((lengths, (np.broadcast_to(at, move.shape)[move], ahead[move])), shape=(size, size))


def _around(grid: np.ndarray, r0: int, r1: int, c0: int, c1: int) -> np.ndarray:
    """Rows r0:r1 and columns c0:c1 of the bool map ``grid`` and REACH cells round them, True off the map."""
    rows, cols = grid.shape
    out = np.ones((r1 - r0 + 2 * REACH, c1 - c0 + 2 * REACH), bool)
    e0, e1, f0, f1 = max(0, r0 - REACH), min(rows, r1 + REACH), max(0, c0 - REACH), min(cols, c1 + REACH)
    out[e0 - r0 + REACH:e1 - r0 + REACH, f0 - c0 + REACH:f1 - c0 + REACH] = grid[e0:e1, f0:f1]
    return out
