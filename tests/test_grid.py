"""Map formats: MovingAI .map/.scen, ROS map_server YAML + PGM/PNG, plain images; inflation and frames."""
import numpy as np
import pytest
from PIL import Image

import tdp
from tdp.grid import ros_occupancy


def test_nav2_testmap_loads_to_the_published_occupancy(data_dir):
    grid = tdp.load_map(data_dir / "nav2_testmap" / "testmap.yaml")
    lines = [l for l in (data_dir / "nav2_testmap" / "expected_occupancy.txt").read_text().splitlines()
             if l and not l.startswith("#")]
    expected_bottom_first = np.array([[int(v) for v in l.split()] for l in lines])
    np.testing.assert_array_equal(grid.occupied, expected_bottom_first[::-1] == 100)
    assert grid.resolution == 0.1
    assert grid.origin == (2.0, 3.0, 1.0)


def test_nav2_testmap_values_equal_map_servers(data_dir):
    values = ros_occupancy(data_dir / "nav2_testmap" / "testmap.pgm", "trinary", False, 0.65, 0.196)
    lines = [l for l in (data_dir / "nav2_testmap" / "expected_occupancy.txt").read_text().splitlines()
             if l and not l.startswith("#")]
    np.testing.assert_array_equal(values[::-1], np.array([[int(v) for v in l.split()] for l in lines]))


def test_turtlebot3_world_keeps_resolution_and_origin(data_dir):
    grid = tdp.load_map(data_dir / "turtlebot3_world" / "map.yaml")
    assert grid.shape == (384, 384)
    assert grid.resolution == pytest.approx(0.05)
    assert grid.origin == (-10.0, -10.0, 0.0)
    # The origin is the lower-left corner of the lower-left cell.
    assert grid.world_to_cell(-10.0 + 1e-9, -10.0 + 1e-9) == (383, 0)
    assert grid.cell_to_world(383, 0) == pytest.approx((-9.975, -9.975))
    assert grid.world_to_cell(0.0, 0.0) == (183, 200)
    free = int((~grid.occupied).sum())
    assert 0 < free < grid.occupied.size
    assert int((~tdp.load_map(data_dir / "turtlebot3_world" / "map.yaml", unknown_is_free=True).occupied).sum()) > free


@pytest.mark.parametrize("cell", [(0, 0), (3, 7), (9, 9)])
def test_world_and_cell_round_trip_with_yaw(data_dir, cell):
    grid = tdp.load_map(data_dir / "nav2_testmap" / "testmap.yaml")  # yaw 1.0 rad
    assert grid.world_to_cell(*grid.cell_to_world(*cell)) == cell


def write(path, text):
    path.write_text(text)
    return path


def test_ascii_pgm_with_comments_and_negate(tmp_path):
    write(tmp_path / "m.pgm", "P2\n# a comment\n3 2\n# another\n255\n0 255 128\n255 0 255\n")
    write(tmp_path / "m.yaml", "image: m.pgm\nresolution: 0.5\norigin: [0, 0, 0]\nnegate: 0\n"
          "occupied_thresh: 0.65\nfree_thresh: 0.196\n")
    grid = tdp.load_map(tmp_path / "m.yaml")
    np.testing.assert_array_equal(grid.occupied, [[True, False, True], [False, True, False]])  # 128: unknown
    assert tdp.load_map(tmp_path / "m.yaml", unknown_is_free=True).occupied[0, 2] == False  # noqa: E712
    write(tmp_path / "n.yaml", "image: m.pgm\nresolution: 0.5\norigin: [0, 0, 0]\nnegate: 1\n"
          "occupied_thresh: 0.65\nfree_thresh: 0.196\n")
    np.testing.assert_array_equal(tdp.load_map(tmp_path / "n.yaml", unknown_is_free=True).occupied,
                                  [[False, True, False], [True, False, True]])


def test_scale_and_raw_modes_follow_map_server(tmp_path):
    pixels = np.array([[0, 100, 200, 255]], np.uint8)
    Image.fromarray(pixels).save(tmp_path / "g.png")
    # occ = 1 - v/255 = 1, .608, .216, 0 -> scale: 100, rint((.608-.196)/(.65-.196)*100) = 91, 4, 0
    np.testing.assert_array_equal(ros_occupancy(tmp_path / "g.png", "scale", False, 0.65, 0.196), [[100, 91, 4, 0]])
    # raw: the pixel value itself when <= 100, unknown above
    np.testing.assert_array_equal(ros_occupancy(tmp_path / "g.png", "raw", False, 0.65, 0.196), [[0, 100, -1, -1]])
    rgba = np.zeros((1, 2, 4), np.uint8)
    rgba[..., :3] = 255
    rgba[0, 0, 3] = 255
    Image.fromarray(rgba, "RGBA").save(tmp_path / "a.png")
    np.testing.assert_array_equal(ros_occupancy(tmp_path / "a.png", "scale", False, 0.65, 0.196), [[0, -1]])


