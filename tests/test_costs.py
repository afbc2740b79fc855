"""Graded traversal costs (GridMap(cost=...)): the goal layer weighted by L x (cost[u] + cost[v]) / 2, checked against
scipy's Dijkstra on the weighted graph (tests/reference.py) for every stencil and corner rule, from scratch, after
random edits, focused and by synchronous iterations; a map whose costs are all 1 gives the binary map's values bit for
bit."""
import dataclasses
import warnings
from pathlib import Path

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from PIL import Image
from hypothesis import strategies as st

import tdp
from reference import assert_distances_match, distances_to

ROOT = Path(__file__).resolve().parents[1]
#: The costs' ranges: mild (1-1.5), a robot map's inflation gradient (1-10), extreme (1-250).
RANGES = [1.5, 10.0, 250.0]


@st.composite
def cost_maps(draw):
    """(occupied, cost, goal): a random map with random costs over one of RANGES."""
    rows, cols = draw(st.integers(3, 16)), draw(st.integers(3, 16))
    rng = np.random.default_rng(draw(st.integers(0, 2**31)))
    occupied = rng.random((rows, cols)) < draw(st.sampled_from([0.0, 0.15, 0.3]))
    top = draw(st.sampled_from(RANGES))
    cost = 1.0 + (top - 1.0) * rng.random((rows, cols)) ** draw(st.sampled_from([1.0, 4.0]))
    goal = (draw(st.integers(0, rows - 1)), draw(st.integers(0, cols - 1)))
    occupied[goal] = False
    return occupied, cost, goal


def reference(grid: tdp.GridMap, goal, neighbourhood: int, corner_cutting: bool) -> np.ndarray:
    return distances_to(grid.occupied, goal, neighbourhood, corner_cutting, cost=grid.cost)


def assert_equal_within_float32(ours: np.ndarray, expected: np.ndarray) -> None:
    assert_distances_match(ours, expected, rtol=1e-5)


