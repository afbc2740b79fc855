"""The setup phase and its repair: DistanceField.converge() next to scipy's Dijkstra (and scikit-fmm) in one process.

    python -m benchmarks.convergence [--quick] [--only NAME ...]

Maps: random (20 % obstacles) from 128² to 2048², with 30 % obstacles at 512² and 1024² and 40 % at 512², each with
goals at a corner, the centre and a random cell; open ground of side 1024 (no obstacle: ``open_cases``), goals the
same; perfect mazes of side 512 with corridors 1, 2 and 4 cells wide
(``tdp.random_worlds.maze``) and of side 256 with 1-cell corridors, braided mazes (1-cell corridors, a tenth of the
walls between rooms knocked through: loops) of side 256 and 512, and serpentines of side 256 and 512 (one corridor a
cell wide winding row by row: ``serpentine``) and rings of side 256 and 512 (concentric corridors a cell wide, a door in
each wall between two: ``rings``), goals at a corner, the centre and a random free cell; caves of side 512 and 1024 (a
cellular automaton's winding passages: ``caves``), goals in their largest region; halls of 4096 x 64 and 64 x 4096 cells
(random, 20 % obstacles: a long corridor or aisle), goals at the middle of an end, the centre and a random free cell;
the MovingAI maps in ../shared/data with several scenario goals each (skipped when absent); the ROS maps (turtlebot3's
world, nav2's 1674 x 1006 warehouse and its depot, inflated by 0.2 m) with random goals. All on the default stencil (16
neighbours, no corner cutting); three of them (random 512² with the centre goal, the 1-cell maze with the corner goal,
turtlebot3's world) again with 8 neighbours, 8 with corners cut and 4 (STENCILS). The graph is built once and
timed apart; Dijkstra's solve and a from-scratch converge() (``reset()`` then ``converge()``) are timed in turn,
warm, in the same process (their ratio is the median of each pair's; 5 times the repeats where the solve takes under
5 ms), and the field is checked equal to Dijkstra's. Timed only, as warm medians, where installed (``pip install
tcod scikit-fmm``): tcod's ``dijkstra2d`` (C, one thread, the 16-neighbour edge map with integer costs x 1000; it
cannot forbid corner cutting, so its graph has more edges than ours) and scikit-fmm's whole-field distance (a
different, continuous distance).

Repair, on maps of 65,536 cells or more (4,096 with --quick): from the converged field, a 3 x 3 box on the middle of the
optimal route from the farthest reachable cell, a wall of 16 cells across that route, a pocket sealed (a square ring of
obstacles, side an eighth of the map's, around the farthest reachable cell: every cell inside rises to inf), the same
pocket opened again (the ring removed, from the sealed field), the goal sealed in (a ring of side a sixteenth of the
map's around it: every cell outside rises to inf, where a restart searches the few inside), the goal let out again, the
goal sealed in a room (a ring of side a quarter of the map's: a twentieth to a tenth of the cells inside, which a
restart searches while a mend would raise the rest), a goal move, noise (64 free cells blocked and 64 obstacle cells
freed at random all over the map, as a costmap flickers: on a maze each blocked cell cuts a corridor and each freed one
opens a wall) and boxes (eight 3 x 3 boxes set down at random all at once). Each edit is timed (``set_occupied``,
``set_goal``), then its ``converge()`` (the edit undone, untimed, between repeats); the repair is checked bit for bit
against a fresh field's converge() on the edited map and set against that field's from-scratch converge(), the two timed
in turn: the ratio is a repair's - the edit and its converge, what a user pays (the goal layer paints an edit in the
converge's launch) - to the from-scratch converge's, again the median of each pair's (as many pairs as fill about
REPAIR_PAIRS_S seconds of from-scratch converges, from the repeats up to MAX_REPAIR_PAIRS); the converge's alone beside
it. A repair's work follows the cells it changes: each reports how many cells' distances it changed, its converge's time
per changed cell, and the from-scratch converge's per cell it reaches; and the edit with its converge timed again back
to back, with no other field's converge between them (caches warm, as in a planner's loop).

Doors (not with --quick): on the 1-cell perfect maze of side 512 with its corner goal, a door closes - one cell of
the optimal route from the farthest reachable cell - and the goal keeps the cells on its side: DOOR_SHARES of the
cells it reached, the cell picked along the route for each (the maze is a tree: any cell of it cuts it in two).
Where the goal keeps few cells a restart searches them; where it keeps most, a mend raises the rest to inf; in
between neither side can be told cheaply, and each is timed as a repair.
"""
from __future__ import annotations

import math
import time
from pathlib import Path

import numpy as np
from scipy import ndimage
from scipy.sparse.csgraph import dijkstra

import tdp
from benchmarks.common import median_time, paired_times, print_table, quick_parser, save_results
from benchmarks.reference_graph import grid_graph
from tdp.random_worlds import maze