def test_scale_and_raw_maps_give_costs_as_nav2s_static_layer_reads_them_without_trinary_costmap(tmp_path, data_dir):
    Image.fromarray(np.array([[0, 100, 200, 255]], np.uint8)).save(tmp_path / "g.png")
    for mode in ("scale", "raw"):
        write(tmp_path / f"{mode}.yaml", f"image: g.png\nresolution: 0.05\norigin: [1.0, 2.0, 0.0]\nmode: {mode}\n"
              "occupied_thresh: 0.65\nfree_thresh: 0.196\n")
    # scale occupancy 100, 91, 4, 0 (above): 100 lethal; 91 -> trunc(0.91 x 254) = 231, 4 -> 10, 0 -> 0; NavFn's
    # 1 + 0.8 c / 50 then gives the traversal cost
    scale = tdp.load_map(tmp_path / "scale.yaml", trinary_costmap=False)
    assert scale.occupied.tolist() == [[True, False, False, False]]
    assert scale.cost[0, 1:].tolist() == pytest.approx([1 + 0.8 * 231 / 50, 1 + 0.8 * 10 / 50, 1.0])
    assert scale.resolution == 0.05 and scale.origin[:2] == (1.0, 2.0)
    assert tdp.load_map(tmp_path / "scale.yaml").occupied.tolist() == [[True, True, True, False]]  # band: unknown
    # raw occupancy 0, 100, -1, -1: free, lethal, unknown (an obstacle unless unknown_is_free, then free ground)
    raw = tdp.load_map(tmp_path / "raw.yaml", trinary_costmap=False)
    assert raw.occupied.tolist() == [[False, True, True, True]]
    free = tdp.load_map(tmp_path / "raw.yaml", trinary_costmap=False, unknown_is_free=True)
    assert free.occupied.tolist() == [[False, True, False, False]] and free.cost[0, 2] == 1.0
    np.testing.assert_array_equal(tdp.grid.occupancy_costmap(np.array([-1, 0, 1, 50, 99, 100])),
                                  [255, 0, 2, 127, 251, 254])
    with pytest.raises(ValueError, match="trinary_costmap"):
        tdp.load_map(data_dir / "arena.map", trinary_costmap=False)


def test_plain_image_threshold(tmp_path):
    Image.fromarray(np.array([[0, 90, 200]], np.uint8)).save(tmp_path / "i.png")
    np.testing.assert_array_equal(tdp.load_map(tmp_path / "i.png").occupied, [[True, True, False]])
    np.testing.assert_array_equal(tdp.load_map(tmp_path / "i.png", threshold=0.3).occupied, [[True, False, False]])


def test_movingai_map_letters(tmp_path):
    """The format's terrain rules: swamp (S) is passable from ordinary ground, water (W) is not; '@', 'O' and 'T'
    are blocked. (Swamp was read as blocked before.)"""
    path = write(tmp_path / "t.map", "type octile\r\nheight 2\r\nwidth 4\r\nmap\r\n.G@T\r\nOSW.")
    np.testing.assert_array_equal(tdp.load_map(path).occupied, [[False, False, True, True], [True, False, True, False]])


def test_movingai_unknown_terrain_letter_is_an_error_naming_line_and_column(tmp_path):
    path = write(tmp_path / "t.map", "type octile\nheight 2\nwidth 3\nmap\n...\n.x.\n")
    with pytest.raises(ValueError, match=r"line 6, column 2: unknown terrain 'x'"):
        tdp.load_map(path)


def test_scen_tolerates_crlf_no_final_newline_and_trailing_text(tmp_path):
    row = "0\tmaps/x.map\t4\t2\t0\t0\t3\t1\t3.41421"
    path = write(tmp_path / "a.scen", f"version 1\r\n{row}\r\n{row}\r\n\r\n\r\nsome notes\r\nmore")
    problems = tdp.load_scenarios(path)
    assert len(problems) == 2
    start, goal, length = problems[0]
    assert (start, goal, length) == ((0, 0), (1, 3), pytest.approx(3.41421))
    assert tdp.load_scenarios(write(tmp_path / "b.scen", f"version 1\n{row}")) == problems[:1]


def test_inflate_grows_obstacles_by_a_disk():
    occupied = np.zeros((9, 9), bool)
    occupied[4, 4] = True
    inflated = tdp.GridMap(occupied).inflate(2).occupied
    rows, cols = np.indices((9, 9))
    np.testing.assert_array_equal(inflated, (rows - 4) ** 2 + (cols - 4) ** 2 <= 4)
    assert tdp.GridMap(occupied).inflate(1.5).occupied.sum() == 9
    assert tdp.GridMap(occupied).inflate(0).occupied.sum() == 1


