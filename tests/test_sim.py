"""PyBullet layer in DIRECT mode: wheel kinematics, rasterising, and every scenario end to end."""
import json
import math
import subprocess
import sys
import warnings
from types import SimpleNamespace

import numpy as np
import pybullet as p
import pytest

import tdp
from sim.__main__ import main as sim_command
from sim.episode import (CLEARANCE_M, SimConfig, connect, episode_ticks, margin_floor_m, run_episode,
                         steering_cells)
from sim.render import oracle_text
from sim.robot import DiffDriveRobot, wheel_speeds
from sim.world import SHAPES_PER_BODY, WALL_TILE_CELLS, SimWorld, box_cells, wall_groups
from tdp.contract import Mode, WorldFeed
from tdp.grid import rectangles
from tdp.random_worlds import boxes_on_map


@pytest.fixture
def client():
    client = connect(gui=False)
    p.setTimeStep(1 / 240, physicsClientId=client)
    floor = p.createCollisionShape(p.GEOM_PLANE, physicsClientId=client)
    p.createMultiBody(0, floor, physicsClientId=client)
    yield client
    p.disconnect(physicsClientId=client)


def drive(client, robot, v, w, seconds):
    robot.command(v, w)
    for _ in range(int(seconds * 240)):
        p.stepSimulation(physicsClientId=client)


@pytest.mark.parametrize("v, w", [(0.3, 0.0), (0.0, 1.5), (0.2, 0.8), (-0.2, 0.0)])
def test_commanded_wheel_speeds_give_the_expected_body_motion(client, v, w):
    robot = DiffDriveRobot(client, 0.0, 0.0, 0.3)
    drive(client, robot, v, w, 1.0)  # settle
    x0, y0, yaw0 = robot.pose()
    drive(client, robot, v, w, 1.0)
    x1, y1, yaw1 = robot.pose()
    measured_w = math.atan2(math.sin(yaw1 - yaw0), math.cos(yaw1 - yaw0))
    assert measured_w == pytest.approx(w, abs=0.08 * max(1.0, abs(w)))
    chord = math.hypot(x1 - x0, y1 - y0)
    expected_chord = abs(v) if w == 0 else abs(2 * v / w * math.sin(w / 2))
    assert chord == pytest.approx(expected_chord, abs=0.03)
    assert robot.velocity()[0] == pytest.approx(v, abs=0.03)


def test_wheel_speed_formula():
    left, right = wheel_speeds(0.5, 0.0)
    assert left == right == pytest.approx(10.0)  # 0.5 m/s on 0.05 m wheels
    left, right = wheel_speeds(0.0, 1.0)
    assert right == -left == pytest.approx(0.12 / 0.05)


def test_a_robot_left_alone_stays_put(client):
    robot = DiffDriveRobot(client, 1.0, 2.0, 0.0)
    drive(client, robot, 0.0, 0.0, 2.0)
    x, y, yaw = robot.pose()
    assert math.hypot(x - 1.0, y - 2.0) < 0.005 and abs(yaw) < 0.01


def test_box_rasterises_to_the_expected_cells_with_inflation():
    grid = tdp.GridMap(np.zeros((10, 10), bool), resolution=0.1)  # cell (r, c) centre: ((c + .5)/10, (9.5 - r)/10)
    cells = box_cells(grid, (0.30, 0.30, 0.50, 0.40), 0.0)
    assert sorted(map(tuple, np.argwhere(cells))) == [(6, 3), (6, 4)]  # centres (0.35, 0.35), (0.45, 0.35)
    inflated = box_cells(grid, (0.30, 0.30, 0.50, 0.40), 0.1)
    expected = set()
    for r in range(10):
        for c in range(10):
            x, y = (c + 0.5) / 10, (9.5 - r) / 10
            dx, dy = max(0.30 - x, 0, x - 0.50), max(0.30 - y, 0, y - 0.40)
            if dx * dx + dy * dy <= 0.01 + 1e-12:
                expected.add((r, c))
    assert set(map(tuple, np.argwhere(inflated))) == expected
    assert len(expected) == 12


