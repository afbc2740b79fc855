"""Bad and unusual input: each case here was silently wrong, a traceback or a hang before, and is now a clear
ValueError naming what was wrong, or the right answer."""
import json
import math
import re
import os
import struct
import subprocess
import sys
import time
import warnings
import zlib
from pathlib import Path

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from PIL import Image

import tdp
from tdp.__main__ import main as tdp_command
from tdp.cli import config_from, output_folder, save_json, world_from
from tdp.field import cells_from
from tdp.sweep import load_spec, run_sweep

ROOT = Path(__file__).resolve().parents[1]
ROS_YAML = "image: {image}\nresolution: 0.05\norigin: [0, 0, 0]\nnegate: 0\noccupied_thresh: 0.65\nfree_thresh: 0.196\n"


def cli(*args, cwd=ROOT):
    return subprocess.run([sys.executable, *args], cwd=cwd, capture_output=True, text=True, timeout=300)


# -- maps ---------------------------------------------------------------------------------------------------------
def test_sixteen_bit_pgm_through_a_ros_yaml_follows_map_servers_shades(tmp_path):
    """Pixels 0, 1000, 30000, 65535 of 65535: occupied, occupied, unknown (an obstacle), free. They were clipped
    at 255 on the way through Pillow, giving [[1, 0, 0, 0]]."""
    pixels = np.array([[0, 1000, 30000, 65535]], ">u2")
    (tmp_path / "m.pgm").write_bytes(b"P5\n4 1\n65535\n" + pixels.tobytes())
    (tmp_path / "m.yaml").write_text(ROS_YAML.format(image="m.pgm"))
    np.testing.assert_array_equal(tdp.load_map(tmp_path / "m.yaml").occupied, [[True, True, True, False]])
    (tmp_path / "a.pgm").write_text("P2\n4 1\n65535\n0 1000 30000 65535\n")
    np.testing.assert_array_equal(tdp.load_map(tmp_path / "a.pgm", threshold=0.5).occupied,
                                  [[True, True, True, False]])


def test_sixteen_bit_png_with_a_threshold(tmp_path):
    Image.fromarray(np.array([[0, 1000, 30000, 65535]], np.uint16)).save(tmp_path / "m.png")
    np.testing.assert_array_equal(tdp.load_map(tmp_path / "m.png", threshold=0.5).occupied,
                                  [[True, True, True, False]])
    np.testing.assert_array_equal(tdp.load_map(tmp_path / "m.png", threshold=0.4).occupied,
                                  [[True, True, False, False]])


def test_pgm_with_a_small_maxval_reads_shades_as_fractions_of_it(tmp_path):
    (tmp_path / "m.pgm").write_bytes(b"P5\n4 1\n100\n" + bytes([0, 40, 60, 100]))
    np.testing.assert_array_equal(tdp.load_map(tmp_path / "m.pgm", threshold=0.5).occupied,
                                  [[True, True, False, False]])


def png_header_only(path: Path, width: int, height: int) -> Path:
    """A PNG whose header declares width x height greyscale pixels, with no pixel data to speak of."""
    def chunk(kind: bytes, data: bytes) -> bytes:
        return struct.pack(">I", len(data)) + kind + data + struct.pack(">I", zlib.crc32(kind + data))
    header = struct.pack(">IIBBBBB", width, height, 8, 0, 0, 0, 0)
    path.write_bytes(b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", header) + chunk(b"IDAT", zlib.compress(b"")) +
                     chunk(b"IEND", b""))
    return path


@pytest.mark.parametrize("side", [30000, 9000])  # Pillow's own bomb limit, and ours (8192 x 8192)
def test_an_image_too_large_to_be_a_map_is_a_clear_error(tmp_path, side):
    path = png_header_only(tmp_path / "huge.png", side, side)
    with pytest.raises(ValueError, match="huge.png"):
        tdp.load_map(path)


def test_plan_on_an_image_too_large_is_one_error_line(tmp_path):
    path = png_header_only(tmp_path / "huge.png", 30000, 30000)
    done = cli("-m", "tdp", "plan", str(path), "--start", "0", "0", "--goal", "1", "1", "--out", str(tmp_path / "o"))
    assert done.returncode == 2 and done.stderr.startswith("error:") and "Traceback" not in done.stderr


@pytest.mark.parametrize("load, what", [(tdp.load_map, "map file"), (tdp.load_scenarios, "scenario file"),
                                         (tdp.load_world, "world file")])
def test_a_missing_file_or_a_folder_is_named_as_such(tmp_path, load, what):
    with pytest.raises(FileNotFoundError, match=f"^{what} not found: .*nothing.map$"):
        load(tmp_path / "nothing.map")
    (tmp_path / "maps.map").mkdir()
    with pytest.raises(FileNotFoundError, match=f"^{what} not found: .*maps.map is a folder$"):
        load(tmp_path / "maps.map")


