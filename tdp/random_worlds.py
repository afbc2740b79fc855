"""Seeded random dynamic worlds in eight families, for benchmarks and quick worlds on any size.

Each family stresses one thing the planner must get right (sizes in cells scale with the map's side ``size``):

* ``cluttered``: static clutter and 3-6 boxes sliding back and forth a cell clear of the clutter, over open
  ground: no route is ever cut, so a blockage detection there is suspect unless a box really closed a gap.
* ``rooms``: a 3 x 3 grid of rooms with a door in every wall; a box closes a door on the robot's route (drawn
  among those more than a fifth of the side from the start) while it drives, and in half the worlds a second box
  closes a door on the detour a little later.
* ``corridor``: a long corridor between two halls and a longer side route; a box drives out of an alcove into the
  corridor ahead of the robot and parks there for good.
* ``clearing``: a wall with a short passage, plugged, and a long one; the plug vanishes mid-journey.
* ``moving-target``: the target walks a free street among clutter and sliding boxes.
* ``crossing``: one or two boxes keep crossing the robot's route near its middle, back and forth.
* ``passing``: one or two pairs of boxes shuttle across the route in neighbouring lanes 0-1 cell apart, passing each
  other the other way or overtaking: boxes that touch and part again, where a tracker must tell one from the other
  (two pairs sweep a cell clear of each other).
* ``wandering``: small boxes drive to and fro across the middle of the robot's route through random waypoints near
  it, turning at any angle at each (a warehouse's carts; every other family's boxes run on a line and turn only
  back), and may cross each other's ways.

``make_world(family, size, seed)`` is deterministic: the same arguments give the same :class:`~tdp.world.Scenario`.
``maze(size, corridor, seed, loops)`` draws a perfect (or, with ``loops``, braided) maze's occupancy, a static map for
benchmarks and tests.
"""
from __future__ import annotations

import math
import warnings

import numpy as np

from . import checks
from .engine import MAX_MAP_SIDE
from .field import DistanceField
from .grid import GridMap
from .world import Obstacle, Scenario

FAMILIES = ("cluttered", "rooms", "corridor", "clearing", "moving-target", "crossing", "passing", "wandering")
#: Metres per cell of the generated maps (as in the named scenarios: a robot at 0.5 m/s crosses a cell per 0.2 s
#: tick).
CELL_M = 0.1
#: The tick of the worlds made here, in seconds per metre of a cell: 0.2 s on CELL_M, the time a robot at 0.5 m/s
#: takes to cross a cell, so that boxes at 0.3-0.6 cells a tick move at a third to a half of its speed on any map.
TICK_S_PER_M = 2.0
#: A quick world's tick limit in ticks per move of the shortest route on its map without boxes (boxes_on_map): room to
#: wait for boxes and to go round them, as a random world's 6 x size is about 4 times its route.
ROUTE_TICKS = 4
#: The generator's version, part of a sweep's key for a family's world: a journal's episodes on worlds an earlier
#: version drew are run again, not read as this one's. 2 (2026-11-30): the clutter's count no longer grows with the
#: map's area while its pieces grow with its side (at 500 cells a side cluttered worlds were 68 % obstacles, without
#: room for a single box; clearing worlds of 1,500 could not be drawn; below 100, a count times 0, none at all).
GENERATION = 2
#: The first number of boxes_on_map's random stream (a family's is its index in FAMILIES): 6, the count of families
#: when it was written, kept so that its worlds stay as they were.
_QUICK_STREAM = 6
#: Waypoints a wandering box draws for its next leg before it stops where it is (``_wanderer``).
WANDER_TRIES = 20
#: Families whose worlds contain a change that cuts or opens a route (the others never cut one).
CUTTING = ("rooms", "corridor", "clearing")


def _map_side(size, least: int) -> int:
    """``size`` as a map's side in cells, an integer from ``least`` to the engine's largest map side (MAX_MAP_SIDE:
    past it numpy's own error, in a world's draw read as "no valid world" after 100 draws, or a MemoryError)."""
    size = checks.integer(size, "size", least)
    if size > MAX_MAP_SIDE:
        raise ValueError(f"size must be at most {MAX_MAP_SIDE} cells (the engine's largest map), got {size}")
    return size