def test_moving_box_footprint_comes_from_its_body(client):
    grid = tdp.GridMap(np.zeros((20, 20), bool))
    box = tdp.Obstacle(box=(4, 6, 7, 10), waypoints=[(4, 16)], speed=1.0)
    scenario = tdp.Scenario(grid, (19, 0), (19, 19), obstacles=[box])
    world = SimWorld(client, scenario, cell_m=0.1, tick_s=0.5)
    np.testing.assert_array_equal(world.moving_footprints(0.0, 0.0), scenario.occupancy(0))
    world.update(2.0)  # 4 ticks at 1 cell per tick
    np.testing.assert_array_equal(world.moving_footprints(0.0, 2.0), scenario.occupancy(4))
    world.update(2.5)  # measured 0.2 m/s to the right: swept 0.5 s ahead covers one more tick's cells
    np.testing.assert_array_equal(world.moving_footprints(0.0, 2.5, horizon_s=0.5),
                                  scenario.occupancy(5) | scenario.occupancy(6))


def test_a_box_appearing_after_another_vanished_is_not_swept_from_where_the_other_was(client):
    """PyBullet gives a new body the id of one removed; the velocity of a box that appeared was measured from the
    last pose of the box that had vanished under that id, and its sweep crossed the map towards it."""
    grid = tdp.GridMap(np.zeros((40, 40), bool))
    gone = tdp.Obstacle(box=(2, 2, 5, 5), vanish_at=2)
    late = tdp.Obstacle(box=(30, 30, 33, 33), appear_at=4)
    scenario = tdp.Scenario(grid, (39, 0), (0, 39), obstacles=[gone, late])
    world = SimWorld(client, scenario, cell_m=0.1, tick_s=0.5)
    for tick in range(6):
        world.update(tick * 0.5)
        swept = world.moving_footprints(0.0, tick * 0.5, horizon_s=2.0)
        np.testing.assert_array_equal(swept, scenario.occupancy(tick))


@pytest.mark.parametrize("seed", range(5))
def test_rectangles_cover_exactly_the_occupied_cells(seed):
    occupied = np.random.default_rng(seed).random((15, 17)) < 0.4
    cover = np.zeros_like(occupied, dtype=int)
    for r0, c0, r1, c1 in rectangles(occupied):
        cover[r0:r1, c0:c1] += 1
    np.testing.assert_array_equal(cover, occupied.astype(int))


def test_an_episode_on_a_coarse_map_lasts_as_long_as_the_robot_needs_to_cross_it():
    fine = tdp.Scenario(tdp.GridMap(np.zeros((30, 50), bool), resolution=0.1), (0, 0), (29, 49))
    coarse = tdp.Scenario(tdp.GridMap(np.zeros((30, 50), bool), resolution=1.0), (0, 0), (29, 49))
    assert episode_ticks(fine, SimConfig()) == fine.tick_limit == 320  # 0.5 m/s x 0.2 s: a cell a tick
    assert episode_ticks(coarse, SimConfig()) == 3200  # a tenth of a cell a tick
    assert episode_ticks(coarse, SimConfig(max_speed=1.0)) == 1600
    assert episode_ticks(fine, SimConfig(max_speed=2.0)) == 320  # never below the grid's limit
    bounded = tdp.Scenario(coarse.grid, (0, 0), (29, 49), max_ticks=77)
    assert episode_ticks(bounded, SimConfig()) == 77  # the world's own limit stands


@pytest.mark.parametrize("resolution", [0.05, 0.1, 1.0])
def test_a_quick_worlds_tick_is_the_time_the_robot_takes_to_cross_a_cell(resolution):
    """So its boxes (0.3-0.6 cells a tick) move at a third to a half of the robot's 0.5 m/s on any map: at 0.2 s
    ticks on a MovingAI map's 1 m cells they moved at 1.5-3 m/s and rammed it (RESULTS, "Planner in PyBullet")."""
    world = boxes_on_map(tdp.GridMap(np.zeros((40, 40), bool), resolution), (1, 1), (38, 38), boxes=3)
    assert world.tick_s == pytest.approx(2 * resolution)
    assert episode_ticks(world, SimConfig()) == world.tick_limit  # a cell a tick: nothing to stretch
    speeds = [box.speed * resolution / world.tick_s for box in world.obstacles]
    assert speeds and all(0.15 - 1e-9 <= v <= 0.3 + 1e-9 for v in speeds)  # metres a second