@pytest.mark.parametrize("length", ["nan", "-7", "inf"])
def test_scen_optimal_length_must_be_a_finite_non_negative_number(tmp_path, length):
    path = tmp_path / "s.scen"
    path.write_text(f"version 1\n0\tm.map\t4\t4\t0\t0\t3\t3\t{length}\n")
    with pytest.raises(ValueError, match="line 2: the optimal length"):
        tdp.load_scenarios(path)


# -- arguments ----------------------------------------------------------------------------------------------------
GRID = tdp.GridMap(np.zeros((10, 10), bool))


@pytest.mark.parametrize("make, message", [
    (lambda: tdp.simulate(tdp.scenarios.get("static"), max_ticks=0), "max_ticks must be an integer >= 1, got 0"),
    (lambda: tdp.Scenario(GRID, (0, 0), (5, 5), max_ticks=-5), "max_ticks must be an integer >= 1, got -5"),
    (lambda: tdp.Scenario(GRID, (0, 0), (5, 5), change_tick="soon"), "change_tick .* must be an integer"),
    (lambda: tdp.Scenario(GRID, (0, 0), (5, 5), target_speed=True), "target_speed"),
    (lambda: tdp.Obstacle(box=(0.5, 0, 2.9, 3)), "box"),
    (lambda: tdp.Obstacle(box=(0, 0, 2, 3), waypoints=[(1.5, 2)]), "waypoints"),
    (lambda: tdp.Obstacle(box=(0, 0, 2, 3), waypoints=[(1, 2, 3)]), "waypoints"),
    (lambda: tdp.Scenario(GRID, (0, 0), (5, 5), obstacles=5), "obstacles must be a list of tdp.Obstacle"),
    (lambda: tdp.Scenario(GRID, (0, 0), (5, 5), target_waypoints=5), "target_waypoints must be a list of cells"),
    (lambda: tdp.Scenario(tdp.GridMap(np.arange(100).reshape(10, 10) % 10 == 4), (0, 0), (5, 5),
                          target_waypoints=[(9, 5), (9, 1)], target_speed=3.0),
     r"the target's path from \(9, 5\) to \(9, 1\) crosses an obstacle of the map at \(9, 4\)"),
    (lambda: tdp.load_map(5), "path must be a file path"),
    (lambda: tdp.Navigator(tdp.GridMap(np.zeros((5, 7), bool)), (0, 0), (4, 6), tdp.NavigatorConfig(
        planner="accelerating", nodes=36)), "nodes=36 is more than the 5 x 7 map's cells"),
    (lambda: tdp.costmap_grid(np.full((5, 5), -5)), "costmap values must be 0-255, got values from -5 to -5"),
    (lambda: tdp.costmap_grid([[0, 0], [0]]), "costmap must be a 2-D integer array, got \\[\\[0, 0\\], \\[0\\]\\]"),
    (lambda: tdp.costmap_grid(np.zeros((2, 2), int), unknown_is_free="no"), "unknown_is_free must be True or False"),
    (lambda: tdp.load_map(ROOT / "tests" / "data" / "arena.map", unknown_is_free="no"),
     "unknown_is_free must be True or False"),
    (lambda: tdp.load_world(None), "path must be a file path"),
    (lambda: tdp.load_scenarios(3.5), "path must be a file path"),
    (lambda: load_spec(7), "path must be a file path"),
    (lambda: run_sweep(load_spec(ROOT / "benchmarks" / "specs" / "paper-quick.yaml"), 5,
                       serial=True), "out must be a folder path .* got 5"),
    (lambda: tdp.DistanceField(GRID, (0, 0)).distance((0.9, 0.9)), "cell must be a \\(row, col\\) pair of integers"),
    (lambda: tdp.DistanceField(GRID, (0, 0), corner_cutting="no"), "corner_cutting must be True or False"),
    (lambda: tdp.DistanceField(GRID, (0, 0)).set_occupied([(1, 1)], occupied="yes"), "occupied must be True"),
    (lambda: tdp.DistanceField(GRID, (0, 0)).step(2.0), "k must be an integer"),
    (lambda: tdp.DistanceField(GRID, (0, 0)).set_occupied(5), "set_occupied: expected .* got an array of shape \\(\\)"),
    (lambda: tdp.DistanceField(GRID, (0, 0)).set_occupied([(1, 2), (3,)]), "set_occupied: .* a ragged sequence"),
    (lambda: tdp.DistanceField(GRID, (0, 0)).set_occupied([(1, 2.5)]), "set_occupied: expected .* dtype float64"),
    (lambda: tdp.DistanceField(GRID, (0, 0)).set_occupied([(1, 10)]), "set_occupied: cell \\(1, 10\\) is outside"),
    (lambda: tdp.DistanceField(GRID, (0, 0)).set_occupied(np.zeros((9, 10), bool)), "a mask must have the map's"),
    (lambda: tdp.DistanceField(GRID, (0, 0)).set_occupied(np.array([(1, 2**32 + 3)])),
     "set_occupied: cell \\(1, 4294967299\\) is outside"),  # not 3, as int32 would read it
    (lambda: tdp.DistanceField(GRID, (0, 0)).set_occupied(np.array([(2, -1)], ">i2")),
     "set_occupied: cell \\(2, -1\\) is outside"),
    (lambda: tdp.Navigator(GRID, (0, 0), (9, 9)).update_map([(-1, 3)]), "update_map: cell \\(-1, 3\\) is outside"),
    (lambda: tdp.Navigator(GRID, (0, 0), (9, 9)).set_goal((2.5, 3.7)), "goal must be a \\(row, col\\) pair"),
    (lambda: tdp.Navigator(GRID, (0, 0), (9, 9)).move_robot((-5, 100)), "robot cell \\(-5, 100\\) is outside"),
    (lambda: tdp.Navigator(np.zeros((10, 10), bool), (0, 0), (9, 9)), "grid must be a tdp.GridMap"),
    (lambda: GRID.check_free_cell((True, 2), "start"), "start must be a \\(row, col\\) pair of integers"),
])
def test_bad_arguments_are_clear_errors(make, message):
    with pytest.raises(ValueError, match=message):
        make()


