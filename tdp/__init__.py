"""tdp: robot path planning in changing maps by dynamic programming with accelerating nodes.

Kala, Shukla and Tiwari (2012), "Robot Path Planning using Dynamic Programming with Accelerating Nodes".
"""
from .field import DistanceField
from .grid import GridMap, Problem, load_map, load_scenarios

__all__ = ["DistanceField", "GridMap", "Problem", "load_map", "load_scenarios"]
__version__ = "0.1.0"