def make_world(family: str, size: int = 100, seed: int = 0) -> Scenario:
    """A random world of ``family`` on a ``size`` x ``size`` map, from ``seed``; ``max_ticks`` is 6 x size.

    Raises:
        ValueError: an unknown family, ``size`` not an integer from 60 to the engine's largest map side
            (``MAX_MAP_SIDE``), ``seed`` not an integer >= 0.
    """
    if family not in FAMILIES:
        raise ValueError(f"unknown world family {family!r}; choose one of {', '.join(FAMILIES)}")
    size, seed = _map_side(size, 60), checks.integer(seed, "seed", 0)
    rng = np.random.default_rng([FAMILIES.index(family), size, seed])
    for _ in range(100):
        try:
            scenario = _BUILDERS[family](size, rng)
        except (_Redraw, ValueError):  # ValueError: the Scenario found its start or goal covered
            continue
        scenario.name = f"{family}-{size}-{seed}"
        scenario.max_ticks = 6 * size
        if _route(scenario.occupancy(0), scenario.start, scenario.goal) and _route(
                scenario.occupancy(scenario.max_ticks), scenario.start, scenario.target(scenario.max_ticks)):
            return scenario
    raise RuntimeError(f"no valid {family} world of size {size} from seed {seed} in 100 draws")


def maze(size: int, corridor: int = 1, seed: int = 0, loops: float = 0.0) -> np.ndarray:
    """A perfect maze (one way between any two places) as a bool (size, size) occupancy map, True = wall: a
    recursive backtracker over a lattice of rooms ``corridor`` cells wide, walls 1 cell thick, the map's border a
    wall. The worst case for a converge in rounds of tiles: a tile holds pieces of corridors at very different
    distances from a goal (a 1-cell maze of side 512 has routes of 26,000+ cells). With ``loops`` > 0, a braided
    maze: that share of the walls the backtracker left between neighbouring rooms (a perfect maze of n x n rooms
    leaves (n - 1)² of them) is knocked through at random afterwards, each one a loop - a blocked corridor then has a
    way round, as in a building's corridors or a game's braided mazes.

    Raises:
        ValueError: ``size`` not an integer from ``corridor + 2`` to the engine's largest map side
            (``MAX_MAP_SIDE``), ``corridor`` less than 1, ``seed`` not an integer >= 0, or ``loops`` not a number in
            [0, 1].

    Examples:
        >>> occupied = maze(9, corridor=1, seed=0)
        >>> occupied.shape, bool(occupied[0].all()), bool(occupied[1, 1])
        ((9, 9), True, False)
        >>> int((maze(41, seed=0, loops=1.0) < maze(41, seed=0)).sum())  # 20 x 20 rooms: every (20 - 1)² wall through
        361
    """
    corridor = checks.integer(corridor, "corridor", 1)
    size, seed = _map_side(size, corridor + 2), checks.integer(seed, "seed", 0)
    loops = checks.number(loops, "loops", 0.0, high=1.0)
    pitch = corridor + 1
    rooms = (size - 1) // pitch
    occupied = np.ones((size, size), bool)
    rng = np.random.default_rng(seed)
    seen = np.zeros((rooms, rooms), bool)

    def open_room(r: int, c: int) -> None:
        occupied[1 + r * pitch:1 + r * pitch + corridor, 1 + c * pitch:1 + c * pitch + corridor] = False

    def open_between(r: int, c: int, nr: int, nc: int) -> None:
        top, left = 1 + min(r, nr) * pitch, 1 + min(c, nc) * pitch
        occupied[top:top + corridor + (nr != r) * pitch, left:left + corridor + (nc != c) * pitch] = False

    stack = [(0, 0)]
    seen[0, 0] = True
    open_room(0, 0)
    while stack:
        r, c = stack[-1]
        options = [(r + dr, c + dc) for dr, dc in ((1, 0), (-1, 0), (0, 1), (0, -1))
                   if 0 <= r + dr < rooms and 0 <= c + dc < rooms and not seen[r + dr, c + dc]]
        if not options:
            stack.pop()
            continue
        nr, nc = options[rng.integers(len(options))]
        seen[nr, nc] = True
        open_between(r, c, nr, nc)
        stack.append((nr, nc))
    standing = [(r, c, r + dr, c + dc) for r in range(rooms) for c in range(rooms) for dr, dc in ((1, 0), (0, 1))
                if r + dr < rooms and c + dc < rooms
                and occupied[1 + r * pitch + dr * corridor, 1 + c * pitch + dc * corridor]]
    for k in rng.permutation(len(standing))[:round(loops * len(standing))]:
        open_between(*standing[k])
    return occupied