def test_cells_of_any_integer_array_are_read_as_their_values():
    """Cells come as lists or arrays of any integer type and byte order: each is read as the cell it names."""
    cells = [(0, 3), (9, 9), (4, 0)]
    for array in (cells, np.array(cells, np.uint8), np.array(cells, ">i4"), np.array(cells, np.int64)[::-1]):
        field = tdp.DistanceField(GRID, (0, 0))
        field.set_occupied(array)
        assert sorted(map(tuple, np.argwhere(field.occupied).tolist())) == sorted(cells)


#: What a cell's coordinate might be: small ints (in and out of the 10 x 10 map), ints past every numpy type, bools,
#: numpy ints, floats, None.
COORDINATE = st.one_of(st.integers(-3, 12), st.integers(-2**70, 2**70), st.booleans(),
                       st.integers(0, 9).map(np.int16), st.floats(0, 9), st.none())


@settings(max_examples=300, deadline=None)
@given(st.lists(st.one_of(st.tuples(COORDINATE, COORDINATE), st.lists(st.integers(0, 9), max_size=3),
                          st.tuples(st.integers(0, 9), st.integers(0, 9)).map(np.array)), max_size=12),
       st.sampled_from([list, tuple]))
def test_a_list_of_cells_reads_as_numpy_reads_it(cells, container):
    """A list or tuple of pairs is read column by column (``field._read_cells``, faster): the cells, or the error,
    are what numpy's own reading of it gives."""
    cells = container(cells)

    def outcome(read):
        try:
            return read().tolist()
        except ValueError as error:
            return str(error)

    def as_numpy_reads_it():
        try:
            array = np.asarray(cells)
        except ValueError:
            return cells_from(GRID.shape, [(1, 2), (3,)], "set_occupied")  # numpy's ragged sequence, as it is told
        return cells_from(GRID.shape, array, "set_occupied")
    assert outcome(lambda: cells_from(GRID.shape, cells, "set_occupied")) == outcome(as_numpy_reads_it)


@settings(max_examples=60, deadline=None)
@given(st.integers(1, 40), st.integers(1, 40), st.floats(0, 1), st.sampled_from(["C", "F", "strided"]),
       st.integers(0, 2**32 - 1))
def test_a_masks_cells_are_argwheres_row_by_row(rows, cols, share, layout, seed):
    """A mask's cells are found as flat indices (2-D nonzero took ten times as long): the cells np.argwhere gives, in
    its order, for masks in any memory layout."""
    mask = np.random.default_rng(seed).random((2 * rows, 2 * cols)) < share
    layouts = {"C": mask[:rows, :cols].copy(), "F": np.asfortranarray(mask[:rows, :cols]), "strided": mask[::2, ::2]}
    mask = layouts[layout]
    cells = cells_from(mask.shape, mask, "update_map")
    assert cells.dtype == np.int32 and cells.flags.c_contiguous and np.array_equal(cells, np.argwhere(mask))


