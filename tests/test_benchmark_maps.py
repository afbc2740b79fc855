"""The maps the benchmarks make for themselves, checked against hand-drawn ones."""
import numpy as np
from scipy import ndimage

from benchmarks.convergence import serpentine
from benchmarks.equal_time import hall_worlds


def test_serpentine_is_one_corridor_a_cell_wide():
    drawn = ["#########",
             "#.......#",
             "#######.#",
             "#.......#",
             "#.#######",
             "#.......#",
             "#######.#",
             "#.......#",
             "#########"]
    assert (serpentine(9) == (np.array([list(row) for row in drawn]) == "#")).all()
    free = ~serpentine(64)
    assert ndimage.label(free)[1] == 1
    neighbours = ndimage.convolve(free.astype(int), [[0, 1, 0], [1, 0, 1], [0, 1, 0]], mode="constant")[free]
    assert np.bincount(neighbours, minlength=3)[1:3].tolist() == [2, free.sum() - 2]  # two ends, the rest between


def test_the_standing_hall_is_the_lying_one_turned_and_is_driven_end_to_end():
    lying, standing = hall_worlds()
    assert lying.grid.shape == standing.grid.shape[::-1] and lying.grid.shape[1] > 20 * lying.grid.shape[0]
    for tick in (0, 17, 250):
        assert (standing.occupancy(tick) == lying.occupancy(tick).T).all()
    assert standing.start == lying.start[::-1] and standing.goal == lying.goal[::-1]
    assert lying.start[1] == 0 and lying.goal[1] == lying.grid.shape[1] - 1
    labels = ndimage.label(~lying.occupancy(0), structure=np.ones((3, 3)))[0]
    assert labels[lying.start] == labels[lying.goal] != 0
