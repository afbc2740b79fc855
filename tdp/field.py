"""DistanceField: the distance-to-goal of every cell, kept by the DP of eqs. 4-7 (a thin face over the engine)."""
from __future__ import annotations

import math

import numpy as np

from . import checks
from .engine import Engine
from .grid import GridMap


def check_cap(value: float, name: str) -> float:
    """Return ``value`` as a float if it is a positive number (inf allowed), else raise ValueError naming it."""
    return checks.number(value, name, 0.0, inclusive=False, finite=False)


def _read_cells(cells) -> np.ndarray:
    """``cells`` as numpy reads it; a list or tuple of integer pairs read column by column - each pair once, where
    numpy's reading of nested sequences walks them twice: 418 cells 56 against 155 µs warm, 1,700 cells 0.8 against
    1.2 ms right after a converge (RESULTS §2, the thirtieth session). Anything else, faults included, is read by
    numpy, whose reading the caller's messages describe."""
    if isinstance(cells, (list, tuple)) and cells:
        try:
            columns = np.array(tuple(zip(*cells, strict=True)))
        except (TypeError, ValueError):  # not sequences, or of unequal lengths: numpy's reading names the fault
            columns = None
        if columns is not None and columns.ndim == 2 and columns.shape[0] == 2 and columns.dtype.kind in "iu":
            return columns.T
    return np.asarray(cells)


def _mask_cells(mask: np.ndarray) -> np.ndarray:
    """The (row, col) cells of a 2-D bool mask, row by row, as an (n, 2) int32 array: ``np.argwhere``'s, found as
    flat indices (numpy's 2-D nonzero took 0.2 ms for a 300 x 300 mask where the flat one takes 0.02)."""
    flat = np.flatnonzero(mask)
    cells = np.empty((len(flat), 2), np.int32)
    cells[:, 0], cells[:, 1] = np.divmod(flat, mask.shape[1])
    return cells


def cells_from(grid_shape: tuple[int, int], cells_or_mask, name: str) -> np.ndarray:
    """An (n, 2) int32 array of (row, col) cells, contiguous (as the engine's kernels take them), from a bool mask of
    the map's shape or a sequence of cells.

    Raises:
        ValueError: a mask of another shape, anything but (row, col) integer pairs, or a cell outside the map.
    """
    try:
        array = _read_cells(cells_or_mask)
    except ValueError:  # a ragged sequence
        raise ValueError(f"{name}: expected a bool mask or (row, col) integer cells, got a ragged sequence") from None
    if array.dtype == bool:
        if array.shape != grid_shape:
            raise ValueError(f"{name}: a mask must have the map's shape {grid_shape}, got {array.shape}")
        return _mask_cells(array)
    if array.size == 0:
        return np.zeros((0, 2), np.int32)
    if array.dtype.kind not in "iu" or array.ndim == 0 or array.shape[-1] != 2:
        raise ValueError(f"{name}: expected a bool mask or (row, col) integer cells, got an array of "
                         f"shape {array.shape} and dtype {array.dtype}")
    cells = array.reshape(-1, 2)
    try:  # the bounds in one call: an edit's numpy calls cost 2-30 µs each right after a converge (caches cold)
        np.ravel_multi_index((cells[:, 0], cells[:, 1]), grid_shape)
    except ValueError:
        outside = cells[~((cells >= 0) & (cells < grid_shape)).all(axis=1)][0]
        raise ValueError(f"{name}: cell {tuple(int(v) for v in outside)} is outside the "
                         f"{grid_shape[0]} x {grid_shape[1]} map") from None
    return np.ascontiguousarray(cells, np.int32)