def test_numpy_numbers_are_numbers_everywhere(tmp_path):
    """d_max, a resolution, an inflation radius, a threshold and a node spacing read from numpy arrays (np.float32,
    np.int64) were refused as "must be a positive number" while np.float64, a float's subclass, passed."""
    occupied = np.zeros((10, 10), bool)
    grid = tdp.GridMap(occupied, resolution=np.float32(0.05), origin=(np.float32(1.0), 0.0))
    assert grid.resolution == pytest.approx(0.05) and type(grid.resolution) is float
    assert grid.inflate(np.int64(1)).occupied.sum() == 0
    field = tdp.DistanceField(grid, (0, 0), d_max=np.float32(5.0))
    field.converge()
    assert field.distance((9, 9)) == 5.0
    Image.fromarray(np.full((3, 4), 255, np.uint8)).save(tmp_path / "m.png")
    assert not tdp.load_map(tmp_path / "m.png", threshold=np.float32(0.5)).occupied.any()
    config = tdp.NavigatorConfig(planner="accelerating", spacing=np.float32(5.0))
    navigator = tdp.Navigator(grid, (0, 0), (9, 9), config)
    navigator.setup()
    assert navigator.tick().next_cell == (1, 1)
    for make in (lambda: tdp.DistanceField(grid, (0, 0), neighbourhood=16.0),
                 lambda: tdp.DistanceField(grid, (0, 0), d_max=np.float32(-1.0)),
                 lambda: tdp.GridMap(occupied, resolution=np.float64("nan")),
                 lambda: tdp.load_map(tmp_path / "m.png", threshold=np.float32(1.5))):
        with pytest.raises(ValueError):
            make()


def test_numpy_integers_are_cells():
    field = tdp.DistanceField(GRID, (np.int64(0), np.int32(0)))
    field.converge()
    assert field.distance(np.array([0, 4])) == 4.0 and field.successor((np.int8(0), np.int16(1))) == (0, 0)


def test_a_round_limit_beyond_32_bits_is_no_limit():
    """converge(max_rounds=10**20) ended in an OverflowError from the launch's int32 array."""
    field = tdp.DistanceField(GRID, (0, 0))
    field.converge()
    field.set_occupied([(0, 1)])
    field.converge(max_rounds=10**20)
    fresh = tdp.DistanceField(tdp.GridMap(field.occupied), (0, 0))
    fresh.converge()
    assert not field.pending and np.array_equal(field.distances(), fresh.distances())


def test_step_counts_beyond_32_bits_and_returns_at_once_on_a_settled_field():
    """step(2**31) then converge() ended in a TypeError from Taichi; step(3 * 10**9) never returned."""
    field = tdp.DistanceField(GRID, (0, 0))
    field.converge()
    began = time.perf_counter()
    field.step(3 * 10**9)
    field.step(2**31)
    assert time.perf_counter() - began < 5
    assert field.iterations == 3 * 10**9 + 2**31
    field.converge()
    assert field.distance((9, 9)) == pytest.approx(9 * np.sqrt(2), rel=1e-6)
    field.set_occupied([(5, 5)])
    field.step(1000)  # the edit runs, then the rest is counted
    assert field.iterations == 1000


def test_a_covered_goal_emits_nothing():
    """Decided: covering the goal is a map change like any other; the goal emits nothing while covered (an obstacle
    wins over a source), so distances rise under step() (for ever with d_max = inf) and converge() says inf."""
    field = tdp.DistanceField(GRID, (0, 0))
    field.converge()
    field.set_occupied([(0, 0)])
    field.step(3)
    assert field.distance((0, 1)) > 1.0
    field.converge()
    assert np.isinf(field.distances()).all() and field.path((5, 5)) == []
    field.set_occupied([(0, 0)], occupied=False)
    field.converge()
    assert field.distance((0, 1)) == 1.0


# -- command lines and output -------------------------------------------------------------------------------------
def test_cli_max_ticks_zero_is_an_error_not_a_success(tmp_path):
    done = cli("-m", "tdp", "run", "--scenario", "static", "--max-ticks", "0", "--out", str(tmp_path))
    assert done.returncode == 2 and "max_ticks must be an integer >= 1, got 0" in done.stderr
    assert "reached" not in done.stdout


@pytest.mark.parametrize("command", [
    ["-m", "tdp", "run", "--scenario", "static"],
    ["-m", "tdp", "plan", "tests/data/arena.map", "--start", "1", "1", "--goal", "3", "3"],
    ["-m", "sim", "run", "--scenario", "static"],
])
@pytest.mark.parametrize("through", [False, True])
def test_an_output_folder_that_cannot_be_is_refused_before_the_work(tmp_path, command, through):
    """--out naming a file (or a path through one) used to fail after the whole run, losing it."""
    blocker = tmp_path / "a-file"
    blocker.write_text("")
    out = blocker / "sub" if through else blocker
    began = time.perf_counter()
    done = cli(*command, "--out", str(out))
    assert done.returncode == 2 and done.stderr.startswith("error: --out") and "Traceback" not in done.stderr
    assert "running" not in done.stdout and time.perf_counter() - began < 60


