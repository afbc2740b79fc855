"""World files: the named scenarios load through them, worlds round-trip, metres convert, every mistake names the
file and the key, and a world on a real ROS map runs at grid level and in PyBullet."""
import json
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

import tdp
from sim.__main__ import main as sim_command
from tdp.__main__ import main as tdp_command

ROOT = Path(__file__).resolve().parents[1]
EXAMPLE = ROOT / "examples" / "turtlebot3-world.yaml"


def same_world(a: tdp.Scenario, b: tdp.Scenario, ticks: int = 400) -> bool:
    return (a.start == b.start and a.goal == b.goal and a.max_ticks == b.max_ticks and a.tick_s == b.tick_s
            and a.change_tick == b.change_tick and a.blocking == b.blocking
            and all(np.array_equal(a.occupancy(t), b.occupancy(t)) for t in range(ticks))
            and all(a.target(t) == b.target(t) for t in range(ticks)))


@pytest.mark.parametrize("name", tdp.scenarios.names())
def test_named_scenarios_are_world_files_that_round_trip(tmp_path, name):
    scenario = tdp.scenarios.get(name)
    assert tdp.scenarios.path(name).suffix == ".yaml" and scenario.name == name and scenario.description
    (tmp_path / "w.yaml").write_text(scenario.to_yaml())
    assert same_world(scenario, tdp.load_world(tmp_path / "w.yaml"))


def test_the_sudden_blockage_world_file_says_what_the_paper_does():
    scenario = tdp.scenarios.get("sudden-blockage")
    assert scenario.grid.shape == (100, 100) and scenario.start == (3, 3) and scenario.goal == (96, 96)
    assert scenario.occupancy(9)[44:48, 45:55].sum() == 0 and scenario.occupancy(10)[44:48, 45:55].all()


def test_a_world_on_a_ros_map_in_metres(tmp_path):
    scenario = tdp.load_world(EXAMPLE)
    grid = tdp.load_map(ROOT / "tdp" / "maps" / "turtlebot3_world" / "map.yaml")
    assert scenario.grid.resolution == 0.05
    assert scenario.start == grid.world_to_cell(-1.9, -0.4) and scenario.goal == grid.world_to_cell(1.9, 0.4)
    assert scenario.max_ticks == 400  # 80 s at 0.2 s a tick
    patrol, appearing = scenario.obstacles
    assert patrol.speed == pytest.approx(0.15 * 0.2 / 0.05)  # 0.15 m/s: 0.6 cells per tick
    assert appearing.appear_at == 5  # 1 s
    r0, c0, r1, c1 = appearing.box  # [0.4, -0.35, 0.7, -0.05] m: 6 x 6 cells whose centres lie inside
    assert (r1 - r0, c1 - c0) == (6, 6)
    x, y = grid.cell_to_world(r0, c0)
    assert 0.4 < x < 0.7 and -0.35 < y < -0.05
    (tmp_path / "w.yaml").write_text(scenario.to_yaml())  # written back in cells, the map by its file
    assert same_world(scenario, tdp.load_world(tmp_path / "w.yaml"))


BASE = "map: {rows: 20, cols: 30, obstacles: [[0, 10, 15, 12]]}\nstart: [1, 1]\ngoal: [18, 28]\n"


@pytest.mark.parametrize("text, message", [
    (BASE + "speed: 3\n", r"speed: unknown key"),
    ("start: [1, 1]\ngoal: [2, 2]\n", r"map: missing"),
    (BASE.replace("start: [1, 1]", "start: [1, 11]"), r"start \(1, 11\) is on an obstacle"),
    (BASE.replace("start: [1, 1]", "start: [1, 1.5]"), r"start: expected a pair \[row, col\]"),
    (BASE + "obstacles:\n  - box: [18, 27, 22, 30]\n", r"obstacles\[0\].box: the box would be off the 20 x 30 map"),
    (BASE + "obstacles:\n  - box: [5, 5, 7, 7]\n    waypoints: [[1, 2], 3]\n", r"obstacles\[0\].waypoints\[1\]"),
    (BASE + "obstacles:\n  - box: [5, 5, 7, 7]\n    waypoints: [1, 2]\n", r"obstacles\[0\].waypoints\[0\]"),
    (BASE + "obstacles:\n  - box: [5, 5, 7, 7]\n    waypoints: [[2, 29]]\n", r"waypoints\[0\]: the box would be off"),
    (BASE + "obstacles:\n  - box: [5, 5, 7, 7]\n    speed: -1\n", r"obstacles\[0\].speed"),
    (BASE + "obstacles:\n  - box: [5, 5, 7, 7]\n    appear_s: 3\n", r"obstacles\[0\].appear_s: unknown key"),
    (BASE + "units: feet\n", r"units: expected one of"),
    (BASE + "tick_s: 0\n", r"tick_s: expected a number > 0"),
    (BASE + "tick_s: 1e-1\n", r"tick_s: expected a finite number, got '1e-1' \(YAML reads 1e-1 as text"),
    ("map: nowhere.yaml\nstart: [1, 1]\ngoal: [2, 2]\n", r"map.file: no such map file"),
    (BASE + "target: {waypoints: [[10, 11]]}\n", r"target waypoint \(10, 11\) is on an obstacle"),
    (BASE + "target: {waypoints: [[18, 1], [2, 1], [2, 28]]}\n", r"the target's path from \(2, 1\) to \(2, 28\) "
                                                                 r"crosses an obstacle of the map at \(2, 10\)"),
    ("- just\n- a list\n", r"the file: expected a mapping"),
    ("root:x:0:0:root:/root:/bin/bash " * 40 + "\n", r"the file: expected a mapping, got 'root:x:0:0:.{30,60}\.\.\.$"),
    ("map: [unclosed\n", r"not valid YAML"),
    (BASE + "name: [a, b]\n", r"name must be text, got \['a', 'b'\]"),
    (BASE + "description: {door: shut}\n", r"description must be text"),
    (BASE + "name: yes\n", r"name must be text, got True"),
    (BASE + "start: [2, 2]\n", r"not valid YAML \('start' is given twice"),
    (BASE + "obstacles:\n  - {box: [5, 5, 7, 7], box: [8, 8, 9, 9]}\n", r"'box' is given twice"),
    (BASE + "max_ticks: 40\nmax_s: 3\n", r"max_s: a key of the other units \(this file's units are cells: give "
                                         r"max_ticks\)"),
    (BASE + "units: metres\nchange_tick: 4\n", r"change_tick: a key of the other units"),
    (BASE + "target: {waypoints: [[10, 1]], speed: 0}\n", r"yaml: target.speed: expected a number > 0"),
    (BASE + "target: {speed: 0.3}\n", r"target.waypoints: a target needs a waypoint"),
    ("map: {rows: 100000, cols: 100000}\nstart: [1, 1]\ngoal: [2, 2]\n", r"map: 100000 x 100000 cells is more than"),
])
def test_mistakes_in_a_world_file_name_the_file_and_the_key(tmp_path, text, message):
    path = tmp_path / "bad-world.yaml"
    path.write_text(text)
    with pytest.raises(ValueError, match=message) as raised:
        tdp.load_world(path)
    assert str(raised.value).startswith(str(path)) and str(raised.value).count(str(path)) == 1


