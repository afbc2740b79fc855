"""Grid-level dynamic world: box obstacles that move, appear and vanish, and a moving target (ARCHITECTURE §6)."""
from __future__ import annotations

import math
from collections.abc import Iterable
from dataclasses import dataclass, field

import numpy as np

from . import checks
from .grid import GridMap


def _polyline_point(points: list[tuple[float, float]], travelled: float) -> tuple[float, float]:
    """The point ``travelled`` cells along the polyline through ``points`` (its end once travelled past it)."""
    for (r0, c0), (r1, c1) in zip(points, points[1:]):
        length = math.hypot(r1 - r0, c1 - c0)
        if travelled <= length and length > 0:
            t = travelled / length
            return r0 + t * (r1 - r0), c0 + t * (c1 - c0)
        travelled -= length
    return points[-1]


def _segment_cells(a: tuple[int, int], b: tuple[int, int], step: float) -> np.ndarray:
    """int (n, 2): the cells (row, col) the straight segment from cell ``a`` to cell ``b`` passes, sampled every
    ``step`` cells along it and at its ends, each rounded to the nearest cell as :meth:`Scenario.target` rounds."""
    samples = np.append(np.arange(0.0, 1.0, step / max(math.dist(a, b), step)), 1.0)[:, None]
    return np.floor(np.add(a, samples * np.subtract(b, a)) + 0.5).astype(np.int64)


def box_distance(cell: tuple[int, int], box: tuple[int, int, int, int]) -> float:
    """Euclidean distance in cells from ``cell`` to the nearest cell of ``box`` = (r0, c0, r1, c1) (0 inside)."""
    r0, c0, r1, c1 = box
    return math.hypot(max(r0 - cell[0], 0, cell[0] - (r1 - 1)), max(c0 - cell[1], 0, cell[1] - (c1 - 1)))


#: Cells between the samples that check a target's straight segments for obstacles (:meth:`Scenario.__post_init__`).
TARGET_PATH_STEP = 0.25


def _round(x: float) -> int:
    return int(math.floor(x + 0.5))


@dataclass(frozen=True)
class Obstacle:
    """A box obstacle: rows r0..r1-1 and cols c0..c1-1 at tick 0 (``box = (r0, c0, r1, c1)``), whose top-left
    corner then visits ``waypoints`` in order at ``speed`` cells per tick along straight segments, stopping at the
    last one. It exists from tick ``appear_at`` (None: from the start; its motion starts then) until tick
    ``vanish_at`` (None: never)."""

    box: tuple[int, int, int, int]
    waypoints: tuple[tuple[int, int], ...] = ()
    speed: float = 0.5
    appear_at: int | None = None
    vanish_at: int | None = None

    def __post_init__(self):
        try:
            box = tuple(checks.integer(v, "Obstacle box") for v in self.box)
            waypoints = tuple(checks.pair(w, "Obstacle waypoint") for w in self.waypoints)
        except (TypeError, ValueError):
            raise ValueError(f"Obstacle box must be (r0, c0, r1, c1) and waypoints (row, col) pairs of integers, "
                             f"got box={self.box!r}, waypoints={self.waypoints!r}") from None
        if len(box) != 4 or box[2] <= box[0] or box[3] <= box[1]:
            raise ValueError(f"Obstacle box must be (r0, c0, r1, c1) with r1 > r0 and c1 > c0, got {self.box!r}")
        checks.number(self.speed, "Obstacle speed (cells per tick)", 0.0, inclusive=False)
        for name in ("appear_at", "vanish_at"):
            checks.optional_integer(getattr(self, name), f"Obstacle {name} (a tick)", 0)
        if self.appear_at is not None and self.vanish_at is not None and self.vanish_at <= self.appear_at:
            raise ValueError(f"Obstacle vanish_at ({self.vanish_at}) must come after appear_at ({self.appear_at})")
        object.__setattr__(self, "box", box)
        object.__setattr__(self, "waypoints", waypoints)

    def present(self, tick: int) -> bool:
        """Whether the box exists at ``tick`` (a number: the PyBullet world moves boxes between ticks)."""
        tick = checks.number(tick, "tick")
        return (self.appear_at is None or tick >= self.appear_at) and (self.vanish_at is None or tick < self.vanish_at)

    def corner(self, tick: int) -> tuple[float, float]:
        """Top-left corner (row, col) at ``tick`` (a number), in cells (fractional while between cells)."""
        tick = checks.number(tick, "tick")
        return _polyline_point(self._points(), self.speed * max(0, tick - (self.appear_at or 0)))

    def travel(self, tick: int) -> float:
        """Cells the corner moves along its way from ``tick`` - 1 to ``tick``: its speed, or less where it starts or
        reaches its last waypoint on the way."""
        tick, start, points = checks.number(tick, "tick"), self.appear_at or 0, self._points()
        length = sum(math.dist(a, b) for a, b in zip(points, points[1:]))
        return min(self.speed * max(0, tick - start), length) - min(self.speed * max(0, tick - 1 - start), length)

    def _points(self) -> list[tuple[float, float]]:
        """The corner's way: where it starts, then each waypoint."""
        return [(float(self.box[0]), float(self.box[1]))] + [(float(r), float(c)) for r, c in self.waypoints]

    def footprint(self, tick: int) -> tuple[int, int, int, int]:
        """(r0, c0, r1, c1) of the cells covered at ``tick`` (the corner rounded to the nearest cell)."""
        r, c = (_round(v) for v in self.corner(tick))
        return r, c, r + self.box[2] - self.box[0], c + self.box[3] - self.box[1]