class _Redraw(Exception):
    """A draw that does not make a valid world of its family: draw again from the same generator."""


# ------------------------------------------------------------------------------------------------------- helpers
def _scaled(size: int, cells: float) -> int:
    """``cells`` at size 100, scaled to ``size``, at least 1."""
    return max(1, int(round(cells * size / 100)))


def _near(rng, size: int, centre: tuple[float, float], spread: float) -> tuple[int, int]:
    """A random cell within ``spread`` x size of ``centre`` (fractions of the side), inside the map."""
    r, c = (int(np.clip((v + rng.uniform(-spread, spread)) * size, 1, size - 2)) for v in centre)
    return r, c


def _clear(occupied: np.ndarray, cell: tuple[int, int], radius: int) -> None:
    r, c = cell
    occupied[max(0, r - radius):r + radius + 1, max(0, c - radius):c + radius + 1] = False


def _clutter(rng, size: int, count: int, keep_free: list[tuple[int, int]]) -> np.ndarray:
    """``count`` random static rectangles of side 4-10 cells (scaled), none within 4 cells of ``keep_free``."""
    occupied = np.zeros((size, size), bool)
    for _ in range(count):
        h, w = (int(rng.integers(_scaled(size, 4), _scaled(size, 10) + 1)) for _ in range(2))
        r, c = int(rng.integers(0, size - h)), int(rng.integers(0, size - w))
        occupied[r:r + h, c:c + w] = True
    for cell in keep_free:
        _clear(occupied, cell, _scaled(size, 4))
    return occupied


def _band(shape: tuple[int, int], box: tuple[int, int, int, int], corners: list[tuple[int, int]],
          margin: int) -> np.ndarray:
    """bool mask of the cells a box sweeps between its corners (straight segments), grown by ``margin``."""
    h, w = box[2] - box[0], box[3] - box[1]
    mask = np.zeros(shape, bool)
    for (r0, c0), (r1, c1) in zip(corners, corners[1:]):
        steps = max(abs(r1 - r0), abs(c1 - c0), 1)
        for t in np.linspace(0.0, 1.0, steps + 1):
            r, c = int(round(r0 + t * (r1 - r0))), int(round(c0 + t * (c1 - c0)))
            mask[max(0, r - margin):max(0, r + h + margin), max(0, c - margin):max(0, c + w + margin)] = True
    return mask


def _shuttle(a: tuple[int, int], b: tuple[int, int], size: int, speed: float) -> list[tuple[int, int]]:
    """Waypoints going b, a, b, a, ... often enough to last 6 x size ticks at ``speed``."""
    length = max(1.0, math.dist(a, b))
    return [b, a] * (int(6 * size * speed / (2 * length)) + 2)


def _sliding_boxes(rng, size: int, count: int, blocked: np.ndarray, speeds=(0.3, 0.8)) -> list[Obstacle]:
    """Up to ``count`` boxes of side 3-8 (scaled) shuttling straight across the middle of the map, each sweep
    clear of ``blocked`` by a cell (boxes may cross each other's sweeps, and pass over lattice nodes)."""
    boxes = []
    for _ in range(40 * count):
        if len(boxes) == count:
            break
        side = int(rng.integers(_scaled(size, 3), _scaled(size, 8) + 1))
        r, c = (int(rng.integers(int(0.1 * size), int(0.9 * size) - side)) for _ in range(2))
        length = int(rng.integers(int(0.2 * size), int(0.5 * size)))
        if rng.random() < 0.5:
            end = (r, int(np.clip(c + length * rng.choice([-1, 1]), 0, size - side)))
        else:
            end = (int(np.clip(r + length * rng.choice([-1, 1]), 0, size - side)), c)
        box = (r, c, r + side, c + side)
        if (_band(blocked.shape, box, [(r, c), end], 1) & blocked).any():
            continue
        speed = float(rng.uniform(*speeds))
        boxes.append(Obstacle(box=box, waypoints=_shuttle((r, c), end, size, speed), speed=speed))
    return boxes