def test_a_tick_shorter_than_a_physics_step_is_refused():
    """A tick of 1 ms ran no physics step at 240 Hz: the robot stood still for 48,000 ticks and the run said only
    that it had not arrived."""
    world = tdp.Scenario(tdp.GridMap(np.zeros((30, 30), bool), resolution=0.1), (2, 2), (2, 27), tick_s=0.001)
    with pytest.raises(ValueError, match=r"the world's tick, 0.001 s, is shorter than half a physics step"):
        run_episode(world, tdp.NavigatorConfig())


def test_a_robot_that_did_not_reach_the_goal_has_no_ratio_where_the_oracle_did():
    """Ticks of 0.05 s: the robot crosses a quarter of a cell a tick, the grid's oracle a cell; in 40 ticks the
    oracle arrives and the robot is a third of the way. Its ratio was its path so far over the oracle's, 0.4."""
    world = tdp.Scenario(tdp.GridMap(np.zeros((30, 30), bool), resolution=0.1), (2, 2), (2, 27), max_ticks=40,
                         tick_s=0.05)
    metrics = run_episode(world, tdp.NavigatorConfig())
    assert not metrics["reached"] and metrics["oracle_reached"] and metrics["oracle_length_m"] > 2.0
    assert 0 < metrics["path_length_m"] < 1.5 and metrics["ratio"] is None


def test_an_episode_whose_limit_runs_out_says_so_and_the_margins_flag(tmp_path, capsys):
    world = tdp.Scenario(tdp.GridMap(np.zeros((30, 30), bool), resolution=0.1), (2, 2), (27, 27), max_ticks=3)
    (tmp_path / "short.yaml").write_text(world.to_yaml())
    assert sim_command(["run", "--world", str(tmp_path / "short.yaml"), "--out", str(tmp_path)]) == 0
    assert ("reached False (the episode's limit, 3 ticks, ran out; a world file's max_ticks or max_s, or tdp run's "
            "--max-ticks, sets it) in 0.6 s") in capsys.readouterr().out
    metrics = json.loads((tmp_path / "metrics.json").read_text())
    assert metrics["ticks"] == metrics["max_ticks"] == 3 and not metrics["reached"]
    with pytest.warns(UserWarning, match=r"--margin 0.708 on the command line"):  # 1 m cells: the flag it names
        sim_command(["run", "--map", "tests/data/arena.map", "--start", "1", "3", "--goal", "5", "5", "--boxes", "0",
                     "--margin", "0.5", "--out", str(tmp_path)])
    assert sim_command(["run", "--map", "tests/data/arena.map", "--start", "1", "3", "--goal", "5", "5", "--boxes",
                        "0", "--margin", "0.708", "--out", str(tmp_path)]) == 0
    assert json.loads((tmp_path / "metrics.json").read_text())["contacts"] == 0


