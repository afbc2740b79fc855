"""DistanceField against scipy's Dijkstra on the same graph, and the DP's synchronous semantics."""
import math
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

import tdp
from reference import assert_distances_match, distances_to


@st.composite
def maps_with_goal(draw):
    rows = draw(st.integers(3, 14))
    cols = draw(st.integers(3, 14))
    density = draw(st.sampled_from([0.0, 0.15, 0.3, 0.45]))
    seed = draw(st.integers(0, 2**31))
    occupied = np.random.default_rng(seed).random((rows, cols)) < density
    corner = draw(st.sampled_from([None, (0, 0), (0, cols - 1), (rows - 1, 0), (rows - 1, cols - 1),
                                   (0, cols // 2), (rows // 2, cols - 1)]))
    if corner is None:
        corner = (draw(st.integers(0, rows - 1)), draw(st.integers(0, cols - 1)))
    occupied[corner] = False
    return occupied, corner


def field_on(occupied: np.ndarray, goal: tuple[int, int], **options) -> tdp.DistanceField:
    """A DistanceField on the bool map ``occupied``."""
    return tdp.DistanceField(tdp.GridMap(occupied), goal, **options)


def assert_same_distances(ours: np.ndarray, reference: np.ndarray) -> None:
    assert_distances_match(ours, reference, rtol=2e-6)


@settings(max_examples=60, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(maps_with_goal(), st.sampled_from([4, 8, 16]), st.booleans())
def test_converged_field_equals_dijkstra(map_goal, neighbourhood, corner_cutting):
    occupied, goal = map_goal
    field = field_on(occupied, goal, neighbourhood=neighbourhood, corner_cutting=corner_cutting)
    field.converge()
    assert_same_distances(field.distances(), distances_to(occupied, goal, neighbourhood, corner_cutting))


@settings(max_examples=25, deadline=None)
@given(maps_with_goal(), st.sampled_from([4, 8, 16]), st.booleans())
def test_synchronous_iterations_reach_the_same_fixed_point_bit_for_bit(map_goal, neighbourhood, corner_cutting):
    occupied, goal = map_goal
    field = field_on(occupied, goal, neighbourhood=neighbourhood, corner_cutting=corner_cutting)
    field.converge()
    swept = field.distances().copy()
    jacobi = field_on(occupied, goal, neighbourhood=neighbourhood, corner_cutting=corner_cutting)
    while jacobi.step():
        pass
    np.testing.assert_array_equal(jacobi.distances(), swept)


@settings(max_examples=25, deadline=None)
@given(maps_with_goal(), st.sampled_from([4, 8, 16]), st.integers(0, 12))
def test_after_k_iterations_exactly_the_cells_within_k_moves_are_finite(map_goal, neighbourhood, k):
    occupied, goal = map_goal
    field = field_on(occupied, goal, neighbourhood=neighbourhood)
    field.step(k)
    hops = distances_to(occupied, goal, neighbourhood, hops=True)
    np.testing.assert_array_equal(np.isfinite(field.distances()), hops <= k)
    assert field.iterations == k


def test_d_max_caps_every_value():
    occupied = np.zeros((20, 20), bool)
    field = field_on(occupied, (0, 0), d_max=7.5)
    field.converge()
    reference = np.minimum(distances_to(occupied, (0, 0)), 7.5)
    np.testing.assert_allclose(field.distances(), reference, rtol=1e-6)
    assert field.successor((19, 19)) is None
    assert field.path((19, 19)) == []


def open_map_with_gap_wall():
    """A 24 x 24 open map; the wall cells close the direct way between the corners, leaving detours."""
    occupied = np.zeros((24, 24), bool)
    wall = np.zeros_like(occupied)
    wall[4:20, 12] = True
    return occupied, wall


def test_wall_makes_values_rise_to_the_new_distances_and_removal_restores_them():
    occupied, wall = open_map_with_gap_wall()
    goal = (12, 23)
    field = field_on(occupied, goal)
    field.converge()
    before = field.distances().copy()

    field.set_occupied(wall)
    iterations = 0
    while field.step():
        iterations += 1
        assert iterations < 500
    after = field.distances()
    assert_same_distances(after, distances_to(occupied | wall, goal))
    assert after[12, 0] > before[12, 0] + 1  # the far side had to go round the wall

    field.set_occupied(wall, occupied=False)
    while field.step():
        pass
    np.testing.assert_array_equal(field.distances(), before)


def test_set_occupied_accepts_cells_and_masks_alike():
    occupied, wall = open_map_with_gap_wall()
    by_mask = field_on(occupied, (0, 0))
    by_cells = field_on(occupied, (0, 0))
    by_mask.set_occupied(wall)
    by_cells.set_occupied([tuple(c) for c in np.argwhere(wall)])
    by_mask.converge()
    by_cells.converge()
    np.testing.assert_array_equal(by_mask.distances(), by_cells.distances())
    np.testing.assert_array_equal(by_mask.occupied, wall)


def test_set_goal_moves_the_source():
    occupied, wall = open_map_with_gap_wall()
    field = tdp.DistanceField(tdp.GridMap(occupied | wall), (0, 0))
    field.converge()
    field.set_goal((23, 23))
    field.converge()
    assert field.goal == (23, 23)
    assert_same_distances(field.distances(), distances_to(occupied | wall, (23, 23)))


@pytest.mark.parametrize("neighbourhood", [4, 8, 16])
def test_path_from_every_reachable_cell_reaches_the_goal_with_its_distance(neighbourhood):
    occupied = np.random.default_rng(7).random((18, 22)) < 0.3
    goal = (9, 11)
    occupied[goal] = False
    field = field_on(occupied, goal, neighbourhood=neighbourhood)
    field.converge()
    d = field.distances()
    for start in map(tuple, np.argwhere(~occupied)):
        path = field.path(start)
        if not np.isfinite(d[start]):
            assert path == []
            continue
        assert path[0] == start and path[-1] == goal
        length = sum(math.dist(a, b) for a, b in zip(path, path[1:]))
        assert length == pytest.approx(float(d[start]), rel=1e-5)
        assert all(not occupied[c] for c in path)


def test_successor_ties_follow_straight_then_diagonal_then_knight():
    # From (2, 2) to goal (0, 2) on an open map: straight up is the argmin, uniquely.
    field = tdp.DistanceField(tdp.GridMap(np.zeros((5, 5), bool)), (0, 2))
    field.converge()
    assert field.successor((2, 2)) == (1, 2)
    assert field.successor((0, 2)) is None
    # (1, 0) -> goal (0, 2): the knight move (-1, +2) costs sqrt 5 = 2.236, while the straight and diagonal
    # first steps cost 1 + 2 = 3 and sqrt 2 + 1 = 2.414.
    assert field.successor((1, 0)) == (0, 2)


def test_diagonal_gap_is_closed_without_corner_cutting_and_open_with_it():
    occupied = np.array([[0, 1], [1, 0]], bool)
    strict = field_on(occupied, (0, 0), neighbourhood=8)
    strict.converge()
    assert math.isinf(strict.distance((1, 1)))
    cutting = field_on(occupied, (0, 0), neighbourhood=8, corner_cutting=True)
    cutting.converge()
    assert cutting.distance((1, 1)) == pytest.approx(math.sqrt(2))


def test_knight_move_needs_both_crossed_cells_free():
    # From (0, 0) to (1, 2): crosses (0, 1) and (1, 1).
    for blocked in [(0, 1), (1, 1)]:
        occupied = np.zeros((2, 3), bool)
        occupied[blocked] = True
        field = field_on(occupied, (1, 2), neighbourhood=16)
        field.converge()
        assert field.distance((0, 0)) > math.sqrt(5) + 1e-6
    field = tdp.DistanceField(tdp.GridMap(np.zeros((2, 3), bool)), (1, 2))
    field.converge()
    assert field.distance((0, 0)) == pytest.approx(math.sqrt(5))


@pytest.mark.parametrize("kwargs, message", [
    ({"goal": (5, 0)}, "outside"),
    ({"goal": (-1, 0)}, "outside"),
    ({"goal": (1, 1)}, "obstacle"),
    ({"goal": (0.5, 0)}, "integers"),
    ({"goal": (0, 0), "neighbourhood": 6}, "neighbourhood"),
    ({"goal": (0, 0), "d_max": -1.0}, "d_max"),
    ({"goal": (0, 0), "d_max": float("nan")}, "d_max"),
])
def test_bad_arguments_raise_clear_errors(kwargs, message):
    occupied = np.zeros((4, 4), bool)
    occupied[1, 1] = True
    with pytest.raises(ValueError, match=message):
        tdp.DistanceField(tdp.GridMap(occupied), **kwargs)


def test_bad_queries_and_edits_raise_clear_errors():
    occupied = np.zeros((4, 4), bool)
    occupied[1, 1] = True
    field = field_on(occupied, (0, 0))
    with pytest.raises(ValueError, match="outside"):
        field.distance((4, 0))
    with pytest.raises(ValueError, match="obstacle"):
        field.path((1, 1))
    with pytest.raises(ValueError, match="obstacle"):
        field.set_goal((1, 1))
    with pytest.raises(ValueError, match="shape"):
        field.set_occupied(np.zeros((3, 3), bool))
    with pytest.raises(ValueError, match="outside"):
        field.set_occupied([(0, 9)])
    with pytest.raises(ValueError, match="k must"):
        field.step(-1)
    with pytest.raises(ValueError, match="GridMap"):
        tdp.DistanceField(occupied, (0, 0))


S2, S5 = math.sqrt(2), math.sqrt(5)
INF = math.inf


def test_literal_open_5x5_with_16_neighbours():
    """Distances to the top-left corner, written out by hand: straight 1, diagonal sqrt 2, knight sqrt 5."""
    expected = [
        [0, 1, 2, 3, 4],
        [1, S2, S5, 1 + S5, 2 + S5],
        [2, S5, 2 * S2, S2 + S5, 2 * S5],
        [3, 1 + S5, S2 + S5, 3 * S2, 2 * S2 + S5],
        [4, 2 + S5, 2 * S5, 2 * S2 + S5, 4 * S2],
    ]
    field = field_on(np.zeros((5, 5), bool), (0, 0))
    field.converge()
    np.testing.assert_allclose(field.distances(), expected, rtol=1e-6)


def test_literal_wall_with_a_gap_and_4_neighbours():
    """A wall down column 2 with a gap at the bottom: the right half goes round through (4, 2)."""
    occupied = np.zeros((5, 5), bool)
    occupied[0:4, 2] = True
    expected = [
        [0, 1, INF, 11, 12],
        [1, 2, INF, 10, 11],
        [2, 3, INF, 9, 10],
        [3, 4, INF, 8, 9],
        [4, 5, 6, 7, 8],
    ]
    field = field_on(occupied, (0, 0), neighbourhood=4)
    field.converge()
    np.testing.assert_array_equal(field.distances(), np.array(expected, np.float32))
    # Ties go to the first move in the order up, right, down, left.
    assert field.path((0, 4)) == [(0, 4), (1, 4), (2, 4), (3, 4), (4, 4), (4, 3), (4, 2), (4, 1), (3, 1), (2, 1),
                                  (1, 1), (0, 1), (0, 0)]


def test_literal_two_synchronous_iterations():
    """Eq. 5 from the initial state: after two iterations only cells within two moves are finite."""
    field = field_on(np.zeros((5, 5), bool), (2, 2), neighbourhood=4)
    field.step(2)
    expected = [
        [INF, INF, 2, INF, INF],
        [INF, 2, 1, 2, INF],
        [2, 1, 0, 1, 2],
        [INF, 2, 1, 2, INF],
        [INF, INF, 2, INF, INF],
    ]
    np.testing.assert_array_equal(field.distances(), np.array(expected, np.float32))


def test_a_goal_moved_after_a_converge_cut_short_steps_and_then_converges_exactly():
    """A converge cut short by ``max_rounds`` leaves work pending; the goal then moves to a cell that cannot reach
    much of what the old goal reached (a map with 40 % obstacles). step() used to finish the old goal's pending work
    by settling, which raised the cells cut off from the new goal a step a round for ever (the cap inf): the process
    hung. The goal move drops that work now: the step returns, and a converge equals a fresh field's. Run in a
    process of its own, so that a hang fails the test instead of the suite."""
    script = (
        "import numpy as np, tdp\n"
        "occupied = np.random.default_rng(1).random((51, 16)) < 0.4\n"
        "occupied[36, 1] = occupied[15, 15] = False\n"
        "field = tdp.DistanceField(tdp.GridMap(occupied), (36, 1))\n"
        "field.converge(max_rounds=1)\n"
        "assert field.pending\n"
        "field.set_goal((15, 15))\n"
        "assert not field.pending\n"
        "field.step(1)\n"
        "field.converge()\n"
        "fresh = tdp.DistanceField(tdp.GridMap(occupied), (15, 15))\n"
        "fresh.converge()\n"
        "assert np.array_equal(field.distances(), fresh.distances())\n")
    done = subprocess.run([sys.executable, "-c", script], capture_output=True, text=True, timeout=240,
                          cwd=Path(__file__).resolve().parents[1])
    assert done.returncode == 0, done.stderr[-2000:]
