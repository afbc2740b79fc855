"""The PyBullet world of a tdp.Scenario: floor, static boxes, moving boxes; and its rasterising into the grid.

One scenario cell is ``cell_m`` metres; the grid's row 0 is the top (largest y), as in tdp.GridMap. Moving boxes
are kinematic (mass 0) and follow their waypoints continuously, moved every physics step; boxes appear and vanish
at their ticks. The robot is never moved this way: only its wheel motors move it.
"""
from __future__ import annotations

import math

import numpy as np
import pybullet as p

import tdp
from tdp.grid import rectangles

BOX_HEIGHT_M = 0.3
WALL_COLOUR = (0.45, 0.45, 0.45, 1)

#: The most shapes PyBullet keeps in one body (``createCollisionShapeArray`` drops the rest).
SHAPES_PER_BODY = 16

#: The map's walls are grouped into bodies tile by tile, tiles this many cells a side, so each body stays local.
WALL_TILE_CELLS = 16


class SimWorld:
    """Bodies of a scenario in a PyBullet client, with ``cell_m`` metres per cell and ``tick_s`` seconds per tick."""

    def __init__(self, client: int, scenario: tdp.Scenario, cell_m: float, tick_s: float):
        self.client, self.scenario, self.cell_m, self.tick_s = client, scenario, cell_m, tick_s
        self.grid = tdp.GridMap(scenario.grid.occupied, cell_m)
        floor = p.createCollisionShape(p.GEOM_PLANE, physicsClientId=client)
        self.floor = p.createMultiBody(0, floor, physicsClientId=client)
        self.half_extents: dict[int, tuple[float, float, float]] = {}  # moving box's body -> half extents (m)
        self.static_bodies = [self._wall_body(group) for group in wall_groups(rectangles(scenario.grid.occupied))]
        self._static = frozenset(self.static_bodies)
        self.moving: dict[int, int] = {}  # obstacle index -> body
        self._last_seen: dict[int, tuple[float, float, float]] = {}  # body -> (time, x, y) at the last rasterising
        self.update(0.0)

    def _wall_body(self, boxes: list[tuple[int, int, int, int]]) -> int:
        """One static body of the map's wall rectangles ``boxes`` (at most SHAPES_PER_BODY). A body of its own for
        each of the thousands of rectangles of a large map made every physics step cost tens of milliseconds."""
        halves = [self._half(box) for box in boxes]
        centres = [self._centre(box) for box in boxes]
        types = [p.GEOM_BOX] * len(boxes)
        shape = p.createCollisionShapeArray(types, halfExtents=halves, collisionFramePositions=centres,
                                            physicsClientId=self.client)
        visual = p.createVisualShapeArray(types, halfExtents=halves, visualFramePositions=centres,
                                          physicsClientId=self.client)
        body = p.createMultiBody(0, shape, visual, (0, 0, 0), useMaximalCoordinates=True, physicsClientId=self.client)
        p.changeVisualShape(body, -1, rgbaColor=WALL_COLOUR, physicsClientId=self.client)
        return body

    def _box_body(self, box: tuple[float, float, float, float], colour) -> int:
        half = self._half(box)
        shape = p.createCollisionShape(p.GEOM_BOX, halfExtents=half, physicsClientId=self.client)
        visual = p.createVisualShape(p.GEOM_BOX, halfExtents=half, rgbaColor=colour, physicsClientId=self.client)
        body = p.createMultiBody(0, shape, visual, self._centre(box), physicsClientId=self.client)
        self.half_extents[body] = half
        return body

    def _half(self, box) -> tuple[float, float, float]:
        r0, c0, r1, c1 = box
        return self.cell_m * (c1 - c0) / 2, self.cell_m * (r1 - r0) / 2, BOX_HEIGHT_M / 2

    def _centre(self, box) -> tuple[float, float, float]:
        r0, c0, r1, c1 = box
        rows = self.grid.shape[0]
        return self.cell_m * (c0 + c1) / 2, self.cell_m * (rows - (r0 + r1) / 2), BOX_HEIGHT_M / 2

    def obstacle_box(self, index: int, time_s: float) -> tuple[float, float, float, float]:
        """(r0, c0, r1, c1) in fractional cells of obstacle ``index`` at ``time_s`` (its continuous motion)."""
        obstacle = self.scenario.obstacles[index]
        r, c = obstacle.corner(time_s / self.tick_s)
        r0, c0, r1, c1 = obstacle.box
        return r, c, r + r1 - r0, c + c1 - c0

    def update(self, time_s: float) -> None:
        """Add, move and remove the moving boxes for ``time_s``."""
        tick = time_s / self.tick_s
        for index, obstacle in enumerate(self.scenario.obstacles):
            present = obstacle.present(math.floor(tick + 1e-9))
            if present and index not in self.moving:
                self.moving[index] = self._box_body(self.obstacle_box(index, time_s), (0.7, 0.4, 0.2, 1))
            elif not present and index in self.moving:
                body = self.moving.pop(index)
                del self.half_extents[body]
                self._last_seen.pop(body, None)  # PyBullet gives its id to the next body made
                p.removeBody(body, physicsClientId=self.client)
            elif present:
                p.resetBasePositionAndOrientation(self.moving[index], self._centre(self.obstacle_box(index, time_s)),
                                                  (0, 0, 0, 1), physicsClientId=self.client)

    def is_obstacle(self, body: int) -> bool:
        """Whether ``body`` is a wall or a moving box."""
        return body in self._static or body in self.moving.values()

    def obstacles_near(self, low: tuple[float, float, float], high: tuple[float, float, float]) -> list[int]:
        """The bodies of the walls whose bounding boxes meet the box from ``low`` to ``high`` (metres), and every
        moving box."""
        found = p.getOverlappingObjects(low, high, physicsClientId=self.client) or ()
        return sorted({body for body, _ in found if body in self._static}) + list(self.moving.values())

    def moving_footprints(self, inflate_m: float, time_s: float, horizon_s: float = 0.0) -> np.ndarray:
        """bool (H, W): cells whose centres lie within ``inflate_m`` of a moving box, from the bodies' poses, each
        box swept along its velocity (measured from its pose at the previous call) over ``horizon_s``."""
        mask = np.zeros(self.grid.shape, bool)
        for body in self.moving.values():
            (x, y, _), _ = p.getBasePositionAndOrientation(body, physicsClientId=self.client)
            hx, hy, _ = self.half_extents[body]
            last_time, last_x, last_y = self._last_seen.get(body, (time_s, x, y))
            elapsed = time_s - last_time
            dx = (x - last_x) / elapsed * horizon_s if elapsed > 0 else 0.0
            dy = (y - last_y) / elapsed * horizon_s if elapsed > 0 else 0.0
            self._last_seen[body] = (time_s, x, y)
            swept = (min(x, x + dx) - hx, min(y, y + dy) - hy, max(x, x + dx) + hx, max(y, y + dy) + hy)
            mask |= box_cells(self.grid, swept, inflate_m)
        return mask