@pytest.mark.parametrize("start, goal, words", [
    (("99", "3"), ("9", "9"), "--start (99, 3) is outside the 49 x 49 map"),
    (("1", "3"), ("99", "0"), "--goal (99, 0) is outside the 49 x 49 map"),
    (("1", "3"), ("0", "0"), "--goal (0, 0) is on an obstacle"),
])
def test_plan_names_the_option_whose_cell_is_wrong(tmp_path, start, goal, words):
    done = cli("-m", "tdp", "plan", "tests/data/arena.map", "--start", *start, "--goal", *goal, "--out",
               str(tmp_path))
    assert done.returncode == 2 and done.stderr.strip() == f"error: {words}"


def test_a_command_lines_warning_is_one_line(tmp_path):
    """Python's format printed the warning with the file, line and source of the call that warned."""
    done = cli("-m", "sim", "run", "--map", "tests/data/arena.map", "--start", "1", "3", "--goal", "1", "4", "--boxes",
               "0", "--margin", "0.5", "--out", str(tmp_path))
    warned = [line for line in done.stderr.splitlines() if "margin_m 0.5" in line]
    assert done.returncode == 0 and len(warned) == 1 and warned[0].startswith("warning: margin_m 0.5 is less than")
    assert "UserWarning" not in done.stderr and "run_episode(" not in done.stderr


def test_output_folder_is_made_and_checked(tmp_path):
    assert output_folder(tmp_path / "a" / "b").is_dir()


def test_results_that_cannot_be_written_where_asked_are_kept_elsewhere(tmp_path, capsys):
    gone = tmp_path / "gone"
    saved = save_json({"ratio": 1.0}, gone / "metrics.json")
    assert saved != gone / "metrics.json" and '"ratio": 1.0' in saved.read_text()
    assert str(saved) in capsys.readouterr().err
    saved.unlink()


def test_results_are_strict_json_with_null_for_numbers_that_are_not_finite(tmp_path):
    """metrics.json held NaN (a ratio with no oracle) and Infinity (a run that never moved), which are not JSON."""
    saved = save_json({"ratio": float("nan"), "clearance": float("inf"), "runs": [{"x": float("-inf")}], "ok": 1.5},
                      tmp_path / "metrics.json")
    strict = json.loads(saved.read_text(), parse_constant=lambda name: pytest.fail(f"{name} in the JSON"))
    assert strict == {"ratio": None, "clearance": None, "runs": [{"x": None}], "ok": 1.5}


def test_cost_options_on_the_command_line_plan_on_nav2s_inflation_cost_and_half_of_them_is_an_error(tmp_path, capsys):
    """The plan runs in this process (a fresh one would load every kernel again); the error through the entry
    point."""
    ros = [str(ROOT / "tdp" / "maps" / "turtlebot3_world" / "map.yaml"), "--start", "192", "161", "--goal", "175",
           "238"]
    assert tdp_command(["plan", *ros, "--cost-scaling-factor", "3", "--inflation-radius", "0.6",
                        "--out", str(tmp_path / "plan")]) == 0
    assert "cost from (192, 161) to (175, 238)" in capsys.readouterr().out
    done = cli("-m", "tdp", "run", "--map", *ros, "--boxes", "0", "--cost-scaling-factor", "3", "--out", str(tmp_path))
    assert done.returncode == 2 and done.stderr.strip() == ("error: --cost-scaling-factor and --inflation-radius go "
                                                            "together (nav2's inflation layer)")


@pytest.mark.parametrize("shape", [(3000, 2), (2, 3000)])
def test_plan_on_a_map_thousands_of_times_longer_than_wide_draws_a_figure_of_ordinary_size(tmp_path, shape):
    """The figure was sized by the map's proportion alone: a map of 3,000 x 2 cells asked matplotlib for a figure
    9,000 inches tall, and ``tdp plan`` was killed for memory (23 GB) after two minutes."""
    from tdp.plot import map_figsize

    assert map_figsize((3000, 2)) == (2.0, 6.4) and map_figsize((50, 100)) == (6.0, 3.4)
    Image.fromarray(np.full(shape, 255, np.uint8)).save(tmp_path / "hall.png")
    assert tdp_command(["plan", str(tmp_path / "hall.png"), "--start", "0", "0", "--goal", "1", "1",
                        "--out", str(tmp_path / "plan")]) == 0
    width, height = Image.open(tmp_path / "plan" / "plan.png").size
    assert max(width, height) <= 1000 and min(width, height) >= 150


