"""The planner a config names: one constructor for every runner (grid episodes, PyBullet, sweeps, benchmarks)."""
from __future__ import annotations

from .exact import ExactPlanner
from .grid import GridMap
from .config import NavigatorConfig
from .navigator import Navigator


def make_planner(grid: GridMap, start: tuple[int, int], goal: tuple[int, int],
                 config: NavigatorConfig = NavigatorConfig()) -> ExactPlanner | Navigator:
    """The planner of ``config.planner`` on ``grid`` from ``start`` to ``goal`` (cells), not yet set up: an
    :class:`~tdp.exact.ExactPlanner` for "exact", a :class:`~tdp.navigator.Navigator` for "accelerating" and
    "plain-dp". Call its ``setup()`` before the first tick.

    Raises:
        ValueError: as the planner's constructor (a bad grid, config, start or goal).

    Examples:
        >>> import numpy as np, tdp
        >>> grid = tdp.GridMap(np.zeros((10, 10), bool))
        >>> type(tdp.make_planner(grid, (0, 0), (9, 9), tdp.NavigatorConfig(planner="plain-dp"))).__name__
        'Navigator'
    """
    if isinstance(config, NavigatorConfig) and config.planner == "exact":
        return ExactPlanner(grid, start, goal, config)
    return Navigator(grid, start, goal, config)
