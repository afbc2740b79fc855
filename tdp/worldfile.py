"""World files: a dynamic world in YAML - a map, a start and a goal, moving boxes, a moving target - read into a
:class:`~tdp.world.Scenario` and written back.

```yaml
name: my-world                # optional
description: a box closes the door
map: maps/office.yaml         # any file tdp.load_map reads, relative to this file; or a mapping:
                              #   {file: ..., unknown_is_free: false, threshold: 0.5, inflate_m: 0.2,
                              #    cost_scaling_factor: 3.0, inflation_radius: 1.0,  (nav2's inflation costs)
                              #    trinary_costmap: false}  (a ROS map's graded values as costs)
                              #   {rows: 100, cols: 100, obstacles: [[r0, c0, r1, c1], ...],
                              #    resolution: 1.0, origin: [x, y, yaw]}   (a map made of rectangles)
units: cells                  # cells (default) or metres
tick_s: 0.2                   # seconds per tick (needed with metres; default 0.2)
start: [3, 3]                 # cells: [row, col]; metres: [x, y] in the map frame
goal: [96, 96]
max_ticks: 400                # optional (metres: max_s in seconds)
obstacles:
  - box: [44, 45, 48, 55]     # cells: [r0, c0, r1, c1] (rows r0..r1-1); metres: [x0, y0, x1, y1]
    waypoints: [[44, 60]]     # where the box's first corner goes next: cells [row, col] of its top-left cell,
                              # metres [x, y] of its (x0, y0) corner
    speed: 0.5                # cells per tick; metres: m/s
    appear_at: 10             # tick (metres: appear_s, seconds); optional
    vanish_at: 80             # tick (metres: vanish_s); optional
target:                       # optional: the goal moves
  waypoints: [[96, 40]]
  speed: 0.5
change_tick: 10               # optional, for metrics: when the blockage happens (metres: change_s)
blocking: 0                   # optional, for metrics: the obstacle that causes it
```

Every mistake is a ValueError naming the file, the key and what is wrong.
"""
from __future__ import annotations

import math
from pathlib import Path
from typing import Any

import numpy as np
import yaml

from . import checks
from .grid import MAX_CELLS, GridMap, load_map, rectangles
from .world import Obstacle, Scenario

UNITS = ("cells", "metres")
_TOP = {"name", "description", "map", "units", "tick_s", "start", "goal", "max_ticks", "max_s", "obstacles", "target",
        "change_tick", "change_s", "blocking"}
_MAP_FILE = {"file", "unknown_is_free", "threshold", "trinary_costmap", "inflate_m", "cost_scaling_factor",
             "inflation_radius"}
_MAP_INLINE = {"rows", "cols", "obstacles", "resolution", "origin"}
_OBSTACLE = {"cells": {"box", "waypoints", "speed", "appear_at", "vanish_at"},
             "metres": {"box", "waypoints", "speed", "appear_s", "vanish_s"}}


class _Reader:
    """Reads one world file's values, each error naming the file and the key."""

    def __init__(self, path: Path):
        self.path = path

    def fail(self, key: str, problem: str):
        raise ValueError(f"{self.path}: {key or 'the file'}: {problem}")

    def mapping(self, value, key: str, allowed: set[str]) -> dict:
        if not isinstance(value, dict):
            self.fail(key, f"expected a mapping, got {checks.shown(value)}")
        unknown = sorted(set(value) - allowed)
        if unknown:
            self.fail(f"{key}.{unknown[0]}" if key else unknown[0],
                      f"unknown key; expected one of {', '.join(sorted(allowed))}")
        return value

    def number(self, value, key: str, low: float | None = None, strict: bool = False) -> float:
        if isinstance(value, bool) or not isinstance(value, (int, float)) or not math.isfinite(value):
            self.fail(key, f"expected a finite number, got {checks.shown(value)}{checks.yaml_text_hint(value)}")
        if low is not None and (value < low or (strict and value == low)):
            self.fail(key, f"expected a number {'>' if strict else '>='} {low}, got {checks.shown(value)}")
        return float(value)

    def integer(self, value, key: str, low: int = 0) -> int:
        if isinstance(value, bool) or not isinstance(value, int) or value < low:
            self.fail(key, f"expected an integer >= {low}, got {checks.shown(value)}")
        return value

    def numbers(self, value, key: str, count: int, units: str, shape: str) -> tuple:
        """``count`` numbers (integers in cells) as a tuple, or an error showing ``shape``."""
        ok = isinstance(value, (list, tuple)) and len(value) == count and all(
            isinstance(v, (int, float)) and not isinstance(v, bool) and math.isfinite(v) for v in value)
        if not ok or (units == "cells" and not all(isinstance(v, int) for v in value)):
            kind = "integers" if units == "cells" else "numbers"
            self.fail(key, f"expected {shape} ({kind}), got {checks.shown(value)}")
        return tuple(value) if units == "cells" else tuple(float(v) for v in value)

    def pair(self, value, key: str, units: str) -> tuple:
        return self.numbers(value, key, 2, units, "a pair [row, col]" if units == "cells" else "a pair [x, y]")

    def quad(self, value, key: str, units: str) -> tuple:
        shape = "[r0, c0, r1, c1]" if units == "cells" else "[x0, y0, x1, y1]"
        return self.numbers(value, key, 4, units, shape)