def test_an_empty_name_or_description_takes_the_default_and_digits_are_text(tmp_path):
    """``name:`` with nothing after it is YAML's null: the world was called "None"."""
    path = tmp_path / "door.yaml"
    path.write_text(BASE + "name:\ndescription: 2024\n")
    world = tdp.load_world(path)
    assert world.name == "door" and world.description == "2024"


def test_a_missing_world_file():
    with pytest.raises(FileNotFoundError, match="world file not found"):
        tdp.load_world("no/such/world.yaml")


def run(*args):
    return subprocess.run([sys.executable, *args], cwd=ROOT, capture_output=True, text=True, timeout=300)


def test_the_ros_world_runs_at_grid_level_and_in_pybullet_with_one_command_each(tmp_path):
    """Each command's main() in this process (a fresh one would load every kernel again; the entry points
    themselves run in the command-line tests of test_inputs and test_sim)."""
    assert tdp_command(["run", "--world", str(EXAMPLE), "--out", str(tmp_path / "grid")]) == 0
    grid = json.loads((tmp_path / "grid" / "metrics.json").read_text())
    assert grid["reached"] and grid["collisions"] == 0 and grid["hits"] == 0
    assert sim_command(["run", "--world", str(EXAMPLE), "--out", str(tmp_path / "sim")]) == 0
    physics = json.loads((tmp_path / "sim" / "metrics.json").read_text())
    assert physics["reached"] and physics["contacts"] == 0 and physics["sim"]["cell_m"] == 0.05


def test_quick_worlds_on_any_map_use_the_family_generator_and_keep_a_way_open(tmp_path, capsys):
    from tdp.random_worlds import boxes_on_map

    grid = tdp.load_map(ROOT / "tests" / "data" / "arena.map")
    world = boxes_on_map(grid, (1, 3), (47, 46), boxes=4, seed=1, blockage=True)
    again = boxes_on_map(grid, (1, 3), (47, 46), boxes=4, seed=1, blockage=True)
    assert same_world(world, again, ticks=100)  # deterministic
    assert len(world.obstacles) == 5 and world.blocking == 4 and world.change_tick == world.obstacles[4].appear_at
    for obstacle in world.obstacles[:4]:  # the shuttling boxes sweep free ground only
        for tick in range(0, 300, 5):
            r0, c0, r1, c1 = obstacle.footprint(tick)
            assert not grid.occupied[r0:r1, c0:c1].any()
    plugged = tdp.DistanceField(tdp.GridMap(world.occupancy(world.change_tick)), world.goal)
    plugged.converge()
    assert np.isfinite(plugged.distance(world.start))
    arena = str(ROOT / "tests" / "data" / "arena.map")
    assert tdp_command(["run", "--map", arena, "--start", "1", "3", "--goal", "47", "46", "--boxes", "4", "--seed",
                        "1", "--blockage", "--out", str(tmp_path)]) == 0
    assert json.loads((tmp_path / "metrics.json").read_text())["reached"]
    assert tdp_command(["run", "--map", arena, "--start", "1", "3", "--goal", "47", "46", "--max-ticks", "5",
                        "--out", str(tmp_path)]) == 0
    assert ("reached: False (the episode's limit, 5 ticks, ran out; a world file's max_ticks or max_s, or tdp run's "
            "--max-ticks, sets it) in 5 ticks") in capsys.readouterr().out
    done = run("-m", "tdp", "run", "--map", "tests/data/arena.map", "--out", str(tmp_path))
    assert done.returncode == 2 and "--map needs --start" in done.stderr
