"""The D* Lite baseline of the benchmarks agrees with scipy's Dijkstra, before and after map changes."""
import numpy as np
import pytest

from tdp.dstar_lite import DStarLite
from reference import distances_to


@pytest.mark.parametrize("seed", range(6))
def test_dstar_lite_distances_equal_dijkstra_through_changes(seed):
    rng = np.random.default_rng(seed)
    occupied = rng.random((18, 21)) < 0.25
    start, goal = (0, 0), (17, 20)
    occupied[start] = occupied[goal] = False
    planner = DStarLite(occupied, start, goal, neighbourhood=[4, 8, 16][seed % 3])
    neighbourhood = [4, 8, 16][seed % 3]
    assert planner.distance() == pytest.approx(distances_to(occupied, goal, neighbourhood)[start])
    for _ in range(4):
        cells = np.argwhere(rng.random(occupied.shape) < 0.05)
        cells = cells[(cells != start).any(axis=1) & (cells != goal).any(axis=1)]
        values = rng.random(len(cells)) < 0.6
        occupied[cells[:, 0], cells[:, 1]] = values
        planner.update_map(cells, values)
        assert planner.distance() == pytest.approx(distances_to(occupied, goal, neighbourhood)[start])
        result = planner.tick()
        if np.isfinite(planner.distance()):
            planner.move_robot(result.next_cell)
            start = result.next_cell
            assert planner.distance() == pytest.approx(distances_to(occupied, goal, neighbourhood)[start])
