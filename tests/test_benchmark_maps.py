"""The maps the benchmarks make for themselves, checked against hand-drawn ones."""
import numpy as np
from scipy import ndimage

from benchmarks.convergence import serpentine


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