def test_gridmap_is_read_only_and_validated():
    grid = tdp.GridMap(np.zeros((2, 3), bool), resolution=0.05, origin=(1.0, 2.0))
    assert grid.shape == (2, 3) and grid.origin == (1.0, 2.0, 0.0)
    with pytest.raises(ValueError):
        grid.occupied[0, 0] = True
    with pytest.raises(ValueError, match="bool"):
        tdp.GridMap(np.zeros((2, 2)))
    with pytest.raises(ValueError, match="2-D"):
        tdp.GridMap(np.zeros(4, bool))
    with pytest.raises(ValueError, match="resolution"):
        tdp.GridMap(np.zeros((2, 2), bool), resolution=0)
    with pytest.raises(ValueError, match="radius_cells"):
        grid.inflate(-1)


MAP_HEADER = "type octile\nheight 2\nwidth 3\nmap\n"
YAML = "image: m.pgm\nresolution: 0.5\norigin: [0, 0, 0]\nnegate: 0\noccupied_thresh: 0.65\nfree_thresh: 0.196\n"


@pytest.mark.parametrize("name, text, message", [
    ("a.map", "type octile\nheight 2\nwidth 3\nmap\n...\n", "truncated"),
    ("b.map", "type octile\nheight 2\n", "truncated header"),
    ("c.map", "type octile\nwidth 3\nheight 2\nmap\n...\n...\n", "expected 'height"),
    ("d.map", "type octile\nheight two\nwidth 3\nmap\n...\n...\n", "positive integer"),
    ("e.map", MAP_HEADER + "...\n....\n", "line 6: row has 4 cells"),
    ("f.map", MAP_HEADER + "...\n...\n...\n", "more than"),
    ("g.scen", "0\tm\t1\t1\t0\t0\t0\t0\t0\n", "version"),
    ("h.scen", "version 1\n0\tm\t1\t1\t0\t0\t0\n", "line 2: expected 9"),
    ("i.scen", "version 1\n0\tm\t1\t1\t0\tx\t0\t0\t0\n", "line 2: fields"),
    ("j.yaml", "resolution: 0.5\n", "missing key 'image'"),
    ("k.yaml", YAML.replace("negate: 0", "mode: fancy"), "unknown mode 'fancy'"),
    ("l.yaml", YAML.replace("0.196", "0.9"), "free_thresh"),
    ("m.yaml", YAML.replace("0.5", "-1"), "resolution"),
    ("n.yaml", YAML.replace("[0, 0, 0]", "[0, 0]"), "origin"),
    ("o.yaml", "image: [unclosed\n", "not valid YAML"),
    ("p.txt", "hello", "unknown map format"),
    ("q.png", "not a png", "cannot read image"),
])
def test_bad_files_raise_errors_naming_file_and_problem(tmp_path, name, text, message):
    path = write(tmp_path / name, text)
    with pytest.raises(ValueError, match=message) as error:
        tdp.load_scenarios(path) if name.endswith(".scen") else tdp.load_map(path)
    assert name in str(error.value) or name.endswith(".txt")


def test_missing_files_raise_file_not_found(tmp_path):
    with pytest.raises(FileNotFoundError, match="nowhere.map"):
        tdp.load_map(tmp_path / "nowhere.map")
    with pytest.raises(FileNotFoundError, match="nowhere.scen"):
        tdp.load_scenarios(tmp_path / "nowhere.scen")
    write(tmp_path / "y.yaml", YAML)
    with pytest.raises(FileNotFoundError, match="m.pgm"):
        tdp.load_map(tmp_path / "y.yaml")


def test_an_image_name_too_long_for_the_file_system_is_a_clear_error(tmp_path):
    """The image's is_file() raised the file system's OSError (name too long), and the message held the whole name."""
    write(tmp_path / "y.yaml", YAML.replace("m.pgm", "y" * 3000 + ".pgm"))
    with pytest.raises(ValueError, match=r"y.yaml: image 'y{50,60}\.\.\.: File name too long"):
        tdp.load_map(tmp_path / "y.yaml")


def test_truncated_pgm_is_a_clear_error(tmp_path, data_dir):
    data = (data_dir / "nav2_testmap" / "testmap.pgm").read_bytes()
    (tmp_path / "m.pgm").write_bytes(data[:40])
    write(tmp_path / "m.yaml", YAML)
    with pytest.raises(ValueError, match="m.pgm"):
        tdp.load_map(tmp_path / "m.yaml")


def test_scenario_checked_against_its_map(tmp_path, data_dir):
    grid = tdp.load_map(data_dir / "arena.map")
    bad_size = write(tmp_path / "s.scen", "version 1\n0\tarena.map\t50\t49\t1\t11\t1\t12\t1\n")
    with pytest.raises(ValueError, match="does not match"):
        tdp.load_scenarios(bad_size, grid)
    blocked = write(tmp_path / "t.scen", "version 1\n0\tarena.map\t49\t49\t0\t0\t1\t12\t1\n")
    with pytest.raises(ValueError, match="start .* obstacle"):
        tdp.load_scenarios(blocked, grid)
    outside = write(tmp_path / "u.scen", "version 1\n0\tarena.map\t49\t49\t1\t11\t1\t99\t1\n")
    with pytest.raises(ValueError, match="goal .* outside"):
        tdp.load_scenarios(outside, grid)