def load_world(path: str | Path) -> Scenario:
    """Read a world file (see the module's documentation) into a Scenario."""
    path = checks.existing_file(checks.path(path, "path"), "world file")
    try:
        data = checks.yaml_data(path.read_text())
    except (yaml.YAMLError, UnicodeDecodeError) as error:
        raise ValueError(f"{path}: not valid YAML ({error})") from None
    read = _Reader(path)
    data = read.mapping(data, "", _TOP)
    for key in ("map", "start", "goal"):
        if key not in data:
            read.fail(key, "missing")
    units = data.get("units", "cells")
    if units not in UNITS:
        read.fail("units", f"expected one of {UNITS}, got {checks.shown(units)}")
    tick_s = read.number(data.get("tick_s", 0.2), "tick_s", 0.0, strict=True)
    grid, source = _map(read, data["map"], path.parent)
    place = _Placement(read, grid, units, tick_s)
    obstacles = [place.obstacle(o, f"obstacles[{i}]") for i, o in enumerate(_list(read, data, "obstacles"))]
    target = read.mapping(data.get("target", {}), "target", {"waypoints", "speed"})
    cells = {key: place.cell(data[key], key) for key in ("start", "goal")}
    waypoints = [place.cell(w, f"target.waypoints[{i}]") for i, w in enumerate(_list(read, target, "waypoints",
                                                                                         "target."))]
    if "target" in data and not waypoints:
        read.fail("target.waypoints", "a target needs a waypoint to walk to (leave target out for a goal that stays)")
    timing = {"change_tick": place.tick(data, "change_tick", "change_s"),
              "max_ticks": place.tick(data, "max_ticks", "max_s", low=1),
              "blocking": None if data.get("blocking") is None else read.integer(data["blocking"], "blocking")}
    target_speed = place.speed(target.get("speed", 0.5), "target.speed")
    try:
        return Scenario(grid, cells["start"], cells["goal"], obstacles=obstacles, target_waypoints=waypoints,
                        target_speed=target_speed,
                        name=checks.text(data.get("name"), "name", path.stem),
                        description=checks.text(data.get("description"), "description", ""),
                        map_source=source, tick_s=tick_s, **timing)
    except ValueError as error:
        raise ValueError(f"{path}: {error}") from None


def _list(read: _Reader, data: dict, key: str, prefix: str = "") -> list:
    value = data.get(key, [])
    if not isinstance(value, list):
        read.fail(prefix + key, f"expected a list, got {checks.shown(value)}")
    return value