@pytest.mark.parametrize("command, named", [
    (["run", "--scenario", "static", "--start", "1", "1"], "--start"),
    (["run", "--world", "examples/turtlebot3-world.yaml", "--boxes", "3", "--seed", "0"], "--boxes, --seed"),
    (["run", "--scenario", "static", "--blockage", "--graded"], "--blockage, --graded"),
    (["run", "--scenario", "static", "--cost-scaling-factor", "3", "--inflation-radius", "0.8"],
     "--cost-scaling-factor, --inflation-radius"),
])
def test_a_quick_worlds_options_with_another_world_are_an_error_not_ignored(tmp_path, capsys, command, named):
    """``tdp run --scenario static --start 1 1`` ran the scenario from its own start, the option silently dropped;
    a quick world's options (and, for ``tdp run``, the cost options, which shape a quick world's map) now name
    themselves in the error. ``sim`` applies the cost options to any world (``SimConfig``) and takes them."""
    assert tdp_command([*command, "--out", str(tmp_path)]) == 2
    assert capsys.readouterr().err.strip() == (f"error: {named}: options of a quick world on --map; --scenario and "
                                               "--world are worlds of their own")
    from sim.__main__ import parser as sim_parser

    args = sim_parser().parse_args(["run", "--scenario", "static", "--cost-scaling-factor", "3",
                                    "--inflation-radius", "0.8"])
    assert world_from(args, costs_on_any_world=True).name == "static"
    args = sim_parser().parse_args(["run", "--scenario", "static", "--graded"])
    with pytest.raises(ValueError, match="--graded: options of a quick world"):
        world_from(args, costs_on_any_world=True)


@pytest.mark.parametrize("options, message", [
    (["--nodes", "9"], "--nodes: not read by exact replanning (--planner exact)"),
    (["--updates", "1", "--predict-ticks", "4", "--avoid-boxes"],
     "--updates, --predict-ticks: not read by exact replanning (--planner exact)"),
    (["--planner", "plain-dp", "--vision", "2", "--detect-window", "4"],
     "--vision, --detect-window: not read by plain DP (--planner plain-dp)"),
])
def test_a_planner_option_the_planner_does_not_read_is_an_error_not_ignored(tmp_path, capsys, options, message):
    """``tdp run --scenario static --nodes 9`` ran the exact planner (the default) and dropped --nodes without a
    word; an option the chosen planner does not read now names itself (``tdp.config.fields_read``, as the sweep
    specs refuse such a field). ``sim compare`` runs every planner with the same options: each takes those it
    reads."""
    assert tdp_command(["run", "--scenario", "static", *options, "--out", str(tmp_path)]) == 2
    assert capsys.readouterr().err.strip() == f"error: {message}"
    from tdp.__main__ import parser as tdp_parser
    from sim.__main__ import parser as sim_parser

    args = tdp_parser().parse_args(["run", "--scenario", "static", "--planner", "accelerating", "--nodes", "9",
                                    "--updates", "1", "--neighbourhood", "8"])
    assert config_from(args, "accelerating") == tdp.NavigatorConfig(planner="accelerating", nodes=9,
                                                                     updates_per_move=1, neighbourhood=8)
    args = sim_parser().parse_args(["run", "--scenario", "static", "--updates", "2"])
    with pytest.raises(ValueError, match="--updates: not read by exact replanning"):
        config_from(args, args.planner)
    args = sim_parser().parse_args(["compare", "--scenario", "static", "--updates", "2", "--predict-ticks", "3"])
    assert config_from(args, "exact", strict=False) == tdp.NavigatorConfig()
    assert config_from(args, "plain-dp", strict=False) == tdp.NavigatorConfig(planner="plain-dp", updates_per_move=2,
                                                                              predict_ticks=3)


def test_coordinates_origins_and_route_lengths_that_are_not_numbers_are_value_errors():
    """A fuzz of the public calls with odd values found four that ended in a TypeError from deep inside:
    world_to_cell and cell_to_world of a list, a GridMap origin that is not a sequence, and route() of a
    non-integer number of steps; a huge one is as many moves as any route can have."""
    with pytest.raises(ValueError, match=r"x must be a number, got \[1, 2\]"):
        GRID.world_to_cell([1, 2], 0.0)
    with pytest.raises(ValueError, match="y must be a finite number, got inf"):
        GRID.world_to_cell(0.0, math.inf)
    with pytest.raises(ValueError, match=r"col must be a number, got '3'"):
        GRID.cell_to_world(1, "3")
    for origin in (True, (0.0, "1"), (0.0, True), (1.0,), np.zeros(4)):
        with pytest.raises(ValueError, match="origin must be finite"):
            tdp.GridMap(np.zeros((3, 3), bool), origin=origin)
    assert tdp.GridMap(np.zeros((3, 3), bool), origin=np.array([1.0, 2.0])).origin == (1.0, 2.0, 0.0)
    for planner in ("exact", "accelerating"):
        navigator = tdp.make_planner(GRID, (0, 0), (9, 9), tdp.NavigatorConfig(planner=planner, nodes=4))
        navigator.setup()
        with pytest.raises(ValueError, match=r"steps must be an integer, got \(1, 2\)"):
            navigator.route((1, 2))
        assert navigator.route(10**30) == [(k, k) for k in range(1, 10)] and navigator.route(-1) == []


