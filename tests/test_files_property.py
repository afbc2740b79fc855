"""Generated map files, well formed, odd or broken: each loads to the map an independent reading of the format's
rules gives, or fails with a ValueError naming the file and what is wrong - never another exception type, a hang
or a silent difference."""
import io

import numpy as np
import pytest
import yaml
from hypothesis import HealthCheck, assume, given, settings
from hypothesis import strategies as st
from PIL import Image

import tdp

SETTINGS = settings(max_examples=40, deadline=None, suppress_health_check=[HealthCheck.function_scoped_fixture])
FREE_LETTERS, BLOCKED_LETTERS = ".GS", "@OTW"  # MovingAI: ground, swamp free; out of bounds, trees, water blocked


def expect_clear_error_or(path, load, expected):
    """``load()`` either equals ``expected`` (when not None) or raises a ValueError that names the file."""
    try:
        occupied = load().occupied
    except ValueError as error:
        assert path.name in str(error)
        return None
    assert expected is not None, "a broken file loaded without an error"
    np.testing.assert_array_equal(occupied, expected)
    return occupied


# -- MovingAI .map ------------------------------------------------------------------------------------------------
@st.composite
def movingai_files(draw):
    rows, cols = draw(st.integers(1, 7)), draw(st.integers(1, 7))
    grid = [[draw(st.sampled_from(FREE_LETTERS + BLOCKED_LETTERS)) for _ in range(cols)] for _ in range(rows)]
    newline = draw(st.sampled_from(["\n", "\r\n"]))
    fault = draw(st.sampled_from(["none", "none", "truncated", "taller", "wider", "stray", "header", "bytes"]))
    header = ["type octile", f"height {rows + (fault == 'taller')}", f"width {cols + (fault == 'wider')}", "map"]
    if fault == "header":
        header[draw(st.integers(0, 3))] = draw(st.sampled_from(["", "size 3", "height x", "height -2", "map 1"]))
    lines = ["".join(r) for r in grid]
    if fault == "truncated":
        lines = lines[:draw(st.integers(0, rows - 1))]
    if fault == "stray":
        r, c = draw(st.integers(0, rows - 1)), draw(st.integers(0, cols - 1))
        lines[r] = lines[r][:c] + draw(st.sampled_from("x#1 ?")) + lines[r][c + 1:]
    text = newline.join(header + lines)
    if draw(st.booleans()):
        text += newline
    if fault == "none" and draw(st.booleans()):
        text += newline + newline + "trailing notes" + newline
    data = text.encode()
    if fault == "bytes":
        data = data[:len(data) // 2] + b"\xff\xfe" + data[len(data) // 2:]
    expected = np.array([[ch in BLOCKED_LETTERS for ch in row] for row in grid]) if fault == "none" else None
    return data, expected


@SETTINGS
@given(movingai_files())
def test_movingai_files(tmp_path, case):
    data, expected = case
    path = tmp_path / "generated.map"
    path.write_bytes(data)
    expect_clear_error_or(path, lambda: tdp.load_map(path), expected)


# -- images: PGM (binary and ASCII, 8 and 16 bits, any maxval, comments) and PNG (8 and 16 bits) ---------------------
@st.composite
def image_files(draw):
    rows, cols = draw(st.integers(1, 6)), draw(st.integers(1, 6))
    kind = draw(st.sampled_from(["P5", "P2", "PNG8", "PNG16"]))
    maxval = {"PNG8": 255, "PNG16": 65535}.get(kind) or draw(st.sampled_from([1, 15, 100, 255, 256, 1000, 65535]))
    values = np.array(draw(st.lists(st.integers(0, maxval), min_size=rows * cols, max_size=rows * cols)))
    values = values.reshape(rows, cols)
    shade = values / maxval
    assume(not np.any(np.abs(shade - 0.5) < 1e-3))  # the threshold itself: rounding may go either way
    truncated = kind in ("P5", "P2") and draw(st.integers(0, 4)) == 0
    if kind in ("PNG8", "PNG16"):
        buffer = io.BytesIO()
        Image.fromarray(values.astype(np.uint8 if kind == "PNG8" else np.uint16)).save(buffer, format="PNG")
        return ".png", buffer.getvalue(), shade < 0.5
    comment = "# made by hypothesis\n" if draw(st.booleans()) else ""
    header = f"{kind}\n{comment}{cols} {rows}\n{comment}{maxval}\n".encode()
    if kind == "P2":
        numbers = [str(v) for v in values.ravel()]
        body = " ".join(numbers[:-1] if truncated else numbers).encode() + b"\n"
    else:
        body = values.astype(">u2" if maxval > 255 else np.uint8).tobytes()
        body = body[:len(body) // 2] if truncated else body
    return ".pgm", header + body, None if truncated else shade < 0.5


@SETTINGS
@given(image_files())
def test_image_files(tmp_path, case):
    suffix, data, expected = case
    path = tmp_path / f"generated{suffix}"
    path.write_bytes(data)
    expect_clear_error_or(path, lambda: tdp.load_map(path, threshold=0.5), expected)


# -- ROS map_server YAML: every key missing or wrong ----------------------------------------------------------------
GOOD = {"image": "m.pgm", "resolution": 0.05, "origin": [1.0, -2.0, 0.0], "negate": 0, "occupied_thresh": 0.65,
        "free_thresh": 0.196, "mode": "trinary"}
WRONG = {"image": ["", 3, None, "missing.pgm"], "resolution": [0, -1, "fine", None, True],
         "origin": [[0, 0], "here", [0, "y", 0], None], "negate": [2, "yes", -1],
         "occupied_thresh": [1.5, "high", None, 0.1], "free_thresh": [-0.1, "low", 0.9, None],
         "mode": ["binary", 3]}
REQUIRED = ("image", "resolution", "origin", "occupied_thresh", "free_thresh")


@SETTINGS
@given(st.sampled_from(sorted(GOOD)), st.data())
def test_ros_yaml_keys(tmp_path, key, data):
    (tmp_path / "m.pgm").write_bytes(b"P5\n2 1\n255\n" + bytes([0, 255]))
    meta = dict(GOOD)
    if key in REQUIRED and data.draw(st.booleans()):
        del meta[key]
    else:
        meta[key] = data.draw(st.sampled_from(WRONG[key]))
    path = tmp_path / "m.yaml"
    path.write_text(yaml.safe_dump(meta))
    with pytest.raises((ValueError, FileNotFoundError)) as raised:
        tdp.load_map(path)
    assert "m.yaml" in str(raised.value) and (key in str(raised.value) or "missing.pgm" in str(raised.value))


def test_ros_yaml_that_is_not_a_mapping_or_not_yaml(tmp_path):
    for text in ("- a\n- b\n", "image: [unclosed\n", "\x00\x01"):
        path = tmp_path / "m.yaml"
        path.write_text(text)
        with pytest.raises(ValueError, match="m.yaml"):
            tdp.load_map(path)