def _map(read: _Reader, value, folder: Path) -> tuple[GridMap, dict]:
    """The map and the entry that reproduces it (file paths made absolute)."""
    if isinstance(value, str):
        value = {"file": value}
    if isinstance(value, dict) and "file" in value:
        spec = read.mapping(value, "map", _MAP_FILE)
        file = Path(spec["file"]) if Path(spec["file"]).is_absolute() else folder / spec["file"]
        options = {}
        for key in ("unknown_is_free", "trinary_costmap"):
            if key in spec:
                if not isinstance(spec[key], bool):
                    read.fail(f"map.{key}", f"expected true or false, got {checks.shown(spec[key])}")
                options[key] = spec[key]
        if "threshold" in spec:
            options["threshold"] = read.number(spec["threshold"], "map.threshold", 0.0, strict=True)
        try:
            grid = load_map(file, **options)
        except FileNotFoundError:
            read.fail("map.file", f"no such map file {file}")
        inflation = {key: read.number(spec[key], f"map.{key}", 0.0)
                     for key in ("cost_scaling_factor", "inflation_radius") if key in spec}
        if len(inflation) == 1:
            read.fail(f"map.{next(iter(inflation))}", "cost_scaling_factor and inflation_radius go together (nav2's "
                                                      "inflation layer)")
        if "inflate_m" in spec or inflation:
            radius_m = read.number(spec.get("inflate_m", 0.0), "map.inflate_m", 0.0)
            grid = grid.inflate(radius_m / grid.resolution, **inflation)
        return grid, {**spec, "file": str(file.resolve())}
    spec = read.mapping(value, "map", _MAP_INLINE)
    rows, cols = (read.integer(spec.get(k), f"map.{k}", 1) for k in ("rows", "cols"))
    if rows * cols > MAX_CELLS:  # as a map file's: a typo's 100000 x 100000 took all memory before any check
        read.fail("map", f"{rows} x {cols} cells is more than the {MAX_CELLS} cells tdp reads")
    occupied = np.zeros((rows, cols), bool)
    for i, box in enumerate(_list(read, spec, "obstacles", "map.")):
        r0, c0, r1, c1 = read.quad(box, f"map.obstacles[{i}]", "cells")
        occupied[max(r0, 0):max(r1, 0), max(c0, 0):max(c1, 0)] = True
    origin = spec.get("origin", [0.0, 0.0, 0.0])
    if not (isinstance(origin, list) and len(origin) in (2, 3)):
        read.fail("map.origin", f"expected [x, y] or [x, y, yaw], got {checks.shown(origin)}")
    grid = GridMap(occupied, read.number(spec.get("resolution", 1.0), "map.resolution", 0.0, strict=True),
                   tuple(read.number(v, "map.origin") for v in origin))
    return grid, None


