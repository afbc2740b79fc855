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


class SimWorld:
    """Bodies of a scenario in a PyBullet client, with ``cell_m`` metres per cell and ``tick_s`` seconds per tick."""

    def __init__(self, client: int, scenario: tdp.Scenario, cell_m: float, tick_s: float):
        self.client, self.scenario, self.cell_m, self.tick_s = client, scenario, cell_m, tick_s
        self.grid = tdp.GridMap(scenario.grid.occupied, cell_m)
        floor = p.createCollisionShape(p.GEOM_PLANE, physicsClientId=client)
        self.floor = p.createMultiBody(0, floor, physicsClientId=client)
        self.half_extents: dict[int, tuple[float, float, float]] = {}  # body -> half extents (m)
        self.static_bodies = [self._box_body(box, (0.45, 0.45, 0.45, 1)) for box in rectangles(scenario.grid.occupied)]
        self.moving: dict[int, int] = {}  # obstacle index -> body
        self._last_seen: dict[int, tuple[float, float, float]] = {}  # body -> (time, x, y) at the last rasterising
        self.update(0.0)

    def _box_body(self, box: tuple[float, float, float, float], colour) -> int:
        r0, c0, r1, c1 = box
        half = (self.cell_m * (c1 - c0) / 2, self.cell_m * (r1 - r0) / 2, BOX_HEIGHT_M / 2)
        shape = p.createCollisionShape(p.GEOM_BOX, halfExtents=half, physicsClientId=self.client)
        visual = p.createVisualShape(p.GEOM_BOX, halfExtents=half, rgbaColor=colour, physicsClientId=self.client)
        body = p.createMultiBody(0, shape, visual, self._centre(box), physicsClientId=self.client)
        self.half_extents[body] = half
        return body

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
                p.removeBody(body, physicsClientId=self.client)
            elif present:
                p.resetBasePositionAndOrientation(self.moving[index], self._centre(self.obstacle_box(index, time_s)),
                                                  (0, 0, 0, 1), physicsClientId=self.client)

    def obstacle_bodies(self) -> list[int]:
        return self.static_bodies + list(self.moving.values())

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