@settings(max_examples=60, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(cost_maps(), st.sampled_from([4, 8, 16]), st.booleans())
def test_converged_weighted_field_equals_dijkstra_on_the_weighted_graph(case, neighbourhood, corner_cutting):
    occupied, cost, goal = case
    grid = tdp.GridMap(occupied, cost=cost)
    field = tdp.DistanceField(grid, goal, neighbourhood=neighbourhood, corner_cutting=corner_cutting)
    field.converge()
    assert_equal_within_float32(field.distances(), reference(grid, goal, neighbourhood, corner_cutting))


@settings(max_examples=30, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(cost_maps(), st.sampled_from([8, 16]), st.lists(st.tuples(st.integers(0, 15), st.integers(0, 15),
                                                                   st.booleans()), min_size=1, max_size=12))
def test_repairs_after_random_edits_equal_dijkstra_on_the_edited_map(case, neighbourhood, edits):
    occupied, cost, goal = case
    grid = tdp.GridMap(occupied, cost=cost)
    field = tdp.DistanceField(grid, goal, neighbourhood=neighbourhood)
    field.converge()
    now = occupied.copy()
    for row, col, blocked in edits:
        cell = (row % now.shape[0], col % now.shape[1])
        if cell == goal:
            continue
        field.set_occupied([cell], blocked)
        now[cell] = blocked
        field.converge()
        expected = distances_to(now, goal, neighbourhood, False, cost=grid.cost)
        assert_equal_within_float32(field.distances(), expected)


@settings(max_examples=40, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(cost_maps(), st.sampled_from([8, 16]), st.lists(
    st.tuples(st.integers(0, 15), st.integers(0, 15), st.integers(0, 4), st.sampled_from([1.0, 3.0, 40.0, 400.0])),
    min_size=1, max_size=10), st.booleans())
def test_repairs_after_random_cost_edits_equal_dijkstra_on_the_new_costs(case, neighbourhood, edits, batched):
    """Cost edits raise and lower costs in boxes of up to 3 x 3 (past the map's largest cost too), some on
    occupied cells (kept for when they are freed), mixed with occupancy edits; repaired after each edit, or after
    all of them at once."""
    occupied, cost, goal = case
    grid = tdp.GridMap(occupied, cost=cost)
    field = tdp.DistanceField(grid, goal, neighbourhood=neighbourhood)
    field.converge()
    now, costs = occupied.copy(), grid.cost.astype(np.float64)
    for row, col, side, value in edits:
        rows = slice(row % now.shape[0], row % now.shape[0] + max(side, 1))
        cols = slice(col % now.shape[1], col % now.shape[1] + max(side, 1))
        mask = np.zeros(now.shape, bool)
        mask[rows, cols] = True
        if side == 0:  # an occupancy flip of one cell instead
            cell = (row % now.shape[0], col % now.shape[1])
            if cell != goal:
                now[cell] = not now[cell]
                field.set_occupied([cell], bool(now[cell]))
        else:
            field.set_costs(mask, value)
            costs[mask] = value
        if not batched:
            field.converge()
            expected = distances_to(now, goal, neighbourhood, False, cost=np.where(now, 1.0, costs))
            assert_equal_within_float32(field.distances(), expected)
    field.converge()
    assert_equal_within_float32(field.distances(), distances_to(now, goal, neighbourhood, False,
                                                                cost=np.where(now, 1.0, costs)))


def dear_corridor() -> tdp.GridMap:
    """A hall (goal side, left) joined to a room (right) by a corridor of cells costing 1e6: the room's distances pass
    2**24, where float32 rounds a move of 1 back to the value it is added to."""
    occupied, cost = np.zeros((40, 90), bool), np.ones((40, 90))
    occupied[:, 40:60] = True
    occupied[20, 40:60] = False
    cost[20, 40:60] = 1e6
    return tdp.GridMap(occupied, cost=cost)


@pytest.mark.parametrize("neighbourhood", [4, 8, 16])
def test_distances_past_float32s_whole_numbers_still_fall_along_every_route(neighbourhood):
    """Each move adds at least one float32 step (ARCHITECTURE §4): a route from every cell of the room reaches the
    goal, its values falling at each step (before, the room's cells took equal values and their successors led round
    in rings: no route from any), and iterations from the initial state reach the converge's values bit for bit."""
    grid, goal = dear_corridor(), (20, 5)
    field = tdp.DistanceField(grid, goal, neighbourhood=neighbourhood)
    field.converge()
    distances = field.distances()
    assert distances[:, 60:].min() > 2**24
    assert_distances_match(distances, reference(grid, goal, neighbourhood, False), rtol=1e-5)
    for start in [(0, 89), (39, 60), (20, 75), (5, 61)]:
        path = field.path(start)
        values = [distances[cell] for cell in path]
        assert path[-1] == goal and all(a > b for a, b in zip(values, values[1:]))
    iterated = tdp.DistanceField(grid, goal, neighbourhood=neighbourhood)
    while iterated.step(1):
        pass
    np.testing.assert_array_equal(iterated.distances(), distances)


@pytest.mark.parametrize("before", ["nothing", "iterations", "a focused converge"])
def test_a_room_past_float32s_whole_numbers_cut_off_rises_to_inf(before):
    """The corridor closed: the room's cells rise to inf by a mend (at the fixed point), or by rounds of tiles (after
    iterations or a focused converge left work pending); before, two cells of equal value held each other up."""
    grid, goal = dear_corridor(), (20, 5)
    field = tdp.DistanceField(grid, goal)
    field.converge()
    field.set_occupied([(20, 50)])
    if before == "iterations":
        field.step(2)
    elif before == "a focused converge":
        field.converge(focus=(20, 30))
    field.converge()
    assert np.isinf(field.distances()[:, 50:]).all()
    fresh = tdp.DistanceField(tdp.GridMap(field.occupied, cost=grid.cost), goal)
    fresh.converge()
    np.testing.assert_array_equal(field.distances(), fresh.distances())


def test_a_map_whose_costs_rise_past_float32s_whole_numbers_takes_the_kernels_for_them():
    """Costs of 1 everywhere at first (the plain kernels: no distance can reach 2**24), then the corridor's set to
    1e6: the field's values and routes are a fresh converge's, and closing the corridor sends the room to inf."""
    dear, goal = dear_corridor(), (20, 5)
    field = tdp.DistanceField(tdp.GridMap(dear.occupied, cost=np.ones(dear.shape)), goal)
    field.converge()
    corridor = dear.cost > 1
    field.set_costs(corridor, 1e6)
    field.converge()
    fresh = tdp.DistanceField(dear, goal)
    fresh.converge()
    np.testing.assert_array_equal(field.distances(), fresh.distances())
    assert field.path((0, 89))[-1] == goal
    field.set_occupied([(20, 50)])
    field.converge()
    assert np.isinf(field.distances()[:, 50:]).all()


def test_distances_past_int32s_largest_keep_dials_order_through_cuts_and_reopenings():
    """A corridor of 2,300 cells costing 1e6: distances reach 2.3e9, past int32's largest (2**31), where a search's
    bucket (a whole number of distance) had no int32 - a cell went into the bucket being emptied, and a repair that
    closed the corridor or opened it again ran on without end. From 2**30 on such a layer's buckets are one float32
    step wide: the converge matches scipy's Dijkstra, the cut-off part rises to inf, reopening restores the field bit
    for bit, and a focused converge agrees at its focus."""
    occupied, cost = np.zeros((1, 2300), bool), np.full((1, 2300), 1e6)
    cost[0, :3] = 1.0
    grid, goal, far = tdp.GridMap(occupied, cost=cost), (0, 0), (0, 2299)
    field = tdp.DistanceField(grid, goal, neighbourhood=4)
    field.converge()
    distances = field.distances().copy()
    assert distances[far] > 2**31
    # float32 rounds each sum to a multiple of 128-256 here: 2,300 of them drift 3.4e-5 from float64's
    assert_distances_match(distances, reference(grid, goal, 4, False), rtol=1e-4)
    path = field.path(far)
    assert path[-1] == goal and all(distances[a] > distances[b] for a, b in zip(path, path[1:]))
    for cut in [(0, 2000), (0, 900)]:  # beyond 2**31 and below 2**30
        field.set_occupied([cut])
        field.converge()
        assert np.isinf(field.distances()[0, cut[1]:]).all()
        np.testing.assert_array_equal(field.distances()[0, :cut[1]], distances[0, :cut[1]])
        field.set_occupied([cut], False)
        field.converge()
        np.testing.assert_array_equal(field.distances(), distances)
    focused = tdp.DistanceField(grid, goal, neighbourhood=4)
    focused.converge(focus=far)
    assert focused.distances()[far] == distances[far]


def test_cost_edits_need_a_map_with_costs_and_costs_from_1_to_max_cost():
    field = tdp.DistanceField(tdp.GridMap(np.zeros((5, 5), bool)), (0, 0))
    with pytest.raises(ValueError, match="binary"):
        field.set_costs([(1, 1)], 2.0)
    costed = tdp.DistanceField(tdp.GridMap(np.zeros((5, 5), bool), cost=np.ones((5, 5))), (0, 0))
    for bad in (0.5, float("nan"), float("inf"), 2e6):
        with pytest.raises(ValueError, match="costs must be between 1 and"):
            costed.set_costs([(1, 1)], bad)
    with pytest.raises(ValueError, match="set_costs"):
        costed.set_costs([(9, 9)], 2.0)
    # numpy reads "2" and True as costs
    for bad in ([2.0, 3.0], "dear", [[2.0]] * 3, "2", True, [True], None, [[2.0], [3.0, 4.0]]):
        with pytest.raises(ValueError, match="costs must be"):
            costed.set_costs([(1, 1)], bad)
    with pytest.raises(ValueError, match="trinary_costmap must be True or False"):
        tdp.load_map(ROOT / "tests" / "data" / "arena.map", trinary_costmap="no")


@settings(max_examples=25, deadline=None)
@given(cost_maps(), st.sampled_from([4, 8, 16]))
def test_synchronous_iterations_reach_the_weighted_fixed_point_bit_for_bit(case, neighbourhood):
    occupied, cost, goal = case
    grid = tdp.GridMap(occupied, cost=cost)
    converged = tdp.DistanceField(grid, goal, neighbourhood=neighbourhood)
    converged.converge()
    iterated = tdp.DistanceField(grid, goal, neighbourhood=neighbourhood)
    iterated.step(occupied.size + 1)
    np.testing.assert_array_equal(iterated.distances(), converged.distances())


@settings(max_examples=25, deadline=None)
@given(cost_maps(), st.sampled_from([8, 16]), st.integers(0, 2**31))
def test_a_focused_converge_gives_the_focus_its_exact_weighted_distance_and_route(case, neighbourhood, seed):
    occupied, cost, goal = case
    grid = tdp.GridMap(occupied, cost=cost)
    free = np.argwhere(~occupied)
    focus = tuple(int(v) for v in free[np.random.default_rng(seed).integers(len(free))])
    field = tdp.DistanceField(grid, goal, neighbourhood=neighbourhood)
    field.converge(focus=focus)
    full = tdp.DistanceField(grid, goal, neighbourhood=neighbourhood)
    full.converge()
    assert field.distance(focus) == full.distance(focus)
    assert field.path(focus) == full.path(focus)


def test_costs_of_one_give_the_binary_values_bit_for_bit():
    rng = np.random.default_rng(5)
    occupied = rng.random((40, 50)) < 0.25
    occupied[20, 25] = False
    binary = tdp.DistanceField(tdp.GridMap(occupied), (20, 25))
    ones = tdp.DistanceField(tdp.GridMap(occupied, cost=np.ones(occupied.shape)), (20, 25))
    binary.converge()
    ones.converge()
    np.testing.assert_array_equal(ones.distances(), binary.distances())


def test_a_path_on_a_cost_map_keeps_to_cheap_ground_and_its_cost_is_the_distance():
    occupied = np.zeros((21, 21), bool)
    cost = np.ones((21, 21))
    cost[8:13, 3:18] = 20.0  # an expensive band across the straight line from (10, 0) to (10, 20)
    grid = tdp.GridMap(occupied, cost=cost)
    field = tdp.DistanceField(grid, (10, 20))
    field.converge()
    path = field.path((10, 0))
    assert max(grid.cost[cell] for cell in path) < 20.0  # round the band, not through it
    paid = sum(np.hypot(b[0] - a[0], b[1] - a[1]) * (grid.cost[a] + grid.cost[b]) / 2 for a, b in zip(path, path[1:]))
    assert paid == pytest.approx(field.distance((10, 0)), rel=1e-5)


def test_the_exact_planner_drives_the_cheapest_route_on_a_cost_map():
    occupied = np.zeros((21, 21), bool)
    cost = np.ones((21, 21))
    cost[8:13, 3:18] = 20.0
    grid = tdp.GridMap(occupied, cost=cost)
    planner = tdp.ExactPlanner(grid, (10, 0), (10, 20))
    planner.setup()
    robot, paid = (10, 0), 0.0
    for _ in range(100):
        step = planner.tick().next_cell
        if step is None:
            break
        paid += np.hypot(step[0] - robot[0], step[1] - robot[1]) * (grid.cost[robot] + grid.cost[step]) / 2
        robot = step
        planner.move_robot(robot)
    assert robot == (10, 20)
    expected = reference(grid, (10, 20), 16, False)[10, 0]
    assert paid == pytest.approx(expected, rel=1e-5)


@pytest.mark.parametrize("cost, message", [
    (np.ones((4, 4)), "shape"),
    (np.ones((4, 5), int), "float numpy array of traversal costs .* got int64; a nav2 costmap's 0-255 values: "
                           "tdp.costmap_grid"),
    ([[1.0] * 5] * 4, "float"),
    (np.full((4, 5), 0.5), "below 1"),
    (np.full((4, 5), np.nan), "NaN"),
    (np.full((4, 5), np.inf), "infinite"),
])
def test_a_bad_cost_array_is_a_clear_value_error(cost, message):
    with pytest.raises(ValueError, match=message):
        tdp.GridMap(np.zeros((4, 5), bool), cost=cost)


def test_half_precision_costs_are_checked_without_a_warning():
    """The check compared float16 costs with MAX_COST cast to float16 (inf): numpy warned of an overflow."""
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        grid = tdp.GridMap(np.zeros((4, 5), bool), cost=np.full((4, 5), 3.0, np.float16))
    assert grid.cost.dtype == np.float32 and (grid.cost == 3.0).all()


def test_costs_on_obstacles_are_ignored_and_inflating_keeps_the_costs():
    occupied = np.zeros((5, 5), bool)
    occupied[2, 2] = True
    cost = np.full((5, 5), 2.0)
    cost[2, 2] = np.nan  # on an obstacle: ignored
    grid = tdp.GridMap(occupied, cost=cost)
    assert grid.cost[2, 2] == 1.0 and grid.cost[0, 0] == 2.0
    inflated = grid.inflate(1)
    free = ~inflated.occupied
    assert np.array_equal(inflated.cost[free], grid.cost[free]) and (inflated.cost[~free] == 1).all()


@pytest.mark.parametrize("planner", ["plain-dp", "accelerating"])
def test_the_navigators_goal_layer_plans_on_costs(planner):
    occupied = np.zeros((21, 21), bool)
    cost = np.ones((21, 21))
    cost[8:13, 3:18] = 20.0
    grid = tdp.GridMap(occupied, cost=cost)
    navigator = tdp.Navigator(grid, (10, 0), (10, 20), tdp.NavigatorConfig(planner=planner, updates_per_move=50))
    navigator.setup()
    assert max(grid.cost[cell] for cell in navigator.current_path()) < 20.0


def test_a_chains_move_costs_are_lengths_on_a_binary_map_and_weighted_by_the_cells_costs_otherwise():
    chain = [(0, 0), (0, 1), (1, 2), (3, 3)]
    cost = np.array([[1.0, 3.0, 1.0, 1.0], [1.0, 1.0, 5.0, 1.0], [1.0] * 4, [1.0, 1.0, 1.0, 2.0]])
    lengths, costs = tdp.stencil.chain_moves(chain)
    assert lengths == pytest.approx([1.0, np.sqrt(2), np.sqrt(5)]) and costs == pytest.approx(lengths)
    lengths, costs = tdp.stencil.chain_moves(chain, cost)
    assert lengths == pytest.approx([1.0, np.sqrt(2), np.sqrt(5)])
    assert costs == pytest.approx([2.0, 4 * np.sqrt(2), 3.5 * np.sqrt(5)])


def test_accelerating_nodes_detect_back_up_and_reach_on_a_costed_world_with_the_other_planners():
    world = tdp.random_worlds.make_world("rooms", 100, seed=0)
    costed = dataclasses.replace(world, grid=world.grid.inflate(0, cost_scaling_factor=3.0, inflation_radius=0.8))
    episodes = {planner: tdp.simulate(costed, tdp.NavigatorConfig(planner=planner))
                for planner in ("exact", "plain-dp", "accelerating")}
    for episode in episodes.values():
        assert episode.reached and episode.collisions == 0
    accelerating = episodes["accelerating"]
    assert accelerating.detections and accelerating.backups  # the node layers' rules ran on the costed map


def test_nav2_inflation_costs_decay_from_the_inscribed_radius_as_nav2_computes_them():
    occupied = np.zeros((9, 9), bool)
    occupied[4, 4] = True
    grid = tdp.GridMap(occupied, resolution=0.1).inflate(1, cost_scaling_factor=10.0, inflation_radius=0.3)
    assert grid.occupied.sum() == 5  # the obstacle and its four neighbours within 1 cell
    for cell, metres in (((3, 3), 0.1 * np.sqrt(2)), ((2, 4), 0.2), ((2, 2), 0.2 * np.sqrt(2))):
        nav2 = 252 * np.exp(-10.0 * (metres - 0.1))  # nav2's inflation layer, then NavFn's 1 + 0.8 c / 50
        assert grid.cost[cell] == pytest.approx(1 + 0.8 * nav2 / 50, rel=1e-6)
    assert grid.cost[1, 4] == 1.0 and grid.cost[0, 0] == 1.0  # beyond the inflation radius (0.3 m)
    with pytest.raises(ValueError, match="together"):
        tdp.GridMap(occupied).inflate(1, cost_scaling_factor=3.0)


def test_a_nav2_costmap_converts_lethal_inscribed_and_unknown_to_obstacles_and_the_rest_to_costs():
    costmap = np.array([[0, 100, 252], [253, 254, 255]], np.uint8)
    grid = tdp.costmap_grid(costmap, resolution=0.05)
    assert grid.occupied.tolist() == [[False, False, False], [True, True, True]]
    assert grid.cost[0].tolist() == pytest.approx([1.0, 1 + 0.8 * 100 / 50, 1 + 0.8 * 252 / 50])
    assert not tdp.costmap_grid(costmap, unknown_is_free=True).occupied[1, 2]
    for bad in (np.array([[0.5]]), np.array([[300]]), np.zeros(3, np.uint8)):
        with pytest.raises(ValueError, match="costmap"):
            tdp.costmap_grid(bad)


def costed_world(tmp_path, extra: str = "inflation_radius: 0.6"):
    """The TurtleBot3 world of examples/ with nav2's inflation costs in its map entry."""
    text = (ROOT / "examples" / "turtlebot3-world.yaml").read_text()
    map_line = "map: ../tdp/maps/turtlebot3_world/map.yaml"
    path = tmp_path / "costed.yaml"
    path.write_text(text.replace(map_line, f"map: {{file: {ROOT / 'tdp/maps/turtlebot3_world/map.yaml'}, "
                                           f"cost_scaling_factor: 3.0, {extra}}}"))
    return path


@pytest.mark.parametrize("planner", ["exact", "plain-dp", "accelerating"])
def test_a_world_file_with_inflation_costs_plans_on_them_at_grid_level_and_in_pybullet(tmp_path, planner):
    from sim.episode import run_episode

    world = tdp.load_world(costed_world(tmp_path))
    assert world.grid.cost is not None and world.grid.cost.max() > 1
    episode = tdp.simulate(world, tdp.NavigatorConfig(planner=planner))
    assert episode.reached and episode.collisions == 0
    metrics = run_episode(world, tdp.NavigatorConfig(planner=planner))
    assert metrics["reached"] and metrics["contacts"] == 0


def test_a_world_file_with_only_half_of_the_inflation_parameters_is_refused(tmp_path):
    with pytest.raises(ValueError, match="go together"):
        tdp.load_world(costed_world(tmp_path, extra="threshold: 0.5"))


def test_a_world_file_reads_a_scale_maps_graded_values_as_costs_with_trinary_costmap_false(tmp_path):
    shade = np.full((20, 30), 255, np.uint8)
    shade[5:15, 10:20] = 180  # occupancy 1 - 180/255 = 0.29: graded in scale mode
    Image.fromarray(shade).save(tmp_path / "m.png")
    (tmp_path / "m.yaml").write_text("image: m.png\nresolution: 0.1\norigin: [0, 0, 0]\nmode: scale\n"
                                     "occupied_thresh: 0.65\nfree_thresh: 0.196\n")
    entry = "map: {file: m.yaml, trinary_costmap: %s}\nstart: [10, 2]\ngoal: [10, 27]\n"
    (tmp_path / "w.yaml").write_text(entry % "false")
    world = tdp.load_world(tmp_path / "w.yaml")
    assert not world.grid.occupied.any() and world.grid.cost[10, 15] > 1 and world.grid.cost[0, 0] == 1
    episode = tdp.simulate(world, tdp.NavigatorConfig())
    assert episode.reached and all(world.grid.cost[cell] == 1 for cell in episode.trajectory)  # round the patch
    (tmp_path / "w.yaml").write_text(entry % "1")
    with pytest.raises(ValueError, match="trinary_costmap"):
        tdp.load_world(tmp_path / "w.yaml")


def test_figures_shade_the_costs_above_open_ground_and_binary_maps_draw_as_before():
    from tdp.plot import draw_map, pyplot

    occupied = np.zeros((4, 5), bool)
    occupied[0, 0] = True
    cost = np.ones((4, 5))
    cost[2, 1:4] = [2.0, 3.0, 5.0]
    _, ax = pyplot().subplots()
    shading = draw_map(ax, occupied, tdp.GridMap(occupied, cost=cost).cost)
    assert shading.get_clim() == (1, 5.0)
    shown = shading.get_array()
    assert shown.mask.sum() == 17 and shown[2, 1:4].tolist() == [2.0, 3.0, 5.0]  # open ground and the wall clear
    assert draw_map(ax, occupied) is None
    pyplot().close("all")