@dataclass
class Scenario:
    """A world: static ``grid``, robot ``start``, target ``goal`` (which then visits ``target_waypoints`` at
    ``target_speed`` cells per tick), and box ``obstacles``.

    The target walks straight from ``goal`` through each waypoint on free cells of ``grid``: a way through one of its
    obstacles is a ValueError (boxes may cover the target; they move on).

    ``change_tick`` (when the blockage or clearing happens) and ``blocking`` (index of the obstacle that causes it)
    are used by the metrics; ``max_ticks`` bounds an episode; ``tick_s`` is the duration of a tick in seconds (for
    runners on a clock); ``map_source`` is the map entry of the world file it came from, if any.
    """

    grid: GridMap
    start: tuple[int, int]
    goal: tuple[int, int]
    obstacles: list[Obstacle] = field(default_factory=list)
    target_waypoints: list[tuple[int, int]] = field(default_factory=list)
    target_speed: float = 0.5
    name: str = "custom"
    description: str = ""
    change_tick: int | None = None
    blocking: int | None = None
    max_ticks: int | None = None
    tick_s: float = 0.2
    map_source: dict | None = None

    def __post_init__(self):
        if not isinstance(self.grid, GridMap):
            raise ValueError(f"Scenario grid must be a tdp.GridMap, got {type(self.grid).__name__}")
        given = self.obstacles
        self.obstacles = list(given) if isinstance(given, Iterable) else [given]
        if not all(isinstance(o, Obstacle) for o in self.obstacles):
            raise ValueError(f"Scenario obstacles must be a list of tdp.Obstacle objects, got {checks.shown(given)}")
        occupied = self.occupancy(0)
        for name in ("start", "goal"):
            cell = self.grid.check_free_cell(getattr(self, name), name)
            if occupied[cell]:
                raise ValueError(f"{name} {cell} is covered by an obstacle at tick 0")
            setattr(self, name, cell)
        if not isinstance(self.target_waypoints, Iterable):
            raise ValueError("Scenario target_waypoints must be a list of cells, got "
                             f"{checks.shown(self.target_waypoints)}")
        self.target_waypoints = [self.grid.check_free_cell(w, "target waypoint") for w in self.target_waypoints]
        self.target_speed = checks.number(self.target_speed, "target_speed (cells per tick)", 0.0, inclusive=False)
        self._check_target_path()
        if not isinstance(self.name, str) or not isinstance(self.description, str):
            raise ValueError(f"Scenario name and description must be strings, got {self.name!r}, {self.description!r}")
        checks.optional_integer(self.max_ticks, "Scenario max_ticks", 1)
        self.tick_s = checks.number(self.tick_s, "tick_s (seconds)", 0.0, inclusive=False)
        checks.optional_integer(self.change_tick, "Scenario change_tick (a tick)", 0)
        if self.blocking is not None and not 0 <= checks.integer(self.blocking, "blocking") < len(self.obstacles):
            raise ValueError(f"blocking must index an obstacle (0..{len(self.obstacles) - 1}), got {self.blocking}")

    def _check_target_path(self) -> None:
        """Refuse a target that walks through the static map's obstacles (a wall between two waypoints): it would
        stand on them at some ticks, or jump them. Boxes may cover it; they move."""
        points = [self.goal] + self.target_waypoints
        for a, b in zip(points, points[1:]):
            cells = _segment_cells(a, b, TARGET_PATH_STEP)
            blocked = self.grid.occupied[cells[:, 0], cells[:, 1]]
            if blocked.any():
                cell = tuple(int(v) for v in cells[np.argmax(blocked)])
                raise ValueError(f"the target's path from {a} to {b} crosses an obstacle of the map at {cell}; "
                                 "its straight segments (goal, then each waypoint) must keep to free cells")

    @property
    def tick_limit(self) -> int:
        """The ticks an episode may last: ``max_ticks``, or 4 (H + W) when the scenario sets none."""
        return self.max_ticks or 4 * sum(self.grid.shape)

    def to_yaml(self) -> str:
        """This world as a world file (:mod:`tdp.worldfile`), in cells; :func:`tdp.load_world` reads it back."""
        from .worldfile import world_yaml

        return world_yaml(self)

    def occupancy(self, tick: int) -> np.ndarray:
        """bool (H, W): the static map plus every box present at ``tick``."""
        tick = checks.number(tick, "tick")
        occupied = self.grid.occupied.copy()
        rows, cols = self.grid.shape
        for obstacle in self.obstacles:
            if obstacle.present(tick):
                r0, c0, r1, c1 = obstacle.footprint(tick)
                occupied[max(0, r0):max(0, min(rows, r1)), max(0, c0):max(0, min(cols, c1))] = True
        return occupied

    def holds(self, tick: int, cell: tuple[int, int]) -> bool:
        """Whether a box covering ``cell`` at ``tick`` is moving (its corner moved since the tick before): a box
        that drives onto the robot holds it while it moves on; one standing still (a door that closed, a box that
        parked) does not, and the robot may drive off it."""
        return any(moving for _, moving in self._covering(tick, cell))

    def parked_over(self, tick: int, cell: tuple[int, int]) -> np.ndarray:
        """bool (H, W): the cells of the boxes that cover ``cell`` at ``tick`` and stand still (see :meth:`holds`),
        less the static map's obstacles - a robot under such a box may drive through them to get out."""
        mask = np.zeros(self.grid.shape, bool)
        for (r0, c0, r1, c1), moving in self._covering(tick, cell):
            if not moving:
                mask[max(0, r0):max(0, r1), max(0, c0):max(0, c1)] = True
        return mask & ~self.grid.occupied

    def jumped_over(self, tick: int, cell: tuple[int, int]) -> bool:
        """Whether a box faster than a cell a tick passed over ``cell`` on its way from tick - 1 to tick, looked at
        every whole cell of its way before its place at ``tick``: a hit that the occupancy at ``tick`` does not show
        (a box 2 cells long at 8 cells a tick would otherwise cross a robot unseen 3 times in 4)."""
        tick, (r, c) = checks.number(tick, "tick"), checks.pair(cell, "cell")
        for obstacle in (o for o in self.obstacles if o.speed > 1):  # a cell of its way every 1 / speed of a tick,
            cells = math.ceil(obstacle.travel(tick))  # as far as it went (a box at 10^6 cells a tick stops at its end)
            for when in (tick - 1 + k / obstacle.speed for k in range(1, cells)):
                r0, c0, r1, c1 = obstacle.footprint(when)
                if obstacle.present(when) and r0 <= r < r1 and c0 <= c < c1:
                    return True
        return False

    def _covering(self, tick: int, cell: tuple[int, int]):
        """(footprint, moving) of each box present at ``tick`` that covers ``cell`` (row, col)."""
        tick, (r, c) = checks.number(tick, "tick"), checks.pair(cell, "cell")
        for obstacle in self.obstacles:
            if obstacle.present(tick):
                r0, c0, r1, c1 = obstacle.footprint(tick)
                if r0 <= r < r1 and c0 <= c < c1:
                    yield (r0, c0, r1, c1), obstacle.corner(tick) != obstacle.corner(tick - 1)

    def target(self, tick: int) -> tuple[int, int]:
        """The target's cell at ``tick``."""
        tick = checks.number(tick, "tick")
        points = [tuple(map(float, self.goal))] + [tuple(map(float, w)) for w in self.target_waypoints]
        r, c = _polyline_point(points, self.target_speed * tick)
        return _round(r), _round(c)