def test_a_quick_world_with_fewer_boxes_than_asked_says_so():
    """On a 1-cell corridor or a maze no box fits; ``--boxes 5`` gave none without a word."""
    from tdp.random_worlds import boxes_on_map

    corridor = np.ones((20, 100), bool)
    corridor[10, :] = False
    with pytest.warns(UserWarning, match="only 0 of the 5 boxes asked for fit on this map"):
        assert boxes_on_map(tdp.GridMap(corridor), (10, 0), (10, 99), boxes=5).obstacles == []
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        assert len(boxes_on_map(tdp.GridMap(np.zeros((60, 60), bool)), (0, 0), (59, 59), boxes=3).obstacles) == 3


def test_a_quick_world_on_a_maze_gives_the_robot_ticks_for_its_route():
    """A 1-cell maze of 128²: its route is 1,372 moves, and the default limit of 4 (H + W) = 1,024 ticks ran out on
    the way (the summary said so; the robot never arrived). A quick world's limit is 4 times its route's moves."""
    from tdp.random_worlds import boxes_on_map, maze

    occupied = maze(128, 1, seed=1)
    free = np.argwhere(~occupied)
    start, goal = tuple(map(int, free[0])), tuple(map(int, free[-1]))
    with pytest.warns(UserWarning, match="only 0 of the 3 boxes"):
        world = boxes_on_map(tdp.GridMap(occupied), start, goal)
    field = tdp.DistanceField(world.grid, goal)
    field.converge()
    moves = len(field.path(start)) - 1
    assert moves > 4 * 256 and world.tick_limit == 4 * moves
    episode = tdp.simulate(world)
    assert episode.reached and episode.ticks == moves


def test_world_building_calls_refuse_what_is_not_a_tick_a_count_or_a_map():
    """The same fuzz, on the world's side: boxes_on_map truncated boxes=2.5 to 2 and died on a list or infinity
    (TypeError, OverflowError) or on a grid that is not a GridMap (AttributeError), drew for ever where more boxes
    were asked for than the map has free cells (a hundred draws a box), and put a blockage's plug over the start of a
    short route (a ValueError saying the start was on an obstacle); a scenario's occupancy, target,
    holds and a box's footprint at a tick that is not a number ended in a TypeError; maze took a NaN seed to
    numpy; nav2's inflation with a steep factor warned of overflow from numpy, its result right."""
    from tdp.random_worlds import boxes_on_map, maze

    for boxes, seed, message in ((2.5, 0, "boxes must be an integer, got 2.5"), ([1], 0, "boxes must be an integer"),
                                 (1, math.inf, "seed must be an integer, got inf"),
                                 (-1, 0, "boxes must be an integer >= 0"),
                                 (10**12, 0, "boxes must be at most the map's 100 free cells, got 1000000000000")):
        with pytest.raises(ValueError, match=re.escape(message)):
            boxes_on_map(GRID, (0, 0), (9, 9), boxes, seed)
    with pytest.raises(ValueError, match="grid must be a tdp.GridMap, got ndarray"):
        boxes_on_map(np.zeros((10, 10), bool), (0, 0), (9, 9))
    with pytest.raises(ValueError, match="blockage must be"):
        boxes_on_map(GRID, (0, 0), (9, 9), blockage="yes")
    two_corridors = np.ones((5, 20), bool)  # rows 1 and 3, joined at both ends
    two_corridors[[1, 3], 1:19] = False
    two_corridors[1:4, [1, 18]] = False
    with pytest.raises(ValueError, match="no narrow place on the route"):  # the only narrow run covers the start:
        boxes_on_map(tdp.GridMap(two_corridors), (1, 5), (1, 7), 0, blockage=True)  # not "start ... on an obstacle"
    plug = boxes_on_map(tdp.GridMap(two_corridors), (1, 3), (1, 15), 0, blockage=True).obstacles[-1].box
    assert plug[0] <= 1 < plug[2] and not plug[1] <= 3 < plug[3] and not plug[1] <= 15 < plug[3]
    box = tdp.Obstacle(box=(4, 4, 6, 6), waypoints=[(4, 1)], speed=0.5)
    world = tdp.Scenario(GRID, (0, 0), (9, 9), obstacles=[box])
    for call in (lambda: world.occupancy(math.nan), lambda: world.target([1]), lambda: world.holds((1, 2), (4, 4)),
                 lambda: box.footprint(None), lambda: box.present("3")):
        with pytest.raises(ValueError, match="tick must be a number"):
            call()
    with pytest.raises(ValueError, match="cell must be"):
        world.parked_over(3, (4.5, 4))
    assert world.occupancy(np.int64(2))[4, 3] and world.holds(2, (4, 3))
    with pytest.raises(ValueError, match="seed must be an integer, got nan"):
        maze(9, 1, math.nan)
    with pytest.raises(ValueError, match=r"size must be at most 32764 cells \(the engine's largest map\), got 10+$"):
        tdp.random_worlds.make_world("rooms", 10**30)  # numpy's error in every draw: "no valid world" after 100
    for size, seed, fault in ((59, 0, "size must be an integer >= 60, got 59"), (60.0, 0, "size must be an integer"),
                              (60, -1, "seed must be an integer >= 0, got -1"), (60, True, "seed must be an integer")):
        with pytest.raises(ValueError, match=fault):
            tdp.random_worlds.make_world("rooms", size, seed)
    assert tdp.random_worlds.make_world("rooms", np.int64(60), np.uint8(1)).name == "rooms-60-1"
    walled = np.zeros((12, 12), bool)
    walled[6, 6] = True
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        steep = tdp.GridMap(walled).inflate(1.0, cost_scaling_factor=1e12, inflation_radius=3.0)
        flat = tdp.GridMap(np.zeros((12, 12), bool)).inflate(1.0, cost_scaling_factor=0.0, inflation_radius=3.0).cost
    assert steep.occupied.sum() == 5 and (steep.cost[~steep.occupied] == 1.0).all() and (flat == 1.0).all()


