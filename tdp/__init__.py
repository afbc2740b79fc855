"""tdp: robot path planning in changing maps by dynamic programming with accelerating nodes.

Kala, Shukla and Tiwari (2012), "Robot Path Planning using Dynamic Programming with Accelerating Nodes".
"""
from . import random_worlds, scenarios
from .contract import Mode, Planner, TickResult
from .exact import ExactPlanner
from .field import DistanceField
from .grid import GridMap, Problem, costmap_grid, load_map, load_scenarios
from .config import NavigatorConfig
from .navigator import Navigator
from .planners import make_planner
from .simulate import Episode, simulate
from .world import Obstacle, Scenario
from .worldfile import load_world

__all__ = ["DistanceField", "Episode", "ExactPlanner", "GridMap", "Mode", "Navigator", "NavigatorConfig", "Obstacle",
           "Planner", "Problem", "Scenario", "TickResult", "costmap_grid", "load_map", "load_scenarios", "load_world",
           "make_planner", "random_worlds", "scenarios", "simulate"]
__version__ = "0.1.0"
