"""The named scenarios of the paper's section 5, shared by the grid runner and PyBullet (ARCHITECTURE §6).

Each is a world file in ``tdp/worlds/`` read by :func:`tdp.load_world`, the same code that reads a user's. All use
a 100 x 100 map: the robot starts top-left, the goal is bottom-right, and a wall (rows 44-47) crosses the map with
two passages, A in the middle (cols 45-54, on the diagonal: the short way) and B on the left (cols 4-15: the
detour). Obstacles and the target move at half the robot's speed (0.5 cells per tick). In the blockage scenarios
the change happens far ahead of the robot (about 40 cells), on the route it is following.
"""
from __future__ import annotations

from pathlib import Path

from .world import Scenario
from .worldfile import load_world

FOLDER = Path(__file__).parent / "worlds"
ORDER = ("static", "moving-target", "moving-obstacles", "moving-blockage", "sudden-blockage", "clearing")


def names() -> list[str]:
    """The names of the built-in scenarios."""
    return list(ORDER)


def path(name: str) -> Path:
    """The world file of the named scenario."""
    if name not in ORDER:
        raise ValueError(f"unknown scenario {name!r}; choose one of {', '.join(ORDER)}")
    return FOLDER / f"{name}.yaml"


def get(name: str) -> Scenario:
    """A fresh copy of the named scenario."""
    return load_world(path(name))