class DistanceField:
    """Distance to ``goal`` (in cells; on a grid with costs, in cost x cells) of every cell of ``grid``, relaxed by
    synchronous DP iterations.

    ``neighbourhood`` is 4, 8 or 16 (moves of length 1, sqrt 2, sqrt 5); ``corner_cutting=True`` allows the paper's
    literal moves between any two free cells; ``d_max`` caps every value (eq. 5). The field starts at iteration 0
    (0 at the goal, ``d_max`` elsewhere): call :meth:`converge` for exact distances, :meth:`step` to advance.
    Map edits and goal moves take effect at the next iteration.
    """

    def __init__(self, grid: GridMap, goal: tuple[int, int], neighbourhood: int = 16, corner_cutting: bool = False,
                 d_max: float = math.inf):
        if not isinstance(grid, GridMap):
            raise ValueError(f"grid must be a tdp.GridMap, got {type(grid).__name__}")
        self._grid = grid
        goal = grid.check_free_cell(goal, "goal")
        self.d_max = check_cap(d_max, "d_max")
        self._engine = Engine(grid.occupied, goal, goal_cap=self.d_max, neighbourhood=neighbourhood,
                              corner_cutting=checks.flag(corner_cutting, "corner_cutting"), cost=grid.cost)

    @property
    def goal(self) -> tuple[int, int]:
        """The goal cell (row, col)."""
        return self._engine.goal

    @property
    def iterations(self) -> int:
        """Synchronous iterations run since the initial state or the last :meth:`converge` (which leaves 0)."""
        return self._engine.iterations

    @property
    def occupied(self) -> np.ndarray:
        """The current occupancy (bool (H, W), True = obstacle), edits included; a copy."""
        return self._engine.occupied.copy()

    def step(self, k: int = 1) -> int:
        """Run ``k`` synchronous DP iterations (eqs. 5-7); return how many cells the last one changed."""
        k = checks.integer(k, "k", 0)
        self._engine.step(k)
        return self._engine.changed() if k else 0

    def converge(self, max_rounds: int | None = None, focus: tuple[int, int] | None = None) -> int:
        """Relax to the exact fixed point: the setup phase, and the repair after edits; return the rounds it took.

        Works from the current values: after :meth:`set_occupied` it lifts to inf (or ``d_max``) the values that
        lost their route, then settles 8 x 8 tiles in place, each sweeping in cache until stable and waking the
        neighbours its border changes reach, until no tile changes (ARCHITECTURE §7), so its time grows with the
        region the edits affect; after :meth:`set_goal` it starts again from the initial state. The result equals
        a fresh field's converge() and synchronous iteration to convergence, bit for bit. ``max_rounds`` bounds the
        rounds; :attr:`iterations` is 0 after it.

        ``focus`` (a cell, the robot's) makes it a focused repair, as D* Lite's: it stops as soon as nothing still
        to do can change the distance at ``focus`` or the successors from there to the goal, which are then exactly
        those of the fixed point; the rest waits (:attr:`pending`) for a later converge.

        Raises:
            ValueError: ``max_rounds`` is not a positive integer, or ``focus`` is not a cell of the map.

        Examples:
            >>> field.set_occupied([(10, 40), (11, 40)])   # doctest: +SKIP
            >>> field.converge(focus=(30, 0))              # doctest: +SKIP
        """
        max_rounds = checks.optional_integer(max_rounds, "max_rounds", 1)
        if focus is not None:
            focus = self._check_cell(focus, "focus")
        return self._engine.converge(max_rounds, focus)

    @property
    def pending(self) -> bool:
        """Whether the last :meth:`converge` left work for later (it stopped at its focus or at ``max_rounds``); the
        next :meth:`converge` goes on with it, and :meth:`step` finishes it before iterating. :meth:`set_goal` drops
        it: the next converge starts again, and steps iterate from the values as they are."""
        return self._engine.pending()

    def reset(self) -> None:
        """Back to the initial state: 0 at the goal, ``d_max`` elsewhere, iteration 0 (map edits kept)."""
        self._engine.reset()

    def distances(self) -> np.ndarray:
        """float32 (H, W) distances in cells: inf (or ``d_max``) where the goal is not reached."""
        return self._engine.goal_distances()

    def distance(self, cell: tuple[int, int]) -> float:
        """Distance of one cell in cells (``d_max`` on an obstacle)."""
        cell = self._check_cell(cell, "cell")
        return float(self._engine.sample([cell])[0, 0])

    def successor(self, cell: tuple[int, int]) -> tuple[int, int] | None:
        """S(V) of eq. 7: the neighbour minimising D(Z) + |V - Z| over the allowed moves, ties in the order
        straight, diagonal, knight; None at the goal or where every candidate is at ``d_max``."""
        step = self._engine.trace(0, self._check_cell(cell, "cell"), 1)
        return step[0] if step else None

    def path(self, start: tuple[int, int]) -> list[tuple[int, int]]:
        """Cells from ``start`` to the goal following successors; [] if the goal is not reached from ``start``.

        On a converged field the path's length equals ``distance(start)``; on one still relaxing it follows the
        current successors and may stop short, in which case [] is returned.
        """
        start = self._check_free(start, "start")
        if start == self.goal:
            return [start]
        rows, cols = self._grid.shape
        cells = [start] + self._engine.trace(0, start, rows * cols)
        return cells if cells[-1] == self.goal else []

    def set_occupied(self, cells_or_mask, occupied: bool = True) -> None:
        """Mark cells (a bool mask of the map's shape, or (row, col) cells) as obstacles or, with
        ``occupied=False``, as free. Only cells whose state changes cost a repair."""
        cells = cells_from(self._grid.shape, cells_or_mask, "set_occupied")
        self._engine.set_cells(cells, checks.flag(occupied, "occupied"))

    def set_costs(self, cells, costs) -> None:
        """Set the traversal costs of ``cells`` ((row, col) cells, or a bool mask of the map's shape) to ``costs`` (a
        number or one per cell, 1 to ``tdp.grid.MAX_COST``) on a map with costs; distances follow at the next
        converge (or over the next iterations).

        Raises:
            ValueError: the map has no costs, a cell is outside it, or a cost is not a number from 1 to MAX_COST.
        """
        self._engine.set_costs(cells_from(self._grid.shape, cells, "set_costs"), costs)

    def set_goal(self, cell: tuple[int, int]) -> None:
        """Move the goal (a free cell); distances follow over the next iterations."""
        self._engine.set_goal(self._check_free(cell, "goal"))

    def _check_free(self, cell, name: str) -> tuple[int, int]:
        cell = self._check_cell(cell, name)
        if self._engine.occupied[cell]:
            raise ValueError(f"{name} {cell} is on an obstacle")
        return cell

    def _check_cell(self, cell, name: str) -> tuple[int, int]:
        return checks.cell(cell, self._grid.shape, name)