ROOT = Path(__file__).resolve().parents[1]
SHARED = ROOT.parent / "shared" / "data"
NAV2 = ROOT / "benchmarks" / "data" / "nav2_maps"
ROBOT_RADIUS_M = 0.2
SIZES, QUICK_SIZES = [128, 192, 256, 512, 1024, 2048], [64, 128]
#: Open ground (side): no obstacle at all - a room's or a yard's floor, the widest front a search has, every cell's
#: route one of many of the same length.
OPEN, QUICK_OPEN = [1024], [64]
#: Dense random maps as well: (side, obstacle density); routes wind far more than at 20 %.
DENSE, QUICK_DENSE = [(512, 0.3), (1024, 0.3), (512, 0.4)], [(64, 0.3)]
#: Mazes: (side, corridor width, loops); a tile holds pieces of corridors at very different distances. Perfect mazes
#: (no loop: a tree, where a blocked corridor cuts off all beyond it) and braided ones (``maze``'s ``loops``: a tenth
#: of the walls a perfect maze leaves between rooms knocked through, so that a blocked corridor has a way round).
MAZES = [(256, 1, 0.0), (512, 1, 0.0), (512, 2, 0.0), (512, 4, 0.0), (256, 1, 0.1), (512, 1, 0.1)]
QUICK_MAZES = [(64, 1, 0.0), (64, 1, 0.1)]
#: Serpentines (side): one corridor a cell wide winding row by row, a search's frontier one cell all the way - where
#: Dijkstra's heap is at its cheapest and each cell has two edges against our stencil's 16 moves.
SERPENTINES, QUICK_SERPENTINES = [256, 512], [64]
#: Rings (side): concentric square corridors a cell wide, each wall between two with one door (``rings``) - a
#: labyrinth of loops where a serpentine and a perfect maze are trees: a blocked cell cuts nothing alone, a freed wall
#: cell is a shortcut past a ring's length.
RINGS, QUICK_RINGS = [256, 512], [64]
#: Caves (side): a cellular automaton's winding passages round blobs of rock (``caves``), as game and outdoor maps.
CAVES, QUICK_CAVES = [512, 1024], [64]
#: The caves' rock before the automaton smooths it, and its steps: 0.48 leaves 55-59 % of the map free and nearly
#: all of it one region of passages 1 to 10 cells wide (0.45: open ground round blobs; 0.5: pockets).
CAVE_FILL, CAVE_STEPS = 0.48, 5
#: Halls (rows, cols): random maps (20 % obstacles) far longer than wide - a corridor or an aisle -, tall and wide
#: (a row-major layout walks them differently). A ring round the goal is clipped to the hall's sides, so sealing a
#: room there cuts the hall across and leaves most of it behind the cut.
HALLS, QUICK_HALLS = [(4096, 64), (64, 4096)], [(512, 16)]
MAPS, QUICK_MAPS = ["arena", "den312d", "maze512-32-0", "random512-10-0", "8room_000"], ["arena"]
GOALS_PER_MAP = 3
#: Every case runs on the default stencil (16 neighbours, no corner cutting); these maps run again on each of
#: STENCILS, (neighbourhood, corner_cutting) - most ROS costmaps are planned on 8 neighbours, grids of rooms on 4.
DEFAULT_STENCIL = (16, False)
STENCILS = [(8, False), (8, True), (4, False)]
STENCIL_MAPS = ["random 512² centre", "maze 512² 1-cell corner", "turtlebot3_world #1"]
QUICK_STENCIL_MAPS = ["random 64² centre"]
LARGE = 65536  # maps from this size on get the repair cases (4096 with --quick)
CONVERGE_LARGE = 32768  # maps from this size on count for the from-scratch converge's worst-case target
FAST_S, FAST_REPEATS = 0.005, 5  # a reference solve under 5 ms gets 5 times the repeats: its timings are noisier
WALL = 16
#: A 3 x 3 box's cells, as offsets from its centre.
BOX = [(i, j) for i in (-1, 0, 1) for j in (-1, 0, 1)]
#: The field against scipy's (float64) Dijkstra: float32 sums of sqrt 2 and sqrt 5 along routes of 10,000+ moves
#: (mazes with 2- and 4-cell corridors) drift up to 3e-5 from the float64 ones; straight moves alone are exact.
EQUAL_RTOL = 1e-4
REPAIRS = ("box", "wall", "seal", "open", "goal-seal", "goal-open", "goal-room", "goal", "noise", "boxes")
#: Cells a noise edit blocks, and obstacle cells it frees, at random all over the map (a costmap's flicker).
NOISE = 64
#: 3 x 3 boxes a boxes edit sets down at once, centred on random free cells (obstacles appearing all over the map).
BOXES = 8
#: The shares of the cells it reached that the goal keeps when a door closes on the 1-cell maze (``doors``).
DOOR_SHARES = (0.02, 0.05, 0.1, 0.2, 0.35, 0.5, 0.7, 0.9)
#: Repairs are timed in pairs with a from-scratch converge until the from-scratch side adds up to about this many
#: seconds (at most MAX_REPAIR_PAIRS pairs, at least the repeats): on a map that converges in 10-30 ms five pairs
#: left a goal move, which is a restart by construction, anywhere in 0.85-1.25x.
REPAIR_PAIRS_S, MAX_REPAIR_PAIRS = 0.5, 25

try:
    import skfmm
except ImportError:  # an optional reference: pip install scikit-fmm
    skfmm = None
try:
    import tcod.path
except ImportError:  # an optional reference: pip install tcod
    tcod = None