def test_wall_groups_hold_each_rectangle_once_at_most_sixteen_a_body_within_a_tile():
    boxes = rectangles(np.random.default_rng(0).random((70, 90)) < 0.3)
    groups = wall_groups(boxes)
    assert sorted(box for group in groups for box in group) == sorted(boxes)
    assert max(len(group) for group in groups) == SHAPES_PER_BODY  # some tiles hold more than one body's worth
    for group in groups:
        assert len({(r0 // WALL_TILE_CELLS, c0 // WALL_TILE_CELLS) for r0, c0, _, _ in group}) == 1


def test_every_wall_is_solid_and_found_near_where_it_stands(client):
    """The map's wall rectangles, many to a PyBullet body: a probe at each rectangle's centre touches a wall (a
    body holds only the first 16 shapes it is given: the rest would be silently missing), and the walls
    ``obstacles_near`` finds round a probe include every one within CLEARANCE_M of it."""
    occupied = np.random.default_rng(1).random((60, 70)) < 0.25
    world = SimWorld(client, tdp.Scenario(tdp.GridMap(occupied), (0, 0), (1, 1)), cell_m=0.1, tick_s=0.2)
    assert len(world.static_bodies) < len(rectangles(occupied))
    probe = p.createMultiBody(1, p.createCollisionShape(p.GEOM_SPHERE, radius=0.02, physicsClientId=client), -1,
                              (0, 0, 0.1), physicsClientId=client)
    for r0, c0, r1, c1 in rectangles(occupied):
        centre = (0.1 * (c0 + c1) / 2, 0.1 * (60 - (r0 + r1) / 2), 0.1)
        p.resetBasePositionAndOrientation(probe, centre, (0, 0, 0, 1), physicsClientId=client)
        p.performCollisionDetection(physicsClientId=client)
        distances = [point[8] for body in world.static_bodies
                     for point in p.getClosestPoints(probe, body, 0.05, physicsClientId=client)]
        assert distances and min(distances) < 0, (r0, c0, r1, c1)
        low, high = p.getAABB(probe, physicsClientId=client)
        near = set(world.obstacles_near(tuple(np.subtract(low, CLEARANCE_M)), tuple(np.add(high, CLEARANCE_M))))
        within = {body for body in world.static_bodies
                  if p.getClosestPoints(probe, body, CLEARANCE_M, physicsClientId=client)}
        assert within <= near


@pytest.mark.parametrize("name", tdp.scenarios.names())
def test_every_scenario_reaches_the_goal_in_pybullet_without_contact(name):
    metrics = run_episode(tdp.scenarios.get(name))
    assert metrics["reached"]
    assert metrics["contacts"] == 0
    assert metrics["min_clearance_m"] > 0
    assert metrics["time_s"] <= tdp.scenarios.get(name).max_ticks * tdp.scenarios.get(name).tick_s
    assert 0.8 < metrics["ratio"] < 1.3


def test_a_run_that_starts_at_its_goal_has_one_picture():
    """No tick, so no picture: compare --animate ended in an IndexError from the animation's first frame."""
    frames = []
    grid = tdp.GridMap(np.zeros((30, 30), bool), resolution=0.1)
    metrics = run_episode(tdp.Scenario(grid, (5, 5), (5, 5)), frames=frames)
    assert metrics["ticks"] == 0 and metrics["reached"] and len(frames) == 1 and frames[0].std() > 10


def test_a_coarse_map_keeps_the_episodes_metrics_where_its_oracle_has_no_room():
    """On a map of 1 m cells the run grows obstacles by 0.25 m, which leaves a cell beside a wall or a box free; the
    oracle grew them by whole cells, found the start on an obstacle and raised a ValueError once the robot had driven
    the whole episode, its metrics lost. The oracle now grows the walls by the run's margin (here: it has room) and
    the boxes by whole cells (here: a box beside the goal leaves it none: no oracle, the metrics kept)."""
    occupied = np.zeros((12, 14), bool)
    occupied[1:3, 7:10] = True  # a wall beside the start
    grid = tdp.GridMap(occupied, resolution=1.0)
    walled = tdp.Scenario(grid, (2, 10), (9, 3), max_ticks=60, tick_s=1.0)
    with pytest.warns(UserWarning, match=r"margin_m 0.1 is less than half a cell's diagonal \(0.707 m"):
        metrics = run_episode(walled)
    assert metrics["reached"] and metrics["oracle_length_m"] > 0 and metrics["ratio"] >= 0.99
    boxed = tdp.Scenario(grid, (2, 10), (9, 3), obstacles=[tdp.Obstacle(box=(10, 2, 12, 5))], max_ticks=60,
                         tick_s=1.0)
    with pytest.warns(UserWarning, match="margin_m 0.1 is less than"):
        metrics = run_episode(boxed)
    assert metrics["reached"] and metrics["oracle_length_m"] is None and metrics["ratio"] is None
    assert metrics["path_length_m"] > 0 and metrics["oracle_trajectory"] == []


def test_a_margin_below_half_a_cells_diagonal_warns_and_the_default_does_not():
    """Obstacles grow centre to centre, so a margin below half a cell's diagonal lets the planners route the robot
    through gaps it does not fit (docs/worlds.md: a rooms world at margin 0 pressed the robot on a door's jamb for
    94 % of its steps); run_episode says so before it runs, and names a margin that covers the grid."""
    grid = tdp.GridMap(np.zeros((30, 30), bool), resolution=0.1)
    here = tdp.Scenario(grid, (5, 5), (5, 5))
    with pytest.warns(UserWarning, match=r"margin_m 0.05 is less than half a cell's diagonal \(0.0707 m on this "
                                         r"map's 0.1 m cells\).*SimConfig\(margin_m=0.071\)"):
        run_episode(here, sim=SimConfig(margin_m=0.05))
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        assert run_episode(here)["reached"]
        assert run_episode(here, sim=SimConfig(margin_m=margin_floor_m(0.1)))["reached"]


@pytest.mark.parametrize("settings, message", [
    ({"control_hz": 0}, "control_hz must be an integer >= 1, got 0"),
    ({"physics_hz": "240"}, "physics_hz must be an integer, got '240'"),
    ({"frame_every": 0}, "frame_every must be an integer >= 1, got 0"),
    ({"physics_hz": 250, "control_hz": 20}, "physics_hz must be a multiple of control_hz, got 250 and 20"),
])
def test_sim_settings_that_are_not_counts_are_value_errors(settings, message):
    """A fuzz of SimConfig: control_hz 0 divided by zero, a rate given as text compared a str with an int, and
    frame_every 0 would have divided by zero at the first frame."""
    with pytest.raises(ValueError, match=message):
        SimConfig(**settings)


@pytest.mark.parametrize("arguments, message", [
    (("static",), "scenario must be a tdp.Scenario, got str"),
    ((None, {"planner": "exact"}), "config must be a tdp.NavigatorConfig, got dict"),
    ((None, tdp.NavigatorConfig(), {"margin_m": 0.1}), "sim must be a sim.episode.SimConfig, got dict"),
    ((None, tdp.NavigatorConfig(), SimConfig(), "no"), "gui must be True or False"),
])
def test_run_episodes_arguments_of_the_wrong_kind_are_value_errors(arguments, message):
    """They ended in an AttributeError from inside the run (or, for gui="no", asked for a display)."""
    arguments = (tdp.scenarios.get("static"),) + arguments[1:] if arguments[0] is None else arguments
    with pytest.raises(ValueError, match=message):
        run_episode(*arguments)


def test_a_world_the_grown_robot_cannot_cross_reports_no_oracle_length():
    """A gap of two 0.1 m cells lets the grid's point robot through but not the simulated one (obstacles grown by
    0.25 m): the robot waits and its oracle, on the same grown map, never reaches the goal. Its metrics said so with
    an oracle length of 0.00 m, the distance the oracle had driven; an oracle that did not reach has none."""
    occupied = np.zeros((30, 30), bool)
    occupied[:, 15] = True
    occupied[14:16, 15] = False  # the gap, 0.2 m
    world = tdp.Scenario(tdp.GridMap(occupied, resolution=0.1), (15, 3), (15, 27), max_ticks=8)
    assert tdp.simulate(world, max_ticks=40).reached  # at grid level there is a way
    metrics = run_episode(world)
    assert not metrics["reached"] and metrics["oracle_reached"] is False
    assert metrics["oracle_length_m"] is None and metrics["ratio"] is None
    assert oracle_text(metrics) == "not reached"


@pytest.mark.parametrize("planner", ["exact", "accelerating"])
def test_nav2s_inflation_cost_round_every_obstacle_keeps_the_robot_clearer_at_a_little_more_length(planner):
    """A box closes the route (sudden-blockage): with the inflation cost around walls and boxes the robot keeps
    farther from them all the way, and still reaches without contact."""
    scenario, config = tdp.scenarios.get("sudden-blockage"), tdp.NavigatorConfig(planner=planner)
    binary = run_episode(scenario, config)
    costed = run_episode(scenario, config, SimConfig(cost_scaling_factor=3.0, inflation_radius=0.8))
    assert costed["reached"] and costed["contacts"] == 0
    assert costed["min_clearance_m"] > 2 * binary["min_clearance_m"]
    assert costed["mean_clearance_m"] > binary["mean_clearance_m"]
    assert costed["path_length_m"] < 1.1 * binary["path_length_m"]


def test_the_feed_sends_changed_costs_before_occupancy_and_the_planner_repairs_on_them():
    calls = []

    class Recorder:
        def update_costs(self, cells, costs):
            calls.append(("costs", cells.tolist(), costs.tolist()))

        def update_map(self, cells, occupied):
            calls.append(("map", cells.tolist(), occupied.tolist()))

    occupied, cost = np.zeros((2, 3), bool), np.ones((2, 3))
    feed = WorldFeed(occupied, (0, 0), cost)
    now, dearer = occupied.copy(), cost.copy()
    now[1, 2], dearer[0, 1] = True, 4.0
    feed.update(Recorder(), now, (0, 0), dearer)
    feed.update(Recorder(), now, (0, 0), dearer)  # nothing changed: nothing sent
    assert calls == [("costs", [[0, 1]], [4.0]), ("map", [[1, 2]], [True])]
    grid = tdp.GridMap(np.zeros((5, 9), bool), cost=np.ones((5, 9)))
    planner = tdp.ExactPlanner(grid, (2, 0), (2, 8), tdp.NavigatorConfig(neighbourhood=8))
    planner.setup()
    planner.update_costs([(row, 4) for row in range(5)], 50.0)  # a dear column across the way
    planner.tick()
    assert planner.engine.goal_distances()[2, 0] == pytest.approx(6 + 2 * 25.5, rel=1e-6)  # two moves touch it


ROUTE = [(5, 6), (5, 7), (6, 8)]


@pytest.mark.parametrize("robot, move, route, cells", [
    ((5, 5), (5, 6), ROUTE, ROUTE),          # the move starts the route: look ahead along it
    ((5, 5), None, ROUTE, []),              # no move (wait, yield, a budget's repair behind): stop
    ((5, 5), (4, 5), ROUTE, [(4, 5)]),      # a step aside from a box's way: that cell alone
    ((5, 5), (5, 6), [], [(5, 6)]),         # a move and no route (a way out): the move
    ((9, 9), None, [], [(9, 9)]),           # on the target's cell: its centre
])
def test_the_robot_steers_through_the_ticks_move_or_stops(robot, move, route, cells):
    """The steering used to follow the planner's route whatever the tick decided, and head for the target where the
    route was empty: a robot yielding to a box drove on at full speed."""
    assert steering_cells(robot, (9, 9), move, route) == cells


def test_a_robot_yielding_to_a_box_in_pybullet_stays_put():
    """A crossing world where obstacle prediction yields (avoid_boxes): on the ticks the planner yields, the robot
    moved 0.101 m a tick against 0.097 on the others (it followed the route regardless); it now stops. Medians: a
    yield's first tick is spent braking (0.04-0.07 m), and the ticks after a stop accelerating."""
    world = tdp.random_worlds.make_world("crossing", 80, 7300)
    config = tdp.NavigatorConfig(planner="accelerating", updates_per_move=1, predict_ticks=8, avoid_boxes=True)
    episode = run_episode(world, config)
    trace = episode["trace"]
    moved = {Mode.YIELD: [], Mode.DP: []}
    for before, after in zip(trace, trace[1:]):
        moved.get(after[2], []).append(math.hypot(after[0] - before[0], after[1] - before[1]))
    assert episode["reached"] and len(moved[Mode.YIELD]) >= 5
    assert np.median(moved[Mode.YIELD]) < 0.3 * np.median(moved[Mode.DP])


@pytest.mark.parametrize("name", ["max_speed", "goal_tolerance_m"])
def test_a_robot_that_cannot_move_or_cannot_arrive_is_refused(name):
    """At 0 m/s the robot stood still, and with no tolerance it was never close enough: every episode ran to its
    limit and said only that the robot had not arrived."""
    with pytest.raises(ValueError, match=f"{name} must be a number > 0, got 0"):
        SimConfig(**{name: 0.0})


def test_sim_config_takes_both_inflation_parameters_or_neither():
    with pytest.raises(ValueError, match="go together"):
        SimConfig(cost_scaling_factor=3.0)
    with pytest.raises(ValueError, match="inflation_radius must be"):
        SimConfig(cost_scaling_factor=3.0, inflation_radius=-1.0)


def test_start_without_room_for_the_robot_is_a_clear_error():
    occupied = np.zeros((20, 20), bool)
    occupied[:, 3] = True
    scenario = tdp.Scenario(tdp.GridMap(occupied, resolution=0.1), (5, 4), (10, 15))
    with pytest.raises(ValueError, match="no room for the robot"):
        run_episode(scenario)


@pytest.mark.parametrize("args, message", [
    (["run", "--scenario", "nowhere"], "unknown scenario"),
    (["run", "--scenario", "static", "--gui"], "needs a display"),
    (["run", "--scenario", "static", "--updates", "0"], "positive integer"),
    (["run", "--scenario", "static", "--margin", "-0.1"], "margin_m must be a number >= 0, got -0.1"),
])
def test_cli_errors_are_one_line(args, message, monkeypatch):
    env = {"PATH": "/usr/bin:/bin", "HOME": "/tmp"}
    done = subprocess.run([sys.executable, "-m", "sim", *args], capture_output=True, text=True, env=env)
    assert done.returncode == 2
    assert message in done.stderr and "Traceback" not in done.stderr


@pytest.mark.parametrize("ticks", [0, 1, 7, 8, 9, 40, 41, 333])
def test_a_long_episodes_film_is_thinned_evenly_and_keeps_its_last_state(ticks, monkeypatch):
    """``run_episode``'s pictures (a stand-in camera that names the tick it was asked at): every second tick from the
    first and the last state; past MAX_FRAMES (4 here) every other picture goes and the rest come half as often."""
    import sim.episode as episode

    monkeypatch.setattr(episode, "MAX_FRAMES", 4)
    now = {"tick": 0}
    frames = ["kept from before"]
    film = episode._Film(frames, SimpleNamespace(picture=lambda: now["tick"]), every=2)
    for tick in range(1, ticks + 1):
        now["tick"] = tick
        film.shoot(tick)
    film.finish(ticks)
    shots = frames[1:]
    assert frames[0] == "kept from before" and shots[-1] == ticks and len(shots) <= 4 + 1
    unthinned = list(range(1, ticks + 1, 2))
    if ticks <= 8:  # at most four pictures: the rule as it always was
        assert shots == unthinned + ([ticks] if ticks not in unthinned else [])
    else:
        spacing = set(np.diff(shots[:-1]).tolist())
        assert shots[0] == 1 and len(spacing) == 1 and spacing.pop() in (4, 8, 16, 32, 64, 128)
        assert 0 < shots[-1] - shots[-2] <= np.diff(shots[:2])[0]


def test_camera_frames_and_the_side_by_side_animation(tmp_path, capsys):
    """--animate: the simulator's own camera looks down on the world (headless), one picture every second tick and
    one at the end; compare writes the three planners' runs side by side as a GIF. The command's main() in this
    process (a fresh one would load every kernel again)."""
    assert sim_command(["compare", "--scenario", "static", "--animate", "--out", str(tmp_path)]) == 0
    assert f"animation: {tmp_path / 'animation.gif'}" in capsys.readouterr().out
    from PIL import Image

    kinds = ("exact", "accelerating", "plain-dp")
    ticks = max(json.loads((tmp_path / f"{kind}.json").read_text())["ticks"] for kind in kinds)
    with Image.open(tmp_path / "animation.gif") as gif:
        assert gif.n_frames == ticks // 2 + 1 and gif.size == (3 * 360, 360 + 18)
        gif.seek(0)
        first = np.asarray(gif.convert("RGB"), float)
        gif.seek(gif.n_frames - 1)
        last = np.asarray(gif.convert("RGB"), float)
    assert first.std() > 10 and np.abs(first - last).sum() > 0  # a picture, not a blank; and the robot moved