class _Placement:
    """Turns a world file's positions, speeds and times into cells, cells per tick and ticks."""

    def __init__(self, read: _Reader, grid: GridMap, units: str, tick_s: float):
        self.read, self.grid, self.units, self.tick_s = read, grid, units, tick_s
        if units == "metres" and grid.origin[2] != 0.0:
            read.fail("units", "metres need a map whose origin has no yaw (boxes must stay axis-aligned)")

    def cell(self, value, key: str) -> tuple[int, int]:
        if self.units == "cells":
            return self.read.pair(value, key, "cells")
        return self.grid.world_to_cell(*self.read.pair(value, key, "metres"))

    def box(self, value, key: str) -> tuple[int, int, int, int]:
        if self.units == "cells":
            return self.read.quad(value, key, "cells")
        x0, y0, x1, y1 = self.read.quad(value, key, "metres")
        if not (x1 > x0 and y1 > y0):
            self.read.fail(key, f"expected x1 > x0 and y1 > y0, got {list(value)}")
        ox, oy, _ = self.grid.origin
        res, rows = self.grid.resolution, self.grid.shape[0]
        return (rows - math.ceil(round((y1 - oy) / res, 9)), math.floor(round((x0 - ox) / res, 9)),
                rows - math.floor(round((y0 - oy) / res, 9)), math.ceil(round((x1 - ox) / res, 9)))

    def corner(self, value, key: str, box_m: tuple | None) -> tuple[int, int]:
        """A waypoint: cells, the box's top-left cell; metres, where its (x0, y0) corner goes."""
        if self.units == "cells":
            return self.read.pair(value, key, "cells")
        x, y = self.read.pair(value, key, "metres")
        x0, y0, x1, y1 = box_m
        r0, c0, _, _ = self.box([x, y, x + x1 - x0, y + y1 - y0], key)
        return r0, c0

    def speed(self, value, key: str) -> float:
        speed = self.read.number(value, key, 0.0, strict=True)
        return speed if self.units == "cells" else speed * self.tick_s / self.grid.resolution

    def tick(self, data: dict, tick_key: str, seconds_key: str, low: int = 0) -> int | None:
        """A time given as ``tick_key`` in cells or ``seconds_key`` in metres, in ticks; the other units' key is an
        error (it would be ignored)."""
        given, other = (tick_key, seconds_key) if self.units == "cells" else (seconds_key, tick_key)
        if other in data:
            self.read.fail(other, f"a key of the other units (this file's units are {self.units}: give {given})")
        if self.units == "cells":
            return None if data.get(tick_key) is None else self.read.integer(data[tick_key], tick_key, low)
        if data.get(seconds_key) is None:
            return None
        return max(low, round(self.read.number(data[seconds_key], seconds_key, 0.0) / self.tick_s))

    def obstacle(self, value, key: str) -> Obstacle:
        spec = self.read.mapping(value, key, _OBSTACLE[self.units])
        if "box" not in spec:
            self.read.fail(f"{key}.box", "missing")
        box_m = None if self.units == "cells" else self.read.quad(spec["box"], f"{key}.box", "metres")
        box = self.box(spec["box"], f"{key}.box")
        waypoints = [self.corner(w, f"{key}.waypoints[{i}]", box_m)
                     for i, w in enumerate(_list(self.read, spec, "waypoints", f"{key}."))]
        for where, (r, c) in [("box", box[:2])] + [(f"waypoints[{i}]", w) for i, w in enumerate(waypoints)]:
            if r < 0 or c < 0 or r + box[2] - box[0] > self.grid.shape[0] or c + box[3] - box[1] > self.grid.shape[1]:
                self.read.fail(f"{key}.{where}", f"the box would be off the {self.grid.shape[0]} x "
                                                 f"{self.grid.shape[1]} map there (top-left cell {(r, c)})")
        try:
            return Obstacle(box=box, waypoints=waypoints, speed=self.speed(spec.get("speed", 0.5), f"{key}.speed"),
                            appear_at=self.tick(spec, "appear_at", "appear_s"),
                            vanish_at=self.tick(spec, "vanish_at", "vanish_s"))
        except ValueError as error:
            if str(error).startswith(str(self.read.path)):
                raise
            self.read.fail(key, str(error))


def world_yaml(scenario: Scenario) -> str:
    """The world file of ``scenario``, in cells: its map by file when it came from one, else as rectangles."""
    if scenario.map_source:
        map_entry: Any = dict(scenario.map_source)
    else:
        grid = scenario.grid
        map_entry = {"rows": grid.shape[0], "cols": grid.shape[1],
                     "obstacles": [list(box) for box in rectangles(grid.occupied)],
                     "resolution": grid.resolution, "origin": list(grid.origin)}
    data: dict[str, Any] = {"name": scenario.name, "description": scenario.description, "map": map_entry,
                            "units": "cells", "tick_s": scenario.tick_s,
                            "start": list(scenario.start), "goal": list(scenario.goal)}
    if scenario.max_ticks is not None:
        data["max_ticks"] = scenario.max_ticks
    data["obstacles"] = [_obstacle_entry(o) for o in scenario.obstacles]
    if scenario.target_waypoints:
        data["target"] = {"waypoints": [list(w) for w in scenario.target_waypoints], "speed": scenario.target_speed}
    for key in ("change_tick", "blocking"):
        if getattr(scenario, key) is not None:
            data[key] = getattr(scenario, key)
    return yaml.safe_dump(data, sort_keys=False, default_flow_style=None, width=118)


def _obstacle_entry(obstacle: Obstacle) -> dict:
    entry: dict[str, Any] = {"box": list(obstacle.box)}
    if obstacle.waypoints:
        entry["waypoints"] = [list(w) for w in obstacle.waypoints]
    entry["speed"] = obstacle.speed
    for key in ("appear_at", "vanish_at"):
        if getattr(obstacle, key) is not None:
            entry[key] = getattr(obstacle, key)
    return entry