def wall_groups(boxes: list[tuple[int, int, int, int]]) -> list[list[tuple[int, int, int, int]]]:
    """The rectangles ``boxes`` (r0, c0, r1, c1) in groups of at most SHAPES_PER_BODY, each within one tile of
    WALL_TILE_CELLS cells a side (by its first cell)."""
    tiles: dict[tuple[int, int], list] = {}
    for box in boxes:
        tiles.setdefault((box[0] // WALL_TILE_CELLS, box[1] // WALL_TILE_CELLS), []).append(box)
    return [group[k:k + SHAPES_PER_BODY] for _, group in sorted(tiles.items())
            for k in range(0, len(group), SHAPES_PER_BODY)]


def cell_centres(grid: tdp.GridMap) -> tuple[np.ndarray, np.ndarray]:
    """World x and y (metres) of every cell's centre, as two (H, W) arrays (an unrotated map)."""
    rows, cols = np.indices(grid.shape)
    return (grid.origin[0] + (cols + 0.5) * grid.resolution,
            grid.origin[1] + (grid.shape[0] - rows - 0.5) * grid.resolution)


def box_cells(grid: tdp.GridMap, box_xy: tuple[float, float, float, float], inflate_m: float) -> np.ndarray:
    """bool (H, W): cells whose centre is within ``inflate_m`` (Euclidean) of the box x0, y0, x1, y1 (metres)."""
    x0, y0, x1, y1 = box_xy
    cx, cy = cell_centres(grid)
    dx = np.maximum(np.maximum(x0 - cx, 0), cx - x1)
    dy = np.maximum(np.maximum(y0 - cy, 0), cy - y1)
    return dx * dx + dy * dy <= inflate_m * inflate_m
