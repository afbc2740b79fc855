"""The maps the benchmarks make for themselves, checked against hand-drawn ones."""
import numpy as np
from scipy import ndimage

from benchmarks.convergence import caves, caves_cases, rings, serpentine
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


def test_rings_are_corridors_a_cell_wide_round_the_centre_each_wall_with_one_door():
    drawn = ["###########",
             "#.........#",
             "#.#####.#.#",
             "#.#.....#.#",
             "#.#.###.#.#",
             "#.#.#.#.#.#",
             "#.#.#.#.#.#",
             "#.#.....#.#",
             "#.#######.#",
             "#.........#",
             "###########"]
    assert (rings(11) == (np.array([list(row) for row in drawn]) == "#")).all()
    for side in (64, 65):
        free = ~rings(side)
        assert ndimage.label(free)[1] == 1
        # every corridor cell lies on a loop: two or more free 4-neighbours, but the centre's
        neighbours = ndimage.convolve(free.astype(int), [[0, 1, 0], [1, 0, 1], [0, 1, 0]], mode="constant")[free]
        assert (neighbours >= 2).sum() >= free.sum() - 4


def test_caves_are_mostly_one_region_of_passages_and_their_goals_lie_in_it():
    occupied = caves(128)
    assert (occupied == caves(128)).all() and 0.35 < occupied.mean() < 0.55
    labels, count = ndimage.label(~occupied, structure=np.ones((3, 3)))
    sizes = np.bincount(labels.ravel())[1:]
    assert sizes.max() > 0.7 * sizes.sum()  # 0.79 here, 0.97 at 512²
    cases = caves_cases(128)
    assert [name for name, _, _ in cases] == ["caves 128² corner", "caves 128² centre", "caves 128² random"]
    main = np.argmax(sizes) + 1
    assert all(labels[goal] == main and not grid[goal] for _, grid, goal in cases)


def test_the_standing_hall_is_the_lying_one_turned_and_is_driven_end_to_end():
    lying, standing = hall_worlds()
    assert lying.grid.shape == standing.grid.shape[::-1] and lying.grid.shape[1] > 20 * lying.grid.shape[0]
    for tick in (0, 17, 250):
        assert (standing.occupancy(tick) == lying.occupancy(tick).T).all()
    assert standing.start == lying.start[::-1] and standing.goal == lying.goal[::-1]
    assert lying.start[1] == 0 and lying.goal[1] == lying.grid.shape[1] - 1
    labels = ndimage.label(~lying.occupancy(0), structure=np.ones((3, 3)))[0]
    assert labels[lying.start] == labels[lying.goal] != 0