def random_cases(size: int, density: float = 0.2) -> list[tuple[str, np.ndarray, tuple[int, int]]]:
    """A random map with ``density`` obstacles and its goals: a corner, the centre, a random free cell. Named
    ``random {size}² {place}`` at 20 %, with the density in the name otherwise."""
    occupied = np.random.default_rng(size).random((size, size)) < density
    free = np.argwhere(~occupied)
    goals = {"corner": (0, 0), "centre": (size // 2, size // 2),
             "random": tuple(int(v) for v in free[np.random.default_rng(size + 1).integers(len(free))])}
    dense = "" if density == 0.2 else f"{round(100 * density)} % "
    return goal_cases(f"random {size}² {dense}", occupied, goals)


def open_cases(size: int) -> list[tuple[str, np.ndarray, tuple[int, int]]]:
    """Open ground (``OPEN``) and its goals: a corner, the centre, a random cell."""
    goals = {"corner": (0, 0), "centre": (size // 2, size // 2),
             "random": tuple(int(v) for v in np.random.default_rng(size + 1).integers(size, size=2))}
    return goal_cases(f"open {size}² ", np.zeros((size, size), bool), goals)


def goal_cases(prefix: str, occupied: np.ndarray, goals: dict[str, tuple[int, int]]
               ) -> list[tuple[str, np.ndarray, tuple[int, int]]]:
    """A case for each of ``goals`` (place: cell), named ``prefix`` + the place, on ``occupied`` with the goal's cell
    freed."""
    cases = []
    for place, goal in goals.items():
        grid = occupied.copy()
        grid[goal] = False
        cases.append((f"{prefix}{place}", grid, goal))
    return cases


def hall_cases(rows: int, cols: int) -> list[tuple[str, np.ndarray, tuple[int, int]]]:
    """A hall (``HALLS``: random, 20 % obstacles) and its goals: the middle of one end, the centre, a random free
    cell."""
    occupied = np.random.default_rng(rows * cols + rows).random((rows, cols)) < 0.2
    free = np.argwhere(~occupied)
    goals = {"end": (0, cols // 2) if rows > cols else (rows // 2, 0), "centre": (rows // 2, cols // 2),
             "random": tuple(int(v) for v in free[np.random.default_rng(rows + 1).integers(len(free))])}
    return goal_cases(f"hall {rows}x{cols} ", occupied, goals)


def maze_cases(size: int, corridor: int, loops: float = 0.0) -> list[tuple[str, np.ndarray, tuple[int, int]]]:
    """A maze (perfect, or braided with ``loops``) and its goals (``walled_goals``: the corner room first)."""
    occupied = maze(size, corridor, seed=size + corridor, loops=loops)
    braided = f"braided {round(100 * loops)} % " if loops else ""
    return goal_cases(f"maze {size}² {corridor}-cell {braided}", occupied, walled_goals(occupied))


def walled_goals(occupied: np.ndarray) -> dict[str, tuple[int, int]]:
    """Goals on a square map walled round (a maze, a serpentine): its first free cell, (1, 1), the free cell nearest
    the centre, and a random free cell (seeded by the map's side)."""
    size = occupied.shape[0]
    free = np.argwhere(~occupied)
    centre = free[np.argmin(np.abs(free - size // 2).sum(axis=1))]
    return {"corner": (1, 1), "centre": tuple(int(v) for v in centre),
            "random": tuple(int(v) for v in free[np.random.default_rng(size + 1).integers(len(free))])}


def serpentine(size: int) -> np.ndarray:
    """One corridor a cell wide winding across a (size, size) map, True = wall: rows 1, 3, 5 ... free, the walls
    between them open at the right and the left end in turn, the border a wall (a boustrophedon)."""
    occupied = np.ones((size, size), bool)
    occupied[1:size - 1:2, 1:size - 1] = False
    for row in range(2, size - 2, 2):
        occupied[row, size - 2 if row % 4 == 2 else 1] = False
    return occupied


def serpentine_cases(size: int) -> list[tuple[str, np.ndarray, tuple[int, int]]]:
    """A serpentine (``serpentine``) and its goals (``walled_goals``: the corridor's first cell first)."""
    occupied = serpentine(size)
    return goal_cases(f"serpentine {size}² ", occupied, walled_goals(occupied))


def rings(size: int) -> np.ndarray:
    """Concentric square corridors a cell wide round the centre of a (size, size) map, True = wall: walls on the
    border and every second ring inside it, each inner wall with one door, next to a corner of its top, bottom, left
    and right side in turn, so that a route from the border winds round ring after ring."""
    occupied = np.zeros((size, size), bool)
    for ring, top in enumerate(range(0, size // 2, 2)):
        bottom = size - 1 - top
        if bottom - top < 2:
            break
        occupied[[top, bottom], top:bottom + 1] = True
        occupied[top:bottom + 1, [top, bottom]] = True
        if ring:
            doors = ((top, bottom - 1), (bottom, top + 1), (top + 1, top), (bottom - 1, bottom))
            occupied[doors[(ring - 1) % 4]] = False
    return occupied


def rings_cases(size: int) -> list[tuple[str, np.ndarray, tuple[int, int]]]:
    """Rings (``rings``) and their goals (``walled_goals``: the outer corridor's corner first)."""
    occupied = rings(size)
    return goal_cases(f"rings {size}² ", occupied, walled_goals(occupied))


def caves(size: int) -> np.ndarray:
    """A cave map of side ``size``, True = rock: CAVE_FILL of the cells rock at random (seeded by the side), then
    CAVE_STEPS times each cell rock where 5 or more of its 3 x 3 block are (outside the map counts as rock)."""
    occupied = np.random.default_rng(size).random((size, size)) < CAVE_FILL
    for _ in range(CAVE_STEPS):
        occupied = ndimage.convolve(occupied.astype(np.int8), np.ones((3, 3), np.int8), mode="constant", cval=1) >= 5
    return occupied


def caves_cases(size: int) -> list[tuple[str, np.ndarray, tuple[int, int]]]:
    """Caves (``caves``) and their goals in the largest region of passages: its cells nearest the top-left corner
    and the centre, and a random one."""
    occupied = caves(size)
    free = largest_free_region(occupied)
    picks = {"corner": np.argmin(free.sum(axis=1)), "centre": np.argmin(np.abs(free - size // 2).sum(axis=1)),
             "random": np.random.default_rng(size + 1).integers(len(free))}
    goals = {place: tuple(int(v) for v in free[k]) for place, k in picks.items()}
    return goal_cases(f"caves {size}² ", occupied, goals)


def movingai_cases(name: str) -> list[tuple[str, np.ndarray, tuple[int, int]]]:
    path = SHARED / "movingai" / f"{name}.map"
    if not path.exists():
        print(f"  {name}: not found in {path.parent}, skipped")
        return []
    grid = tdp.load_map(path)
    scenarios = tdp.load_scenarios(path.with_suffix(".map.scen"), grid)
    picks = np.linspace(len(scenarios) - 1, 0, GOALS_PER_MAP).astype(int)
    return [(f"{name} #{k}", grid.occupied, scenarios[k].goal) for k in picks]


def ros_cases() -> list[tuple[str, np.ndarray, tuple[int, int]]]:
    """The ROS maps: turtlebot3's world (tests/data) and nav2's warehouse and depot (benchmarks/data), inflated by
    ROBOT_RADIUS_M as a navigator would; goals at random cells of the largest free region (a goal in a pocket
    would flatter every method alike)."""
    maps = [("turtlebot3_world", ROOT / "tests" / "data" / "turtlebot3_world" / "map.yaml"),
            ("nav2 warehouse", NAV2 / "warehouse.yaml"), ("nav2 depot", NAV2 / "depot.yaml")]
    cases = []
    for name, path in maps:
        grid = tdp.load_map(path)
        occupied = grid.inflate(ROBOT_RADIUS_M / grid.resolution).occupied
        free = largest_free_region(occupied)
        rng = np.random.default_rng(0)
        cases += [(f"{name} #{k}", occupied, tuple(int(v) for v in free[rng.integers(len(free))]))
                  for k in range(GOALS_PER_MAP)]
    return cases


def largest_free_region(occupied: np.ndarray) -> np.ndarray:
    """The (row, col) cells of the largest 8-connected free region."""
    labels, _ = ndimage.label(~occupied, structure=np.ones((3, 3)))
    return np.argwhere(labels == np.argmax(np.bincount(labels.ravel())[1:]) + 1)


def field_on(occupied: np.ndarray, goal, stencil: tuple[int, bool] = DEFAULT_STENCIL,
             cost: np.ndarray | None = None) -> tdp.DistanceField:
    """A field on ``occupied`` (and ``cost``, if given: a freed cell costs what it says, as ``set_occupied`` frees
    a cell at the cost its map gave it)."""
    return tdp.DistanceField(tdp.GridMap(occupied, cost=cost), goal, neighbourhood=stencil[0],
                             corner_cutting=stencil[1])


def stencil_name(stencil: tuple[int, bool]) -> str:
    return f"{stencil[0]} neighbours" + (", corners cut" if stencil[1] else "")


def from_scratch(field: tdp.DistanceField) -> None:
    field.reset()
    field.converge()


def fmm_seconds(occupied: np.ndarray, goal, repeats: int) -> float | None:
    """scikit-fmm's whole-field distance from the goal around the obstacles (masked), or None when absent or when
    it has no front to march (a goal walled in on its four sides: skfmm raises "no zero contour")."""
    if skfmm is None:
        return None
    phi = np.ones(occupied.shape)
    phi[goal] = -1.0
    phi = np.ma.MaskedArray(phi, mask=np.array(occupied))
    try:
        return median_time(lambda: skfmm.distance(phi), repeats)
    except ValueError:
        return None


#: The moves (|dr|, |dc|) of each neighbourhood, for tcod's edge map.
TCOD_MOVES = {4: {(0, 1), (1, 0)}, 8: {(0, 1), (1, 0), (1, 1)}, 16: {(0, 1), (1, 0), (1, 1), (1, 2), (2, 1)}}


def tcod_edges(neighbourhood: int) -> np.ndarray:
    """tcod's edge map: the cost of each move (integers: lengths x 1000) at its offset from the centre."""
    return np.array([[round(1000 * math.hypot(dr, dc)) if (abs(dr), abs(dc)) in TCOD_MOVES[neighbourhood] else 0
                      for dc in range(-2, 3)] for dr in range(-2, 3)], np.int32)


def tcod_seconds(occupied: np.ndarray, goal, repeats: int, neighbourhood: int = 16) -> float | None:
    """tcod's ``dijkstra2d`` over the neighbourhood's edge map from the goal (its distance array set afresh each
    time, as a converge from scratch starts afresh), or None when tcod is absent."""
    if tcod is None:
        return None
    cost, edges = (~occupied).astype(np.int32), tcod_edges(neighbourhood)

    def solve():
        distance = np.full(occupied.shape, np.iinfo(np.int32).max, np.int32)
        distance[goal] = 0
        tcod.path.dijkstra2d(distance, cost, edge_map=edges, out=distance)

    return median_time(solve, repeats)


def measure(name: str, occupied: np.ndarray, goal, repeats: int, repair_cells: int,
            stencil: tuple[int, bool] = DEFAULT_STENCIL) -> dict:
    rows, cols = occupied.shape
    began = time.perf_counter()
    graph = grid_graph(occupied, *stencil).T.tocsr()  # transposed: distances *to* the goal
    build_s = time.perf_counter() - began
    source = goal[0] * cols + goal[1]
    began = time.perf_counter()
    reference = dijkstra(graph, indices=source).reshape(rows, cols)
    repeats *= FAST_REPEATS if time.perf_counter() - began < FAST_S else 1
    field = field_on(occupied, goal, stencil)
    rounds = field.converge()
    converge_s, dijkstra_s, ratio = paired_times(lambda: from_scratch(field), lambda: dijkstra(graph, indices=source),
                                                 repeats)
    ours = field.distances()
    finite = np.isfinite(reference)
    exact = bool(np.array_equal(np.isfinite(ours), finite)) and bool(
        np.allclose(ours[finite], reference[finite], rtol=EQUAL_RTOL))
    fmm_s, tcod_s = fmm_seconds(occupied, goal, repeats), tcod_seconds(occupied, goal, repeats, stencil[0])
    result = {"map": name, "stencil": list(stencil), "cells": rows * cols, "build_ms": build_s * 1e3,
              "dijkstra_ms": dijkstra_s * 1e3,
              "converge_ms": converge_s * 1e3, "rounds": rounds, "ratio": ratio, "equal": exact,
              "fmm_ms": None if fmm_s is None else fmm_s * 1e3,
              "fmm_ratio": None if fmm_s is None else converge_s / fmm_s,
              "tcod_ms": None if tcod_s is None else tcod_s * 1e3,
              "tcod_ratio": None if tcod_s is None else converge_s / tcod_s}
    if rows * cols >= repair_cells:
        pairs = min(max(repeats, math.ceil(REPAIR_PAIRS_S / converge_s)), MAX_REPAIR_PAIRS)
        result["repairs"] = [measure_repair(field, kind, reference, pairs, stencil) for kind in REPAIRS]
    return result


def route_middle(field: tdp.DistanceField, reference: np.ndarray) -> tuple[tuple[int, int], tuple[int, int]]:
    """The middle cell of the optimal route from the farthest reachable cell, and that route's direction there."""
    reachable = np.where(np.isfinite(reference), reference, -1.0)
    start = tuple(int(v) for v in np.unravel_index(np.argmax(reachable), reference.shape))
    path = field.path(start)
    middle = len(path) // 2
    after = path[min(middle + 1, len(path) - 1)]
    return path[middle], (after[0] - path[middle][0], after[1] - path[middle][1])


def pocket_ring(field: tdp.DistanceField, reference: np.ndarray, around_goal: bool,
                side_share: float = 1 / 16) -> list[tuple[int, int]]:
    """The free cells of a square ring around the farthest reachable cell, side an eighth of the map's, or around
    the goal, side ``side_share`` of it (clipped to the map, whose edge closes it): blocked, it seals off the pocket
    inside."""
    rows, cols = reference.shape
    if around_goal:
        (r, c), half = field.goal, max(int(max(rows, cols) * side_share / 2), 2)
    else:
        reachable = np.where(np.isfinite(reference), reference, -1.0)
        r, c = (int(v) for v in np.unravel_index(np.argmax(reachable), reference.shape))
        half = max(max(rows, cols) // 16, 2)
    top, bottom, left, right = max(r - half, 0), min(r + half, rows - 1), max(c - half, 0), min(c + half, cols - 1)
    ring = {(top, j) for j in range(left, right + 1)} | {(bottom, j) for j in range(left, right + 1)}
    ring |= {(i, left) for i in range(top, bottom + 1)} | {(i, right) for i in range(top, bottom + 1)}
    return sorted(cell for cell in ring if not field.occupied[cell] and cell != field.goal)


def repair_edit(field: tdp.DistanceField, kind: str, reference: np.ndarray):
    """(apply, undo) of one repair case on a converged field; an opening leaves the field sealed (and converged)
    until its undo."""
    goal = field.goal
    if kind in ("seal", "open", "goal-seal", "goal-open", "goal-room"):
        ring = pocket_ring(field, reference, kind.startswith("goal"), 1 / 4 if kind == "goal-room" else 1 / 16)
        seal, unseal = (lambda: field.set_occupied(ring)), (lambda: field.set_occupied(ring, False))
        if kind.endswith("seal") or kind == "goal-room":
            return seal, unseal
        seal()
        field.converge()
        return unseal, seal
    if kind in ("noise", "boxes"):
        return scattered_edit(field, kind)
    if kind == "goal":
        free = np.argwhere(~field.occupied)
        target = tuple(int(v) for v in free[np.random.default_rng(len(free)).integers(len(free))])
        return (lambda: field.set_goal(target)), (lambda: field.set_goal(goal))
    (r, c), (dr, dc) = route_middle(field, reference)
    rows, cols = reference.shape
    if kind == "box":
        cells = [(r + i, c + j) for i, j in BOX]
    elif abs(dr) >= abs(dc):  # the route runs along the rows here: the wall runs across them
        cells = [(r, c + j) for j in range(-WALL // 2, WALL // 2)]
    else:
        cells = [(r + i, c) for i in range(-WALL // 2, WALL // 2)]
    cells = [cell for cell in cells if 0 <= cell[0] < rows and 0 <= cell[1] < cols and cell != goal
             and not field.occupied[cell]]
    return (lambda: field.set_occupied(cells)), (lambda: field.set_occupied(cells, False))


def scattered_edit(field: tdp.DistanceField, kind: str):
    """(apply, undo) of edits all over the map, anywhere but the goal (the same cells every run: the generator is
    seeded by the map's size): "noise", NOISE free cells blocked and NOISE obstacle cells freed at once; "boxes",
    BOXES 3 x 3 boxes set down on free cells."""
    rng = np.random.default_rng(field.occupied.size)
    free, blocked = np.argwhere(~field.occupied), np.argwhere(field.occupied)
    if kind == "noise":
        on = free[rng.choice(len(free), min(NOISE, len(free)), replace=False)]
        off = blocked[rng.choice(len(blocked), min(NOISE, len(blocked)), replace=False)]
    else:
        centres = free[rng.choice(len(free), min(BOXES, len(free)), replace=False)]
        on = (centres[:, None, :] + np.array(BOX)).reshape(-1, 2)
        on = np.unique(on[((on >= 0) & (on < field.occupied.shape)).all(axis=1)], axis=0)
        on, off = on[~field.occupied[on[:, 0], on[:, 1]]], np.zeros((0, 2), int)
    on = on[(on != field.goal).any(axis=1)]

    def flip(block: bool) -> None:
        field.set_occupied(on, block)
        if len(off):
            field.set_occupied(off, not block)
    return (lambda: flip(True)), (lambda: flip(False))


def measure_repair(field: tdp.DistanceField, kind: str, reference: np.ndarray, repeats: int,
                   stencil: tuple[int, bool] = DEFAULT_STENCIL, cost: np.ndarray | None = None) -> dict:
    """A repair case (``repair_edit``), timed by ``measure_edit``."""
    before = field.occupied.copy()
    return measure_edit(field, kind, *repair_edit(field, kind, reference), before, repeats, stencil, cost)


def measure_edit(field: tdp.DistanceField, kind: str, apply, undo, before: np.ndarray, repeats: int,
                 stencil: tuple[int, bool] = DEFAULT_STENCIL, cost: np.ndarray | None = None) -> dict:
    """An edit (``apply``, undone by ``undo``), then converge(), from the converged field (its map was ``before``,
    its costs ``cost`` if any), against a fresh field's from-scratch converge() on the edited map, the two timed in
    turn; the ratio - of the edit and the converge together, and of the converge alone - is the median of each
    pair's (the VM's speed drifts: pairing keeps it out of the ratio). The field is left on its map, converged."""
    apply()
    fresh = field_on(field.occupied, field.goal, stencil, cost)
    undo()
    field.converge()
    start = field.distances().copy()
    edits, repairs, scratches = [], [], []
    for _ in range(repeats + 1):  # the first of each is a warm-up
        began = time.perf_counter()
        apply()
        edits.append(time.perf_counter() - began)
        began = time.perf_counter()
        field.converge()
        repairs.append(time.perf_counter() - began)
        repaired = field.distances().copy()
        undo()
        field.converge()
        began = time.perf_counter()
        from_scratch(fresh)
        scratches.append(time.perf_counter() - began)
    back_to_back = []  # the edit and its converge again, no other field's converge between: caches warm
    for _ in range(repeats + 1):
        began = time.perf_counter()
        apply()
        field.converge()
        back_to_back.append(time.perf_counter() - began)
        undo()
        field.converge()
    changed = field.occupied != before  # an opening's undo left the pocket sealed
    field.set_occupied(changed & before)
    field.set_occupied(changed & ~before, False)
    field.converge()
    edits_s, repairs_s, scratches_s = (np.array(times[1:]) for times in (edits, repairs, scratches))
    repair_s, scratch_s = float(np.median(repairs_s)), float(np.median(scratches_s))
    cells_changed, reached = int(np.count_nonzero(start != repaired)), int(np.count_nonzero(np.isfinite(repaired)))
    return {"kind": kind, "edit_ms": float(np.median(edits_s)) * 1e3,
            "repair_ms": repair_s * 1e3, "scratch_ms": scratch_s * 1e3,
            "ratio": float(np.median((edits_s + repairs_s) / scratches_s)),
            "converge_ratio": float(np.median(repairs_s / scratches_s)),
            "back_to_back_ms": float(np.median(back_to_back[1:])) * 1e3,
            "changed": cells_changed, "reached": reached,
            "converge_ns_per_changed": repair_s * 1e9 / max(cells_changed, 1),
            "scratch_ns_per_reached": scratch_s * 1e9 / max(reached, 1),
            "equal": bool(np.array_equal(repaired, fresh.distances()))}


def doors(repeats: int) -> list[dict]:
    """A door closes on the 1-cell maze of side 512 (its corner goal): for each of DOOR_SHARES, the cell of the
    optimal route from the farthest reachable cell whose closing leaves the goal's side nearest that share of the
    cells it reached (scipy's labels of the free cells, the stencil's 8-connected reach), timed as a repair
    (``measure_edit``)."""
    (_, occupied, goal), = [case for case in maze_cases(512, 1) if case[0].endswith("corner")]
    field = field_on(occupied, goal)
    field.converge()
    reference = field.distances().copy()
    reached = np.count_nonzero(np.isfinite(reference))
    far = tuple(int(v) for v in np.unravel_index(np.argmax(np.where(np.isfinite(reference), reference, -1)),
                                                 reference.shape))
    shares = []
    for cell in field.path(far)[1:-1]:
        closed = occupied.copy()
        closed[cell] = True
        labels, _ = ndimage.label(~closed, structure=np.ones((3, 3)))
        shares.append((np.count_nonzero(labels == labels[goal]) / reached, cell))
    out = []
    for share in DOOR_SHARES:
        kept, cell = min(shares, key=lambda pair: abs(pair[0] - share))
        apply, undo = (lambda c=cell: field.set_occupied([c])), (lambda c=cell: field.set_occupied([c], False))
        result = measure_edit(field, f"door {kept:.0%}", apply, undo, occupied, repeats)
        out.append({"share": kept, "cell": list(cell), **result})
        print(f"  door keeping {kept:.1%}: {result['ratio']:.2f}x", flush=True)
    return out


def figure(results: list[dict], path: Path) -> None:
    from tdp.plot import pyplot, save_figure

    plt = pyplot()
    fig, (left, right) = plt.subplots(1, 2, figsize=(11, max(4.2, 0.16 * len(results))))
    names = [r["map"] for r in results]
    y = np.arange(len(results))
    left.barh(y, [r["ratio"] for r in results], color="tab:blue")
    left.axvline(1.0, color="k", lw=0.8)
    left.set_yticks(y, names, fontsize=6)
    left.invert_yaxis()
    left.set_xlabel("from-scratch converge() / scipy Dijkstra (lower is faster)")
    repaired = [r for r in results if r.get("repairs")]
    colours = dict(zip(REPAIRS, ["tab:green", "tab:orange", "tab:purple", "tab:cyan", "tab:brown", "tab:olive",
                                 "tab:pink", "tab:red", "tab:gray", "tab:blue"]))
    width = 0.8 / len(colours)
    for k, kind in enumerate(colours):  # one row per map, its changes side by side
        ratios = [next(q["ratio"] for q in r["repairs"] if q["kind"] == kind) for r in repaired]
        right.barh(np.arange(len(repaired)) + (k - len(colours) // 2) * width, ratios, width, color=colours[kind],
                   label=kind)
    right.set_yticks(range(len(repaired)), [r["map"] for r in repaired], fontsize=6)
    right.invert_yaxis()
    right.set_xscale("log")
    right.axvline(0.1, color="k", lw=0.8, ls="--")
    right.axvline(1.0, color="k", lw=0.8)
    right.set_xlabel("repair / from-scratch converge() (log)")
    right.legend(fontsize=7, ncol=4, loc="lower center", bbox_to_anchor=(0.5, 1.0))
    save_figure(fig, path)


def main() -> None:
    parser = quick_parser(__doc__)
    parser.add_argument("--repeats", type=int, default=5)
    parser.add_argument("--only", nargs="+", metavar="NAME",
                        help="only the cases whose name holds one of these (no doors; saved as convergence-only)")
    args = parser.parse_args()
    if args.quick:
        sizes, opens, dense, mazes, serpentines, ring_sides, cave_sides, halls, maps, stencil_maps = (
            QUICK_SIZES, QUICK_OPEN, QUICK_DENSE, QUICK_MAZES, QUICK_SERPENTINES, QUICK_RINGS, QUICK_CAVES, QUICK_HALLS,
            QUICK_MAPS, QUICK_STENCIL_MAPS)
    else:
        sizes, opens, dense, mazes, serpentines, ring_sides, cave_sides, halls, maps, stencil_maps = (
            SIZES, OPEN, DENSE, MAZES, SERPENTINES, RINGS, CAVES, HALLS, MAPS, STENCIL_MAPS)
    repeats = 3 if args.quick else args.repeats
    cases = [case for size in sizes for case in random_cases(size)]
    cases += [case for size in opens for case in open_cases(size)]
    cases += [case for size, density in dense for case in random_cases(size, density)]
    cases += [case for size, corridor, loops in mazes for case in maze_cases(size, corridor, loops)]
    cases += [case for size in serpentines for case in serpentine_cases(size)]
    cases += [case for size in ring_sides for case in rings_cases(size)]
    cases += [case for size in cave_sides for case in caves_cases(size)]
    cases += [case for rows, cols in halls for case in hall_cases(rows, cols)]
    cases += [case for name in maps for case in movingai_cases(name)]
    if not args.quick:
        cases += ros_cases()
    cases = [(*case, DEFAULT_STENCIL) for case in cases] + [
        (f"{name}, {stencil_name(stencil)}", occupied, goal, stencil)
        for name, occupied, goal in cases if name in stencil_maps for stencil in STENCILS]
    if args.only:
        cases = [case for case in cases if any(part in case[0] for part in args.only)]
        if not cases:
            raise SystemExit(f"--only {' '.join(args.only)}: no case's name holds any of these")
    results = []
    for name, occupied, goal, stencil in cases:
        results.append(measure(name, occupied, goal, repeats, 4096 if args.quick else LARGE, stencil))
        r = results[-1]
        repairs = "".join(f", {q['kind']} {q['repair_ms']:.1f} ms ({q['ratio']:.2f}x)" for q in r.get("repairs", []))
        print(f"  {name}: converge {r['converge_ms']:.1f} ms ({r['rounds']} rounds), "
              f"Dijkstra {r['dijkstra_ms']:.1f} ms{repairs}", flush=True)
    print_table(["map", "cells", "graph build ms", "Dijkstra ms", "converge ms", "converge / Dijkstra", "tcod ms",
                 "converge / tcod", "scikit-fmm ms", "converge / fmm", "rounds", "equal"],
                [[r["map"], str(r["cells"]), f"{r['build_ms']:.1f}", f"{r['dijkstra_ms']:.1f}",
                  f"{r['converge_ms']:.1f}", f"{r['ratio']:.2f}", *optional(r, "tcod"), *optional(r, "fmm"),
                  str(r["rounds"]), str(r["equal"])] for r in results])
    print_table(["map", "change", "edit ms", "converge ms", "back to back ms", "from scratch ms",
                 "(edit + converge) / from scratch", "converge / from scratch", "cells changed",
                 "converge ns / cell changed", "from scratch ns / cell reached", "equal"],
                [[r["map"], q["kind"], f"{q['edit_ms']:.2f}", f"{q['repair_ms']:.2f}", f"{q['back_to_back_ms']:.2f}",
                  f"{q['scratch_ms']:.1f}",
                  f"{q['ratio']:.3f}", f"{q['converge_ratio']:.3f}", str(q["changed"]),
                  f"{q['converge_ns_per_changed']:.0f}", f"{q['scratch_ns_per_reached']:.0f}", str(q["equal"])]
                 for r in results for q in r.get("repairs", [])])
    closing = [] if args.quick or args.only else doors(args.repeats)
    summary = summarise(results, closing)
    print(summary)
    save_results("convergence" + ("-quick" if args.quick else "") + ("-only" if args.only else ""),
                 {"results": results, "doors": closing, "summary": summary}, lambda png: figure(results, png))


def optional(result: dict, reference: str) -> list[str]:
    """A timed-only reference's ms and our ratio to it, as table cells ("-" when it is not installed)."""
    ms, ratio = result[f"{reference}_ms"], result[f"{reference}_ratio"]
    return ["-", "-"] if ms is None else [f"{ms:.1f}", f"{ratio:.2f}"]


def summarise(results: list[dict], closing: list[dict]) -> dict:
    """The issue's figures: median and worst from-scratch ratio to scipy's Dijkstra (worst on maps of
    CONVERGE_LARGE cells or more), the worst to tcod's, the median repair ratio (the edit and its converge) for
    local changes (box, wall) and the worst for any change, the converge's alone for both; for local changes the
    median share of the reachable cells a repair changes, its converge's time per changed cell and a from-scratch
    converge's per reached cell (a repair's work follows the cells it changes), and the median ``floor``; and the
    slowest 9-cell box repair on a 256² map (its converge, with its edit, and the two back to back with no other
    field's converge between); the worst door (``doors``: ``closing``) among any change's."""
    repairs = [q for r in results for q in r.get("repairs", [])] + closing
    local = [q for q in repairs if q["kind"] in ("box", "wall")]
    boxes_256 = [q for r in results if r["map"].startswith("random 256² ") for q in r.get("repairs", [])
                 if q["kind"] == "box"]
    return {"converge_over_dijkstra_median": _median(r["ratio"] for r in results),
            "converge_over_dijkstra_worst_large": _worst(r["ratio"] for r in results if r["cells"] >= CONVERGE_LARGE),
            "converge_over_tcod_worst": _worst(r["tcod_ratio"] for r in results if r["tcod_ratio"] is not None),
            "local_repair_median": _median(q["ratio"] for q in local),
            "repair_worst": _worst(q["ratio"] for q in repairs),
            "local_converge_median": _median(q["converge_ratio"] for q in local),
            "local_changed_share_median": _median(q["changed"] / max(q["reached"], 1) for q in local),
            "local_ns_per_changed_median": _median(q["converge_ns_per_changed"] for q in local),
            "local_floor_median": _median(floor(q) for q in local),
            "scratch_ns_per_reached_median": _median(q["scratch_ns_per_reached"] for q in local),
            "converge_worst": _worst(q["converge_ratio"] for q in repairs),
            "box_repair_256_worst_ms": max((q["repair_ms"] for q in boxes_256), default=float("nan")),
            "box_edit_and_repair_256_worst_ms": max((q["edit_ms"] + q["repair_ms"] for q in boxes_256),
                                                    default=float("nan")),
            "box_back_to_back_256_worst_ms": max((q["back_to_back_ms"] for q in boxes_256), default=float("nan")),
            "all_equal": all(r["equal"] for r in results) and all(q["equal"] for q in repairs)}


def floor(repair: dict) -> float:
    """The ratio a repair would have if its converge cost one cell of a from-scratch converge for each cell it
    changed, its edit as timed: a changed cell must be written and its neighbours read, as a search's is, so no repair
    that visits each changed cell costs much less."""
    return (repair["changed"] * repair["scratch_ns_per_reached"] * 1e-6 + repair["edit_ms"]) / repair["scratch_ms"]


def _median(values) -> float:
    return float(np.median(list(values) or [float("nan")]))


def _worst(values) -> float:
    return float(max(list(values) or [float("nan")]))


if __name__ == "__main__":
    main()