def _route(occupied: np.ndarray, start: tuple[int, int], goal: tuple[int, int]) -> list[tuple[int, int]]:
    """The shortest path from start to goal on a static map ([] if there is none)."""
    field = DistanceField(GridMap(occupied), goal)
    field.converge()
    return field.path(start)


def _keep_free(shape: tuple[int, int], cells: list[tuple[int, int]], radius: int) -> np.ndarray:
    """bool mask of the squares of ``radius`` around ``cells`` on a map of ``shape``."""
    mask = np.zeros(shape, bool)
    for r, c in cells:
        mask[max(0, r - radius):r + radius + 1, max(0, c - radius):c + radius + 1] = True
    return mask


# ------------------------------------------------------------------------------------------------------ families
def _cluttered(size: int, rng) -> Scenario:
    start, goal = _near(rng, size, (0.06, 0.06), 0.04), _near(rng, size, (0.94, 0.94), 0.04)
    occupied = _clutter(rng, size, int(rng.integers(6, 12)), [start, goal])
    boxes = _sliding_boxes(rng, size, int(rng.integers(3, 7)), occupied | _keep_free((size, size), [start, goal], 6))
    return Scenario(GridMap(occupied, CELL_M), start, goal, obstacles=boxes,
                    description="clutter and sliding boxes; no route is ever cut")