def test_a_map_wider_than_the_engine_packs_is_a_clear_error():
    """Kernels index a padded cell row-major in an int32 (the search's buckets after the cells): a side of 2**15 - 4
    cells or more is refused by name, not mis-indexed."""
    wide = np.zeros((1, 32765), bool)
    with pytest.raises(ValueError, match="at most 32764 cells a side, got 1 x 32765"):
        tdp.DistanceField(tdp.GridMap(wide), (0, 0))


@pytest.mark.parametrize("occupied", [[True, False], "yes", [0.5, 2.0], [[True, False, True]], np.ones(3, int)])
@pytest.mark.parametrize("planner", ["exact", "accelerating"])
def test_update_map_flags_are_true_false_or_one_bool_per_cell(planner, occupied):
    """update_map took ``occupied`` through numpy's bool cast and broadcast: a string or floats went in silently
    as True, a wrong length raised numpy's broadcasting error; now either is a ValueError naming ``occupied``."""
    navigator = tdp.make_planner(GRID, (0, 0), (9, 9), tdp.NavigatorConfig(planner=planner))
    with pytest.raises(ValueError, match=r"occupied must be True, False or one of them per cell \(3 cells\)"):
        navigator.update_map([(1, 1), (2, 2), (3, 3)], occupied)
    navigator.update_map([(1, 1), (2, 2), (3, 3)], np.array([True, False, True]))
    navigator.update_map([(1, 1), (2, 2), (3, 3)], False)


# -- the engine's environment -------------------------------------------------------------------------------------
@pytest.mark.parametrize("arch, threads, says", [("cuda", "2", "TDP_ARCH=cuda asked for Taichi's cuda backend"),
                                                 ("gpu_please", "2", "TDP_ARCH must name a Taichi arch"),
                                                 ("cpu", "two", "TDP_THREADS must be a positive integer")])
def test_a_backend_taichi_cannot_start_is_a_clear_error_not_a_silent_cpu(arch, threads, says):
    """TDP_ARCH=cuda on a machine with no CUDA: Taichi falls back to the CPU with a warning on stderr, and the engine
    then ran as if on a GPU (every wave a parallel launch). Now a ValueError says which backend was missing; so do
    an arch Taichi does not know and a thread count that is no number. (On a machine with CUDA the first case
    starts, and is skipped.)"""
    env = dict(os.environ, TDP_ARCH=arch, TDP_THREADS=threads)
    done = subprocess.run([sys.executable, "-c", "from tdp.engine import init_taichi; init_taichi()"], cwd=ROOT,
                          env=env, capture_output=True, text=True, timeout=300)
    if arch == "cuda" and done.returncode == 0 and "falling back" not in done.stderr:
        pytest.skip("this machine has CUDA: Taichi started on it")
    assert done.returncode != 0 and f"ValueError: {says}" in done.stderr
