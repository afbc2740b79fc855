"""The planner contract: what every planner (the navigator, the oracle, D* Lite) offers a runner (the grid runner,
PyBullet), what one tick returns, and how its timings are summarised.

A runner, each tick: hands the planner the cells whose occupancy changed (:meth:`Planner.update_map`) and the
target's new cell if it moved (:meth:`Planner.set_goal`), tells it where the robot is (:meth:`Planner.move_robot`),
then asks :meth:`Planner.tick` where to go. :class:`WorldFeed` does the first two for any source of occupancy.
"""
from __future__ import annotations

import time
from contextlib import contextmanager
from dataclasses import dataclass, field
from enum import Enum
from typing import Iterator, Protocol, Sequence

import numpy as np

from .field import cells_from


class Mode(str, Enum):
    """What the robot did on a tick: followed the goal layer (``DP``), a backup subgoal's layer (``BACKUP``), the goal
    layer repaired exactly for its route (``EXACT``) or, with a budget that ran out first, as far as the repair got or
    towards where a moving target was (``BEHIND``), D* Lite's search (``DSTAR``), stayed where it was (``WAIT``), or
    gave way to a box (``YIELD``, with ``avoid_boxes``): stayed because a box is predicted to enter the cell it would
    have moved to, or, on a tick that gave no move, stepped aside from a box about to drive onto it.
    A mode is written (``str``, JSON) as its value: "dp", "backup", ...; code compares modes with the members, never
    with strings."""

    DP = "dp"
    BACKUP = "backup"
    WAIT = "wait"
    YIELD = "yield"
    EXACT = "exact"
    BEHIND = "behind"
    DSTAR = "d*lite"

    def __str__(self) -> str:
        return self.value


@dataclass
class Detection:
    """A pair of nodes found blocked at DP iteration ``iteration``; ``relevant`` if near the robot's path."""

    iteration: int
    pair: tuple[int, int]
    relevant: bool


@dataclass
class TickResult:
    """What one tick decided: the mode, the cell to move to (None: stay), and what happened on the way. ``timings``
    maps a phase ("dp", "monitor", "search", "converge", ...) to the seconds it took."""

    mode: Mode
    next_cell: tuple[int, int] | None
    detections: list[Detection] = field(default_factory=list)
    backup_path: list[int] | None = None
    backup_cost: float | None = None
    subgoal: int | None = None
    switched_back: bool = False
    iterations: int = 0  # DP iterations the tick ran
    timings: dict = field(default_factory=dict)


class PhaseClock:
    """Seconds a tick spends in each phase: ``with clock("dp"): ...`` adds the block's wall time to
    ``clock.seconds["dp"]`` (a :attr:`TickResult.timings`)."""

    def __init__(self, *phases: str):
        self.seconds = dict.fromkeys(phases, 0.0)

    @contextmanager
    def __call__(self, phase: str) -> Iterator[None]:
        began = time.perf_counter()
        try:
            yield
        finally:
            self.seconds[phase] = self.seconds.get(phase, 0.0) + time.perf_counter() - began


class Planner(Protocol):
    """A planner a runner can drive (:func:`tdp.simulate.run_planner`, ``sim``)."""

    def update_map(self, cells: np.ndarray, occupied: np.ndarray) -> None:
        """Cells (n, 2) whose occupancy changed, and their new state (bool per cell)."""

    def update_costs(self, cells: np.ndarray, costs: np.ndarray) -> None:
        """Cells (n, 2) whose traversal cost changed, and their new costs (a map with costs only)."""

    def set_goal(self, cell: tuple[int, int]) -> None:
        """The target moved to ``cell``."""

    def move_robot(self, cell: tuple[int, int]) -> None:
        """The robot is now at ``cell``."""

    def tick(self) -> TickResult:
        """Plan; say where to go."""


def timing_summary(seconds: Sequence[float]) -> dict:
    """Median, mean, 95th percentile and maximum of ``seconds``, in milliseconds (zeros for no sample)."""
    values = np.asarray(seconds, np.float64) * 1e3 if len(seconds) else np.zeros(1)
    return {"median": float(np.median(values)), "mean": float(values.mean()),
            "p95": float(np.percentile(values, 95)), "max": float(values.max())}


def detection_records(results: Sequence[TickResult]) -> list[dict]:
    """Every detection of a run as a record: its tick (1-based), DP iteration, node pair and relevance."""
    return [{"tick": tick, "iteration": d.iteration, "pair": list(d.pair), "relevant": d.relevant}
            for tick, result in enumerate(results, start=1) for d in result.detections]


def landmarks(results: Sequence[TickResult]) -> tuple[int | None, int | None]:
    """The ticks (1-based) of the first relevant blockage detection (the turn point A of the paper's figures) and
    of the first switch back to the DP (B); None where there is none."""
    turn = next((t for t, r in enumerate(results, start=1) if any(d.relevant for d in r.detections)), None)
    back = next((t for t, r in enumerate(results, start=1) if r.switched_back), None)
    return turn, back


class WorldFeed:
    """Hands a planner what changed in its world since the last tick: the cells whose occupancy flipped (only
    those), on a map with changing traversal costs the cells whose cost changed, and the target's moves."""

    def __init__(self, occupied: np.ndarray, target: tuple[int, int], cost: np.ndarray | None = None):
        self.occupied = np.array(occupied, bool)
        self.target = tuple(target)
        self.cost = None if cost is None else np.array(cost, np.float32)
        self.planner_s = 0.0  # seconds the last update spent in the planner's update_costs, update_map and set_goal

    def update(self, planner: Planner, occupied: np.ndarray, target: tuple[int, int],
               cost: np.ndarray | None = None) -> bool:
        """Send ``planner`` the changes from the last state to ``occupied``, ``cost`` (None: the costs stay) and
        ``target``; return whether the target moved. Costs go first, so that a cell freed now takes its new cost."""
        occupied = np.asarray(occupied, bool)  # kept as it is, not copied: a runner hands a fresh map every tick
        changed = cells_from(occupied.shape, occupied != self.occupied, "occupied")  # argwhere's, 10x faster
        began = time.perf_counter()
        if cost is not None:
            cost = np.asarray(cost, np.float32)
            repriced = cells_from(cost.shape, cost != self.cost, "cost")
            if len(repriced):
                planner.update_costs(repriced, cost[repriced[:, 0], repriced[:, 1]])
            self.cost = cost
        if len(changed):
            planner.update_map(changed, occupied[changed[:, 0], changed[:, 1]])
        self.occupied = occupied
        moved = tuple(target) != self.target
        if moved:
            self.target = tuple(target)
            planner.set_goal(self.target)
        self.planner_s = time.perf_counter() - began
        return moved