def _rooms(size: int, rng) -> Scenario:
    rooms, wall = 3, _scaled(size, 2)
    edges = [int(round(k * size / rooms)) for k in range(rooms + 1)]
    occupied = np.zeros((size, size), bool)
    doors = []
    for k in edges[1:-1]:
        occupied[k - wall // 2:k - wall // 2 + wall, :] = True
        occupied[:, k - wall // 2:k - wall // 2 + wall] = True
    for k in edges[1:-1]:
        for a, b in zip(edges, edges[1:]):
            width = int(rng.integers(_scaled(size, 4), _scaled(size, 7) + 1))
            offset = int(rng.integers(a + wall + 2, b - wall - 2 - width))
            for door in ((k - wall // 2, offset, k - wall // 2 + wall, offset + width),
                         (offset, k - wall // 2, offset + width, k - wall // 2 + wall)):
                occupied[door[0]:door[2], door[1]:door[3]] = False
                doors.append(door)
    start = _near(rng, size, (0.15, 0.15), 0.1)
    goal = _near(rng, size, (0.85, 0.85), 0.1)
    for cell in (start, goal):
        _clear(occupied, cell, 1)
    route = _route(occupied, start, goal)
    obstacles, closed = [], occupied.copy()
    first = _door_on(route, doors, start, 0.2 * size, rng)
    if first is None:
        raise _Redraw
    tick = int(rng.integers(5, int(0.15 * size)))
    obstacles.append(Obstacle(box=first, appear_at=tick))
    closed[first[0]:first[2], first[1]:first[3]] = True
    if rng.random() < 0.5:
        detour = _route(closed, start, goal)
        second = _door_on(detour, [d for d in doors if d != first], start, 0.2 * size, rng)
        if second is not None:
            closed[second[0]:second[2], second[1]:second[3]] = True
            if _route(closed, start, goal):
                obstacles.append(Obstacle(box=second, appear_at=tick + int(rng.integers(5, int(0.25 * size)))))
    return Scenario(GridMap(occupied, CELL_M), start, goal, obstacles=obstacles, change_tick=tick, blocking=0,
                    description="rooms whose doors close on the robot's route (sometimes a second on the detour)")


def _door_on(route, doors, start, beyond: float, rng):
    """A random door among those the route passes through more than ``beyond`` cells (straight line) from the
    start (None if there is none)."""
    passed = []
    for r, c in route:
        if math.dist((r, c), start) > beyond:
            passed += [d for d in doors if d[0] <= r < d[2] and d[1] <= c < d[3] and d not in passed]
    return passed[int(rng.integers(len(passed)))] if passed else None


def _corridor(size: int, rng) -> Scenario:
    hall = int(0.2 * size)
    width = int(rng.integers(_scaled(size, 5), _scaled(size, 8) + 1))
    occupied = np.ones((size, size), bool)
    occupied[:, :hall] = occupied[:, size - hall:] = False
    main = int(rng.integers(int(0.4 * size), int(0.6 * size) - width))
    occupied[main:main + width, :] = False
    side_on_top = bool(rng.random() < 0.5)
    side = int(rng.integers(int(0.06 * size), int(0.15 * size)))
    side = side if side_on_top else size - side - width
    occupied[side:side + width, :] = False
    park = int(rng.integers(hall + int(0.3 * (size - 2 * hall)), hall + int(0.7 * (size - 2 * hall)) - width))
    alcove = main + width + 1 if side_on_top else main - width - 1
    occupied[min(alcove, main + width):max(alcove + width, main), park:park + width] = False
    start = (int(np.clip(main + width // 2 + rng.integers(-int(0.15 * size), int(0.15 * size)), 1, size - 2)),
             int(rng.integers(2, hall - 2)))
    goal = (int(np.clip(main + width // 2 + rng.integers(-int(0.15 * size), int(0.15 * size)), 1, size - 2)),
            int(rng.integers(size - hall + 2, size - 2)))
    arrive = math.dist(start, (main, park))  # ticks for the robot to reach the parking place, about
    parking = 2 * (width + 1)  # ticks the box needs at 0.5 cells per tick
    latest = max(6, int(arrive) - parking - 10)
    appear = int(rng.integers(min(5, latest - 1), latest))
    box = Obstacle(box=(alcove, park, alcove + width, park + width), waypoints=[(main, park)], speed=0.5,
                   appear_at=appear)
    return Scenario(GridMap(occupied, CELL_M), start, goal, obstacles=[box], change_tick=appear + parking, blocking=0,
                    description="a box drives out of an alcove and parks in the corridor; a longer side route")


def _clearing(size: int, rng) -> Scenario:
    start, goal = _near(rng, size, (0.08, 0.3), 0.06), _near(rng, size, (0.92, 0.7), 0.06)
    occupied = _clutter(rng, size, int(rng.integers(3, 7)), [start, goal])
    row, thick = int(rng.integers(int(0.35 * size), int(0.65 * size))), _scaled(size, 3)
    occupied[row:row + thick, :] = True
    short = int(rng.integers(int(0.35 * size), int(0.65 * size)))
    width = int(rng.integers(_scaled(size, 5), _scaled(size, 9) + 1))
    long_col = int(rng.integers(2, int(0.1 * size))) if rng.random() < 0.5 else size - 2 - width - int(
        rng.integers(0, int(0.1 * size)))
    for col in (short, long_col):
        occupied[row - _scaled(size, 3):row + thick + _scaled(size, 3), col:col + width] = False
    plug = Obstacle(box=(row, short, row + thick, short + width), vanish_at=int(rng.integers(int(0.1 * size),
                                                                                          int(0.4 * size))))
    return Scenario(GridMap(occupied, CELL_M), start, goal, obstacles=[plug], change_tick=plug.vanish_at, blocking=0,
                    description="a plugged short passage opens mid-journey; a long one is always open")


def _moving_target(size: int, rng) -> Scenario:
    start = _near(rng, size, (0.08, 0.08), 0.05)
    points = [_near(rng, size, (0.6, 0.6), 0.3) for _ in range(int(rng.integers(2, 5)))]
    street = _band((size, size), (0, 0, 1, 1), points, _scaled(size, 2))
    occupied = _clutter(rng, size, int(rng.integers(5, 10)), [start]) & ~street
    boxes = _sliding_boxes(rng, size, int(rng.integers(2, 4)),
                           occupied | _band((size, size), (0, 0, 1, 1), points, _scaled(size, 4))
                           | _keep_free((size, size), [start], 6))
    return Scenario(GridMap(occupied, CELL_M), start, points[0], obstacles=boxes, target_waypoints=points[1:],
                    target_speed=float(rng.uniform(0.25, 0.45)),
                    description="the target walks a free street among clutter and sliding boxes")


def _corner_to_corner(size: int, rng) -> tuple[tuple[int, int], tuple[int, int], np.ndarray, list]:
    """A start and a goal near opposite corners, light clutter and the shortest route between them: (start, goal,
    occupied, route)."""
    start, goal = _near(rng, size, (0.08, 0.08), 0.05), _near(rng, size, (0.92, 0.92), 0.05)
    occupied = _clutter(rng, size, int(rng.integers(3, 7)), [start, goal])
    route = _route(occupied, start, goal)
    if not route:
        raise _Redraw
    return start, goal, occupied, route


def _crossing(size: int, rng) -> Scenario:
    start, goal, occupied, route = _corner_to_corner(size, rng)
    boxes = []
    for fraction in sorted(rng.uniform(0.3, 0.7, int(rng.integers(1, 3)))):
        k = int(fraction * (len(route) - 1))
        (r0, c0), (r1, c1) = route[max(0, k - 3)], route[min(len(route) - 1, k + 3)]
        normal = np.array([c1 - c0, -(r1 - r0)], float)
        normal /= max(1e-9, np.linalg.norm(normal))
        side = int(rng.integers(_scaled(size, 3), _scaled(size, 5) + 1))
        reach = float(rng.uniform(0.08, 0.14)) * size
        centre = np.array(route[k], float) - side / 2
        a = tuple(int(v) for v in np.clip(np.round(centre - reach * normal), 0, size - side))
        b = tuple(int(v) for v in np.clip(np.round(centre + reach * normal), 0, size - side))
        speed = float(rng.uniform(0.5, 0.8))
        box = (a[0], a[1], a[0] + side, a[1] + side)
        if (_band((size, size), box, [a, b], 1) & (_keep_free((size, size), [start, goal], 4) | occupied)).any():
            continue
        boxes.append(Obstacle(box=box, waypoints=_shuttle(a, b, size, speed), speed=speed))
    if not boxes:
        raise _Redraw
    return Scenario(GridMap(occupied, CELL_M), start, goal, obstacles=boxes,
                    description="boxes keep crossing the robot's route near its middle")


def _passing(size: int, rng) -> Scenario:
    start, goal, occupied, route = _corner_to_corner(size, rng)
    keep_out = _keep_free((size, size), [start, goal], 4) | occupied
    boxes = []
    for fraction in sorted(rng.uniform(0.3, 0.7, int(rng.integers(1, 3)))):
        k = int(fraction * (len(route) - 1))
        pair = _passing_pair(rng, size, route[max(0, k - 3):k + 4], keep_out)
        for box in pair:  # the next pair's sweeps a cell clear of this one's: pairs pass, they do not meet
            keep_out |= _band(keep_out.shape, box.box, [box.box[:2], box.waypoints[0]], 0)
        boxes += pair
    if not boxes:
        raise _Redraw
    return Scenario(GridMap(occupied, CELL_M), start, goal, obstacles=boxes,
                    description="pairs of boxes pass each other close across the robot's route")


def _passing_pair(rng, size: int, stretch: list[tuple[int, int]], keep_out: np.ndarray) -> list[Obstacle]:
    """Two boxes of side 3-5 (scaled) shuttling across the middle of a ``stretch`` of route in neighbouring lanes 0
    or 1 cell apart, along the axis the stretch crosses more: the other way (passing, 0.5-0.8 cells a tick each) or
    the same way, the second 1.5-1.8 times faster (overtaking, then passing on the way back). [] where a sweep,
    grown by a cell, meets ``keep_out``."""
    (r0, c0), (r1, c1), middle = stretch[0], stretch[-1], stretch[len(stretch) // 2]
    along = 1 if abs(r1 - r0) > abs(c1 - c0) else 0 if abs(r1 - r0) < abs(c1 - c0) else int(rng.integers(2))
    sides = [int(rng.integers(_scaled(size, 3), _scaled(size, 5) + 1)) for _ in range(2)]
    gap, reach = int(rng.integers(2)), float(rng.uniform(0.08, 0.14)) * size
    lane = middle[1 - along] - (sides[0] + gap + sides[1]) // 2
    overtaking = bool(rng.random() < 0.5)
    slow = float(rng.uniform(0.35, 0.5)) if overtaking else float(rng.uniform(0.5, 0.8))
    speeds = [slow, slow * float(rng.uniform(1.5, 1.8))] if overtaking else [slow, float(rng.uniform(0.5, 0.8))]
    pair = []
    for side, across, speed, back in zip(sides, (lane, lane + sides[0] + gap), speeds, (False, not overtaking)):
        if not 0 <= across <= size - side:
            return []
        ends = [int(np.clip(round(middle[along] + way * reach - side / 2), 0, size - side))
                for way in ((1, -1) if back else (-1, 1))]
        a, b = ((across, end) if along else (end, across) for end in ends)
        box = (a[0], a[1], a[0] + side, a[1] + side)
        if (_band(keep_out.shape, box, [a, b], 1) & keep_out).any():
            return []
        pair.append(Obstacle(box=box, waypoints=_shuttle(a, b, size, speed), speed=speed))
    return pair


def _wandering(size: int, rng) -> Scenario:
    start, goal, occupied, route = _corner_to_corner(size, rng)
    keep_out = _keep_free((size, size), [start, goal], 4) | occupied
    boxes = [box for box in (_wanderer(rng, size, route, keep_out) for _ in range(int(rng.integers(2, 5)))) if box]
    if not boxes:
        raise _Redraw
    return Scenario(GridMap(occupied, CELL_M), start, goal, obstacles=boxes,
                    description="boxes wander about the robot's route, turning at any angle")


def _wanderer(rng, size: int, route: list[tuple[int, int]], keep_out: np.ndarray) -> Obstacle | None:
    """A box of side 2-4 (scaled) driving at 0.3-0.8 cells a tick through waypoints each within 8 cells (scaled) of
    a random cell of the middle half of ``route`` and at least 5 (scaled) from the last, every leg a cell clear of
    ``keep_out``, for the world's 6 x size ticks: it crosses the route again and again, at any angle; it stops early
    where no leg fits. None where no first leg fits (each leg's band holds where it starts)."""
    side = int(rng.integers(_scaled(size, 2), _scaled(size, 4) + 1))
    speed, spread, shortest = float(rng.uniform(0.3, 0.8)), _scaled(size, 8), _scaled(size, 5)
    middle = route[len(route) // 4:max(len(route) // 4 + 1, 3 * len(route) // 4)]

    def near_route() -> tuple[int, int]:
        r, c = middle[int(rng.integers(len(middle)))]
        return tuple(int(np.clip(v - side // 2 + rng.integers(-spread, spread + 1), 0, size - side)) for v in (r, c))

    here = near_route()
    box = (here[0], here[1], here[0] + side, here[1] + side)
    waypoints, travelled = [], 0.0
    while travelled < 6 * size * speed:
        for _ in range(WANDER_TRIES):
            there = near_route()
            if math.dist(here, there) >= shortest and not (_band(keep_out.shape, box, [here, there], 1)
                                                            & keep_out).any():
                break
        else:
            break
        waypoints.append(there)
        travelled += math.dist(here, there)
        here = there
    return Obstacle(box=box, waypoints=waypoints, speed=speed) if waypoints else None


_BUILDERS = {"cluttered": _cluttered, "rooms": _rooms, "corridor": _corridor, "clearing": _clearing,
             "moving-target": _moving_target, "crossing": _crossing, "passing": _passing, "wandering": _wandering}


def boxes_on_map(grid: GridMap, start: tuple[int, int], goal: tuple[int, int], boxes: int = 3, seed: int = 0,
                 blockage: bool = False) -> Scenario:
    """A quick world on any map: ``boxes`` boxes of about 0.3-0.6 m shuttling back and forth over free ground at
    0.3-0.6 cells per tick (the family generator's rule, here on a given map), kept clear of the walls, the start
    and the goal; with ``blockage``, one more box appears in a narrow place of the robot's route about a third of the
    way along and stays. Deterministic for a given seed. Its tick (``tick_s``, for runners on a clock as PyBullet's)
    is the time a robot at 0.5 m/s takes to cross a cell of the map (TICK_S_PER_M): 0.2 s on 0.1 m cells, 2 s on a
    MovingAI map's 1 m cells, where the boxes at 0.2 s ticks would have moved at 1.5-3 m/s and rammed a 0.5 m/s robot.
    Its ``max_ticks`` is 4 times the moves of the shortest route on the map without boxes, at least the default 4 (H
    + W): a maze's route is many times its side (a 1-cell maze of 256² 8,744 moves, a maze of 8-cell corridors of 512²
    5,013), and the default limit ran out on the way.

    Raises:
        ValueError: ``grid`` not a GridMap, start or goal not a free cell, no way between them, ``boxes`` not an
            integer from 0 to the map's free cells, ``seed`` not an integer >= 0, ``blockage`` not a bool.

    Warns:
        UserWarning: fewer boxes fit on the map than ``boxes`` (a maze or 1-cell corridors have room for none).
    """
    if not isinstance(grid, GridMap):
        raise ValueError(f"grid must be a tdp.GridMap, got {type(grid).__name__}")
    boxes, seed = checks.integer(boxes, "boxes", 0), checks.integer(seed, "seed", 0)
    free_cells = int(np.count_nonzero(~grid.occupied))
    if boxes > free_cells:  # each box is drawn a hundred times at most: so many would draw for ever
        raise ValueError(f"boxes must be at most the map's {free_cells} free cells, got {boxes}")
    blockage = checks.flag(blockage, "blockage")
    rng = np.random.default_rng([_QUICK_STREAM, boxes, seed])
    start, goal = grid.check_free_cell(start, "start"), grid.check_free_cell(goal, "goal")
    route = _route(grid.occupied, start, goal)
    if not route:
        raise ValueError(f"goal {goal} cannot be reached from start {start} on this map")
    keep_free = grid.occupied | _keep_free(grid.shape, [start, goal], 4)
    free = np.argwhere(~keep_free)
    obstacles: list[Obstacle] = []
    side_cells = max(2, int(round(0.45 / grid.resolution)))
    for _ in range(100 * max(1, boxes)):
        if len(obstacles) == boxes or not len(free):
            break
        side = int(rng.integers(max(2, side_cells * 2 // 3), side_cells * 4 // 3 + 1))
        r, c = (int(v) for v in free[rng.integers(len(free))])
        step = (0, 1) if rng.random() < 0.5 else (1, 0)
        length = int(rng.integers(3 * side, 8 * side))
        end = (r + step[0] * length, c + step[1] * length)
        box = (r, c, r + side, c + side)
        if (end[0] + side > grid.shape[0] or end[1] + side > grid.shape[1]
                or (_band(grid.shape, box, [(r, c), end], 1) & keep_free).any()):
            continue
        speed = float(rng.uniform(0.3, 0.6))
        obstacles.append(Obstacle(box=box, waypoints=_shuttle((r, c), end, max(grid.shape), speed), speed=speed))
    if len(obstacles) < boxes:
        warnings.warn(f"only {len(obstacles)} of the {boxes} boxes asked for fit on this map: a box of about 0.3-0.6 m "
                      "shuttles along a straight run of free ground 3 to 8 times its side, clear of the walls, the "
                      "start and the goal", UserWarning, stacklevel=2)
    change = None
    if blockage:
        plug, change = _plug_on_route(grid, route)
        obstacles.append(plug)
    scenario = Scenario(grid, start, goal, obstacles=obstacles, name=f"boxes-{boxes}-{seed}", change_tick=change,
                        blocking=len(obstacles) - 1 if blockage else None, tick_s=TICK_S_PER_M * grid.resolution,
                        description=f"{boxes} shuttling boxes{' and a blockage on the route' if blockage else ''}")
    scenario.max_ticks = max(scenario.tick_limit, ROUTE_TICKS * (len(route) - 1))
    return scenario


def _plug_on_route(grid: GridMap, route: list[tuple[int, int]]) -> tuple[Obstacle, int]:
    """A box filling the narrowest free run across the route between a third and two thirds of the way that leaves
    the start and the goal free and another way between them, appearing when the robot is about a third of the way
    along; (box, tick)."""
    candidates = []
    for r, c in route[len(route) // 3:2 * len(route) // 3]:
        for vertical in (True, False):
            line = grid.occupied[:, c] if vertical else grid.occupied[r, :]
            lo = hi = r if vertical else c
            while lo > 0 and not line[lo - 1]:
                lo -= 1
            while hi < len(line) - 1 and not line[hi + 1]:
                hi += 1
            if lo > 0 and hi < len(line) - 1 and hi - lo <= max(grid.shape) // 4:
                box = (lo, c - 1, hi + 1, c + 1) if vertical else (r - 1, lo, r + 1, hi + 1)
                candidates.append((hi - lo, box))
    for _, box in sorted(set(candidates)):
        plugged = grid.occupied.copy()
        plugged[max(box[0], 0):box[2], max(box[1], 0):box[3]] = True
        if plugged[route[0]] or plugged[route[-1]]:  # a short route's middle third lies a cell from its ends
            continue
        if _route(plugged, route[0], route[-1]):
            tick = max(1, len(route) // 3 - 10)
            return Obstacle(box=box, appear_at=tick), tick
    raise ValueError("no narrow place on the route between walls whose closing leaves another way; "
                     "leave out the blockage")
