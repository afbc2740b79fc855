"""The named scenarios of the paper's section 5, shared by the grid runner and PyBullet (ARCHITECTURE §6).

All use a 100 x 100 map made in code: the robot starts top-left, the goal is bottom-right, and a wall (rows 44-47)
crosses the map with two passages, A in the middle (cols 45-54, on the diagonal: the short way) and B on the left
(cols 4-15: the detour). Obstacles and the target move at half the robot's speed (0.5 cells per tick). In the
blockage scenarios the change happens far ahead of the robot (about 40 cells), on the route it is following.
"""
from __future__ import annotations

import numpy as np

from .grid import GridMap
from .world import Obstacle, Scenario

SIZE = 100
WALL_ROWS = (44, 48)
PASSAGE_A = (45, 55)
PASSAGE_B = (4, 16)
START, GOAL = (3, 3), (96, 96)
MAX_TICKS = 400


def _wall_map() -> GridMap:
    occupied = np.zeros((SIZE, SIZE), bool)
    occupied[WALL_ROWS[0]:WALL_ROWS[1], :] = True
    for c0, c1 in (PASSAGE_A, PASSAGE_B):
        occupied[WALL_ROWS[0]:WALL_ROWS[1], c0:c1] = False
    return GridMap(occupied)


def _plug_a(**timing) -> Obstacle:
    """A box exactly filling passage A."""
    return Obstacle(box=(WALL_ROWS[0], PASSAGE_A[0], WALL_ROWS[1], PASSAGE_A[1]), **timing)


def _back_and_forth(a: tuple[int, int], b: tuple[int, int], times: int) -> list[tuple[int, int]]:
    return [b, a] * times


def _static() -> Scenario:
    return Scenario(_wall_map(), START, GOAL, name="static", max_ticks=MAX_TICKS,
                    description="no change: the DP path is optimal from the start")


def _moving_target() -> Scenario:
    return Scenario(_wall_map(), START, GOAL, target_waypoints=[(96, 40)], name="moving-target", max_ticks=MAX_TICKS,
                    description="the target walks left along the bottom row while the robot chases it")


def _moving_obstacles() -> Scenario:
    upper = Obstacle(box=(17, 4, 23, 10), waypoints=_back_and_forth((17, 4), (17, 36), 4))
    lower = Obstacle(box=(74, 88, 80, 94), waypoints=_back_and_forth((74, 88), (74, 56), 4))
    return Scenario(_wall_map(), START, GOAL, obstacles=[upper, lower], name="moving-obstacles",
                    max_ticks=MAX_TICKS, description="two boxes sweep across the robot's route; nothing is blocked")


def _moving_blockage() -> Scenario:
    width = PASSAGE_A[1] - PASSAGE_A[0]
    start_col = PASSAGE_A[0] + 6
    slider = Obstacle(box=(WALL_ROWS[0], start_col, WALL_ROWS[1], start_col + width),
                      waypoints=[(WALL_ROWS[0], PASSAGE_A[0])])
    closes = next(t for t in range(MAX_TICKS) if slider.footprint(t)[1] <= PASSAGE_A[0])
    return Scenario(_wall_map(), START, GOAL, obstacles=[slider], name="moving-blockage", change_tick=closes,
                    blocking=0, max_ticks=MAX_TICKS,
                    description="a box slides along the wall and closes passage A ahead of the robot")


def _sudden_blockage() -> Scenario:
    return Scenario(_wall_map(), START, GOAL, obstacles=[_plug_a(appear_at=10)], name="sudden-blockage",
                    change_tick=10, blocking=0, max_ticks=MAX_TICKS,
                    description="a box appears in passage A at tick 10, about 45 cells ahead of the robot (Fig. 10)")


def _clearing() -> Scenario:
    return Scenario(_wall_map(), START, GOAL, obstacles=[_plug_a(vanish_at=12)], name="clearing", change_tick=12,
                    blocking=0, max_ticks=MAX_TICKS,
                    description="passage A is closed, then opens at tick 12: the robot should take it (eq. 2)")


_BUILDERS = {"static": _static, "moving-target": _moving_target, "moving-obstacles": _moving_obstacles,
             "moving-blockage": _moving_blockage, "sudden-blockage": _sudden_blockage, "clearing": _clearing}


def names() -> list[str]:
    """The names of the built-in scenarios."""
    return list(_BUILDERS)


def get(name: str) -> Scenario:
    """A fresh copy of the named scenario."""
    if name not in _BUILDERS:
        raise ValueError(f"unknown scenario {name!r}; choose one of {', '.join(_BUILDERS)}")
    return _BUILDERS[name]()
