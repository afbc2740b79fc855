"""A focused repair (converge with a focus cell, as D* Lite's) stops early but gives the robot exactly what a full
converge gives: the same value at its cell and the same successor chain to the goal, tie-breaking included, through
random edits, goal moves and robot moves on every stencil; the work it leaves pending is done by later converges."""
import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from tdp.engine import TILE, Engine
from test_repair import apply, assert_equal_to_a_fresh_converge, launch_rounds

OPERATIONS = ["box", "free_box", "wall", "open_wall", "scatter", "goal", "robot", "robot", "step"]


@st.composite
def focus_sequences(draw):
    rows, cols = draw(st.integers(6, 48)), draw(st.integers(6, 48))
    density = draw(st.sampled_from([0.0, 0.1, 0.25, 0.35]))
    seed = draw(st.integers(0, 2**31))
    operations = draw(st.lists(st.sampled_from(OPERATIONS), min_size=1, max_size=8))
    return rows, cols, density, seed, operations


def route(engine: Engine, robot: tuple[int, int]) -> tuple[float, list[tuple[int, int]]]:
    """The value at ``robot`` and the successor chain from it (at most every cell of the map)."""
    value = float(engine.sample([robot])[0, 0])
    return value, engine.trace(0, robot, engine.occupied.size)


def repair_in_slices(engine: Engine, robot: tuple[int, int], sweeps: int) -> None:
    """converge(focus=robot), in slices of ``sweeps`` sweeps of tiles (0: one go) until it is through; a slice stops
    before the tile that would begin past its allowance, so its last tile may add up to 4 * TILE - 1 more."""
    engine.converge(focus=robot, max_sweeps=sweeps)
    while engine.cut_short():
        assert engine.swept() < sweeps + 4 * TILE
        engine.converge(focus=robot, max_sweeps=sweeps)


def assert_same_route(engine: Engine, robot: tuple[int, int], options: dict) -> None:
    fresh = Engine(engine.occupied, engine.goal, **options)
    fresh.converge()
    value, chain = route(engine, robot)
    fresh_value, fresh_chain = route(fresh, robot)
    assert value == fresh_value or (np.isinf(value) and np.isinf(fresh_value))
    assert chain == fresh_chain
    values = engine.sample(chain)[:, 0] if chain else np.zeros(0)
    np.testing.assert_array_equal(values, fresh.sample(chain)[:, 0] if chain else np.zeros(0))


@pytest.mark.parametrize("serially", [True, False])
@settings(max_examples=40, deadline=None,
          suppress_health_check=[HealthCheck.too_slow, HealthCheck.function_scoped_fixture])
@given(focus_sequences(), st.sampled_from([4, 8, 16]), st.booleans(), st.sampled_from([0, 1, 3]))
def test_focused_repair_gives_the_robot_the_route_of_a_full_converge(monkeypatch, serially, sequence, neighbourhood,
                                                                    corner_cutting, slice_sweeps):
    """... also when the repair runs in slices of ``slice_sweeps`` sweeps of tiles (0: in one go), as an anytime
    planner's budget cuts it, in the middle of raise waves and lowering rounds."""
    launch_rounds(monkeypatch, serially)
    rows, cols, density, seed, operations = sequence
    rng = np.random.default_rng(seed)
    occupied = rng.random((rows, cols)) < density
    goal = (int(rng.integers(rows)), int(rng.integers(cols)))
    occupied[goal] = False
    options = dict(neighbourhood=neighbourhood, corner_cutting=corner_cutting)
    engine = Engine(occupied, goal, **options)
    free = np.argwhere(~occupied)
    robot = tuple(int(v) for v in free[rng.integers(len(free))])
    repair_in_slices(engine, robot, slice_sweeps)
    assert_same_route(engine, robot, options)
    for operation in operations:
        if operation == "robot":
            robot = (int(rng.integers(rows)), int(rng.integers(cols)))
        else:
            apply(operation, engine, rng)
        repair_in_slices(engine, robot, slice_sweeps)
        assert_same_route(engine, robot, options)
    engine.converge()
    assert not engine.pending()
    assert_equal_to_a_fresh_converge(engine, options)


def test_a_change_behind_the_robot_is_left_pending():
    """A box far behind the robot (every value it changes is above the robot's) costs the robot nothing: the repair
    stops at once and leaves the region pending; a full converge then repairs it exactly."""
    occupied = np.zeros((64, 64), bool)
    engine = Engine(occupied, (32, 2))
    engine.converge()
    robot = (32, 20)
    box = np.array([(r, c) for r in range(30, 35) for c in range(50, 55)])
    engine.set_cells(box, np.ones(len(box), bool))
    rounds = engine.converge(focus=robot)
    assert engine.pending()
    assert_same_route(engine, robot, {})
    assert rounds <= 3
    engine.converge()
    assert not engine.pending()
    assert_equal_to_a_fresh_converge(engine, {})


def test_a_goal_move_settles_towards_the_robot_only():
    """After a goal move a focused converge searches from the new goal towards the robot, as A* does: the far side
    of the map stays at the cap."""
    engine = Engine(np.zeros((40, 200), bool), (20, 0))
    engine.converge()
    engine.set_goal((20, 100))
    engine.converge(focus=(20, 90))
    assert engine.pending()
    assert np.isinf(engine.goal_distances()[20, 199])
    assert_same_route(engine, (20, 90), {})


@pytest.mark.parametrize("neighbourhood", [8, 16])
def test_every_robot_cell_around_a_repair_gets_the_full_converges_route(neighbourhood):
    """The stop rule is tight near the repair: for every free cell of a cluttered map as the robot, after a box
    lands on the goal's main route and again after it is lifted, the focused repair's route is the full one's."""
    rng = np.random.default_rng(7)
    occupied = rng.random((72, 72)) < 0.2
    goal = (2, 3)
    occupied[goal] = False
    box = np.array([(r, c) for r in range(30, 34) for c in range(30, 34) if not occupied[r, c]])
    options = dict(neighbourhood=neighbourhood)
    for robot in map(tuple, np.argwhere(~occupied)[::11]):
        engine = Engine(occupied, goal, **options)
        engine.converge()
        for flag in (True, False):
            engine.set_cells(box, np.full(len(box), flag))
            engine.converge(focus=robot)
            assert_same_route(engine, robot, options)
