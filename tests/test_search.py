"""converge() from the initial state is a search cell by cell (ARCHITECTURE §7): it reaches the fixed point that
rounds of tiles reach, bit for bit, on every stencil, with and without a cap, on random maps and mazes; focused,
it gives the focus the full converge's route and hands its frontier over to the rounds of later converges."""
import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from reference import distances_to
from tdp import stencil
from tdp.engine import Engine
from tdp.random_worlds import maze
from test_focus import assert_same_route


def rounds_of_tiles(engine: Engine) -> np.ndarray:
    """The goal layer converged from the initial state in rounds of tiles (a round limit keeps it off the search)."""
    engine.reset()
    engine.converge(max_rounds=10**8)
    assert not engine.pending()
    return engine.goal_distances()


@settings(max_examples=60, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(st.integers(1, 40), st.integers(1, 40), st.sampled_from([0.0, 0.2, 0.4]), st.integers(0, 2**31),
       st.sampled_from([4, 8, 16]), st.booleans(), st.sampled_from([np.inf, 6.5, 23.0]))
def test_the_search_reaches_the_fixed_point_of_rounds_of_tiles_bit_for_bit(rows, cols, density, seed, neighbourhood,
                                                                          corner_cutting, cap):
    rng = np.random.default_rng(seed)
    occupied = rng.random((rows, cols)) < density
    goal = (int(rng.integers(rows)), int(rng.integers(cols)))  # perhaps on an obstacle: then nothing reaches it
    searched = Engine(occupied, goal, goal_cap=cap, neighbourhood=neighbourhood, corner_cutting=corner_cutting)
    rounds = searched.converge()
    assert rounds >= 0 and not searched.pending()
    np.testing.assert_array_equal(searched.goal_distances(), rounds_of_tiles(searched))


@pytest.mark.parametrize("corridor", [1, 2, 3])
@pytest.mark.parametrize("neighbourhood, corner_cutting", [(16, False), (8, False), (16, True)])
def test_the_search_on_mazes_equals_dijkstra(corridor, neighbourhood, corner_cutting):
    occupied = maze(61, corridor, seed=corridor)
    goal = (1, 1)
    engine = Engine(occupied, goal, neighbourhood=neighbourhood, corner_cutting=corner_cutting)
    engine.converge()
    reference = distances_to(occupied, goal, neighbourhood, corner_cutting)
    ours = engine.goal_distances()
    np.testing.assert_array_equal(np.isinf(ours), np.isinf(reference))
    finite = np.isfinite(reference)
    np.testing.assert_allclose(ours[finite], reference[finite], rtol=2e-6)
    np.testing.assert_array_equal(ours, rounds_of_tiles(engine))


@pytest.mark.parametrize("neighbourhood, corner_cutting", [(4, False), (8, False), (8, True), (16, False), (16, True)])
def test_the_moves_through_a_corner_are_the_moves_a_cell_with_its_corners_blocked_cannot_take(neighbourhood,
                                                                                             corner_cutting):
    """The search skips the moves ``through_corner`` names into a cell whose four diagonal neighbours are blocked (a
    one-cell corridor's): each is blocked there, and every other move open with the rest of its block free."""
    occupied = np.zeros((5, 5), bool)
    occupied[1::2, 1::2] = True  # the corners of the centre
    centre = (2, 2)
    for m in stencil.moves(neighbourhood, corner_cutting):
        start = (centre[0] - m.dr, centre[1] - m.dc)
        reaches = not occupied[start] and centre in [cell for cell, _ in stencil.legal_moves(occupied, start, (m,))]
        assert reaches != stencil.through_corner(m), m


@pytest.mark.parametrize("neighbourhood, corner_cutting", [(4, False), (8, False), (8, True), (16, False), (16, True)])
def test_the_moves_leaving_by_a_corner_are_the_moves_a_cell_with_its_corners_blocked_cannot_leave_by(neighbourhood,
                                                                                                    corner_cutting):
    """A mend's raise skips the moves ``leaves_by_corner`` names out of a cell whose four diagonal neighbours are
    blocked (``leaning``): each is blocked there, and every other move open with the rest of its block free."""
    occupied = np.zeros((5, 5), bool)
    occupied[1::2, 1::2] = True  # the corners of the centre
    centre = (2, 2)
    for m in stencil.moves(neighbourhood, corner_cutting):
        leaves = centre[0] + m.dr, centre[1] + m.dc
        open_ = leaves in [cell for cell, _ in stencil.legal_moves(occupied, centre, (m,))]
        assert open_ != stencil.leaves_by_corner(m), m


@pytest.mark.parametrize("occupied, goal, focus", [
    (np.zeros((100, 100), bool), (5, 5), (60, 60)),
    (maze(63, 1, seed=4), (1, 1), (61, 61)),
    (maze(64, 2, seed=5), (61, 61), (1, 1)),
])
def test_a_focused_search_gives_the_focus_its_route_and_leaves_later_rounds_nothing_due(occupied, goal, focus):
    """The frontier it hands over has nothing that can change the focus's route: a focused converge right after
    settles no tile; a full one then completes the layer to the search's fixed point."""
    engine = Engine(occupied, goal)
    engine.converge(focus=focus)
    assert_same_route(engine, focus, {})
    engine.converge(focus=focus)
    assert engine.swept() == 0
    engine.converge()
    assert not engine.pending()
    full = Engine(occupied, goal)
    full.converge()
    np.testing.assert_array_equal(engine.goal_distances(), full.goal_distances())


def test_a_focused_search_on_an_open_map_leaves_the_far_side_at_the_cap():
    engine = Engine(np.zeros((40, 200), bool), (20, 100))
    engine.converge(focus=(20, 90))
    assert engine.pending()
    assert np.isinf(engine.goal_distances()[20, 199])


def test_edits_between_reset_and_converge_are_searched_through():
    """Edits on a layer still in its initial state (a goal move, then cells) leave it to the search: the result is
    the fixed point of the edited map."""
    occupied = np.zeros((30, 30), bool)
    engine = Engine(occupied, (0, 0))
    engine.converge()
    engine.set_goal((29, 29))
    wall = np.array([(15, c) for c in range(29)])
    engine.set_cells(wall, np.ones(len(wall), bool))
    engine.set_cells(np.array([(29, 29)]), np.array([True]))
    engine.set_cells(np.array([(29, 29)]), np.array([False]))
    engine.converge()
    occupied[15, :29] = True
    fresh = Engine(occupied, (29, 29))
    np.testing.assert_array_equal(engine.goal_distances(), rounds_of_tiles(fresh))


def test_maze_is_a_perfect_maze_of_the_corridor_width():
    occupied = maze(41, corridor=1, seed=3)
    free = ~occupied
    assert occupied[0].all() and occupied[-1].all() and occupied[:, 0].all() and occupied[:, -1].all()
    edges = (free[1:, :] & free[:-1, :]).sum() + (free[:, 1:] & free[:, :-1]).sum()
    assert edges == free.sum() - 1  # connected (every cell reached below) and without a loop: a tree
    assert np.isfinite(distances_to(occupied, (1, 1), 4, False)[free]).all()
    wide = maze(41, corridor=3, seed=3)
    assert not wide[1:4, 1:4].any() and np.array_equal(maze(41, 3, seed=3), wide)


@pytest.mark.parametrize("loops", [0.1, 0.5, 1.0])
def test_a_braided_maze_has_a_loop_for_each_wall_knocked_through(loops):
    """``loops``: that share of the (n - 1)² walls a perfect maze of n x n rooms leaves between neighbours is knocked
    through, each an independent cycle of the corridors' graph (its edges less its cells plus one, a tree's 0); the
    maze stays connected and its border a wall, and a maze with no loops is the perfect one."""
    rooms = (41 - 1) // 2
    braided = maze(41, 1, seed=3, loops=loops)
    free = ~braided
    assert braided[0].all() and braided[-1].all() and braided[:, 0].all() and braided[:, -1].all()
    edges = (free[1:, :] & free[:-1, :]).sum() + (free[:, 1:] & free[:, :-1]).sum()
    assert edges - free.sum() + 1 == round(loops * (rooms - 1) ** 2)
    assert np.isfinite(distances_to(braided, (1, 1), 4, False)[free]).all()
    assert np.array_equal(maze(41, 1, seed=3, loops=0.0), maze(41, 1, seed=3))
    assert not (braided & ~maze(41, 1, seed=3)).any()  # walls knocked through, none added
    assert (~maze(41, 3, seed=3, loops=loops)).sum() > (~maze(41, 3, seed=3)).sum()


@pytest.mark.parametrize("kwargs, message", [(dict(size=2), "size"), (dict(size=10, corridor=0), "corridor"),
                                             (dict(size=4, corridor=3), "size"), (dict(size=9.5), "size"),
                                             (dict(size=2**31), "size must be at most 32764 cells"),
                                             (dict(size=9, corridor=True), "corridor must be an integer"),
                                             (dict(size=9, loops=-0.1), "loops"), (dict(size=9, loops=1.5), "loops"),
                                             (dict(size=9, loops=float("nan")), "loops"),
                                             (dict(size=9, loops="some"), "loops")])
def test_maze_rejects_bad_arguments(kwargs, message):
    with pytest.raises(ValueError, match=message):
        maze(**kwargs)
