"""Taichi fields and kernels of the DP: every layer relaxed in parallel, on CPU threads or a GPU (eqs. 5-7, 10-12).

The only module of tdp that imports taichi. Layout (ARCHITECTURE §4):

* the goal layer is one (H + 4) x (W + 4) float32 array, two cells of padding on each side;
* node layers are windows of side 2r + 1 around their nodes, r = ceil(cap); ``LANES`` of them are packed per cell
  as a ``ti.types.vector`` so that one relaxation updates them all with SIMD (Taichi keeps them as LLVM vectors,
  ``real_matrix_scalarize=False``, which the JIT lowers to the host's widest registers). Group g, lane l is node
  g*LANES + l; unused lanes are walled in and stay at the cap;
* an obstacle holds the cap (eq. 5), written into both buffers when the edit is painted - at once in node
  layers; the goal layer holds its edits back for the converge after them, which paints them in its own launch,
  and anything else that reads it paints them first (``_LayerArrays.paint``) - so a move into it yields at least
  the cap and never wins the minimum; the cells a move crosses are checked in a penalty
  array of the same cells as each layer (padding blocked): a move's candidate is ``D[Z] + |V - Z| + pen[crossed
  cells]``, pen 0 free and inf blocked. The goal layer's is float32; a node window's is one int32 word per cell, a
  bit per lane (1 blocked), so that the penalties of 32 lanes take the memory of one (``crossing``).

Kernels come from ``_kernels_for``, one set per compile-time spec - lanes (0 for the goal layer, LANES for node
windows), neighbourhood, corner rule, weighted, absorbing - closed over as constants, built from small rule
factories (``_lane_rules``, ``_cell_rules``, ``_relax_rules``, ``_sweep_rules``, ``_settle_rules``,
``_search_rules``, ``_paint_rules`` ...) by one kernel factory per phase: iterate, settle, search (the goal layer),
fill (node windows), set up, edit, read.
A launch's several parameters travel as a named tuple (``_SettleRun`` ...). Each kind of layer (``_LayerArrays``:
arrays, edits, reads; ``_Layers``: the work on them) knows its kernels, buffers, penalties, header (changed cells,
source), cap and origins under the names of the kernels' parameters, and calls them with keywords. ``warm_up``
launches every kernel of the set on a scratch layer. Each kind of layer is cut into 8 x 8 tiles, relaxed only when
active (their inputs changed in the previous iteration). Which kernel runs when, and on how many threads
(``_Layers._waves`` alone decides): ARCHITECTURE §7.

Kernels take ndarrays, so they compile once per spec and not once per map. Kernels must live in a ``.py`` file:
Taichi reads their source.
"""
import contextlib
import functools
import inspect
import io
import logging
import math
import os
import textwrap
import time
import weakref
from types import SimpleNamespace
from typing import NamedTuple

os.environ.setdefault("ENABLE_TAICHI_HEADER_PRINT", "0")  # a library's stdout belongs to its user: no banner

import numpy as np  # noqa: E402
import taichi as ti  # noqa: E402
from taichi.lang import impl as _taichi_impl  # noqa: E402
from taichi.lang import runtime_ops as _taichi_runtime_ops  # noqa: E402
from taichi.lang._ndarray import Ndarray as _Ndarray  # noqa: E402
from taichi.types import primitive_types as _primitive  # noqa: E402
from taichi.types.ndarray_type import NdarrayType  # noqa: E402

from . import checks, stencil
from .grid import MAX_COST  # a penalty above it is an obstacle's (inf): kernels test against it, not inf

#: Node layers packed per cell: 32 float32, two AVX-512 registers (measured faster than 16 and 64 at 1024²).
LANES = 32
#: Padding around every array: the stencil's reach, so kernels never test bounds.
PAD = stencil.REACH
#: Active tiles of one kind of layer up to which iterations run one after another on the calling thread, in one
#: launch; beyond, each iteration is a parallel launch. Measured on the 2-core VM: waking the worker threads costs
#: about 55 µs a launch, and one thread relaxes a dense layer of up to about 1000 tiles as fast as two (a parallel
#: loop of fewer than 1,024 iterations runs on one thread in Taichi 1.7: :func:`init_taichi`).
SERIAL_TILES = 512
#: The same for converge()'s rounds on a scalar layer (the goal's): its tiles are light, and a parallel round was no
#: faster than one thread on the 2-core VM (random 1024², 20 % obstacles, from scratch: 155-189 ms on one thread
#: against 194-246 ms with parallel rounds beyond 512 tiles; 256²: 12-18 against 17-24 ms).
SERIAL_SETTLE_TILES = 16384
#: Width, in cells of distance, of the buckets in which converge() settles the goal layer's tiles: a round settles
#: the active tiles whose key (the smallest value that woke them) is within SETTLE_BAND of the lowest key. Narrow
#: buckets settle a tile fewer times where routes wind (random 512², 30 % obstacles: 1.4x scipy's Dijkstra against
#: 2.1x with 256) and cost nothing elsewhere: the goal layer's rounds are cheap (RESULTS §2).
SETTLE_BAND = 32.0
#: The same for packed node layers: their rounds are parallel launches over every lane's fronts, and a key is the
#: lowest of 32 lanes' values; 32-cell buckets took 470 rounds on the warehouse map (setup 0.9-1.1 s, 0.6 s with these).
PACKED_SETTLE_BAND = 256.0
#: Side of an active tile, in cells: a tile is relaxed only when its inputs changed in the previous iteration.
TILE = 8
_FAR = -(1 << 28)  # origin of an unused lane: its window lies far outside every map
_NEVER = 1 << 30  # an iteration number no tile is ever stamped for
_FLOAT32_MAX = float(np.finfo(np.float32).max)
_FREE, _BLOCKED = np.float32(0.0), np.float32(np.inf)  # the penalties of an unweighted free cell and a blocked one
#: The key of a tile just settled: nothing pending can lower its cells (a key is a lower bound, here a vacuous one)
#: until a neighbour's change wakes it with a real key. A tile woken before its turn in a round keeps this, and
#: waits to the end instead of being due at once (which kept a focused repair from stopping).
_SETTLED = 1e38
#: A tile's two keys (the last axis of ``keys``): lowering's, the bound below which none of its cells can fall (inf:
#: unknown, due at once; _SETTLED: nothing to lower), and lifting's, a bound that every cell of it below its
#: relaxation holds more than (inf: none is). A tile with a finite lifting key is lifted before it is lowered.
_LOWER, _LIFT = 0, 1
#: A layer kind's header, an int32 array the kernels read and write: the cells the last iteration changed, the
#: source (padded layer coordinates), the cell held at 0, and the focus of a converge (padded coordinates; row -1:
#: none): the cell whose value and successor chain a focused repair settles first and stops at; the sweeps (passes
#: over an 8 x 8 tile) a serial settling launch has made so far, and how many it may (0: no limit); and a round
#: that a launch's allowance cut short, for the next launch to go on with: the entry of its work list to go on from
#: (0: none open), its bound (float32 bits) and whether it lifts.
CHANGED, SOURCE_ROW, SOURCE_COL, FOCUS_ROW, FOCUS_COL, SWEPT, SWEEP_ALLOWANCE = 0, 1, 2, 3, 4, 5, 6
ROUND_CURSOR, ROUND_BOUND, ROUND_LIFTS, SCANNED = 7, 8, 9, 10
#: Work-list entries a round's scan reads for the price of one sweep of a tile (about 20 ns against 1-2 µs): a
#: launch with an allowance counts its scans against it, so that a slice with thousands of tiles waiting does not
#: begin round after round.
SCANNED_PER_SWEEP = 64
_NO_FOCUS = (-1, -1)
#: Iterations handed to one launch at most (kernel arguments are 32-bit).
_CHUNK = 1 << 20
#: A focused search stops once the bucket it reaches is this many cells beyond the focus's value, so that the
#: settling rounds that take over its frontier find nothing due: they key a tile by the cells within its reach and
#: add the distance from the focus of its nearest cell, up to a tile-and-reach diagonal less than those cells' own
#: (and a priority carries float rounding).
SEARCH_MARGIN = (TILE - 1 + 2 * PAD) * math.sqrt(2) + 1
#: A repair after edits (``_Layers._repair``) gives up for a restart from the initial state once it has taken this
#: share of the last search's time. On the convergence benchmark's 512² maps 0.25 kept the worst edit (a box sealing
#: most of a maze) at 1.65x a restart but made every repair that needs a quarter to all of one cost 1.25x one (the
#: median box or wall 1.14x); 0.5: median 0.44x, worst 2.3x; 1.0: 0.41x and 3.5x. Its
#: first slice makes the sweeps that fit in that time at SLOWEST_SWEEP_S each (1.1-2.2 µs measured on the 2-core VM,
#: mazes the dearest), each later one what the rate measured says fits in the rest, SLICE_GROWTH times the last at
#: most (``sweeps_fitting``).
RESTART_SHARE = 0.5
#: A mend (``_LayerArrays._mend``) gives way to a restart once its look and raise pass this share of a restart's
#: price, the cells the source reaches (the last search's count, or the count a mend since made: its first look's, at
#: least the cells it lowered) and the reset's fills (a ski rental again: at most about 1 + MEND_SHARE times a
#: restart, whatever the cut). Raising a cell is priced at RAISE_COST cells a search takes: measured on the 2-core VM
#: a raise with its seed's relaxation costs 50-75 ns (mazes the cheapest), a cell a search takes 50-65 ns - the
#: dearer price gives way sooner where a raise runs away (a box sealing off half a maze). Its lowering never gives
#: way: it takes each cell it lowers once, as a restart's search would, and a restart searches every cell the source
#: reaches, the lowered ones among them, after a reset. (Giving way there too, a goal let out of a pocket - whose
#: lowering is the whole search - cost a mend its share of the pocket's small price, then the restart: 1.43-1.64x a
#: fresh converge on turtlebot3's world, against 1.10-1.15x now.)
MEND_SHARE = 0.4
RAISE_COST = 2
#: ... and an edited cell at EDIT_COST: a mend paints it, pushes the cells within reach of it for the raise and, if
#: it left its cell free, seeds them: 0.2-0.3 µs an edited cell measured on the 2-core VM where most hold the cap.
#: Without that price, a goal sealed in a pocket of a hundred cells, then 7,200 cells blocked elsewhere on a 520²
#: map cost a mend 1.5 ms where a restart (the edits painted, the pocket searched) takes 0.6 - 3.3 ms before the
#: seeds skipped the cells round a blocked one, 25x a fresh converge.
EDIT_COST = 4
#: A search from the source races a mend's first look and, where the look found the edits' sides apart (the goal may
#: be sealed in a part of any size, or a pocket sealed off), its raise (``_race_rules``), in a spare buffer: RACE_LEAD
#: cells taken for each cell the mend has looked at or raised. If it finishes first, it is the repair, a restart that
#: cost its own cells and the mend's beside them: 1 + 1 / RACE_LEAD of them where those are cells looked at, up to
#: about 1 + RAISE_COST / RACE_LEAD where they are raised cells (1.5-1.9 cells of a search each on corridors, their
#: seeds counted). Paced by the raise's price instead, the worst edits fell from 1.8-2.0x to 1.4-1.7x a fresh
#: converge, but noise on random maps, whose mend finishes with the race beside it, cost 1.3-1.5x more (ARCHITECTURE
#: §7). It runs only where it could win (``race_lead``).
RACE_LEAD = 2
#: The share of a map's free cells in corridors a cell wide from which a mend's raise goes depth first
#: (``depth_first_raise``): 1-cell mazes, rings and serpentines have nearly all their free cells so, random maps
#: with 20 % obstacles 18 % and with 40 % about half, 2-cell mazes and open ROS maps few.
CORRIDOR_SHARE = 2 / 3
#: Where the look found the edits' sides apart, the race gets a head start in the raise: the cells nearer the source
#: than the edits (``kept``: the log's count, a lower bound on what the source still reaches), which a race that wins
#: must take first, and then keeps its lead - a goal sealed in a room is mended at 1 + (1 - kept / reached) /
#: RACE_LEAD of a restart, not 1 + 1 / RACE_LEAD. A race that then loses has taken them in vain, so the head start is
#: given only where they are at most RACE_HEAD_SHARE of a restart (``race_head``): A/B on the 2-core VM, rooms 7-19 %
#: cheaper on 8 of 15 maps (the rest within the VM's spread) and a door keeping a tenth of a maze 19 %, nothing else
#: moved, while with a share of 1/4 a pocket sealed on nav2's warehouse, its ring nearer the source than a fifth of
#: the cells, cost 4.9x more.
RACE_HEAD_SHARE = 1 / 8
#: Where the last search's log says many cells lie below every value within reach of the edits (no cell there
#: changes), the race starts from them instead of the source (``seed_bound``): one pass over the layer copies them
#: into its buffer and lists those within a move of the bound, and the race takes only the cells at or past it - a box
#: that cuts a maze's corridor leaves the goal's side as it was, which a race from the source took again. The pass
#: costs a padded cell about a SEED_PASS-th of a cell a search takes (measured on the 2-core VM: 1.2-1.5 ns against
#: 50-65), so it is made once the mend's look and raise have cost SEED_AFTER times as much: a mend that would have
#: finished just after pays the pass, the race's work and the refill of its buffer, about half as much again (at once,
#: a box on a random 512² map with 40 % obstacles, mended in 0.6 ms, cost 1.9).
SEED_PASS = 32
SEED_AFTER = 2
_SEED_MOST = 1 << 24  # a seeded race's bound is below this: float32 holds every whole number up to it
#: From this value on, float32 may round a value plus a move (at least 1) back to the value; a scalar layer's move
#: then adds at least one float32 step (``_cell_rules``' ``plus``, ARCHITECTURE §4).
ABSORBING = float(1 << 24)
_INF_BITS = 0x7F800000  # float32 +inf's bits: a non-negative float32's bits order as the float does
#: From this value on, an absorbing layer's search buckets are one float32 step wide (``_cell_rules``' ``bucket``):
#: a bucket a whole number of distance would pass int32's largest at 2^31, and a move adds at least a step.
_STEP_BUCKETS = float(1 << 30)
_STEP_BUCKETS_SHIFT = int(np.float32(_STEP_BUCKETS).view(np.int32)) - (1 << 30)  # buckets run on unbroken at 2^30
_LAST_BUCKET = (1 << 31) - 1  # past every bucket (inf's is 1.9e9)


def may_absorb(cells: int, max_cost: float, cap: float) -> bool:
    """Whether a scalar layer of ``cells`` cells, free cells costing at most ``max_cost``, may hold a value from
    ABSORBING on below its ``cap``: a route visits a cell once, and a move adds at most sqrt 5 x the dearest cost."""
    return min(cap, cells * math.sqrt(5) * max_cost) >= ABSORBING


@ti.func
def _above(value):
    """The next float32 above non-negative ``value`` (inf stays inf), by its bits."""
    return ti.bit_cast(ti.min(ti.bit_cast(value, ti.i32) + 1, _INF_BITS), ti.f32)

#: The parts a mend's ``cut_off`` follows at most (free cells beside the cells its edits blocked, each a part until
#: parts meet): a larger edit - a map loaded anew - goes straight to the raise.
CUT_PARTS = 4096
#: The share of a reset's fills (in cells a search takes) that ``cut_off`` may look at, a look priced as a search's
#: cell (measured on the 2-core VM: 45-55 ns a cell looked at, the parts' merges and the marks cleared after counted,
#: 13-25 ns as a plain breadth-first fill, against 50-65 ns a cell a search takes): enough to tell that a box or a
#: wall cut nothing - its sides meet round it within a few rings of cells - and to find a pocket or a goal sealed in
#: of a few hundred cells, little against the raise it spares where it finds nothing. A/B on the 2-core VM: 0.5 made
#: boxes and walls 5-6 % faster (no probe - the race's forerunner - counted in vain after it) and the mend of a goal
#: sealed in a pocket of 62-405 cells 7-32 %, and cost pockets of thousands of cells 1-12 % (it looks in vain); four
#: times as much cost a 1024² map's pocket of 13,000 cells 1.5x.
CUT_SHARE = 0.5
#: Cells a mend's look takes for each edited cell before it pauses the parts beside no cluster whose sides are apart
#: (``pause_joined``: a few passes over the edits a check). `python -m benchmarks.ab`: noise on random 1024² 0.57-0.59x,
#: boxes there 0.67-0.70x; checked from the look's start (no such floor), a pocket sealed 1.11-1.51x on random maps.
PAUSE_AFTER = 8
#: Where the look stops short with parts apart, the outline of the source's part (``_cut_rules``' ``outlined``) is
#: followed for at most 1 / OUTLINE_SHARE of a restart's price in cracks (``outline_cracks``). On a maze a crack costs
#: about a quarter of a cell a search takes (a turn every few cracks: 52,000 cracks added 0.8 ms to a box's 2.4 ms
#: repair on the 1-cell maze 512²); a goal sealed in a room has an outline of a few thousand cracks, and where the room
#: lies at the end of a walk past islands (a wide hall: 6,200 cracks) or winds round every obstacle touching its
#: ring (40 % obstacles: 7,700), at most 1/32 of a restart left the raise to run beside the race (1.7-1.9x a fresh
#: converge, against 1.3-1.45x found: RESULTS §2). An outline that does not close costs a mend at most about 3 % of a
#: restart; followed as far as the mend's budget it made boxes and walls on mazes 1.2-1.7x dearer (``benchmarks.ab``).
OUTLINE_SHARE = 8
#: The same on maps of corridors a cell wide (``depth_first_raise``), whose outlines run along both sides of every
#: corridor of their part - two cracks a cell -, so that 1/8 of a restart would close only round a part of at most a
#: sixteenth of the map's cells, and it made a box's repair on the 1-cell mazes 1.09x dearer, eight boxes' 1.06x and
#: a pocket's 1.05x (``benchmarks.ab``, pass by pass), where the outline runs and does not close.
CORRIDOR_OUTLINE_SHARE = 32
_APART_SIDE = CUT_PARTS  # no part's index: a cluster's open sides in two parts or more (``_cut_rules``)
#: The flags of a part of ``cut_off``: it holds the source; it ran dry (closed); its clusters' sides are all one part
#: (paused: its cells are dropped, not looked at); it dropped cells (truncated: it never reads as closed).
_HOLDS_SOURCE, _CLOSED, _PAUSED, _TRUNCATED = 1, 2, 4, 8
_PARENT, _WAITING, _FLAGS, _PART_INTS = range(4)  # a part's ints in ``cut_off``'s trail
#: A look's ints (``_cut_rules``): cells looked at, queued, parts live, whether crowded, whether the source is blocked,
#: the part holding the source closed (-1: none), whether parts are apart, the cells looked at at the next check of
#: the clusters' sides, the clusters, the parts it started with, the cells it dropped (paused parts').
_LOOKED, _QUEUED, _LIVE, _CROWDED, _LOST, _SEALED, _CUT, _CHECK_AT, _CLUSTERS, _PARTS, _DROPPED = range(11)
#: A raise's ints (``_raise_rules``): its queue's next entry and end, the cells raised, the cells waiting to be looked
#: at again, the cells raised since they were last looked at.
_NEXT, _END, _RAISED, _DEFERRING, _ROSE = range(5)
#: A mend's phases: its look, its raise, and the raise over (the race goes on beside both).
_LOOKING, _RAISING, _RAISE_OVER = range(3)
#: A blocked edit's mark in row 2 of ``cut_off``'s trail when it checks its clusters (a part's is the part + 1):
#: a cluster's root holds -(_ROOT + its side + 1), any other blocked cell -(its parent + 2) - so layers of _ROOT - 2
#: padded cells or more (23,000 cells a side) are not checked.
_ROOT = 1 << 29
_EDITED = -_ROOT
#: A mend's ``trail``: its first look's (parts, queue, marks: ``_cut_rules``), row 0 then its raised cells and seeds.
_TRAIL_ROWS = 3
#: Cells a search must take for its time to price a cell (``_Layers._fills``): a smaller one's time is mostly its
#: launch and hand-over - a goal sealed in a pocket of 20 cells priced a cell at 12 µs, against 50-65 ns.
PRICED_SEARCH = 4096
#: A reset's price in cells a search takes, at most: a search's cell per this many cells of the layer (it fills the
#: layer's arrays; a goal in a pocket of a few cells searches next to nothing, but its reset still fills the whole
#: map). The last reset's measured time gives it, where less (a large map's fills run at memory speed).
FILLS_PER_CELL = 16
SLOWEST_SWEEP_S = 2.5e-6
_FEWEST_SWEEPS = 16  # a repair's slice makes at least this many sweeps
#: A slice of a sliced converge (a repair's here, a budgeted tick's in :class:`tdp.ExactPlanner`) makes at most this
#: many times the sweeps of the slice before it: sweeps cost about the same, but a rate measured on one slice's work
#: need not hold for the next's.
SLICE_GROWTH = 4
_UNLISTED = -1  # a cell's previous entry in the search's links when it is in no bucket (and the end of a bucket)
_STACKED = -(1 << 30)  # ... while it waits in the raise's queue (``_raise_rules``)
_DEFERRED = _STACKED + 1  # ... or among the cells the raise looks at again once it has raised more
#: The fewest buckets of the search's ring: a mend's seeds span many buckets and wait in a list for the ring's
#: window (half of it ahead) to reach them, so a wider ring scans that list less often; 1024 heads cost nothing.
MIN_RING = 1024
#: The buckets of a weighted layer's ring that one mark covers (``_bucket_rules``: its marks, a ring's 64th, fit in
#: row 1 of the ring's links after the search's log, at least 1024 - 120 entries).
_BLOCK = 64
#: ... and that one group mark covers, _BLOCK blocks (a ring of 4096 buckets or more: a 4096th more of it in row 1).
_GROUP = _BLOCK * _BLOCK
#: A mark's values: no cell listed in its buckets since it was cleared - what the links are filled with when made, so
#: that a new ring's first clear, hand-over or race walks none of its buckets (made set, they were all walked once:
#: neutral as measured, the first mend at costs of 1e6 spending its 40 ms on allocating the links) - or some may be.
_UNMARKED, _MARKED = _UNLISTED, 1
#: Padded cells a layer may have a side: kernels index a padded cell row-major in an int32 (the search's buckets after
#: the cells), which 2**15 a side keeps well inside.
MAX_SIDE = 1 << 15
#: The most cells a map may have a side (its layers padded by PAD on each side fit MAX_SIDE).
MAX_MAP_SIDE = MAX_SIDE - 2 * PAD
#: Entries along each axis of the arrays ``warm_up`` hands a kernel for parameters no scratch layer holds.
IDLE_ENTRIES = 16
#: A layer's iteration number past which its stamps are rebased to 0, so that it never reaches _NEVER (2**30).
REBASE_AT = 1 << 29
#: Moves a successor's trace follows on from the cell asked about (``Engine.focus_successor``): a robot stepping
#: along its route finds the next cells' successors read; the trace costs its launch whatever its length.
ROUTE_AHEAD = 32
#: Successors kept at most (``Engine.focus_successor``): asked about every cell of a large map with nothing changing,
#: the kept moves start again from none rather than grow with the map.
SUCCESSORS_KEPT = 1 << 16

# Launch parameters and results of the kernels that take several: named tuples on the host, one int32 numpy array a
# launch in Taichi (``_launch``: the parameters, then room for the results), which kernels index by the slots below.
# Through Taichi's own call an array argument costs about 9 µs a launch on the 2-core VM, an int32 vector 20 µs and a
# struct 25 µs; :class:`_Launcher` sets an array's slot in 1.3-2.4 µs.
class _StepRun(NamedTuple):
    """``iterate``'s launch: the iteration's number and the sample row it writes."""

    tick: int
    step: int


class _IterateRun(NamedTuple):
    """``iterate_serially``'s launch: the first iteration's number, the sample row of the first, how many
    iterations at most, the most active tiles to go on with, the latest iteration the host stamped tiles for."""

    tick: int
    first: int
    steps: int
    limit: int
    woken: int


class _SettleRun(NamedTuple):
    """``settle_serially``'s launch: the first round's number, how many rounds at most, the most active tiles to go on
    with, the focus (padded layer coordinates; row -1: none), the sweeps allowed (0: any number), whether round
    ``tick``'s work list is kept (1) or must be listed first (0), whether round ``tick`` is open (edits painted in
    the launch wake their tiles for the round after it)."""

    tick: int
    rounds: int
    limit: int
    focus_row: int
    focus_col: int
    sweeps: int
    listed: int
    round_open: int


class _SettleResult(NamedTuple):
    """What ``settle_serially`` hands back: the rounds done, whether it settled, stopped at the focus, the sweeps
    made, whether the allowance stopped it, the index of the focus's successor move (-1: none)."""

    rounds: int
    settled: int
    focused: int
    swept: int
    cut: int
    move: int


class _SearchRun(NamedTuple):
    """``search``'s launch: the focus (padded layer coordinates; row -1: none), the round the frontier's tiles are
    stamped for, and whether to search (0: a launch that only compiles)."""

    focus_row: int
    focus_col: int
    tick: int
    go: int


class _SearchResult(NamedTuple):
    """What ``search`` hands back: the buckets emptied, the cells still listed (a focused search's frontier) and the
    cells taken from the buckets."""

    buckets: int
    frontier: int
    taken: int


class _MendRun(NamedTuple):
    """``mend``'s launch: the focus (padded layer coordinates; row -1: none), the round the frontier's tiles are
    stamped for, by the mend and by the restart it may give way to (as a reset leaves the round), its budget (cells a
    search takes: its look and raise past it, the mend gives way to a restart), a restart's price and a reset's
    fills in those units, the cells its first look at the cut may take (``_cut_rules``), the most a move adds to a
    value (``_longest_move``), its race's lead (RACE_LEAD) and the most cells its head start may be
    (RACE_HEAD_SHARE of a restart), the mend's work a race from the kept cells waits for and the price of its pass
    (``seed_bound``: SEED_AFTER and SEED_PASS), whether every tile is settled already (1: the hand-over stamps the
    frontier alone), whether the raise takes the cell queued last first (``depth_first_raise``), and whether to mend
    (0: a launch that only compiles)."""

    focus_row: int
    focus_col: int
    tick: int
    restart_tick: int
    budget: int
    restart: int
    fills: int
    looks: int
    longest_move: int
    lead: int
    head: int
    seed_wait: int
    seed_pass: int
    settled: int
    depth_first: int
    go: int


class _MendResult(NamedTuple):
    """What ``mend`` hands back: the buckets emptied, the cells left to lower (a focused mend's frontier), the cells
    raised to the cap, the cells the source still reaches if its look counted them (-1: not), its work in cells a
    search takes (the race's apart), the cells its race took as the mend ran and its head start (``race_head``),
    whether it gave up for a restart (the race finished first, a restart cost less than the rest of the mend, or its
    look and raise passed the budget), the cells its lowering took - having given up, its race's search took in
    all (the buckets and the frontier then the race's) -, whether its race started from the cells the edits left
    as they were (``seed_bound``: the spare buffer then holds them), and the most cells the source's part can hold
    by its outline, where the look stopped short and the outline closed within ``outline_cracks`` (-1: none;
    ``_cut_rules``' ``outlined``)."""

    buckets: int
    frontier: int
    raised: int
    reached: int
    spent: int
    raced: int
    head: int
    gave_up: int
    lowered: int
    seeded: int
    outlined: int


class _PaintRun(NamedTuple):
    """``paint``'s launch: the iteration or round the woken tiles are stamped for, whether the work lists are kept."""

    tick: int
    listed: int


def _slots(launch: type, after: type | None = None):
    """``launch`` with each field holding its index in a launch's array, for kernels to read ``run[_SETTLE.tick]``;
    a result's fields come ``after`` the parameters of its launch."""
    first = 0 if after is None else len(after._fields)
    return launch(*range(first, first + len(launch._fields)))


def _launch(run: NamedTuple, result: type | None = None) -> np.ndarray:
    """The int32 array a kernel's ``run`` parameter takes: the fields of ``run``, then a slot for each field of
    ``result`` (if any), which the kernel fills (:func:`_outcome` reads them)."""
    return np.array((*run, *[0] * (0 if result is None else len(result._fields))), np.int32)


def _outcome(result: type, launched: np.ndarray):
    """The ``result`` (a named tuple type) a kernel wrote at the end of its launch array."""
    return result(*launched[len(launched) - len(result._fields):].tolist())


_STEP, _ITERATE, _SETTLE, _SEARCH = _slots(_StepRun), _slots(_IterateRun), _slots(_SettleRun), _slots(_SearchRun)
_MEND, _PAINT = _slots(_MendRun), _slots(_PaintRun)
_SETTLED_BY, _SEARCHED = _slots(_SettleResult, _SettleRun), _slots(_SearchResult, _SearchRun)
_MENDED = _slots(_MendResult, _MendRun)


_initialised = False
_on_cpu = True


@functools.lru_cache(maxsize=None)
def _wrapped(width: int, text: str) -> tuple[str, ...]:
    return tuple(textwrap.TextWrapper(width=width).wrap(text))


class _MemoisedWrapper(textwrap.TextWrapper):
    """A ``TextWrapper`` as Taichi's front end makes one for every AST node (``width`` its only option), with
    ``wrap`` memoised."""

    def wrap(self, text: str) -> list[str]:
        return list(_wrapped(self.width, text))


def _memoised_source_lines(source_lines):
    """``source_lines`` (a function's source lines and first line number) memoised by function."""
    cached = functools.lru_cache(maxsize=None)(source_lines)

    def lines(function) -> tuple[list[str], int]:
        text, first = cached(function)
        return list(text), first
    return lines


def _memoised_position(position):
    """Taichi 1.7's ``ASTTransformerContext.get_pos_info`` (``position``: an AST node's file, line and function, and
    its source line with a caret under it, the debug message of each IR statement the node makes) memoised for a
    node on one line by all that it reads there: the file, the line's number and text, the function's name and the
    node's columns. A node over several lines is left to ``position``."""
    cached = {}

    @functools.wraps(position)
    def get_pos_info(context, node) -> str:
        if node.lineno != node.end_lineno:
            return position(context, node)
        key = (context.file, node.lineno + context.lineno_offset, context.func.func.__name__,
               context.src[node.lineno - 1], context.indent + node.col_offset, context.indent + node.end_col_offset)
        info = cached.get(key)
        if info is None:
            info = cached[key] = position(context, node)
        return info
    return get_pos_info


def _quicken_taichi_front_end() -> None:
    """Memoise three pure steps that Taichi 1.7's front end repeats for every kernel it compiles and every ti.func
    call it inlines - about 2,300 of them for the exact planner's 16 kernels, 10.8 s of a 19 s ``tdp run`` with
    the offline cache warm (it caches the compiled code, keyed by the IR these steps build): reading a function's
    source lines (``inspect.getsourcelines`` tokenises its block each time), each AST node's debug message (its
    source line with a caret under it) and, for nodes over several lines, wrapping each line at 80 columns (a
    ``TextWrapper`` per node). The strings out are the same; another Taichi version is left as it is."""
    from taichi.lang import kernel_impl
    from taichi.lang.ast import ast_transformer_utils

    if _DIRECT_TAICHI and ast_transformer_utils.TextWrapper is textwrap.TextWrapper:
        ast_transformer_utils.TextWrapper = _MemoisedWrapper
        kernel_impl.getsourcelines = _memoised_source_lines(kernel_impl.getsourcelines)
        context = ast_transformer_utils.ASTTransformerContext
        context.get_pos_info = _memoised_position(context.get_pos_info)


def init_taichi() -> None:
    """Initialise Taichi once per process: ``TDP_ARCH`` (default cpu) and ``TDP_THREADS`` (default 2).

    Raises:
        ValueError: ``TDP_ARCH`` names no Taichi arch, or one this machine lacks (Taichi would run on the CPU
            instead), or ``TDP_THREADS`` is not a positive integer.

    Packed layers stay LLVM vectors (``real_matrix_scalarize=False``: Taichi's CPU optimiser otherwise targets
    generic x86-64, 4 floats wide). Taichi 1.7 splits a parallel loop on the CPU into one block per thread of at
    least 512 iterations (its ``make_cpu_multithreaded_range_for`` pass; ``block_dim`` and
    ``cpu_block_dim_adaptive`` change nothing there), so a loop of fewer than 1,024 iterations runs on one thread:
    SERIAL_TILES keeps the smaller waves off the worker threads. Turning the pass off (``block_dim`` honoured, 32
    iterations a task) made a dense iteration of 64 node layers on a 512² map 1.2-1.6x slower (2-core VM)."""
    global _initialised, _on_cpu
    if _initialised:
        return
    _quicken_taichi_front_end()
    arch_name = os.environ.get("TDP_ARCH", "cpu")
    arch = getattr(ti, arch_name, None)
    if arch is None:
        raise ValueError(f"TDP_ARCH must name a Taichi arch such as cpu or cuda, got {arch_name!r}")
    threads = os.environ.get("TDP_THREADS", "2")
    if not threads.isdigit() or int(threads) < 1:
        raise ValueError(f"TDP_THREADS must be a positive integer, got {threads!r}")
    with contextlib.redirect_stdout(io.StringIO()) as said:  # ti.init prints "Starting on arch=..."
        ti.init(arch=arch, cpu_max_num_threads=int(threads), default_fp=ti.f32, log_level=ti.WARN,
                real_matrix_scalarize=False)
    logging.getLogger(__name__).debug(said.getvalue().strip())
    started = ti.lang.impl.current_cfg().arch
    if arch != ti.cpu and started == ti.cpu:  # Taichi falls back to the CPU with a warning on stderr alone
        raise ValueError(f"TDP_ARCH={arch_name} asked for Taichi's {arch_name} backend, but Taichi found no such "
                         f"device or driver and started on the CPU; unset TDP_ARCH (or set it to cpu) to run there")
    _initialised = True
    _on_cpu = started == ti.cpu


#: Launch kernels through :class:`_Launcher`'s direct path (tests turn it off to compare the two paths).
DIRECT_LAUNCH = True
#: On the CPU, keep each direct launch's context for the next launch with the same Taichi ndarrays (tests turn it
#: off to compare).
HOLD_CONTEXTS = True
#: The Taichi whose launch internals :class:`_Launcher` was written against (1.7); another takes Taichi's calls.
_DIRECT_TAICHI = tuple(ti.__version__[:2]) == (1, 7)
_SIGNED = (ti.i8, ti.i16, ti.i32, ti.i64)


def _argument_kind(value) -> object:
    """What Taichi compiles a kernel instance for, of one argument: a numpy array's dtype, dimensions and layout, a
    Taichi ndarray's element type and dimensions, else the value's type."""
    if type(value) is np.ndarray:
        return value.dtype, value.ndim, value.flags.c_contiguous
    if isinstance(value, _Ndarray):
        return value.element_type, len(value.shape)
    return type(value)


class _HeldLaunch(NamedTuple):
    """A launch context :class:`_Launcher` keeps for its next launch: the kernel instance it is for, the context,
    (index, weak reference) of each Taichi ndarray argument it holds, the other arguments' indices (set at every
    launch)."""

    instance: object
    context: object
    arrays: tuple
    others: tuple


def _set_host_array(program, context, index: int, array: "_Ndarray") -> None:
    """Set argument ``index`` of launch ``context`` to the host memory of Taichi ndarray ``array`` (CPU only), as
    Taichi sets a numpy array's: its shape without the element's (a vector's lanes)."""
    context.set_arg_external_array_with_shape((index,), program.get_ndarray_data_ptr_as_int(array.arr),
                                              array.arr.nelement() * array.arr.element_size(), array.arr.shape, 0)


class _Launcher:
    """A ``ti.kernel`` launched by keywords, Taichi's per-argument work done once per kind of arguments.

    Taichi 1.7 prices each argument of each launch anew in Python - its part of the instance's key, its checks,
    then its slot in the launch context: 5-10 µs an argument, 73 µs for the mend's eleven on the 2-core VM, where
    setting the slots and launching take about 25. The first launch with a kind of arguments
    (:func:`_argument_kind`) goes through Taichi's own call, which compiles, checks and launches; later ones set each
    argument's slot directly (``Kernel.launch_kernel``'s calls, read from Taichi 1.7.4) and launch the instance the
    first one compiled. A kernel or argument it does not handle (a struct, a returned vector), and any other Taichi
    version, always takes Taichi's call. On the CPU it keeps the last launch's context (:meth:`_held_context`) and,
    while the Taichi ndarrays passed are the same objects, sets only the numpy and scalar arguments again: setting an
    ndarray's slot (4-5 µs), making a context and looking the compiled kernel up cost a mend's launch about 80 µs of
    its 137 on the 2-core VM."""

    def __init__(self, kernel):
        self.kernel = kernel
        self.__name__, self.__doc__, self.__signature__ = kernel.__name__, kernel.__doc__, inspect.signature(kernel)
        self._names = tuple(self.__signature__.parameters)
        # kinds of arguments -> (Taichi's kernel instance, its compiled kernel, argument setters, return reader);
        # False: Taichi's call
        self._ready: dict = {}
        self._held: _HeldLaunch | None = None  # the last direct launch's context, for the next (``_held_context``)

    def __call__(self, **arguments):
        values = tuple(arguments[name] for name in self._names)
        kinds = tuple(map(_argument_kind, values))
        ready = self._ready.get(kinds) if DIRECT_LAUNCH else None
        if ready is None:
            result = self.kernel(**arguments)
            if kinds not in self._ready:
                self._ready[kinds] = self._prepare(values) if _DIRECT_TAICHI else False
            return result
        if ready is False:
            return self.kernel(**arguments)
        instance, compiled, setters, returned = ready
        program = _taichi_impl.get_runtime().prog
        if _on_cpu and HOLD_CONTEXTS:
            context = self._held_context(program, instance, setters, values)
        else:
            context = instance.make_launch_context()
            for index, (setter, value) in enumerate(zip(setters, values)):
                setter(context, (index,), value)
        program.launch_kernel(compiled, context)
        return returned(context) if returned else None

    def _held_context(self, program, instance, setters, values: tuple):
        """The launch context of the last launch, its numpy and scalar arguments set anew, while
        its Taichi ndarrays are the same objects; else a new one, held for the next launch. On the CPU a held
        context's ndarrays are set as the host memory they own (``_set_host_array``): Taichi's CPU launcher turns an
        ndarray's slot into its raw pointer at the first launch, and a second launch of the same context read the
        ndarray's allocation record as its data."""
        held = self._held
        if held is not None and held.instance is instance and all(ref() is values[i] for i, ref in held.arrays):
            for index in held.others:
                setters[index](held.context, (index,), values[index])
            return held.context
        context = instance.make_launch_context()
        arrays, others = [], []
        for index, (setter, value) in enumerate(zip(setters, values)):
            if isinstance(value, _Ndarray):
                _set_host_array(program, context, index, value)
                arrays.append((index, weakref.ref(value)))
            else:
                setter(context, (index,), value)
                others.append(index)
        self._held = _HeldLaunch(instance, context, tuple(arrays), tuple(others))
        return context

    def _prepare(self, values: tuple):
        """The instance Taichi compiled for ``values``' kinds, its compiled kernel (looked up once: Taichi's call
        looks it up at every launch), a setter per argument and a reader of the returned value (None: none
        returned); False where an argument or the return is of a kind not handled."""
        primal = self.kernel._primal
        if primal.has_print or any(isinstance(a.annotation, ti.template) for a in primal.arguments):
            return False
        setters = tuple(_setter(a.annotation, value) for a, value in zip(primal.arguments, values))
        returned = _return_reader(primal.return_type)
        if None in setters or returned is False:
            return False
        instance = primal.compiled_kernels[primal.ensure_compiled(*values)]
        program = _taichi_impl.get_runtime().prog
        compiled = program.compile_kernel(program.config(), program.get_device_caps(), instance)
        return instance, compiled, setters, returned


def _setter(annotation, value):
    """How to put ``value`` in its launch-context slot for a parameter of type ``annotation``: Taichi 1.7's own
    calls (``Kernel.launch_kernel``); None for a kind not handled."""
    if id(annotation) in _primitive.real_type_ids:
        return lambda context, index, v: context.set_arg_float(index, float(v))
    if annotation in _SIGNED:
        return lambda context, index, v: context.set_arg_int(index, int(v))
    if not isinstance(annotation, NdarrayType) or getattr(value, "grad", None) is not None:
        return None
    if isinstance(value, _Ndarray):
        return lambda context, index, v: context.set_arg_ndarray(index, v.arr)
    if type(value) is np.ndarray and value.flags.c_contiguous and id(annotation.dtype) in _primitive.type_ids:
        return lambda context, index, v: context.set_arg_external_array_with_shape(index, v.ctypes.data, v.nbytes,
                                                                                  v.shape, 0)
    return None


def _return_reader(return_type):
    """A reader of a kernel's returned int32 or float32 from its launch context (after a sync, as Taichi's call);
    None when it returns nothing, False for anything else."""
    if return_type is None:
        return None
    if len(return_type) != 1:
        return False
    kind = return_type[0]
    if kind in _SIGNED:
        getter = "get_struct_ret_int"
    elif id(kind) in _primitive.real_type_ids:
        getter = "get_struct_ret_float"
    else:
        return False

    def returned(context):
        _taichi_runtime_ops.sync()
        return getattr(context, getter)((0,))

    return returned


def sweeps_fitting(left_s: float, sweep_s: float, fewest: int, most: int) -> int:
    """The sweeps (passes over an 8 x 8 tile) a slice of a converge may make in ``left_s`` seconds at ``sweep_s``
    seconds each: as many as fit, ``fewest`` at least and ``most`` at most."""
    return max(fewest, min(most, int(min(left_s / sweep_s, _NEVER))))


def _longest_move(max_cost: float) -> int:
    """The most a move adds to a priority, floored, on a layer whose free cells cost at most ``max_cost`` (1:
    unweighted): a move of length L (1 to sqrt 5) adds at most L x ``max_cost`` to a value and L to the distance from
    a focus, so floor(1 + sqrt 5 (max_cost + 1))."""
    return math.floor(1 + math.sqrt(5) * (max_cost + 1))


def _search_buckets(max_cost: float) -> int:
    """The buckets of the search's ring (``_search_rules``) on a layer whose free cells cost at most ``max_cost``. A
    bucket holds the cells whose priority (value, plus the distance from the focus if any) has that floor, and a
    cell joins one at most ``_longest_move`` past the one being emptied: the ring is the next power of 2 beyond, and
    at least MIN_RING."""
    return max(MIN_RING, 1 << _longest_move(max_cost).bit_length())


def _serial_limit(tiles: int) -> int:
    """``tiles`` (SERIAL_TILES or SERIAL_SETTLE_TILES) on the CPU; on a GPU one thread is far slower than a launch,
    so every busy iteration is parallel there."""
    return tiles if _on_cpu else 0


# ------------------------------------------------------------------------------------- kernels, one set per spec
def _lane_rules(lanes: int, weighted: bool) -> SimpleNamespace:
    """How a cell holds the layers of a kind with ``lanes`` packed layers (0: scalar): its values' lanes and its
    penalties (a float, or a bit per lane), as ti.funcs closed over ``lanes``; ``width`` lanes per cell (1 for a
    scalar layer), a sample's ``first_column`` for the kind and its settling ``band``. A scalar layer's penalty is 0
    free and inf blocked, or, ``weighted``, the cell's traversal cost (>= 1) free and inf blocked."""
    width = max(lanes, 1)

    @ti.func
    def broadcast(value):
        """``value`` as a scalar, or as a vector of ``lanes`` copies."""
        if ti.static(lanes == 0):
            return value
        else:
            return ti.Vector.zero(ti.f32, lanes) + value

    @ti.func
    def component(value, lane):
        """Component ``lane`` (a runtime index) of a packed value (the value itself for a scalar layer)."""
        out = 0.0
        if ti.static(lanes == 0):
            out = value
        else:
            out = value[lane]
        return out

    @ti.func
    def differs(a, b):
        """1 if any lane of a differs from b. (Taichi 1.7's ``.any()`` of a vector comparison reads only lane 0 when
        matrices are not scalarised: the comparison is selected into integers first.)"""
        result = 0
        if ti.static(lanes == 0):
            result = ti.i32(a != b)
        else:
            result = ti.select(a != b, 1, 0).max()
        return result

    @ti.func
    def lowest(value):
        """The smallest lane of a packed value (the value itself for a scalar layer)."""
        out = 0.0
        if ti.static(lanes == 0):
            out = value
        else:
            out = value.min()
        return out

    @ti.func
    def blocked(penalty):
        """1 for a scalar layer's blocked cell (it holds the cap: relaxing it is skipped). Packed layers relax every
        cell: reducing 32 lanes costs more than the all-blocked cells skipped (dense 1024², 256 nodes: 29-31 ms
        against 34-37)."""
        out = 0
        if ti.static(lanes == 0 and weighted):
            out = ti.i32(penalty > MAX_COST)
        elif ti.static(lanes == 0):
            out = ti.i32(penalty > 0)
        return out

    @ti.func
    def lanes_in(word):
        """1 in each lane whose bit is set in ``word`` (a packed layer's penalty word), as an int vector."""
        return ((ti.Vector.zero(ti.i32, lanes) + word) >> ti.Vector([lane for lane in ti.static(range(lanes))])) & 1

    @ti.func
    def blocked_lanes(pen: ti.template(), g, i, j):
        """The layers for which cell (i, j) (padded coordinates) is blocked: a bool for a scalar layer, a vector of 0/1
        for a packed one (usable as a select's condition)."""
        if ti.static(lanes == 0):
            return blocked(pen[g, i, j]) != 0
        else:
            return lanes_in(pen[g, i, j]) != 0

    @ti.func
    def store_penalty(pen: ti.template(), g, i, j, lane, value):
        """Set the penalty of cell (i, j) for layer ``lane`` to ``value`` (inf blocked): a packed layer sets or clears
        the lane's bit (its values: 0 free, inf blocked)."""
        if ti.static(lanes == 0):
            pen[g, i, j] = value
        else:
            bit = ti.i32(1) << lane
            pen[g, i, j] = ti.select(value > 0, pen[g, i, j] | bit, pen[g, i, j] & ~bit)

    @ti.func
    def store(arr: ti.template(), g, i, j, lane, value):
        """Write ``value`` into component ``lane`` of arr[g, i, j] (the whole cell for a scalar layer), storing only
        that component: other lanes of the cell may be written by other threads at the same time."""
        if ti.static(lanes == 0):
            arr[g, i, j] = value
        else:
            arr[g, i, j][lane] = value

    return SimpleNamespace(broadcast=broadcast, component=component, differs=differs, lowest=lowest, blocked=blocked,
                           lanes_in=lanes_in, blocked_lanes=blocked_lanes, store_penalty=store_penalty,
                           store=store, width=width, first_column=0 if lanes == 0 else 1,
                           band=SETTLE_BAND if lanes == 0 else PACKED_SETTLE_BAND)


def _cell_rules(lanes: int, moves: tuple, weighted: bool, absorbing: bool = False) -> SimpleNamespace:
    """The per-cell ti.funcs of a layer kind with ``lanes`` packed layers (0: scalar) and the stencil ``moves``,
    closed over as compile-time constants: :func:`_lane_rules` and a cell's relaxation, successor and window. A
    ``weighted`` (scalar) layer's move of length L from V to Z costs L x (cost[V] + cost[Z]) / 2; an ``absorbing``
    (scalar) layer's may hold values from ABSORBING on, and a move adds at least one float32 step (``plus``)."""
    lane = _lane_rules(lanes, weighted)
    broadcast, component, lanes_in, blocked_lanes = lane.broadcast, lane.component, lane.lanes_in, lane.blocked_lanes
    width = lane.width
    leaving = tuple(enumerate(moves))  # (index, move): ``leaning``'s bits, those leaving by a corner apart
    leaving_straight = tuple((k, m) for k, m in leaving if not stencil.leaves_by_corner(m))
    leaving_cornered = tuple((k, m) for k, m in leaving if stencil.leaves_by_corner(m))

    @ti.func
    def penalty(pen: ti.template(), g, i, j, lane):
        """The penalty of cell (i, j) for layer ``lane`` as a crossed cell: 0 free, inf blocked."""
        out = 0.0
        if ti.static(lanes == 0 and weighted):  # no select of an inf constant: fast math may take it for any value
            out = ti.max(pen[g, i, j] - MAX_COST, 0.0)
        elif ti.static(lanes == 0):
            out = pen[g, i, j]
        else:
            out = ti.select((pen[g, i, j] >> lane) & 1, ti.math.inf, 0.0)
        return out

    @ti.func
    def crossing(cand, pen: ti.template(), g, i, j, crossed: ti.template()):
        """``cand`` with the penalties of the ``crossed`` cells (offsets from (i, j)) of a move: + inf where crossing
        is blocked. A packed layer ORs the cells' words and blocks the lanes of the result, without a branch (skipping
        the select where the word is 0 made the warehouse navigator's setup() 10-30 % slower: mispredictions)."""
        out = cand
        if ti.static(lanes == 0):
            for c in ti.static(crossed):
                out += penalty(pen, g, i + c[0], j + c[1], 0)
        else:
            word = 0
            for c in ti.static(crossed):
                word |= pen[g, i + c[0], j + c[1]]
            out = ti.select(lanes_in(word) != 0, broadcast(ti.math.inf), cand)
        return out

    @ti.func
    def plus(there, cost):
        """``there`` + ``cost``, a value plus a move; on an ``absorbing`` layer at least the next float32 above
        ``there`` (from ABSORBING on float32 rounds a move of 1 back to the value: ARCHITECTURE §4)."""
        out = there + cost
        if ti.static(absorbing):
            out = ti.max(out, _above(there))
        return out

    @ti.func
    def bucket(value):
        """The search's bucket of non-negative ``value`` (a priority), an int32: its whole part (Dial's buckets, one
        unit of distance wide); on an ``absorbing`` layer from _STEP_BUCKETS on, one float32 step wide, counted by
        the value's bits - every value up to inf has one, and a move (``plus``) reaches a later one."""
        out = 0
        if ti.static(absorbing):
            if value < _STEP_BUCKETS:
                out = ti.i32(value)
            else:
                out = ti.bit_cast(value, ti.i32) - _STEP_BUCKETS_SHIFT
        else:
            out = ti.i32(value)
        return out

    @ti.func
    def beyond(slot, value):
        """Whether bucket ``slot`` lies past every cell of value ``value`` (inf: none does)."""
        out = slot > value
        if ti.static(absorbing):
            out = slot > bucket(value)
        return out

    @ti.func
    def move_cost(pen: ti.template(), g, i, j, m: ti.template()):
        """The cost of move ``m`` from (i, j): its length, or weighted, its length x the mean of the two cells'
        costs (inf when the target is blocked)."""
        out = ti.f32(m.cost)
        if ti.static(weighted):
            out = ti.f32(m.cost) * (0.5 * (pen[g, i, j] + pen[g, i + m.dr, j + m.dc]))
        return out

    @ti.func
    def pinned(best, pen: ti.template(), header: ti.template(), cap, g, i, j):
        """``best``, the lowest candidate of cell (i, j), as its value: 0 at the source, the cap where blocked
        (eqs. 5 and 10, obstacles before the source)."""
        if i == header[SOURCE_ROW] and j == header[SOURCE_COL]:
            best = broadcast(0.0)
        return ti.select(blocked_lanes(pen, g, i, j), broadcast(cap), best)

    @ti.func
    def updated(src: ti.template(), pen: ti.template(), header: ti.template(), cap, g, i, j):
        """The new value of cell (i, j) (padded coordinates): eqs. 5 and 10, obstacles before the source.
        min(cap, min over allowed moves of D[Z] + |V - Z|) is a select: ``ti.min`` lowers to LLVM's NaN-aware minnum
        (a compare and a blend more per move), and no value here is NaN (the sums are finite or +inf)."""
        best = broadcast(cap)
        for m in ti.static(moves):
            cand = crossing(plus(src[g, i + m.dr, j + m.dc], move_cost(pen, g, i, j, m)), pen, g, i, j, m.crossed)
            best = ti.select(cand < best, cand, best)
        return pinned(best, pen, header, cap, g, i, j)

    @ti.func
    def leaning(src: ti.template(), pen: ti.template(), header: ti.template(), cap, i, j):
        """``updated``'s value of scalar cell (i, j), and a bit per move (in ``moves``' order) whose target's value
        is the cell's plus the move's cost: the neighbours whose route may come through the cell, in the same loads
        (the stencil is symmetric, and a move's cost back is the same sum, bit for bit). The crossed cells'
        penalties come from the cell's 3 x 3 block (``around``), and the moves that leave by a corner of it are
        looked at only where one of its corners is free (``corner_open``): a one-cell corridor's cells look at the
        four straight moves alone, as its search does (``_search_rules``)."""
        best, value, leans, block = cap, src[0, i, j], 0, around(pen, i, j)
        for k, m in ti.static(leaving_straight):
            best, leans = lean(src, pen, i, j, value, block, k, m, best, leans)
        if corner_open(block):
            for k, m in ti.static(leaving_cornered):
                best, leans = lean(src, pen, i, j, value, block, k, m, best, leans)
        return pinned(best, pen, header, cap, 0, i, j), leans

    @ti.func
    def lean(src: ti.template(), pen: ti.template(), i, j, value, block, k: ti.template(), m: ti.template(), best,
             leans):
        """``leaning``'s move ``m`` (the ``k``-th) from scalar cell (i, j) of ``value``: ``best`` and ``leans``
        with its candidate and its target's bit."""
        there, cost = src[0, i + m.dr, j + m.dc], move_cost(pen, 0, i, j, m)
        cand = plus(there, cost)
        for c in ti.static(m.crossed):
            cand += block[c[0] + 1, c[1] + 1]
        return ti.select(cand < best, cand, best), leans | ti.select(there == plus(value, cost), 1 << k, 0)

    @ti.func
    def around(pen: ti.template(), i, j):
        """The penalties (``penalty``) of the 3 x 3 block of scalar cells centred on padded cell (i, j), a 3 x 3
        matrix: the cells a move to or from (i, j) crosses, and its other end but a knight's. Read once, before a
        search's stores: read per move, each is read again after every store (the arrays might alias), 32 reads for
        8 cells on 16 neighbours."""
        return ti.Matrix([[penalty(pen, 0, i + a, j + b, 0) for b in ti.static(range(-1, 2))]
                          for a in ti.static(range(-1, 2))])

    @ti.func
    def corner_open(block):
        """Whether a move by a corner of ``block`` (``around``) can be open: one of its four corners is free."""
        return ti.min(ti.min(block[0, 0], block[0, 2]), ti.min(block[2, 0], block[2, 2])) == 0.0

    @ti.func
    def successor_move(values: ti.template(), pen: ti.template(), header: ti.template(), cap, g, lane, i, j):
        """Index of the argmin move from (i, j) (eqs. 7 and 12), first in tie order; -1 at the source or the cap."""
        best = cap
        found = -1
        index = 0
        for m in ti.static(moves):
            cand = component(plus(values[g, i + m.dr, j + m.dc], move_cost(pen, g, i, j, m)), lane)
            for c in ti.static(m.crossed):
                cand += penalty(pen, g, i + c[0], j + c[1], lane)
            if cand < best:
                best = cand
                found = index
            index += 1
        if i == header[SOURCE_ROW] and j == header[SOURCE_COL]:
            found = -1
        return found

    @ti.func
    def window_cell(origins: ti.template(), cells: ti.template(), k, g, lane):
        """Cell k of ``cells`` (grid coordinates) in the layer coordinates of lane ``lane`` of group g."""
        layer = g * width + lane
        return cells[k, 0] - origins[layer, 0], cells[k, 1] - origins[layer, 1]

    # the moves that cross no cell: every other move's crossed cells must be free and make a way of these from one end
    # to the other (ARCHITECTURE §4), so they join the same cells as the whole stencil (a mend's floods step by them)
    steps = tuple(m for m in moves if not m.crossed)
    return SimpleNamespace(**vars(lane), penalty=penalty, crossing=crossing, move_cost=move_cost, plus=plus,
                           bucket=bucket, beyond=beyond,
                           weighted=weighted, updated=updated,
                           leaning=leaning, around=around, corner_open=corner_open, successor_move=successor_move,
                           window_cell=window_cell, moves=moves, steps=steps)


def _given(argument) -> bool:
    """Whether a ti.func's optional template argument was given (Taichi scope has no ``is``)."""
    return argument is not None


@ti.func
def _cell_at(c, width):
    """The row and column of flat index ``c`` (row-major, ``width`` columns; never negative): C's division, without
    the floor's sign fix-ups that ``//`` and ``%`` compile to (a search 4-7 % faster with ``take_first``)."""
    return ti.raw_div(c, width), ti.raw_mod(c, width)


@ti.func
def _stamp(stamps: ti.template(), queue: ti.template(), g, a, b, tick, listing):
    """Stamp tile (g, a, b) for round or iteration ``tick`` unless it is stamped for it already; with a ``queue``
    (the work lists; None when iterating) and ``listing`` (the lists are kept: always while settling, only while
    they are current when painting) a tile newly stamped joins round ``tick``'s list."""
    if stamps[g, a, b] < tick:
        if ti.static(_given(queue)):
            if listing:
                _enqueue(queue, tick, _tile_index(stamps, g, a, b))
        stamps[g, a, b] = tick


@ti.func
def _tile_index(stamps: ti.template(), g, a, b):
    """The flat index of tile (g, a, b), as work lists hold tiles."""
    return (g * stamps.shape[1] + a) * stamps.shape[2] + b


@ti.func
def _tile_of(stamps: ti.template(), index):
    """(g, a, b) of the tile with flat index ``index`` (``_tile_index``'s inverse)."""
    per_group = stamps.shape[1] * stamps.shape[2]
    return index // per_group, (index % per_group) // stamps.shape[2], index % stamps.shape[2]


@ti.func
def _enqueue(queue: ti.template(), tick, tile):
    """Append ``tile`` (a flat tile index) to the work list of round ``tick``: row tick % 2 of ``queue``, its count
    in the last column."""
    row, last = tick % 2, queue.shape[1] - 1
    queue[row, queue[row, last]] = tile
    queue[row, last] += 1


@ti.func
def _spent(header: ti.template()):
    """Whether a serial settling launch has made all the sweeps it may (header[SWEEP_ALLOWANCE], 0: no limit), its
    scans counted at SCANNED_PER_SWEEP entries a sweep."""
    spent = header[SWEPT] + header[SCANNED] // SCANNED_PER_SWEEP
    return header[SWEEP_ALLOWANCE] > 0 and spent >= header[SWEEP_ALLOWANCE]


@ti.func
def _list_active(stamps: ti.template(), queue: ti.template(), tick):
    """Make round ``tick``'s work list the tiles stamped for it (one pass over every tile, on the calling thread:
    appending is not atomic) and empty the next round's."""
    queue[0, queue.shape[1] - 1] = 0
    queue[1, queue.shape[1] - 1] = 0
    ti.loop_config(serialize=True)
    for g in range(stamps.shape[0]):
        for a in range(stamps.shape[1]):
            for b in range(stamps.shape[2]):
                if stamps[g, a, b] >= tick:
                    _enqueue(queue, tick, _tile_index(stamps, g, a, b))


@ti.func
def _listed_tile(stamps: ti.template(), queue: ti.template(), tick, k):
    """(g, a, b) of entry k of round ``tick``'s work list."""
    return _tile_of(stamps, queue[tick % 2, k])


@ti.func
def _wake_around(stamps: ti.template(), keys: ti.template(), queue: ti.template(), g, ta, tb, u, v, tick, kind, key):
    """Stamp ``tick`` on tile (ta, tb) and the neighbours that its cell (u, v) reaches (``_stamp``); with ``keys``
    (None when iterating: only settling orders tiles) lower their key of ``kind`` (_LOWER or _LIFT) to ``key``: for
    lowering the smallest new value among the cell's lanes (the earliest any of them may change), for lifting the
    smallest old value of the lanes it lifted (the cells that depended on them held more)."""
    for da in ti.static(range(-1, 2)):
        for db in ti.static(range(-1, 2)):
            near_a = da == 0 or (da < 0 and u < PAD) or (da > 0 and u >= TILE - PAD)
            near_b = db == 0 or (db < 0 and v < PAD) or (db > 0 and v >= TILE - PAD)
            a, b = ta + da, tb + db
            if near_a and near_b and 0 <= a < stamps.shape[1] and 0 <= b < stamps.shape[2]:
                _stamp(stamps, queue, g, a, b, tick, 1)
                if ti.static(_given(keys)):
                    ti.atomic_min(keys[g, a, b, kind], key)


@ti.func
def _stamp_near(stamps: ti.template(), keys: ti.template(), queue: ti.template(), g, a, b, tick, listing, kind, key):
    """Activate for iteration or round ``tick`` the tiles of group g that have its layer cell (a, b) within
    reach (a layer sees a cell up to PAD outside it), adding them to its work list if ``listing`` says the lists
    are kept (``_stamp``), and, with ``keys`` (None: iterating only), lower their key of ``kind`` (_LOWER or
    _LIFT) to ``key``."""
    for da in ti.static(range(-PAD, PAD + 1, PAD)):
        for db in ti.static(range(-PAD, PAD + 1, PAD)):
            ta, tb = (a + da) // TILE, (b + db) // TILE
            if 0 <= ta < stamps.shape[1] and 0 <= tb < stamps.shape[2]:
                _stamp(stamps, queue, g, ta, tb, tick, listing)
                if ti.static(_given(keys)):
                    keys[g, ta, tb, kind] = ti.min(keys[g, ta, tb, kind], key)


@ti.func
def _focus_distance(header: ti.template(), a, b):
    """Euclidean distance (cells) from the focus cell to the nearest cell of tile (a, b); 0 without a focus. A lower
    bound on the way from the focus to any cell of the tile (every move costs its Euclidean length)."""
    out = 0.0
    if header[FOCUS_ROW] >= 0:
        row, col = header[FOCUS_ROW] - PAD, header[FOCUS_COL] - PAD
        dr = ti.max(0, a * TILE - row, row - (a * TILE + TILE - 1))
        dc = ti.max(0, b * TILE - col, col - (b * TILE + TILE - 1))
        out = ti.sqrt(ti.f32(dr * dr + dc * dc))
    return out


@ti.func
def _priority(keys: ti.template(), header: ti.template(), g, a, b):
    """The order in which tile (g, a, b) is settled: the lower of its keys (no cell of it can fall below its
    lowering key + 1, and every cell of it below its relaxation holds more than its lifting key) plus its distance
    from the focus, as D* Lite's keys (an unfocused converge orders by key alone)."""
    return _lowest_key(keys, g, a, b) + _focus_distance(header, a, b)


@ti.func
def _lowest_key(keys: ti.template(), g, a, b):
    """The lower of tile (g, a, b)'s lowering and lifting keys."""
    return ti.min(keys[g, a, b, _LOWER], keys[g, a, b, _LIFT])


@ti.func
def _unkeyed(keys: ti.template(), g, a, b):
    """Whether tile (g, a, b)'s lowering key is unknown (inf): its cells may fall to anything, so it is due at once."""
    return keys[g, a, b, _LOWER] == ti.math.inf


@ti.func
def _lifting_priority(keys: ti.template(), header: ti.template(), g, a, b):
    """Tile (g, a, b)'s lifting key plus its distance from the focus (inf: nothing to lift)."""
    return keys[g, a, b, _LIFT] + _focus_distance(header, a, b)


@ti.func
def _round_scan(stamps: ti.template(), keys: ti.template(), header: ti.template(), queue: ti.template(), tick):
    """On the calling thread, over round ``tick``'s work list (the tiles active for it): (their number, the lowest
    finite priority among those with a lowering key, how many have none yet: due at once, the lowest lifting
    priority)."""
    count = queue[tick % 2, queue.shape[1] - 1]
    lowest, unkeyed, lifting = ti.math.inf, 0, ti.math.inf
    for k in range(count):
        g, a, b = _listed_tile(stamps, queue, tick, k)
        away = _focus_distance(header, a, b)
        lifting = ti.min(lifting, keys[g, a, b, _LIFT] + away)
        if _unkeyed(keys, g, a, b):
            unkeyed += 1
        else:
            lowest = ti.min(lowest, _lowest_key(keys, g, a, b) + away)
    return ti.Vector([ti.f32(count), lowest, ti.f32(unkeyed), lifting])


@ti.func
def _active_tiles(stamps: ti.template(), tick):
    """The number of tiles stamped for iteration ``tick``."""
    count = 0
    for g in range(stamps.shape[0]):
        for a in range(stamps.shape[1]):
            for b in range(stamps.shape[2]):
                if stamps[g, a, b] >= tick:
                    count += 1
    return count


@ti.func
def _oriented(index, count, sweep, axis):
    """``index`` of ``count`` along ``axis`` (1: rows, 2: columns) in the order of sweep number ``sweep``: sweeps cycle
    through the four diagonal directions (rows forwards and backwards, times columns), as fast sweeping does, so that
    a wave from a source anywhere runs with the order in at least one of any four consecutive sweeps."""
    backwards = (sweep // axis) % 2 == 1
    return count - 1 - index if backwards else index


@ti.func
def _sweep(header: ti.template(), rows, cols, tick):
    """The sweep number of round ``tick``, ``_oriented``'s directions starting (at a tick that is a multiple of 4) with
    the one that runs away from the source."""
    down = ti.select(header[SOURCE_ROW] - PAD >= rows // 2, 1, 0)
    right = ti.select(header[SOURCE_COL] - PAD >= cols // 2, 2, 0)
    return tick + down + right


def _first_round(tick: int) -> int:
    """The round a layer starts again at after ``tick`` (a reset's, a restart's): the next multiple of 4, so that
    settling's first round sweeps away from the source (``_sweep``)."""
    return tick + -tick % 4


def _relax_rules(cell: SimpleNamespace) -> SimpleNamespace:
    """The per-tile ti.funcs of synchronous (Jacobi) iterations built on a layer kind's cell rules, and sampling.
    A layer's arrays: values (``src``/``dst`` or ``values``), ``pen``, ``stamps``, ``header`` (CHANGED ... SCANNED)."""
    updated, differs, blocked = cell.updated, cell.differs, cell.blocked
    component, window_cell, width, first_column = cell.component, cell.window_cell, cell.width, cell.first_column

    @ti.func
    def relax_tile(src: ti.template(), dst: ti.template(), pen: ti.template(), stamps: ti.template(),
                   header: ti.template(), cap, g, ta, tb, tick):
        """One synchronous (Jacobi) iteration src -> dst of tile (g, ta, tb), if active (stamp >= ``tick``).

        A changed cell stamps its tile, and the neighbouring tiles within the stencil's reach, ``tick + 1``: only
        they can change at the next iteration. Inactive tiles hold equal values in both buffers, so skipping them is
        exact. The changed cells are added to header[CHANGED].
        """
        if stamps[g, ta, tb] >= tick:
            rows, cols = src.shape[1] - 2 * PAD, src.shape[2] - 2 * PAD
            changed = 0
            for u, v in ti.ndrange(TILE, TILE):
                r, c = ta * TILE + u, tb * TILE + v
                if r < rows and c < cols and not blocked(pen[g, r + PAD, c + PAD]):
                    new = updated(src, pen, header, cap, g, r + PAD, c + PAD)
                    if differs(new, src[g, r + PAD, c + PAD]):
                        changed += 1
                        _wake_around(stamps, None, None, g, ta, tb, u, v, tick + 1, _LOWER, 0.0)
                    dst[g, r + PAD, c + PAD] = new
            if changed:
                ti.atomic_add(header[CHANGED], changed)

    @ti.func
    def relax_all(src: ti.template(), dst: ti.template(), pen: ti.template(), stamps: ti.template(),
                  header: ti.template(), cap, tick, serial: ti.template()):
        """One iteration of the active tiles (see ``relax_tile``): a parallel loop at a kernel's top level,
        ``serial`` loops inside a loop (nested loops: an ndrange scan divides per tile, 10x slower)."""
        header[CHANGED] = 0
        if ti.static(serial):
            for g in range(stamps.shape[0]):
                for ta in range(stamps.shape[1]):
                    for tb in range(stamps.shape[2]):
                        relax_tile(src, dst, pen, stamps, header, cap, g, ta, tb, tick)
        else:
            for g, ta, tb in stamps:
                relax_tile(src, dst, pen, stamps, header, cap, g, ta, tb, tick)

    @ti.func
    def sample_into(values: ti.template(), origins: ti.template(), cells: ti.template(), out: ti.template(), cap,
                    step):
        """out[step, k, column] = each layer of ``values`` at cells[k]: column 0 for the goal layer (scalar),
        1 + node for a node layer (its cap outside its window)."""
        rows, cols = values.shape[1] - 2 * PAD, values.shape[2] - 2 * PAD
        ti.loop_config(serialize=True)  # a few hundred reads: cheaper than waking the threads
        for k, g in ti.ndrange(cells.shape[0], values.shape[0]):
            for lane in range(width):
                column = g * width + lane + first_column
                if column < out.shape[2]:
                    a, b = window_cell(origins, cells, k, g, lane)
                    value = cap
                    if 0 <= a < rows and 0 <= b < cols:
                        value = component(values[g, a + PAD, b + PAD], lane)
                    out[step, k, column] = value

    return SimpleNamespace(relax_all=relax_all, sample_into=sample_into)


def _sweep_rules(cell: SimpleNamespace) -> SimpleNamespace:
    """The ti.funcs that settle one tile in place (``sweep_tile``) and key its lowering once lifted
    (``lowering_key``), built on a layer kind's cell rules."""
    updated, differs, lowest, broadcast, blocked = cell.updated, cell.differs, cell.lowest, cell.broadcast, cell.blocked

    @ti.func
    def lowering_key(values: ti.template(), header: ti.template(), cap, g, ta, tb):
        """The lowering key of tile (g, ta, tb) once it is lifted: 0 if it holds the source (a node freed in the same
        edits as an obstacle elsewhere holds the cap, and so may all around it), else the smallest value below the
        cap among its cells and those within the stencil's reach (no cell of the tile can fall below it + 1 until one
        of them falls, which wakes the tile again), inf when every one holds the cap: then each of its cells is at
        its relaxation and nothing is left to lower until a change reaches it."""
        key = ti.math.inf
        top, left = ta * TILE, tb * TILE  # padded coordinates of the reach around the tile start here
        bottom = ti.min(top + TILE + 2 * PAD, values.shape[1])
        right = ti.min(left + TILE + 2 * PAD, values.shape[2])
        if top + PAD <= header[SOURCE_ROW] < top + PAD + TILE and left + PAD <= header[SOURCE_COL] < left + PAD + TILE:
            key = 0.0
        for i, j in ti.ndrange((top, bottom), (left, right)):
            value = lowest(values[g, i, j])
            if value < cap:
                key = ti.min(key, value)
        return key

    @ti.func
    def sweep_tile(values: ti.template(), pen: ti.template(), stamps: ti.template(), keys: ti.template(),
                   header: ti.template(), queue: ti.template(), cap, g, ta, tb, tick, sweep, lifting):
        """Sweep the cells of tile (g, ta, tb) in place until they stop changing (in cache, at most 4 TILE passes),
        each pass in the next of the four diagonal directions from ``sweep`` (``_oriented``): lifting (a lane whose
        relaxation is above its value jumps to the cap) or lowering (a cell takes its relaxation), waking the tiles
        that its changed border cells reach (``_wake_around``) with the lifted lanes' old values as lifting keys or
        the new value as lowering key. Returns (passes made, whether the last pass changed anything)."""
        rows, cols = values.shape[1] - 2 * PAD, values.shape[2] - 2 * PAD
        passes, changed_here = 0, 1
        while changed_here and passes < 4 * TILE:
            changed_here = 0
            for k in range(TILE * TILE):
                u = _oriented(k // TILE, TILE, sweep + passes, 1)
                v = _oriented(k % TILE, TILE, sweep + passes, 2)
                r, c = ta * TILE + u, tb * TILE + v
                if r < rows and c < cols and not blocked(pen[g, r + PAD, c + PAD]):
                    old = values[g, r + PAD, c + PAD]
                    due = 1
                    if lifting:  # a cell at the cap has nothing left to lift (a reduction only here)
                        due = ti.select(lowest(old) < cap, 1, 0)
                    if due:
                        new = updated(values, pen, header, cap, g, r + PAD, c + PAD)
                        lifted = old  # the lifted lanes' old values (the cap elsewhere), when lifting
                        if lifting:
                            rising = new > old
                            new = ti.select(rising, broadcast(cap), old)
                            lifted = ti.select(rising, old, broadcast(cap))
                        if differs(new, old):
                            values[g, r + PAD, c + PAD] = new
                            changed_here = 1
                            if u < PAD or u >= TILE - PAD or v < PAD or v >= TILE - PAD:
                                _wake_around(stamps, keys, queue, g, ta, tb, u, v, tick + 1,
                                             ti.select(lifting, _LIFT, _LOWER),
                                             ti.select(lifting, lowest(lifted), lowest(new)))
            passes += 1
        return passes, changed_here

    return SimpleNamespace(lowering_key=lowering_key, sweep_tile=sweep_tile)


def _settle_rules(cell: SimpleNamespace) -> SimpleNamespace:
    """The ti.funcs of converge()'s rounds of tiles settled in place, in the order of their keys (delta-stepping's
    buckets), the raise wave of a repair before the lowering one: ``settle_tile`` and ``settle_all``."""
    tile = _sweep_rules(cell)
    lowering_key, sweep_tile = tile.lowering_key, tile.sweep_tile

    @ti.func
    def settle_tile(values: ti.template(), pen: ti.template(), stamps: ti.template(), keys: ti.template(),
                    header: ti.template(), queue: ti.template(), cap, g, ta, tb, tick, sweep, bound, lift_round):
        """Asynchronous relaxation in place of tile (g, ta, tb), if active (stamp >= ``tick``) and due (its
        priority at most ``bound``, or its lowering key unknown: due at once); an active tile not yet due is deferred
        to the next round. A due tile is swept until it stops changing (``sweep_tile``). Returns 1 if the tile
        changed or waits. Tiles stamped for the next round join its work list (``queue``, serial settling only;
        None in a parallel round).

        A tile with a lifting key is lifted (the raise wave of a repair): a lane whose relaxation is above its value
        (it lost the move it was the minimum of, and holds too little) jumps to the cap, waking the neighbours with
        its old value as their lifting key; a cell already at the cap has nothing left to lift. If anything rose,
        the tile is then due for lowering, keyed by ``lowering_key``, in a later round. Values only rise, so races
        between threads are benign.

        Any other tile is lowered: a cell takes its relaxation, waking the neighbours with its new value as their
        lowering key. No cell of a lowered tile is below its relaxation (such cells lie in tiles with a lifting key:
        the edit or the lift that put them there gave it), so its relaxation never raises it; races are benign and
        the tiles settle to the unique fixed point of eqs. 5 and 10 (every finite value's chain of minima falls
        strictly, so it is the length of a real path). The order (keys, directions) only decides how fast.
        """
        pending = 0
        if stamps[g, ta, tb] >= tick:
            due = 0
            if lift_round:
                due = _lifting_priority(keys, header, g, ta, tb) < bound
            else:
                due = _unkeyed(keys, g, ta, tb) or _priority(keys, header, g, ta, tb) <= bound
            if not due:
                _stamp(stamps, queue, g, ta, tb, tick + 1, 1)
                pending = 1
            else:
                lifting = keys[g, ta, tb, _LIFT] < ti.math.inf
                if lifting:  # wakes from here on key it again; earlier ones are taken in now
                    keys[g, ta, tb, _LIFT] = ti.math.inf
                else:
                    keys[g, ta, tb, _LOWER] = _SETTLED
                passes, changed_here = sweep_tile(values, pen, stamps, keys, header, queue, cap, g, ta, tb, tick, sweep,
                                                 lifting)
                if ti.static(_given(queue)):  # the unit of a launch's allowance: a tile's sweeps cost 1-32 passes
                    header[SWEPT] += passes
                if passes > 1:
                    pending = 1
                if changed_here:  # not settled within its passes: due at once (lifting, then lowering, if lifting)
                    keys[g, ta, tb, _LOWER] = ti.math.inf
                    if lifting:
                        ti.atomic_min(keys[g, ta, tb, _LIFT], -1.0)
                    _stamp(stamps, queue, g, ta, tb, tick + 1, 1)
                elif lifting:  # lowered in a later round, when the keys say it is due
                    if passes > 1:  # something rose (a pass that changes nothing ends the sweeps)
                        ti.atomic_min(keys[g, ta, tb, _LOWER], lowering_key(values, header, cap, g, ta, tb))
                    if keys[g, ta, tb, _LOWER] != _SETTLED:
                        _stamp(stamps, queue, g, ta, tb, tick + 1, 1)
                        pending = 1
        return pending

    @ti.func
    def settle_all(values: ti.template(), pen: ti.template(), stamps: ti.template(), keys: ti.template(),
                   header: ti.template(), queue: ti.template(), cap, tick, bound, lift_round):
        """One round of ``settle_tile`` over the tiles due: in a lifting round (``lift_round``) those with a lifting
        priority below ``bound``, else those with a priority at most ``bound``. With a ``queue`` (None: a parallel
        loop over every tile, at a kernel's top level) the round runs on the calling thread over its work list (over
        every tile in the round's diagonal direction when the list holds over a quarter of them) and builds the next
        round's; once the launch's allowance of sweeps is spent (``_spent``) the round stops, open
        (header[ROUND_CURSOR]: the entry the next launch goes on from). Returns the tiles that changed or wait."""
        pending = 0
        tiles_a, tiles_b = stamps.shape[1], stamps.shape[2]
        sweep = _sweep(header, values.shape[1] - 2 * PAD, values.shape[2] - 2 * PAD, tick)
        if ti.static(_given(queue)):
            listed = queue[tick % 2, queue.shape[1] - 1]
            total = stamps.shape[0] * tiles_a * tiles_b
            first, cut, limited = header[ROUND_CURSOR], 0, header[SWEEP_ALLOWANCE] > 0
            for k in range(first, total if 4 * listed > total else listed):
                if limited and k > first and _spent(header):  # the rest waits for the next launch, from entry k
                    header[ROUND_CURSOR], cut = k, 1
                    break
                g, ta, tb = 0, 0, 0
                if 4 * listed > total:
                    g, a, b = _tile_of(stamps, k)
                    ta, tb = _oriented(a, tiles_a, sweep, 1), _oriented(b, tiles_b, sweep, 2)
                else:
                    g, ta, tb = _listed_tile(stamps, queue, tick, k)
                pending += settle_tile(values, pen, stamps, keys, header, queue, cap, g, ta, tb, tick, sweep, bound,
                                       lift_round)
            if not cut:
                queue[tick % 2, queue.shape[1] - 1], header[ROUND_CURSOR] = 0, 0
        else:
            for g, a, b in stamps:
                ta, tb = _oriented(a, tiles_a, sweep, 1), _oriented(b, tiles_b, sweep, 2)
                pending += settle_tile(values, pen, stamps, keys, header, None, cap, g, ta, tb, tick, sweep, bound,
                                       lift_round)
        return pending

    return SimpleNamespace(settle_all=settle_all)


def _bucket_rules(weighted: bool) -> SimpleNamespace:
    """The search's buckets (``_search_rules``): doubly linked lists of cells threaded through ``links`` (2, padded
    cells + the ring's buckets, ``_search_buckets``) int32: row 0 each listed cell's next cell in its bucket, and in
    its last entries each bucket's first (``heads`` is where they start); row 1 the previous cell, ``_UNLISTED``
    for a cell in no bucket, -2 - slot for the first of bucket ``slot``. Cells are flat indices into the padded
    layer. A ``weighted`` layer's ring also keeps a mark per _BLOCK buckets in row 1 after the log's steps
    (``_UNMARKED``, as the links are made: no cell listed in them since the mark was cleared), and after those a
    mark per _GROUP buckets (a group of _BLOCK blocks, on a ring of _GROUP buckets or more), so that
    ``next_listed`` passes an empty group or block a load each and ``clear`` empties only the marked ones."""

    @ti.func
    def unlink(links: ti.template(), heads, c):
        """Take cell ``c`` out of its bucket."""
        before, after = links[1, c], links[0, c]
        if before >= 0:
            links[0, before] = after
        else:
            links[0, heads - 2 - before] = after
        if after >= 0:
            links[1, after] = before
        links[1, c] = _UNLISTED

    @ti.func
    def take_first(links: ti.template(), heads, slot):
        """Take the first cell out of bucket ``slot`` (not empty); returns it."""
        c = links[0, heads + slot]
        after = links[0, c]
        links[0, heads + slot] = after
        if after >= 0:
            links[1, after] = -2 - slot
        links[1, c] = _UNLISTED
        return c

    @ti.func
    def mark_of(heads, block):
        """Where block ``block``'s mark lies in row 1 of ``links`` (a weighted layer's: after the search's log)."""
        return heads + _LOG_STEPS + block

    @ti.func
    def group_mark_of(links: ti.template(), heads, group):
        """Where group ``group``'s mark lies in row 1 of ``links``: after the blocks' marks."""
        return mark_of(heads, (links.shape[1] - heads) // _BLOCK + group)

    @ti.func
    def blocks_of(links: ti.template(), heads):
        """The blocks of the ring (its heads start at ``heads``)."""
        return (links.shape[1] - heads) // _BLOCK

    @ti.func
    def marked_from(links: ti.template(), heads, block):
        """The first block of a weighted layer's ring from ``block`` on whose mark and whose group's are set (the
        ring's count of blocks if none): the others list no cell. A group unmarked is passed a load."""
        grouped = blocks_of(links, heads) >= _BLOCK
        found = False
        while block < blocks_of(links, heads) and not found:
            if grouped and block % _BLOCK == 0 and links[1, group_mark_of(links, heads, block // _BLOCK)] == _UNMARKED:
                block += _BLOCK
            elif links[1, mark_of(heads, block)] == _UNMARKED:
                block += 1
            else:
                found = True
        return block

    @ti.func
    def next_listing(links: ti.template(), heads, slot):
        """The bucket of the ring after ``slot`` (-1: its first) that may list a cell - on a weighted layer the next
        in a marked block of a marked group (``marked_from``), else the next -; the ring's size past its last."""
        slot += 1
        if ti.static(weighted):
            if slot % _BLOCK == 0:
                slot = marked_from(links, heads, slot // _BLOCK) * _BLOCK
        return slot

    @ti.func
    def empty_bucket(links: ti.template(), heads, slot):
        """Take every cell out of bucket ``slot``."""
        while links[0, heads + slot] >= 0:
            unlink(links, heads, links[0, heads + slot])

    @ti.func
    def clear(links: ti.template(), heads):
        """Empty every bucket of the ring (its heads start at ``heads``); on a weighted layer only the blocks marked,
        of the groups marked (``marked_from``: a ring of 4 million buckets at costs of 1e6, cleared by every search
        and mend, reads 1,024 group marks where it read 65,536 block marks)."""
        slot = next_listing(links, heads, -1)
        while slot < links.shape[1] - heads:
            links[0, heads + slot] = _UNLISTED
            if ti.static(weighted):
                links[1, mark_of(heads, slot // _BLOCK)] = _UNMARKED
            slot = next_listing(links, heads, slot)
        if ti.static(weighted):
            for group in range(blocks_of(links, heads) // _BLOCK):
                links[1, group_mark_of(links, heads, group)] = _UNMARKED

    @ti.func
    def link(links: ti.template(), heads, c, slot):
        """Put cell ``c`` (in no bucket) first in bucket ``slot``."""
        first = links[0, heads + slot]
        links[0, c], links[1, c] = first, -2 - slot
        if first >= 0:
            links[1, first] = c
        links[0, heads + slot] = c
        if ti.static(weighted):  # (a ring of fewer than _GROUP buckets marks its one group, which nothing reads)
            links[1, mark_of(heads, slot // _BLOCK)] = _MARKED
            links[1, group_mark_of(links, heads, slot // _GROUP)] = _MARKED

    @ti.func
    def empty_group(links: ti.template(), heads, group):
        """Whether group ``group`` lists no cell: it is unmarked, or each of its blocks is (it is then unmarked)."""
        empty = links[1, group_mark_of(links, heads, group)] == _UNMARKED
        if not empty:
            empty = True
            for block in range(group * _BLOCK, (group + 1) * _BLOCK):
                if links[1, mark_of(heads, block)] != _UNMARKED:
                    empty = False
            if empty:
                links[1, group_mark_of(links, heads, group)] = _UNMARKED
        return empty

    @ti.func
    def next_listed(links: ti.template(), heads, bucket):
        """The first bucket from ``bucket`` on that lists a cell (one does: the cells listed lie in the ring's
        buckets ahead): a group of _GROUP buckets a load of its mark where unmarked (``empty_group``), a block of
        _BLOCK buckets a load of its mark where unmarked (the marks lie together; a block's heads, a cache line
        apart, are not read), else a bucket a load; a block found empty from its first bucket on has its mark
        cleared (cells leave buckets without clearing it). Dial's buckets are one unit of distance wide: on a
        weighted layer whose costs reach thousands most are empty, each a pass of a search's loop (6-7 ns: a map of
        36,000 cells whose distances reach 4e7 took 300 ms to converge, 36 ms skipping them a bucket a load, 12 ms
        a block a load, 4.3 ms a group or a block a load, its hand-over walking the marks too - RESULTS §10). A
        binary layer's moves leave at most two empty in a row, and the check cost its repairs 1-5 %
        (``benchmarks.ab``): weighted only."""
        mask = links.shape[1] - heads - 1
        grouped = mask >= _GROUP - 1
        found = False
        while not found:
            slot = bucket & mask
            passed = False
            if grouped and slot & (_GROUP - 1) == 0:  # nested: in one ``and``, Taichi runs ``empty_group`` (a loop of
                passed = empty_group(links, heads, slot // _GROUP)  # 64 loads) at every pass, grouped or not (§7)
            if passed:
                bucket += _GROUP
            else:
                mark = mark_of(heads, slot // _BLOCK)
                end = (bucket | (_BLOCK - 1)) + 1
                if links[1, mark] == _UNMARKED:
                    bucket = end
                else:
                    whole = bucket & (_BLOCK - 1) == 0
                    while bucket < end and links[0, heads + (bucket & mask)] < 0:
                        bucket += 1
                    found = bucket < end
                    if whole and not found:
                        links[1, mark] = _UNMARKED
        return bucket

    return SimpleNamespace(unlink=unlink, link=link, clear=clear, take_first=take_first, next_listed=next_listed,
                           next_listing=next_listing, empty_bucket=empty_bucket)


def _search_rules(cell: SimpleNamespace, logged: bool = False) -> SimpleNamespace:
    """The search from the initial state of a scalar layer: Dial's label-setting algorithm (Dijkstra's with buckets
    one cell wide), cell by cell on the calling thread, with A*'s order and stop when focused. Its fixed point is the
    one eqs. 5 and 10 define, bit for bit: a cell takes the smallest value + move length over its free neighbours,
    in float32, as ``updated`` computes it, and every move is at least 1 long, so the cells of the bucket being
    emptied depend on none of its cells (unfocused: each cell is taken once, with its final value). Its buckets:
    ``_bucket_rules``. ``logged``: its ``links`` have a third row, which logs each cell it lowers from the cap
    (``_race_rules``: a race that loses puts them back). A cell taken reads the penalties of its 3 x 3 block once
    (``around``), and tries the moves through a corner of it (``stencil.through_corner``) only when one of its four
    corners is free: a one-cell corridor's cells try the four straight moves alone."""
    moves, move_cost, penalty, plus, bucket_of = cell.moves, cell.move_cost, cell.penalty, cell.plus, cell.bucket
    around, corner_open = cell.around, cell.corner_open
    buckets = _bucket_rules(cell.weighted)
    unlink, link, clear, take_first = buckets.unlink, buckets.link, buckets.clear, buckets.take_first
    next_listing = buckets.next_listing
    straight = tuple(m for m in moves if not stencil.through_corner(m))
    cornered = tuple(m for m in moves if stencil.through_corner(m))

    @ti.func
    def priority(value, i, j, focus_row, focus_col):
        """The bucket (``_cell_rules``' ``bucket``) of ``value`` plus the Euclidean distance of padded cell (i, j)
        from the focus (none: row -1): a lower bound on a route from the focus through the cell (A*'s f; every move
        costs its Euclidean length)."""
        away = 0.0
        if focus_row >= 0:
            away = ti.sqrt(ti.f32((i - focus_row) ** 2 + (j - focus_col) ** 2))
        return bucket_of(value + away)

    @ti.func
    def past_focus(values: ti.template(), bucket, focus_row, focus_col):
        """Whether a focused search's ``bucket`` lies SEARCH_MARGIN past its focus's value (unfocused, row -1:
        never; the focus's value is read only if there is one - Taichi's ``and`` evaluates both sides)."""
        out = False
        if focus_row >= 0:
            out = cell.beyond(bucket, values[0, focus_row, focus_col] + SEARCH_MARGIN)
        return out

    @ti.func
    def log(links: ti.template(), heads, c):
        """Log padded cell ``c`` (row-major) in row 2 of ``links``, its count at ``links[2, heads]``."""
        links[2, links[2, heads]] = c
        links[2, heads] += 1

    @ti.func
    def empty(values: ti.template(), pen: ti.template(), links: ti.template(), bucket, focus_row, focus_col, cap):
        """Take every cell of ``bucket`` and lower its neighbours through it, listing each lowered one in the bucket
        of its priority (logged, the first time it falls below ``cap``); returns (the change in the cells listed,
        the cells taken)."""
        width, heads = values.shape[2], values.shape[1] * values.shape[2]
        mask = links.shape[1] - heads - 1
        slot, listed, taken = bucket & mask, 0, 0
        while links[0, heads + slot] >= 0:
            c = take_first(links, heads, slot)
            listed -= 1
            taken += 1
            i, j = _cell_at(c, width)
            value, block = values[0, i, j], around(pen, i, j)
            for m in ti.static(straight):
                listed = lower(values, pen, links, bucket, focus_row, focus_col, cap, i, j, value, block, m, listed)
            if corner_open(block):  # one branch a cell, the same all along a corridor or across open ground
                for m in ti.static(cornered):
                    listed = lower(values, pen, links, bucket, focus_row, focus_col, cap, i, j, value, block, m,
                                   listed)
        return ti.Vector([listed, taken])

    @ti.func
    def lower(values: ti.template(), pen: ti.template(), links: ti.template(), bucket, focus_row, focus_col, cap,
              i, j, value, block, m: ti.template(), listed):
        """Lower the cell that move ``m`` takes from padded cell (i, j) (its ``value``, its 3 x 3 ``block`` of
        penalties) through it, if that lowers it - penalties added, 0 or inf, in ``crossing``'s order; one branch,
        rarely taken -, and list it in the bucket of its priority; returns ``listed`` plus the cells newly listed."""
        width, heads = values.shape[2], values.shape[1] * values.shape[2]
        u, v = i - m.dr, j - m.dc
        cand = plus(value, move_cost(pen, 0, u, v, m))
        for c in ti.static(m.crossed):
            cand += block[c[0] - m.dr + 1, c[1] - m.dc + 1]
        if ti.static(abs(m.dr) <= 1 and abs(m.dc) <= 1):
            cand += block[1 - m.dr, 1 - m.dc]
        else:
            cand += penalty(pen, 0, u, v, 0)
        if cand < values[0, u, v]:
            there = u * width + v
            if ti.static(logged):
                if values[0, u, v] >= cap:
                    log(links, heads, there)
            values[0, u, v] = cand
            if links[1, there] == _UNLISTED:
                listed += 1
            else:
                unlink(links, heads, there)
            due = ti.max(bucket, priority(cand, u, v, focus_row, focus_col))
            link(links, heads, there, due & (links.shape[1] - heads - 1))
        return listed

    @ti.func
    def hand_over(values: ti.template(), stamps: ti.template(), keys: ti.template(), links: ti.template(), tick,
                  whole):
        """After a search: every tile settled (lowering key _SETTLED, no lifting key) but those within reach of a
        cell still listed (the frontier a focused search leaves), which are active for round ``tick`` with that
        cell's value as lowering key (``_stamp_near``): the invariants of settling (``settle_tile``) hold, and the
        rounds of a later converge go on from the frontier. Empties the buckets. Not ``whole``, the tiles are
        settled already (a mend's, after a search or mend that left no frontier and nothing that stamped a tile
        since): the frontier's alone are stamped - the pass over every tile cost a mend 0.05 ms on a 1024² map, 0.17
        on a 2048² one."""
        if whole:
            for g in range(stamps.shape[0]):
                for a in range(stamps.shape[1]):
                    for b in range(stamps.shape[2]):
                        stamps[g, a, b] = -1
                        keys[g, a, b, _LOWER], keys[g, a, b, _LIFT] = _SETTLED, ti.math.inf
        heads = values.shape[1] * values.shape[2]
        slot = next_listing(links, heads, -1)  # weighted, the marked blocks alone: a ring of 4 million buckets read
        while slot < links.shape[1] - heads:  # head by head took 7 ms of every search and mend at costs of 1e6
            stamp_listed(values, stamps, keys, links, tick, slot)
            slot = next_listing(links, heads, slot)

    @ti.func
    def stamp_listed(values: ti.template(), stamps: ti.template(), keys: ti.template(), links: ti.template(), tick,
                     slot):
        """Take each cell out of bucket ``slot``, its tile stamped for round ``tick`` with the cell's value as its
        lowering key (``hand_over``)."""
        width, heads = values.shape[2], values.shape[1] * values.shape[2]
        while links[0, heads + slot] >= 0:
            c = take_first(links, heads, slot)
            i, j = _cell_at(c, width)
            _stamp_near(stamps, keys, None, 0, i - PAD, j - PAD, tick, 0, _LOWER, values[0, i, j])

    return SimpleNamespace(hand_over=hand_over, empty=empty, priority=priority, link=link, unlink=unlink, clear=clear,
                           log=log, past_focus=past_focus, next_listed=buckets.next_listed, next_listing=next_listing,
                           empty_bucket=buckets.empty_bucket, weighted=cell.weighted)


def _cut_rules(cell: SimpleNamespace) -> SimpleNamespace:
    """A mend's first look at its edits (``_Layers._mend``), its ``cut_off``: ``cut_start``, then ``cut_step`` while
    ``cutting``, then ``cut_verdict`` tell whether the cells they blocked cut the free cells apart, and cap the parts
    the source no longer reaches - a cell at a time, so that the mend can keep its race going beside the look. It
    steps by the moves that cross no cell (``_cell_rules``' ``steps``: they join the same cells as the whole
    stencil). Row 2 of a mend's ``trail`` marks the cells looked at (their part + 1), row 1 queues them (and logs
    them: nothing is taken off), row 0 holds each part's ints (``_PART_INTS``: union-find parent, cells waiting,
    flags); the look's own ints are a vector (``_LOOKED`` ...)."""
    blocked, steps = cell.blocked, cell.steps
    step_rows, step_cols = tuple(m.dr for m in steps), tuple(m.dc for m in steps)

    @ti.func
    def step_of(s):
        """(rows, columns) of step ``s`` of ``steps``, ``s`` known at run time: the checks over every edit loop over
        the steps at run time, so that each inlines its body once where a static loop inlined it once a step (Taichi's
        whole-kernel CSE takes time that grows faster than the kernel: ARCHITECTURE §7)."""
        return ti.Vector([ti.Vector(step_rows)[s], ti.Vector(step_cols)[s]])

    @ti.func
    def stepped(c, width, s):
        """The padded cell (row-major) step ``s`` (``step_of``) from padded cell ``c``."""
        step = step_of(s)
        return c + step[0] * width + step[1]

    @ti.func
    def at(part, field):
        """Where ``field`` of ``part`` lies in row 0 of the trail."""
        return part * _PART_INTS + field

    @ti.func
    def root(trail: ti.template(), part):
        """The part that ``part`` was merged into (union-find with path halving)."""
        while trail[0, at(part, _PARENT)] != part:
            trail[0, at(part, _PARENT)] = trail[0, at(trail[0, at(part, _PARENT)], _PARENT)]
            part = trail[0, at(part, _PARENT)]
        return part

    @ti.func
    def visit(trail: ti.template(), part, c, tail, source):
        """Mark padded cell ``c`` (row-major) as ``part``'s and queue it at ``tail``; returns the new tail."""
        trail[2, c] |= part + 1
        trail[1, tail] = c
        trail[0, at(part, _WAITING)] += 1
        if c == source:
            trail[0, at(part, _FLAGS)] |= _HOLDS_SOURCE
        return tail + 1

    @ti.func
    def part_of(trail: ti.template(), c):
        """The part that marked padded cell ``c`` (row-major) when it looked at it (-1: none)."""
        return trail[2, c] - 1

    @ti.func
    def merge(trail: ti.template(), part, other):
        """Part ``other`` joins ``part``: its cells waiting and its flags."""
        trail[0, at(other, _PARENT)] = part
        trail[0, at(part, _WAITING)] += trail[0, at(other, _WAITING)]
        trail[0, at(part, _FLAGS)] = (trail[0, at(part, _FLAGS)] | trail[0, at(other, _FLAGS)]) & ~_PAUSED

    @ti.func
    def edited(pen: ti.template(), cells: ti.template(), penalties: ti.template(), k, width):
        """The padded cell (row-major) of edit ``k`` if it blocked it and it is blocked now, else -1."""
        i, j = cells[k, 0] + PAD, cells[k, 1] + PAD
        return ti.select(penalties[k] > MAX_COST and blocked(pen[0, i, j]), i * width + j, -1)

    @ti.func
    def mark_edits(trail: ti.template(), pen: ti.template(), cells: ti.template(), penalties: ti.template(), width,
                   mark):
        """Mark each cell the edits blocked in row 2 of the trail: ``mark``, _EDITED (a cluster of its own, no side
        yet: ``cluster``) or 0 (unmarked)."""
        for k in range(cells.shape[0]):
            c = edited(pen, cells, penalties, k, width)
            if c >= 0:
                trail[2, c] = mark

    @ti.func
    def cluster(trail: ti.template(), c):
        """The root of the cluster of blocked cell ``c``: union-find in row 2 of the trail, where a root holds
        -(_ROOT + its side + 1) (side -1: none yet) and any other cell -(its parent + 2); path halving."""
        while trail[2, c] > -_ROOT:
            parent = -trail[2, c] - 2
            if trail[2, parent] > -_ROOT:
                trail[2, c] = trail[2, parent]
            c = parent
        return c

    @ti.func
    def unite(trail: ti.template(), a, b):
        """One cluster of the clusters of blocked cells ``a`` and ``b`` (before any has a side)."""
        root, other = cluster(trail, a), cluster(trail, b)
        if root != other:
            trail[2, other] = -(root + 2)

    @ti.func
    def closed(trail: ti.template(), part):
        """Whether ``part`` (a root) ran dry: all it joins looked at. Read at part 0 for part -1 (no part): Taichi's
        ``and`` evaluates both sides, so ``part >= 0 and closed(trail, part)`` calls it with -1 too."""
        return trail[0, at(ti.max(part, 0), _FLAGS)] & _CLOSED != 0

    @ti.func
    def beside(trail: ti.template(), c, width, s):
        """The root of the part of the cell step ``s`` (``step_of``) from padded cell ``c`` (-1: none - blocked, or
        not looked at: only free cells join parts)."""
        found = part_of(trail, stepped(c, width, s))
        if found >= 0:
            found = root(trail, found)
        return found

    @ti.func
    def clustered(trail: ti.template(), pen: ti.template(), cells: ti.template(), penalties: ti.template(), width):
        """The blocked cells marked and a step apart in one cluster (``cluster``); returns how many clusters (no
        more parts than that can be left once each cluster's sides are one)."""
        mark_edits(trail, pen, cells, penalties, width, _EDITED)
        for k in range(cells.shape[0]):
            c = edited(pen, cells, penalties, k, width)
            if c >= 0:
                for s in range(ti.static(len(steps))):
                    there = stepped(c, width, s)
                    if trail[2, there] < 0:
                        unite(trail, c, there)
        roots = 0
        for k in range(cells.shape[0]):
            c = edited(pen, cells, penalties, k, width)
            if c >= 0:  # (not ``and``: Taichi would read row 2 at -1 too)
                roots += ti.select(trail[2, c] <= -_ROOT, 1, 0)
        return roots

    @ti.func
    def pockets_joined(trail: ti.template(), pen: ti.template(), cells: ti.template(), penalties: ti.template(),
                       width):
        """The clusters beside one pocket (a closed part) made one, the pockets beside one blocked cell made one
        first (closed parts stay so: the unions hold from one check to the next); every cluster's side forgotten."""
        for k in range(cells.shape[0]):
            c = edited(pen, cells, penalties, k, width)
            if c >= 0:
                first = -1
                for s in range(ti.static(len(steps))):
                    part = beside(trail, c, width, s)
                    if part >= 0 and closed(trail, part):
                        if first < 0:
                            first = part
                        elif part != first:
                            merge(trail, first, part)
        for k in range(cells.shape[0]):  # a pocket's cells waiting (0) hold the first blocked cell beside it + 1
            c = edited(pen, cells, penalties, k, width)
            if c >= 0:
                trail[2, cluster(trail, c)] = _EDITED
                for s in range(ti.static(len(steps))):
                    part = beside(trail, c, width, s)
                    if part >= 0 and closed(trail, part):
                        if trail[0, at(part, _WAITING)] == 0:
                            trail[0, at(part, _WAITING)] = c + 1
                        else:
                            unite(trail, trail[0, at(part, _WAITING)] - 1, c)

    @ti.func
    def sides_joined(trail: ti.template(), pen: ti.template(), cells: ti.template(), penalties: ti.template(),
                     width, per_cluster, whole):
        """Whether the free cells beside each blocked cell that lie in open parts (not closed) are all in one part -
        ``per_cluster``, one part for each cluster (``clustered``, ``pockets_joined``), kept in its root
        (_APART_SIDE once two). It stops at the first blocked cell whose sides are apart, unless ``whole``."""
        apart, k = False, 0
        while k < cells.shape[0] and (whole or not apart):
            c = edited(pen, cells, penalties, k, width)
            if c >= 0:
                side, top = -1, c
                if per_cluster:
                    top = cluster(trail, c)
                    side = -trail[2, top] - _ROOT - 1
                for s in range(ti.static(len(steps))):
                    part = beside(trail, c, width, s)
                    if part >= 0 and not closed(trail, part):
                        if side < 0:
                            side = part
                        elif part != side:
                            apart, side = True, _APART_SIDE
                if per_cluster:
                    trail[2, top] = -(_ROOT + side + 1)
            k += 1
        return not apart

    @ti.func
    def sides_forgotten(trail: ti.template(), pen: ti.template(), cells: ti.template(), penalties: ti.template(),
                        width):
        """After a check of the clusters' sides: each cluster's side forgotten, the pockets' cells waiting (which
        ``pockets_joined`` lent to the clusters beside them) back at 0."""
        for k in range(cells.shape[0]):
            c = edited(pen, cells, penalties, k, width)
            if c >= 0:
                trail[2, cluster(trail, c)] = _EDITED
                for s in range(ti.static(len(steps))):
                    part = beside(trail, c, width, s)
                    if part >= 0 and closed(trail, part):
                        trail[0, at(part, _WAITING)] = 0

    @ti.func
    def joined(trail: ti.template(), pen: ti.template(), cells: ti.template(), penalties: ti.template(), width):
        """Whether the edits cut nothing off the source but pockets (closed parts, set to the cap): the free cells
        in open parts beside the blocked cells of each cluster (``clustered``, then ``pockets_joined``) lie in one
        part. A route through blocked cells enters and leaves a run of them a step apart - one cluster - by free
        cells beside it, joined round it; a route into a pocket leaves it by a blocked cell beside it, whose cluster
        is the pocket's. Each blocked cell's own sides first: most cuts show there, at once."""
        ok = sides_joined(trail, pen, cells, penalties, width, False, False)
        if ok:
            pockets_joined(trail, pen, cells, penalties, width)
            ok = sides_joined(trail, pen, cells, penalties, width, True, False)
            sides_forgotten(trail, pen, cells, penalties, width)
        return ok

    @ti.func
    def pause_joined(trail: ti.template(), pen: ti.template(), cells: ti.template(), penalties: ti.template(), width,
                     parts):
        """Whether the edits cut nothing off the source but pockets (``joined``), every cluster's open sides checked;
        the open parts beside no cluster whose sides are apart paused (``_PAUSED``: flooding them decides nothing -
        edits all over a map leave a part round each, which flooded on until the slowest cluster's sides met)."""
        pockets_joined(trail, pen, cells, penalties, width)
        ok = sides_joined(trail, pen, cells, penalties, width, True, True)
        for part in range(parts):
            if trail[0, at(part, _PARENT)] == part and not closed(trail, part):
                trail[0, at(part, _FLAGS)] |= _PAUSED
        for k in range(cells.shape[0]):
            c = edited(pen, cells, penalties, k, width)
            if c >= 0:  # (Taichi's ``and`` evaluates both sides: cluster(-1) would never return)
                if -trail[2, cluster(trail, c)] - _ROOT - 1 == _APART_SIDE:
                    for s in range(ti.static(len(steps))):
                        part = beside(trail, c, width, s)
                        if part >= 0:
                            trail[0, at(part, _FLAGS)] &= ~_PAUSED
        sides_forgotten(trail, pen, cells, penalties, width)
        return ok

    @ti.func
    def cut_start(values: ti.template(), pen: ti.template(), header: ti.template(), trail: ti.template(),
                  cells: ti.template(), penalties: ti.template(), cap):
        """The look's start: each free cell beside a cell the edits blocked queued as a part of its own (at most
        CUT_PARTS: more leave the look crowded) and the clusters of blocked cells counted (``clustered``). Returns
        the look's ints."""
        width = values.shape[2]
        most = ti.min(CUT_PARTS, trail.shape[1] // _PART_INTS)
        source = header[SOURCE_ROW] * width + header[SOURCE_COL]
        lost = blocked(pen[0, header[SOURCE_ROW], header[SOURCE_COL]])  # no part holds it: it reaches nothing
        clusters = 0  # a layer of 2**29 cells or more would overflow the clusters' marks: no check there
        if ti.i64(values.shape[1]) * width < _ROOT - 2:
            clusters = clustered(trail, pen, cells, penalties, width)
        live, tail, crowded = 0, 0, False
        for k in range(cells.shape[0]):
            if penalties[k] > MAX_COST:
                for s in range(ti.static(len(steps))):
                    step = step_of(s)
                    i, j = cells[k, 0] + PAD + step[0], cells[k, 1] + PAD + step[1]
                    if part_of(trail, i * width + j) < 0 and not blocked(pen[0, i, j]) and values[0, i, j] < cap:
                        if live < most:
                            trail[0, at(live, _PARENT)], trail[0, at(live, _FLAGS)] = live, 0
                            trail[0, at(live, _WAITING)] = 0
                            tail = visit(trail, live, i * width + j, tail, source)
                            live += 1
                        crowded |= live == most
        # parts apart may yet be the ways round clusters of blocked cells far apart, each joined round (``joined``,
        # ``pause_joined``): checked each time the cells looked at have doubled (``looked_at``)
        return ti.Vector([0, tail, live, ti.select(crowded, 1, 0), ti.select(lost, 1, 0), -1,
                          ti.select(live > 1, 1, 0), clusters, clusters, live, 0])

    @ti.func
    def cutting(look, budget):
        """Whether the look goes on: not crowded, the source not blocked, parts apart, none holding the source
        closed, cells queued, fewer than ``budget`` looked at (the mend stops it too once its race has finished)."""
        return (look[_CROWDED] == 0 and look[_LOST] == 0 and look[_CUT] == 1 and look[_SEALED] < 0
                and look[_LOOKED] < look[_QUEUED] and look[_LOOKED] - look[_DROPPED] < budget)

    @ti.func
    def cut_step(values: ti.template(), pen: ti.template(), header: ti.template(), trail: ti.template(),
                 cells: ti.template(), penalties: ti.template(), look):
        """The look's next cell, breadth-first from every free cell beside a cell the edits blocked, each a part of
        its own, in one queue: its free neighbours join its part, parts that meet merge, and a part whose queue runs
        dry is cut off from every other - the whole of what it joins (a part holding the source so: ``_SEALED``).
        The look stops (``cutting``) once one part is left (every other merged into it or closed), or once the
        sides of each cluster of blocked cells are one part (``joined``: clusters far apart, as boxes or noise all
        over a map, leave a part round each that would merge with the others only after most of the map). A paused
        part's cells (``pause_joined``) are dropped, not looked at. Returns the look's ints."""
        width = values.shape[2]
        c = trail[1, look[_LOOKED]]
        look[_LOOKED] += 1
        part = root(trail, part_of(trail, c))
        if trail[0, at(part, _FLAGS)] & _PAUSED:
            trail[0, at(part, _FLAGS)] |= _TRUNCATED
            trail[0, at(part, _WAITING)] -= 1
            look[_DROPPED] += 1
        else:
            look = looked_at(trail, pen, header, cells, penalties, width, look, c, part)
        return look

    @ti.func
    def looked_at(trail: ti.template(), pen: ti.template(), header: ti.template(), cells: ti.template(),
                  penalties: ti.template(), width, look, c, part):
        """``cut_step``'s cell ``c`` of ``part`` (a root, not paused) looked at. Returns the look's ints."""
        source = header[SOURCE_ROW] * width + header[SOURCE_COL]
        i, j = _cell_at(c, width)
        tail, live = look[_QUEUED], look[_LIVE]
        for m in ti.static(steps):
            if not blocked(pen[0, i + m.dr, j + m.dc]):
                there = c + m.dr * width + m.dc
                marked = part_of(trail, there)
                if marked < 0:
                    tail = visit(trail, part, there, tail, source)
                elif marked != part:
                    other = root(trail, marked)
                    if other != part:  # two parts meet: one from here on
                        merge(trail, part, other)
                        live -= 1
        trail[0, at(part, _WAITING)] -= 1
        if trail[0, at(part, _WAITING)] == 0 and trail[0, at(part, _FLAGS)] & _TRUNCATED == 0:  # all it joins looked
            trail[0, at(part, _FLAGS)] |= _CLOSED
            live -= 1
            if trail[0, at(part, _FLAGS)] & _HOLDS_SOURCE:
                look[_SEALED] = part
        cut = live > 1
        # each check of the clusters' sides once the cells looked at have doubled: ``joined`` (it stops at the first
        # blocked cell whose sides are apart) once there are no more parts than clusters; before that, where there
        # are clusters apart, ``pause_joined`` (a few passes over the edits) once the look has taken PAUSE_AFTER
        # cells an edit
        clusters = look[_CLUSTERS]
        if cut and look[_LOOKED] >= look[_CHECK_AT] and look[_SEALED] < 0:
            if live <= clusters:
                cut = not joined(trail, pen, cells, penalties, width)
                look[_CHECK_AT] = 2 * look[_LOOKED]
            elif clusters > 1 and look[_LOOKED] >= PAUSE_AFTER * cells.shape[0]:
                cut = not pause_joined(trail, pen, cells, penalties, width, look[_PARTS])
                look[_CHECK_AT] = 2 * look[_LOOKED]
        look[_QUEUED], look[_LIVE], look[_CUT] = tail, live, ti.select(cut, 1, 0)
        return look

    @ti.func
    def cut_verdict(values: ti.template(), pen: ti.template(), trail: ti.template(), cells: ti.template(),
                    penalties: ti.template(), cap, look):
        """The look's end: if the edits left the source's part closed, the cells in it are what a restart searches
        (none if they blocked the source); else the parts closed without the source - pockets sealed off - have
        their cells set to the cap at once (no raise). If every part merged into one, the edits cut nothing: a way
        round each blocked cell joins its neighbours, so a route through it has a way round too. The trail's marks
        are cleared. Returns (the cells the source's closed part holds, -1 if none; cells looked at, less those
        dropped; 1 if it stopped short with parts apart - the source may lie in one closed - else 0). The verdict
        only chooses how the mend goes on (a race or none): the raise that follows finds every cell that must rise
        either way."""
        width = values.shape[2]
        cut = look[_CUT] == 1
        if cut and look[_CROWDED] == 0 and look[_LOST] == 0 and look[_SEALED] < 0 and look[_LIVE] <= look[_CLUSTERS]:
            cut = not joined(trail, pen, cells, penalties, width)  # stopped short: as it stands
        mark_edits(trail, pen, cells, penalties, width, 0)
        reached = ti.select(look[_SEALED] >= 0 or look[_LOST] == 1, 0, -1)
        for k in range(look[_QUEUED]):
            c = trail[1, k]
            flags = trail[0, at(root(trail, part_of(trail, c)), _FLAGS)]
            trail[2, c] = 0
            if look[_SEALED] >= 0:
                reached += flags & _HOLDS_SOURCE
            elif flags & _CLOSED:
                i, j = _cell_at(c, width)
                values[0, i, j] = cap
        return ti.Vector([reached, look[_LOOKED] - look[_DROPPED], ti.select(look[_CROWDED] == 1 or cut, 1, 0)])

    @ti.func
    def contour(pen: ti.template(), row, line, most):
        """Follow the outline of a part of the free cells (4-connected: ``outlined``) along the cracks between its
        cells and blocked ones, a crack at a time with the free cell on the right, from the corner (``row``,
        ``line``) southwards - the crack between free cell (row, line - 1) and blocked (row, line) - until it is back
        (or ``most`` cracks): at each corner it turns right where the cell ahead on the right is blocked, goes on
        where only the one ahead on the left is, else turns left. Returns (twice the area it encloses - positive
        round a part, negative round a hole in one -, the cracks followed, the least line past ``line`` where it
        crosses row ``row`` (_NEVER if none), whether it closed)."""
        rows, lines = ti.Vector([0, 1, 0, -1]), ti.Vector([1, 0, -1, 0])  # east, south, west, north
        right_rows, right_cols = ti.Vector([0, 0, -1, -1]), ti.Vector([0, -1, -1, 0])  # the cell ahead on the right
        r, x, d, area, taken, exit_line, closed = row, line, 1, ti.i64(0), 0, _NEVER, False
        while not closed and taken < most:
            after_r, after_x = r + rows[d], x + lines[d]
            area += ti.i64(x) * after_r - ti.i64(after_x) * r
            if d % 2 == 1 and ti.min(r, after_r) == row and x > line:
                exit_line = ti.min(exit_line, x)
            r, x = after_r, after_x
            taken += 1
            left = (d + 3) % 4
            if blocked(pen[0, r + right_rows[d], x + right_cols[d]]):
                d = (d + 1) % 4
            elif not blocked(pen[0, r + right_rows[left], x + right_cols[left]]):
                d = left
            closed = r == row and x == line and d == 1
        return area, taken, exit_line, closed

    @ti.func
    def outlined(pen: ti.template(), header: ti.template(), most):
        """An upper bound on the free cells of the source's part, in at most ``most`` steps (-1: none found, or a
        stencil whose steps are not the four straight moves - moves across corners join parts the outline does not
        follow): from the source eastwards to the first blocked cell, then its outline (``contour``); round a hole
        (the blocked cell an island in the part) on from where the outline crosses the row again, past the island;
        round the part, the cells it encloses. Its price is the outline's length, where telling the part's cells
        takes its area: a goal sealed in a room is known at once (``restart_is_cheaper``)."""
        bound = -1
        if ti.static(len(steps) == 4):
            i, j = header[SOURCE_ROW], header[SOURCE_COL]
            spent, going = 0, not blocked(pen[0, i, j])
            while going and spent < most:
                while not blocked(pen[0, i, j + 1]):
                    j += 1
                    spent += 1
                area, taken, exit_line, closed = contour(pen, i, j + 1, most - spent)
                spent += taken
                if not closed or (area < 0 and exit_line == _NEVER):
                    going = False
                elif area > 0:
                    bound, going = ti.i32(area // 2), False
                else:
                    j = exit_line
        return bound

    return SimpleNamespace(cut_start=cut_start, cutting=cutting, cut_step=cut_step, cut_verdict=cut_verdict,
                           outlined=outlined)


@ti.func
def _budget_for(budget, restart, fills, reached):
    """A mend's ``budget`` (the share MEND_SHARE of ``restart``, a restart's price in cells a search takes, the
    reset's ``fills`` in it) once the cells the source reaches are counted (``reached``; -1: not yet): the same share
    of the price of a restart that searches those, where that is less."""
    fallen = budget
    if reached >= 0:
        fallen = ti.min(budget, ti.i32(ti.f64(budget) / restart * (reached + fills)))
    return fallen


def mend_work(looked: int, raised: int) -> int:
    """A mend's work in cells a search takes: the ``looked`` cells of its first look and RAISE_COST for each of the
    ``raised`` cells, which its budget (``_budget_for``) bounds. A pure rule, compiled into the mend as
    ``_mend_work``."""
    return looked + RAISE_COST * raised


def depth_first_raise(occupied: np.ndarray) -> bool:
    """Whether a mend's raise should take the cell it queued last first (depth first) rather than the one queued
    first, on a map of ``occupied`` cells (True = obstacle): where at least CORRIDOR_SHARE of the free cells have at
    most two free cells among their four neighbours (outside the map counts as blocked) - corridors a cell wide. A
    raise there follows a corridor depth first, along memory, where breadth first takes every branch and edit in
    turn; in open ground, breadth first leaves the next cell's loads independent of the last one's checks
    (``benchmarks.ab``, ARCHITECTURE §7). A pure rule over the map: the order changes the raise's speed, never its
    result."""
    free = np.pad(~np.asarray(occupied, bool), 1)
    inner = free[1:-1, 1:-1]
    neighbours = (free[:-2, 1:-1].astype(np.int8) + free[2:, 1:-1] + free[1:-1, :-2] + free[1:-1, 2:])
    cells = int(np.count_nonzero(inner))
    return cells > 0 and int(np.count_nonzero(inner & (neighbours <= 2))) >= CORRIDOR_SHARE * cells


def restart_is_cheaper(reached: int, restart: int, fills: int) -> bool:
    """Whether a source that now reaches ``reached`` cells (-1: not counted) lost so many of the cells the last search
    reached (a restart's price ``restart``, in cells a search takes, less the reset's ``fills``) that raising them
    all (RAISE_COST each) costs a mend more than a restart, which searches the cells it reaches: a goal sealed in a
    pocket. True for a count holds for every smaller one, so ``reached`` may be a bound from above (the outline's,
    ``_cut_rules``' ``outlined``), and a count from below (``kept``) that is not cheaper says no bound can be. A pure
    rule, compiled into the mend as ``_doomed``."""
    return reached >= 0 and RAISE_COST * (restart - fills - reached) > reached + fills


def outline_cracks(restart: int, corridors: int) -> int:
    """The most cracks a mend's outline of the source's part may follow (``_cut_rules``' ``outlined``): 1 /
    OUTLINE_SHARE of a restart's price ``restart`` (in cells a search takes), 1 / CORRIDOR_OUTLINE_SHARE on maps of
    corridors a cell wide (``corridors``: ``depth_first_raise``), where an outline takes two cracks a cell of its
    part. A pure rule, compiled into the mend as ``_outline_cracks``."""
    return restart // (CORRIDOR_OUTLINE_SHARE if corridors else OUTLINE_SHARE)


def race_lead(least: int, looked: int, budget: int, lead: int) -> int:
    """A mend's race's lead (``_race_rules``; ``lead``: RACE_LEAD) once its first look has taken ``looked`` cells
    (none yet, or all, having found the edits' sides apart): none if the least a restart can cost, ``least`` cells a
    search takes - the cells nearer the source than the edits, which keep their routes, and a reset's fills -, is
    more than the race could take before the mend's ``budget`` (in those cells) runs out, the look's cells and the
    most it can raise (RAISE_COST each) ``lead`` times: then the race could only lose, and a pocket sealed far from
    the source, or a box in a pocket of a few cells, is mended at the raise's cost alone. A pure rule, compiled into
    the mend as ``_race_lead``."""
    return lead if least < lead * (looked + max(budget - looked, 0) // RAISE_COST) else 0


def race_head(kept: int, most: int) -> int:
    """A mend's race's head start (RACE_HEAD_SHARE) once its look has found the edits' sides apart: the ``kept``
    cells nearer the source than the edits, which a race that wins takes first, if they are at most ``most`` (the
    share of a restart a race that loses may take in vain), else none. A pure rule, compiled into the mend as
    ``_race_head``."""
    return kept if kept <= most else 0


def seed_bound(below: float, kept: int, costs: int, focus_row: int) -> int:
    """The bound below which a mend's race starts from the cells its edits left as they were (``_race_rules``'
    ``seed``): ``below``, the least value around an edit before it (no cell below it changes: ``_search_kernels``'
    mend), floored, where the last search's log says that the ``kept`` cells below it are more than such a race
    ``costs`` before it takes a cell (in cells a search takes: the mend's work it waits for and its pass), which a
    race from the source would take, each with the mend's work its lead allows beside it or in its head start;
    unfocused (``focus_row`` -1) and below 2**24, up to which float32 holds every whole number. Else -1: the race
    starts from the source. A pure rule, compiled into the mend as ``_seed_bound``."""
    return int(below) if focus_row < 0 and below < _SEED_MOST and kept > costs else -1


def logged_cells(step: int) -> int:
    """The cells a search has taken when it logs ``step`` (``_race_rules``): four steps to each doubling, 1, 1, 1, 1,
    2, 2, 3, 3, 4, 5, 6, 7, 8, 10 ... (2**(step // 4) x (1 + (step % 4) / 4), floored)."""
    return (1 << (step // 4)) + (((step % 4) << (step // 4)) >> 2)


_mend_work, _doomed = ti.func(mend_work), ti.func(restart_is_cheaper)
_race_lead, _race_head = ti.func(race_lead), ti.func(race_head)
_outline_cracks = ti.func(outline_cracks)
_seed_bound = ti.func(seed_bound)
_logged_cells = ti.func(logged_cells)
(_BUCKET, _LISTED, _TAKEN, _EMPTIED, _LEAD, _FOCUS_ROW, _FOCUS_COL, _LOGGED, _HEAD,
 _FROM, _BAND, _PASS, _KEPT) = range(13)  # a race's ints
_FROM_SOURCE, _SEEDED = -1, -2  # a race's _FROM when it starts from the source, and once it started from the kept cells
_LOG_STEPS = 120  # the steps of a search's log, up to 1.75 x 2**29 cells (``logged_cells``)


def _race_rules(cell: SimpleNamespace, logged: bool = False) -> SimpleNamespace:
    """The search from the initial state (``_search_rules``), a bucket at a time: ``search`` runs one to its end, and
    a mend runs one in a spare buffer at the initial state, racing its first look and its raise (``pace``): if it
    finishes first, it is the repair - a restart that cost its own cells and the mend's beside them -, and a mend
    that finishes first puts the buffer back (``clean``). A race is an int32 vector: the bucket it empties next, the
    cells listed, taken, the buckets emptied, its lead (the cells it may take per cell the mend has looked at or
    raised), the focus (padded coordinates; row -1: none), the steps of its log it has reached, its head start (the
    cells it may take before its lead counts: ``race_head``), where it starts (``_FROM``: _FROM_SOURCE, a bound to
    start from the cells below it once the mend has done ``_PASS`` work - ``seed_bound`` -, or _SEEDED once it
    has), the band its seeds start at and the cells it kept (``seed``). Unfocused, it logs in
    row 1 of its links after the cells (``links[1, heads + k]``, unused by the buckets) the bucket it was about to
    empty when it had first taken ``logged_cells(k)`` cells (in the search's log -1 for steps not reached; a mend's
    race that wins hands its log on: ``hand_log``), so that a mend knows how many cells lie nearer the source than its
    edits (``kept``), to a fifth. A mend's race is ``logged`` (its ``links`` have a third
    row: ``_search_rules``), so that ``clean`` finds the cells it lowered."""
    blocked, weighted, bucket_of = cell.blocked, cell.weighted, cell.bucket
    searching = _search_rules(cell, logged)
    empty, priority, link, unlink, clear, log = (searching.empty, searching.priority, searching.link, searching.unlink,
                                                 searching.clear, searching.log)
    next_listed, next_listing, past_focus = searching.next_listed, searching.next_listing, searching.past_focus
    empty_bucket = searching.empty_bucket

    @ti.func
    def start(values: ti.template(), pen: ti.template(), header: ti.template(), links: ti.template(), focus_row,
              focus_col, below, band, passing):
        """A race from the source (none if blocked: it reaches nothing), ``values`` at the initial state, no lead -
        or, with ``below`` 0 or more, a race that waits to start from the cells a mend's edits left below that value
        (``seed``, once the mend has looked at or raised ``passing`` cells: ``pace``), those from ``band`` on its
        seeds. A mend's race finds its buckets empty (a race empties them, to its end or in ``clean``), and its log
        is read only as far as it logs (``hand_log``); the search's buckets are cleared (a binary layer's mend's raise
        queues cells round the whole of their row 0) and its log too (a mend reads it whole: ``kept``)."""
        width, heads = values.shape[2], values.shape[1] * values.shape[2]
        if ti.static(not logged):
            clear(links, heads)
            for k in range(_LOG_STEPS):
                links[1, heads + k] = _UNLISTED
        race = ti.Vector([0, 0, 0, 0, 0, focus_row, focus_col, 0, 0, below, band, passing, 0])
        i, j = header[SOURCE_ROW], header[SOURCE_COL]
        if ti.static(logged):
            links[2, heads] = 0
        if below < 0 and not blocked(pen[0, i, j]):
            if ti.static(logged):
                log(links, heads, i * width + j)
            values[0, i, j] = 0.0
            race[_BUCKET] = priority(0.0, i, j, focus_row, focus_col)
            link(links, heads, i * width + j, race[_BUCKET] & (links.shape[1] - heads - 1))
            race[_LISTED] = 1
        return race

    @ti.func
    def over(values: ti.template(), race):
        """Whether ``race`` has finished: nothing listed, or, focused, the bucket it reached SEARCH_MARGIN past the
        focus's value."""
        past = past_focus(values, race[_BUCKET], race[_FOCUS_ROW], race[_FOCUS_COL])
        return (race[_LISTED] == 0 and race[_FROM] < 0) or past

    @ti.func
    def run(values: ti.template(), pen: ti.template(), links: ti.template(), race, most, cap):
        """Go on with ``race`` until it has taken ``most`` cells or finished; returns it."""
        race = log_steps(values, links, race)
        while race[_TAKEN] < most and race[_FROM] < 0 and not over(values, race):
            change = empty(values, pen, links, race[_BUCKET], race[_FOCUS_ROW], race[_FOCUS_COL], cap)
            race[_LISTED] += change[0]
            race[_TAKEN] += change[1]
            race[_BUCKET] += 1
            race[_EMPTIED] += 1
            race = log_steps(values, links, race)
            if ti.static(weighted) and race[_LISTED] > 0:  # on past empty buckets (counted as emptied)
                skipped = next_listed(links, values.shape[1] * values.shape[2], race[_BUCKET]) - race[_BUCKET]
                race[_BUCKET] += skipped
                race[_EMPTIED] += skipped
        return race

    @ti.func
    def log_steps(values: ti.template(), links: ti.template(), race):
        """Unfocused, log the bucket ``race`` empties next for each step of ``logged_cells`` its cells taken have
        reached since it last logged; returns it."""
        heads = values.shape[1] * values.shape[2]
        while (race[_FOCUS_ROW] < 0 and race[_LOGGED] < _LOG_STEPS
               and race[_TAKEN] >= _logged_cells(race[_LOGGED])):
            links[1, heads + race[_LOGGED]] = race[_BUCKET]
            race[_LOGGED] += 1
        return race

    @ti.func
    def search(values: ti.template(), pen: ti.template(), header: ti.template(), links: ti.template(), cap,
               focus_row, focus_col):
        """Lower ``values`` (the initial state) from the source to the end (or the focus); returns the race."""
        return run(values, pen, links, start(values, pen, header, links, focus_row, focus_col, _FROM_SOURCE, 0, 0),
                   _NEVER, cap)

    @ti.func
    def seed(layer: ti.template(), values: ti.template(), links: ti.template(), race, cap):
        """Start a waiting ``race`` (``start``) from the cells below its bound in ``layer`` (a mend's values, which
        its edits did not change there: ``_search_kernels``' mend), in one pass over the layer: ``values`` takes
        theirs (the cap elsewhere), and those from its band on - the only ones a move can take past the bound - are
        listed as its seeds; the cells below them count as taken and as its head start, less its lead times its
        ``passing`` (the pass's price, paid). Dial's search from the seeds then gives every cell at or past the
        bound the value a search from the source would (the cells below it keep theirs: a move adds at least 1)."""
        width, heads = values.shape[2], values.shape[1] * values.shape[2]
        mask = links.shape[1] - heads - 1
        below, band = race[_FROM], race[_BAND]
        taken, listed, first = 0, 0, below
        for i in range(values.shape[1]):
            for j in range(width):  # selects, not branches, but for the band's few cells: kept cells lie anywhere
                value = layer[0, i, j]
                kept = ti.select(value < below, 1, 0)
                values[0, i, j] = ti.select(kept == 1, value, cap)
                early = ti.select(value < band, 1, 0)
                taken += early
                if kept - early == 1:
                    link(links, heads, i * width + j, bucket_of(value) & mask)
                    listed += 1
                    first = ti.min(first, bucket_of(value))
        race[_BUCKET], race[_LISTED], race[_TAKEN], race[_KEPT], race[_FROM] = first, listed, taken, taken, _SEEDED
        race[_HEAD] += taken - race[_LEAD] * race[_PASS]
        return race

    @ti.func
    def advance(layer: ti.template(), values: ti.template(), pen: ti.template(), links: ti.template(), race, most,
                seeding, cap):
        """Go on with ``race`` until it has taken ``most`` cells or finished, a race waiting to start from the cells
        kept in ``layer`` started first (``seed``) if ``seeding``; ``most`` _NEVER and ``seeding`` run it to its
        end. Each place that calls it inlines a whole search: the mend calls it in one place."""
        if race[_FROM] >= 0 and seeding:
            race = seed(layer, values, links, race, cap)
        return run(values, pen, links, race, most, cap)

    @ti.func
    def paced(race, work):
        """How far ``race`` may go once the mend has done ``work`` (cells looked at or raised): its head start and
        its lead times that work, and whether a race waiting to start from the kept cells starts (the work has paid
        for its pass)."""
        return race[_HEAD] + race[_LEAD] * work, race[_LEAD] > 0 and work >= race[_PASS]

    @ti.func
    def clean(values: ti.template(), links: ti.template(), race, cap):
        """Put ``values`` back at the initial state after a race that lost - the cells it lowered (its log) at the
        cap, those still listed taken out of its buckets (a race that started from kept cells leaves them in
        ``values``, and seeds in its buckets: ``_Layers._mend`` fills the values, and its buckets are emptied
        here)."""
        width, heads = values.shape[2], values.shape[1] * values.shape[2]
        for k in range(links[2, heads]):
            c = links[2, k]
            i, j = _cell_at(c, width)
            values[0, i, j] = cap
            if links[1, c] != _UNLISTED:
                unlink(links, heads, c)
        if race[_FROM] == _SEEDED:  # weighted, the marked blocks alone (``_search_rules``' ``hand_over``)
            slot = next_listing(links, heads, -1)
            while slot < links.shape[1] - heads:
                empty_bucket(links, heads, slot)
                slot = next_listing(links, heads, slot)

    @ti.func
    def hand_log(links: ti.template(), race, into: ti.template(), heads):
        """Hand the log of ``race`` (in ``links``, its heads at ``heads``) on to ``into`` (the search's links), the
        steps it did not reach as none (-1); a race that started from kept cells leaves the steps among them as the
        search's log has them (it took them all at once, in the bucket it started at)."""
        for k in range(_LOG_STEPS):
            if into[1, heads + k] < 0 or _logged_cells(k) > race[_KEPT]:
                into[1, heads + k] = ti.select(k < race[_LOGGED], links[1, heads + k], _UNLISTED)

    @ti.func
    def kept(links: ti.template(), heads, nearest):
        """The most cells that the last unfocused search's log (``links``, its heads at ``heads``) says lay below
        ``nearest`` (0: none it can tell)."""
        most = 0
        for k in range(_LOG_STEPS):
            if links[1, heads + k] >= 0 and links[1, heads + k] <= nearest:
                most = _logged_cells(k)
        return most

    return SimpleNamespace(start=start, over=over, run=run, search=search, advance=advance, paced=paced, clean=clean,
                           hand_log=hand_log, kept=kept)


def _raise_rules(cell: SimpleNamespace) -> SimpleNamespace:
    """The first half of a mend (``_Layers._mend``), the repair after edits of a layer at its fixed point before
    them, cell by cell: the raise, ``raise_start``, then ``raise_step`` while its queue holds cells, then
    ``raise_end`` (the cells the edits cut off rise to the cap; its ints are a vector, ``_NEXT`` ...) and
    ``seed_cut`` (their rim and the edited cells take their relaxations, the seeds of :func:`_lower_rules`'
    search)."""
    moves, blocked, leaning = cell.moves, cell.blocked, cell.leaning

    @ti.func
    def ring_end(values: ti.template(), links: ti.template()):
        """The end of the raise's ring, row 0 of ``links``: on a weighted layer its cells' entries alone (a cell is
        queued once at most, so fewer entries than cells), whose buckets' heads ``clear`` empties only where marked
        and so must hold no queue entry."""
        end = links.shape[1]
        if ti.static(cell.weighted):
            end = values.shape[1] * values.shape[2]
        return end

    @ti.func
    def after(values: ti.template(), links: ti.template(), index):
        """The entry after ``index`` in the raise's ring."""
        return ti.select(index + 1 == ring_end(values, links), 0, index + 1)

    @ti.func
    def before(values: ti.template(), links: ti.template(), index):
        """The entry before ``index`` in the raise's ring."""
        return ti.select(index == 0, ring_end(values, links), index) - 1

    @ti.func
    def push(values: ti.template(), links: ti.template(), cap, tail, i, j):
        """Queue padded cell (i, j) for the raise (row 0 of ``links``, a ring: ``tail`` is its end) unless it is
        queued or at the cap; returns the new tail."""
        c = i * values.shape[2] + j
        if links[1, c] == _UNLISTED and values[0, i, j] < cap:
            links[1, c] = _STACKED
            links[0, tail] = c
            tail = after(values, links, tail)
        return tail

    @ti.func
    def raise_start(values: ti.template(), links: ti.template(), cells: ti.template(), cap, raising):
        """The raise's queue: the cells within reach of each edit of ``cells`` (grid coordinates), if ``raising``.
        Returns the raise's ints."""
        tail = 0
        if raising:
            for k in range(cells.shape[0]):
                for da, db in ti.ndrange((-PAD, PAD + 1), (-PAD, PAD + 1)):
                    tail = push(values, links, cap, tail, cells[k, 0] + PAD + da, cells[k, 1] + PAD + db)
        return ti.Vector([0, tail, 0, 0, 0])

    @ti.func
    def raise_step(values: ti.template(), pen: ti.template(), header: ti.template(), links: ti.template(),
                   trail: ti.template(), cap, rising, depth_first):
        """The raise's next cell (its queue not empty), after edits on a layer at its fixed point before them: a
        cell below its relaxation - its route went through a cell now blocked or dearer, or through a cell raised
        here - jumps to the cap (D* Lite's underconsistent states), its dependants queued after it. The queue is
        first in, first out (row 0 of ``links`` as a ring): a sealed pocket rises at memory speed, with no wave to
        wait for; the next cell is known long before its turn, so the processor loads it while the last one is
        checked, where a stack's next was mostly the cell just pushed (``benchmarks.ab``: boxes 0.95x and walls
        0.90x a stack's, geometric means over nine maps - random and ROS maps 0.80-0.99x, mazes 0.99-1.04x -, the
        goal sealed in a room 1.02x). On maps of corridors a cell wide (``depth_first``: ``depth_first_raise``) it
        takes the cell queued last instead: breadth first there takes every branch of a maze and every edit in turn,
        a cell's loads far from the last one's, where depth first follows one corridor along memory (noise on the
        rings 0.75x, boxes across a 1-cell maze's route 0.88x; ARCHITECTURE §7). The order does not matter for the
        result: a cell looked at before its last route rose is a dependant of the cell that rises, and is looked at
        again. Only a raised cell's dependants - neighbours whose value is its old one plus their move to it - are
        looked at again. A cell that relaxes below its value (a cell freed or made cheaper by the same edits opened a
        move to it) may do so through a neighbour not raised yet, of which it is no dependant: it waits in row 1 of
        ``trail`` and is looked at again once the queue has run dry, as long as cells rose since it was last looked at
        (before, such a cell was kept, and one whose route went through a cell now blocked kept the value that route
        gave, below every route it has). Every cell left below the cap then has a real route (a neighbour at least a
        move lower, down to the source), or relaxes below its value through one that has (the seeds lower it). The
        raised cells go in row 0 of ``trail``. Returns the raise's ints and whether the cell rose."""
        head, tail, raised, waiting, rose = (rising[_NEXT], rising[_END], rising[_RAISED], rising[_DEFERRING],
                                             rising[_ROSE])
        c = 0
        if depth_first:  # the cell queued last (``depth_first_raise``)
            tail = before(values, links, tail)
            c = links[0, tail]
        else:
            c = links[0, head]
            head = after(values, links, head)
        links[1, c] = _UNLISTED
        i, j = _cell_at(c, values.shape[2])
        value = values[0, i, j]
        relaxed, leans = leaning(values, pen, header, cap, i, j)
        went_up = value < cap and relaxed > value
        if went_up:
            values[0, i, j] = cap
            trail[0, raised] = c
            raised += 1
            rose += 1
            for k, m in ti.static(tuple(enumerate(moves))):  # the neighbours whose value came through this cell's
                if leans & (1 << k):  # (their route; a move whose crossing is now blocked starts within reach of an
                    tail = push(values, links, cap, tail, i + m.dr, j + m.dc)  # edit)
        elif relaxed < value:  # through a neighbour that may rise yet: looked at again later
            links[1, c] = _DEFERRED
            trail[1, waiting] = c
            waiting += 1
        if head == tail and rose > 0:  # cells rose since the waiting ones were looked at: again
            for k in range(waiting):
                c = trail[1, k]
                links[1, c] = _UNLISTED
                i, j = _cell_at(c, values.shape[2])
                tail = push(values, links, cap, tail, i, j)
            waiting, rose = 0, 0
        return ti.Vector([head, tail, raised, waiting, rose]), went_up

    @ti.func
    def raise_end(values: ti.template(), links: ti.template(), trail: ti.template(), rising):
        """The raise's end, its queue run dry or its mend over budget: the cells waiting are kept (every cell their
        relaxation goes through stayed), and the queue is emptied (for the restart)."""
        for k in range(rising[_DEFERRING]):
            links[1, trail[1, k]] = _UNLISTED
        head = rising[_NEXT]
        while head != rising[_END]:
            links[1, links[0, head]] = _UNLISTED
            head = after(values, links, head)

    @ti.func
    def relaxation(values: ti.template(), pen: ti.template(), header: ti.template(), cap, i, j):
        """``updated``'s value of scalar cell (i, j) in ``leaning``'s loads: a one-cell corridor's cell looks at 4
        of 16 moves."""
        value, _ = leaning(values, pen, header, cap, i, j)
        return value

    @ti.func
    def seed_cut(values: ti.template(), pen: ti.template(), header: ti.template(), trail: ti.template(),
                 cells: ti.template(), penalties: ti.template(), raised, cap):
        """The seeds of a repair's lowering: each raised cell (``trail``'s first ``raised``) and each cell within
        reach of an edit that left its cell free (freed, or a cost set) whose relaxation is below its value takes
        it - a cell blocked lowers nothing, and what rose through it was raised; the seeds replace the trail (in
        place: no more of them than cells looked at). Returns how many."""
        seeds = 0
        for k in range(raised):
            c = trail[0, k]
            i, j = _cell_at(c, values.shape[2])
            value = relaxation(values, pen, header, cap, i, j)
            if value < values[0, i, j]:
                values[0, i, j] = value
                trail[0, seeds] = c
                seeds += 1
        for k in range(cells.shape[0]):
            for da, db in ti.ndrange((-PAD, PAD + 1), (-PAD, PAD + 1)):
                i, j = cells[k, 0] + PAD + da, cells[k, 1] + PAD + db
                value = cap
                # the padding is blocked too: its cells' neighbours lie outside the arrays
                if penalties[k] <= MAX_COST and not blocked(pen[0, i, j]):
                    value = relaxation(values, pen, header, cap, i, j)
                if value < values[0, i, j]:
                    values[0, i, j] = value
                    trail[0, seeds] = i * values.shape[2] + j
                    seeds += 1
        return seeds

    return SimpleNamespace(raise_start=raise_start, raise_step=raise_step, raise_end=raise_end, seed_cut=seed_cut)


def _lower_rules(searching: SimpleNamespace) -> SimpleNamespace:
    """The second half of a mend: ``lower_cut``, Dial's search from the seeds, with the search's rules
    (``searching``: :func:`_search_rules`' buckets and A*'s order with a focus)."""
    empty, priority, link, clear = searching.empty, searching.priority, searching.link, searching.clear
    next_listed, past_focus, weighted = searching.next_listed, searching.past_focus, searching.weighted

    @ti.func
    def lower_cut(values: ti.template(), pen: ti.template(), links: ti.template(), trail: ti.template(), seeds,
                  focus_row, focus_col, cap):
        """The lowering of a repair: Dial's search from the seeds (``trail``'s first ``seeds``, their values set),
        as a search from the source. Seeds span many buckets, more than the ring holds: they wait in the
        trail and join the ring once their bucket is less than half a ring ahead (the trail is scanned every half
        ring, or jumped to when the ring runs dry). It runs to its end (or its focus): a restart would search every
        cell it lowers. Returns (buckets emptied, cells listed or waiting, seeds waiting: the frontier a focused
        repair leaves, still in the trail, cells taken)."""
        width, heads = values.shape[2], values.shape[1] * values.shape[2]
        mask = links.shape[1] - heads - 1
        clear(links, heads)
        bucket, listed, emptied, scan_at, taken = 0, 0, 0, 0, 0
        half = (mask + 1) // 2
        while (listed > 0 or seeds > 0) and not past_focus(values, bucket, focus_row, focus_col):
            if listed == 0:  # the ring ran dry: on to the nearest seed waiting
                bucket = _LAST_BUCKET
                for k in range(seeds):
                    i, j = _cell_at(trail[0, k], width)
                    bucket = ti.min(bucket, priority(values[0, i, j], i, j, focus_row, focus_col))
                scan_at = bucket
            if bucket >= scan_at:
                waiting = 0
                for k in range(seeds):
                    c = trail[0, k]
                    i, j = _cell_at(c, width)
                    due = priority(values[0, i, j], i, j, focus_row, focus_col)
                    if links[1, c] == _UNLISTED and due <= bucket + half:
                        link(links, heads, c, ti.max(bucket, due) & mask)
                        listed += 1
                    elif links[1, c] == _UNLISTED:
                        trail[0, waiting] = c
                        waiting += 1
                seeds, scan_at = waiting, bucket + half  # a seed lowered and listed since waits no more
            change = empty(values, pen, links, bucket, focus_row, focus_col, cap)
            listed += change[0]
            taken += change[1]
            bucket += 1
            emptied += 1
            if ti.static(weighted) and listed > 0:  # on past empty buckets, but not past the trail's next scan
                ahead = next_listed(links, heads, bucket)
                if seeds > 0:
                    ahead = ti.min(ahead, ti.max(scan_at, bucket))
                emptied += ahead - bucket
                bucket = ahead
        return ti.Vector([emptied, listed + seeds, seeds, taken])

    return SimpleNamespace(lower_cut=lower_cut)


class _KernelTypes:
    """The ndarray types of a layer kind's kernel parameters, ``lanes`` packed layers per cell (0: scalar): the
    layer's ``values`` (``src``, ``dst``), ``penalties`` (float32, or a bit per lane in an int32), an int32 ``ints``
    (``header``, results), ``cells`` (n, 2) int32 (``cells``, ``origins``), ``stamps``, ``keys``, ``samples``
    (steps, cells, 1 + nodes) float32, the serial settling's work lists ``queue`` and an edit's ``costs`` (its
    cells' penalties)."""

    def __init__(self, lanes: int):
        self.values = ti.types.ndarray(dtype=ti.f32 if lanes == 0 else ti.types.vector(lanes, ti.f32), ndim=3)
        self.penalties = ti.types.ndarray(dtype=ti.f32 if lanes == 0 else ti.i32, ndim=3)
        self.ints = ti.types.ndarray(dtype=ti.i32, ndim=1)
        self.cells = ti.types.ndarray(dtype=ti.i32, ndim=2)
        self.stamps = ti.types.ndarray(dtype=ti.i32, ndim=3)
        self.keys = ti.types.ndarray(dtype=ti.f32, ndim=4)
        self.samples = ti.types.ndarray(dtype=ti.f32, ndim=3)
        self.queue = ti.types.ndarray(dtype=ti.i32, ndim=2)
        self.costs = ti.types.ndarray(dtype=ti.f32, ndim=1)


def _iterate_kernels(kernel, cell: SimpleNamespace, t: _KernelTypes) -> None:
    """Iterating: ``iterate`` (one parallel iteration) and ``iterate_serially`` (several on the calling thread)."""
    relax = _relax_rules(cell)
    relax_all, sample_into = relax.relax_all, relax.sample_into

    @kernel
    def iterate(src: t.values, dst: t.values, pen: t.penalties, stamps: t.stamps, header: t.ints, origins: t.cells,
                cells: t.cells, out: t.samples, cap: ti.f32, run: t.ints):
        """One iteration src -> dst of the active tiles (``run``: a _StepRun), shared out among the threads; then
        the layers sampled at ``cells`` into out[step]."""
        relax_all(src, dst, pen, stamps, header, cap, run[_STEP.tick], False)
        sample_into(dst, origins, cells, out, cap, run[_STEP.step])

    @kernel
    def iterate_serially(src: t.values, dst: t.values, pen: t.penalties, stamps: t.stamps, header: t.ints,
                         origins: t.cells, cells: t.cells, out: t.samples, cap: ti.f32,
                         run: t.ints) -> ti.i32:
        """Up to ``steps`` iterations on the calling thread (``run``: an _IterateRun), each
        sampled into out[first + step], for as long as at most ``limit`` tiles are active. ``src`` and ``dst``
        swap roles at each iteration. Returns the iterations done.

        An iteration is idle, and skipped, when the previous one changed nothing (header[CHANGED] == 0) and the
        host has stamped no tile for it or later (``woken``, the latest iteration it stamped for, is earlier):
        then no tile is active and both buffers hold the same values."""
        tick, first, steps = run[_ITERATE.tick], run[_ITERATE.first], run[_ITERATE.steps]
        limit, woken = run[_ITERATE.limit], run[_ITERATE.woken]
        done = 0
        while done < steps:
            busy = header[CHANGED] > 0 or woken >= tick + done
            if busy:
                if _active_tiles(stamps, tick + done) > limit:
                    break
            if done % 2 == 0:
                if busy:
                    relax_all(src, dst, pen, stamps, header, cap, tick + done, True)
                sample_into(dst, origins, cells, out, cap, first + done)
            else:
                if busy:
                    relax_all(dst, src, pen, stamps, header, cap, tick + done, True)
                sample_into(src, origins, cells, out, cap, first + done)
            done += 1
        return done


def _settle_kernels(kernel, cell: SimpleNamespace, t: _KernelTypes) -> None:
    """Settling, converge()'s rounds of tiles: ``settle`` (one parallel round) and ``settle_serially`` (rounds on
    the calling thread, with a focus and an allowance of sweeps)."""
    settle_all, band, lowest = _settle_rules(cell).settle_all, cell.band, cell.lowest
    successor_move, paint_cells = cell.successor_move, _paint_rules(cell).paint_cells

    @kernel
    def rekey(stamps: t.stamps, keys: t.keys, tick: ti.i32):
        """Key the tiles active for round ``tick`` after iterations, which wake tiles without keys and may leave
        cells above or below their relaxation in them: each is lifted at once, then lowered with no key (due at
        once). A tile whose keys were stale (settled, say) was lifted and then dropped as settled, its cells left
        above their relaxation."""
        for g, a, b in ti.ndrange(stamps.shape[0], stamps.shape[1], stamps.shape[2]):
            if stamps[g, a, b] >= tick:
                keys[g, a, b, _LOWER], keys[g, a, b, _LIFT] = ti.math.inf, -1.0

    @kernel
    def settle(values: t.values, pen: t.penalties, stamps: t.stamps, keys: t.keys, header: t.ints, cap: ti.f32,
               tick: ti.i32) -> ti.i32:
        """One round ``tick`` of in-place settling, the tiles shared out among the threads; returns the number of
        tiles that changed or wait."""
        lowest, lifting = ti.math.inf, ti.math.inf  # the lowest priority and lifting priority among the active
        for g, a, b in stamps:
            if stamps[g, a, b] >= tick:
                ti.atomic_min(lowest, _priority(keys, header, g, a, b))
                ti.atomic_min(lifting, _lifting_priority(keys, header, g, a, b))
        lift_round = lifting < _SETTLED  # (a reduction's inf comes back as the largest float)
        return settle_all(values, pen, stamps, keys, header, None, cap, tick,
                          ti.select(lift_round, ti.math.inf, lowest + band), lift_round)

    @kernel
    def settle_serially(values: t.values, pen: t.penalties, stamps: t.stamps, keys: t.keys, header: t.ints,
                        queue: t.queue, cap: ti.f32, run: t.ints):
        """``settle_rounds``, on the calling thread."""
        settle_rounds(values, pen, stamps, keys, header, queue, cap, run)

    @kernel
    def settle_painting(values: t.values, pen: t.penalties, stamps: t.stamps, keys: t.keys, header: t.ints,
                        queue: t.queue, origins: t.cells, cells: t.cells, penalties: t.costs, cap: ti.f32,
                        run: t.ints):
        """``settle_serially`` after painting the edits ``_LayerArrays.paint`` held back (``paint_cells``: a
        launch saved, most of a small edit's cost)."""
        ti.loop_config(serialize=True)
        for _ in range(1):
            paint_cells(values, values, pen, stamps, keys, header, queue, origins, cells, penalties, cap,
                        run[_SETTLE.tick] + run[_SETTLE.round_open], run[_SETTLE.listed])
            settle_rounds(values, pen, stamps, keys, header, queue, cap, run)

    @ti.func
    def settle_rounds(values: ti.template(), pen: ti.template(), stamps: ti.template(), keys: ti.template(),
                      header: ti.template(), queue: ti.template(), cap, run: ti.template()):
        """converge()'s rounds on the calling thread (``run``: a _SettleRun): up to ``rounds`` rounds and ``sweeps``
        sweeps of tiles (0: any number; a round whose sweeps
        are spent stays open, and the next launch goes on with it; scans count against them: ``_spent``) until
        settled, until more than ``limit`` tiles are active, or - with a focus (padded layer coordinates; row -1:
        none) - until no pending tile can change the focus's value or successors: every active tile's lowering
        key known, and the lowest priority at least the focus's value (a pending cell can only fall to its
        lowering key + 1 or more, a cell below its relaxation holds more than its lifting key, and a way from the
        focus through either is at least its distance longer: ARCHITECTURE §6.1). Each round works through a
        list of its active tiles (``queue``, built as the round before stamps them, and kept between launches by
        ``paint``: ``listed`` 1; 0 lists the active tiles first), so a small repair on a large map does not pass
        over every tile. Its results (a _SettleResult) go in ``run`` after the parameters."""
        tick, rounds, limit = run[_SETTLE.tick], run[_SETTLE.rounds], run[_SETTLE.limit]
        focus_row, focus_col = run[_SETTLE.focus_row], run[_SETTLE.focus_col]
        header[FOCUS_ROW], header[FOCUS_COL] = focus_row, focus_col
        header[SWEPT], header[SWEEP_ALLOWANCE], header[SCANNED] = 0, run[_SETTLE.sweeps], 0
        done, settled, focused, cut = 0, 0, 0, 0
        if not run[_SETTLE.listed]:
            _list_active(stamps, queue, tick)
            header[ROUND_CURSOR] = 0
        while done < rounds and settled == 0:
            if _spent(header):
                cut = 1
                break
            if header[ROUND_CURSOR] == 0:  # a new round: its bound, or the focus reached
                scan = _round_scan(stamps, keys, header, queue, tick + done)
                header[SCANNED] += ti.i32(scan[0])
                if scan[0] > limit:
                    break
                aim = ti.math.inf  # the focus's value: no pending tile with a priority at least this changes it
                if focus_row >= 0:
                    aim = lowest(values[0, focus_row, focus_col])
                lift_round = scan[3] < aim
                if not lift_round and scan[0] > 0 and focus_row >= 0 and scan[2] == 0 and scan[1] >= aim:
                    focused = 1
                    break
                header[ROUND_BOUND] = ti.bit_cast(ti.select(lift_round, aim, scan[1] + band), ti.i32)
                header[ROUND_LIFTS] = ti.select(lift_round, 1, 0)
            settle_all(values, pen, stamps, keys, header, queue, cap, tick + done,
                       ti.bit_cast(header[ROUND_BOUND], ti.f32), header[ROUND_LIFTS])
            if header[ROUND_CURSOR] > 0:
                cut = 1
                break
            done += 1
            if queue[(tick + done) % 2, queue.shape[1] - 1] == 0:  # no tile active for the next round
                settled = 1
        run[_SETTLED_BY.rounds], run[_SETTLED_BY.settled], run[_SETTLED_BY.focused] = done, settled, focused
        run[_SETTLED_BY.swept], run[_SETTLED_BY.cut], run[_SETTLED_BY.move] = header[SWEPT], cut, -1
        inside = PAD <= focus_row < values.shape[1] - PAD and PAD <= focus_col < values.shape[2] - PAD
        if inside:  # the focus's successor move, read before the caller asks (a trace is a launch more)
            run[_SETTLED_BY.move] = successor_move(values, pen, header, cap, 0, 0, focus_row, focus_col)


def _search_kernels(kernel, cell: SimpleNamespace, t: _KernelTypes) -> None:
    """Searching from the initial state (a scalar layer's only): ``search``, and ``mend`` after edits."""
    searching = _search_rules(cell)
    bucket_search, hand_over, store_penalty = _race_rules(cell).search, searching.hand_over, cell.store_penalty

    @kernel
    def search(values: t.values, pen: t.penalties, stamps: t.stamps, keys: t.keys, header: t.ints, links: t.queue,
               cap: ti.f32, run: t.ints):
        """converge() from the initial state, on the calling thread (``_search_rules``; ``run``: a _SearchRun), the
        tiles then handed over to settling for round ``tick``; its results (a _SearchResult) go in ``run``."""
        ti.loop_config(serialize=True)
        for _ in range(run[_SEARCH.go]):
            found = bucket_search(values, pen, header, links, cap, run[_SEARCH.focus_row], run[_SEARCH.focus_col])
            hand_over(values, stamps, keys, links, run[_SEARCH.tick], True)
            run[_SEARCHED.buckets], run[_SEARCHED.frontier] = found[_EMPTIED], found[_LISTED]
            run[_SEARCHED.taken] = found[_TAKEN]

    racing = _race_rules(cell, logged=True)
    look_rules, raise_rules = _cut_rules(cell), _raise_rules(cell)
    cut_start, cutting, cut_step, cut_verdict, outlined = (look_rules.cut_start, look_rules.cutting,
                                                           look_rules.cut_step, look_rules.cut_verdict,
                                                           look_rules.outlined)
    raise_start, raise_step, raise_end = raise_rules.raise_start, raise_rules.raise_step, raise_rules.raise_end

    @ti.func
    def least_around(values: ti.template(), i, j, reach):
        """The least of ``values`` within ``reach`` cells of padded cell (i, j) (rows and columns). A cell's route
        reads a cell edited only through a move from a cell next to it (a step: the move's source, or its crossing's
        neighbour) or, opened, one a move away (``reach`` PAD): every cell whose value an edit changes ends above the
        least value there before it, a move adding at least 1 (a new obstacle or a dearer cell changes only the cells
        whose routes went through it; a way opened lowers cells below their values only from there)."""
        least = values[0, i, j]
        for da, db in ti.ndrange((-reach, reach + 1), (-reach, reach + 1)):
            least = ti.min(least, values[0, i + da, j + db])
        return least

    seed_cut, lower_cut = raise_rules.seed_cut, _lower_rules(searching).lower_cut

    @kernel
    def mend(values: t.values, pen: t.penalties, stamps: t.stamps, keys: t.keys, header: t.ints, links: t.queue,
             trail: t.queue, cells: t.cells, penalties: t.costs, cap: ti.f32, spare: t.values, race_links: t.queue,
             run: t.ints):
        """converge() after edits of ``cells`` on a layer that was at its fixed point, cell by cell on the calling
        thread (the look of ``_cut_rules``, the raise and ``seed_cut`` of ``_raise_rules``, ``_lower_rules``'
        ``lower_cut``; ``run``: a _MendRun), the tiles then handed over to settling for round ``tick``; its results
        (a _MendResult) go in ``run``. The edits' ``penalties`` are painted first (``_LayerArrays.paint`` holds them
        back for it). ``trail``: (_TRAIL_ROWS, padded cells), its rows the look's and the raise's, all 0 in row 2. A
        search from the source races the look and, where the look found the edits' sides apart, the raise
        (``_race_rules``, ``race_lead``) in ``spare``, a buffer at the initial state (the cap everywhere), with
        ``race_links`` (3 rows): the look and the raise go a cell at a time in one loop, the race on after each
        (``advance``, in one place: each place inlines a search). If it finishes first, or the mend's work passes
        its budget, or the look finds the goal sealed in so few cells that a restart costs less
        (``restart_is_cheaper``) - or, stopped short, the outline of the goal's part (``outlined``) bounds them so -,
        the mend gives up and the race runs to its end - the restart, in the same launch,
        its tiles handed over for round ``restart_tick``; else the race's cells are put back at the cap."""
        ti.loop_config(serialize=True)
        for _ in range(run[_MEND.go]):
            heads, nearest = values.shape[1] * values.shape[2], cap  # the edits' value nearest the source before them
            below = cap  # ... and the least around one: no cell below it changes (``seed_bound``)
            for k in range(cells.shape[0]):  # the edits painted, in order (``paint``'s first pass)
                i, j = cells[k, 0] + PAD, cells[k, 1] + PAD
                nearest = ti.min(nearest, values[0, i, j])
                below = ti.min(below, least_around(values, i, j, ti.select(penalties[k] < pen[0, i, j], PAD, 1)))
                store_penalty(pen, 0, i, j, 0, penalties[k])
                if penalties[k] > MAX_COST:
                    values[0, i, j] = cap
            budget, restart, fills = run[_MEND.budget], run[_MEND.restart], run[_MEND.fills]
            # cells below this value (less a move) did not route through the edits: the source keeps them
            kept = racing.kept(links, heads, ti.i32(ti.min(nearest, 1e9)) - run[_MEND.longest_move])
            seed_wait, seed_pass = run[_MEND.seed_wait], run[_MEND.seed_pass]
            bound = _seed_bound(below, racing.kept(links, heads, ti.i32(ti.min(below, _SEED_MOST))),
                                seed_wait + seed_pass, run[_MEND.focus_row])
            race = racing.start(spare, pen, header, race_links, run[_MEND.focus_row], run[_MEND.focus_col], bound,
                                bound - run[_MEND.longest_move], seed_wait)
            least = ti.select(bound < 0, kept, seed_pass) + fills  # the least a restart (the race) costs
            race[_LEAD] = _race_lead(least, 0, budget, run[_MEND.lead])
            look = cut_start(values, pen, header, trail, cells, penalties, cap)
            looked, rising, left = ti.Vector([0, 0, 0]), ti.Vector([0, 0, 0, 0, 0]), race
            phase, raising, gave_up, spent, outline = _LOOKING, False, 0, 0, -1
            while phase != _RAISE_OVER:  # the look, then the raise, the race going on beside them in one place
                most, seeding = -1, False
                spent = _mend_work(looked[1], rising[_RAISED])  # the look's cells once it ended, the raise's
                if phase == _LOOKING and cutting(look, run[_MEND.looks]) and not racing.over(spare, race):
                    look = cut_step(values, pen, header, trail, cells, penalties, look)
                    most, seeding = racing.paced(race, look[_LOOKED] - look[_DROPPED])
                elif phase == _LOOKING:
                    looked = cut_verdict(values, pen, trail, cells, penalties, cap, look)
                    stopped_short = looked[2] == 1 and looked[0] < 0  # parts apart, the source's reach not counted
                    # and the cells the source keeps (``kept``) few enough that a restart may yet cost less: the most
                    # its part holds, by its outline
                    if stopped_short and _doomed(kept, restart, fills):
                        outline = outlined(pen, header, _outline_cracks(restart, run[_MEND.depth_first]))
                    most_reached = ti.select(looked[0] >= 0, looked[0], outline)
                    raising = not (_doomed(most_reached, restart, fills) or racing.over(spare, race))
                    if raising:
                        budget = _budget_for(budget, restart, fills, most_reached)
                        # the edits cut nothing apart: the source keeps what it had, a restart costs as much
                        race[_LEAD] = 0
                        if stopped_short:
                            race[_LEAD] = _race_lead(least, looked[1], budget, run[_MEND.lead])
                            race[_HEAD] = ti.select(race[_LEAD] > 0 and bound < 0,
                                                    _race_head(kept, run[_MEND.head]), 0)
                    rising = raise_start(values, links, cells, cap, raising)
                    phase = _RAISING
                elif rising[_NEXT] != rising[_END] and spent <= budget and not racing.over(spare, race):
                    rising, rose = raise_step(values, pen, header, links, trail, cap, rising,
                                              run[_MEND.depth_first])
                    if rose:
                        most, seeding = racing.paced(race, looked[1] + rising[_RAISED])
                else:
                    raise_end(values, links, trail, rising)
                    left, phase = race, _RAISE_OVER
                    if not raising or spent > budget or racing.over(spare, race):
                        gave_up, most, seeding = 1, _NEVER, True  # the race runs to its end: the restart
                if most >= 0:
                    race = racing.advance(values, spare, pen, race_links, race, most, seeding, cap)
            reached, raised = looked[0], rising[_RAISED]
            run[_MENDED.raised], run[_MENDED.reached], run[_MENDED.spent] = raised, reached, spent
            run[_MENDED.raced], run[_MENDED.head] = left[_TAKEN], left[_HEAD]
            run[_MENDED.seeded] = ti.select(left[_FROM] == _SEEDED, 1, 0)
            run[_MENDED.gave_up], run[_MENDED.outlined] = gave_up, outline
            if gave_up:  # the race ran to its end: the restart, its log the search's from now on
                racing.hand_log(race_links, race, links, heads)
                hand_over(spare, stamps, keys, race_links, run[_MEND.restart_tick], True)
                run[_MENDED.buckets], run[_MENDED.frontier] = race[_EMPTIED], race[_LISTED]
                run[_MENDED.lowered] = race[_TAKEN]
                continue
            racing.clean(spare, race_links, race, cap)
            seeds = seed_cut(values, pen, header, trail, cells, penalties, raised, cap)
            found = lower_cut(values, pen, links, trail, seeds, run[_MEND.focus_row], run[_MEND.focus_col], cap)
            run[_MENDED.spent] += found[3]
            run[_MENDED.lowered] = found[3]
            hand_over(values, stamps, keys, links, run[_MEND.tick], run[_MEND.settled] == 0)  # empties the buckets
            width = values.shape[2]
            for k in range(found[2]):  # the seeds a focused mend left waiting join the frontier
                i, j = _cell_at(trail[0, k], width)
                _stamp_near(stamps, keys, None, 0, i - PAD, j - PAD, run[_MEND.tick], 0, _LOWER, values[0, i, j])
            run[_MENDED.buckets], run[_MENDED.frontier] = found[0], found[1]


def _setup_kernels(kernel, cell: SimpleNamespace, t: _KernelTypes) -> None:
    """The initial state: ``seed`` (the source and the tiles around it) and ``gather_penalties``."""
    broadcast, blocked_lanes, store_penalty, width = cell.broadcast, cell.blocked_lanes, cell.store_penalty, cell.width

    @kernel
    def seed(src: t.values, dst: t.values, pen: t.penalties, stamps: t.stamps, header: t.ints, tick: ti.i32):
        """After both buffers are filled with the cap and every tile deactivated: 0 at a free source (eqs. 5 and
        10), and the tiles within the stencil's reach of it active for ``tick``."""
        rows, cols = src.shape[1] - 2 * PAD, src.shape[2] - 2 * PAD
        i, j = header[SOURCE_ROW], header[SOURCE_COL]
        ti.loop_config(serialize=True)  # a few stores per layer group: cheaper than waking the threads
        for g in range(src.shape[0]):
            src[g, i, j] = ti.select(blocked_lanes(pen, g, i, j), src[g, i, j], broadcast(0.0))
            dst[g, i, j] = src[g, i, j]
            for da in ti.static(range(-PAD, PAD + 1, PAD)):
                for db in ti.static(range(-PAD, PAD + 1, PAD)):
                    a = ti.min(ti.max(i - PAD + da, 0), rows - 1) // TILE
                    b = ti.min(ti.max(j - PAD + db, 0), cols - 1) // TILE
                    stamps[g, a, b] = tick

    @kernel
    def gather_penalties(pen: t.penalties, origins: t.cells, grid: ti.types.ndarray(dtype=ti.f32, ndim=2)):
        """Fill every layer's penalties from the grid's (``grid``: (H + 2 PAD) x (W + 2 PAD), 0 free, inf
        blocked and in the padding): inf outside the grid and in the layer's own padding."""
        rows, cols = grid.shape[0] - 2 * PAD, grid.shape[1] - 2 * PAD
        side_rows, side_cols = pen.shape[1] - 2 * PAD, pen.shape[2] - 2 * PAD
        for g, i in ti.ndrange(pen.shape[0], pen.shape[1]):  # by rows: threads take 32 loop items at a time
            for lane in range(width):
                r = origins[g * width + lane, 0] + i - PAD
                left = origins[g * width + lane, 1] - PAD
                inside = PAD <= i < side_rows + PAD and 0 <= r < rows
                for j in range(pen.shape[2]):
                    value = ti.math.inf
                    if inside and PAD <= j < side_cols + PAD and 0 <= left + j < cols:
                        value = grid[r + PAD, left + j + PAD]
                    store_penalty(pen, g, i, j, lane, value)


def _fill_kernels(kernel, cell: SimpleNamespace, t: _KernelTypes) -> None:
    """Packed lanes' fill: ``fill_values`` (Taichi's own fill of a vector ndarray takes the value as a template
    argument: it compiled a kernel for every cap it was given, 0.03-0.15 s each, and took 3 ms a fill after)."""
    broadcast = cell.broadcast

    @kernel
    def fill_values(values: t.values, value: ti.f32):
        """Every cell of ``values``, every lane, to ``value``."""
        for index in ti.grouped(values):
            values[index] = broadcast(value)


def _paint_rules(cell: SimpleNamespace) -> SimpleNamespace:
    """Painting edits into a kind of layer: ``paint_cells`` (``paint``'s work, which ``settle_painting`` does too,
    for the edits ``_LayerArrays.paint`` held back)."""
    component, store, store_penalty = cell.component, cell.store, cell.store_penalty
    window_cell, width = cell.window_cell, cell.width

    @ti.func
    def freed_key(values: ti.template(), header: ti.template(), cap, g, a, b, lane):
        """A bound below which no cell that layer cell (a, b), lane ``lane``, just freed opens a way to can fall
        (less 1): the smallest value below the cap within the stencil's reach of it (a way through a freed region
        enters it from such a cell), -1 at the source."""
        key = ti.math.inf
        if a + PAD == header[SOURCE_ROW] and b + PAD == header[SOURCE_COL]:
            key = -1.0
        for da, db in ti.ndrange((-PAD, PAD + 1), (-PAD, PAD + 1)):
            value = component(values[g, a + PAD + da, b + PAD + db], lane)
            if value < cap:
                key = ti.min(key, value)
        return key

    @ti.func
    def paint_cells(src: ti.template(), dst: ti.template(), pen: ti.template(), stamps: ti.template(),
                    keys: ti.template(), header: ti.template(), queue: ti.template(), origins: ti.template(),
                    cells: ti.template(), penalties: ti.template(), cap, tick, listed):
        """Write changed cells' ``penalties`` (inf occupied; free 0, or a weighted layer's cost) into every layer
        that contains them, and activate the tiles near them for iteration or round ``tick`` (``_stamp_near``; in
        the work list if ``listed``). A newly occupied cell takes its obstacle value, the cap, at once in both
        buffers, and keys the lifting of the cells near it that depended on it by its old value (they held more);
        the cells freed key their lowering by ``freed_key``, the smallest over them (a way through several freed
        cells enters from one of their neighbours). On the calling thread, inside a serial loop."""
        rows, cols = pen.shape[1] - 2 * PAD, pen.shape[2] - 2 * PAD
        freed = ti.math.inf
        for k, g in ti.ndrange(cells.shape[0], pen.shape[0]):
            for lane in range(width):
                a, b = window_cell(origins, cells, k, g, lane)
                if 0 <= a < rows and 0 <= b < cols:
                    store_penalty(pen, g, a + PAD, b + PAD, lane, penalties[k])
                    if penalties[k] > MAX_COST:
                        old = component(src[g, a + PAD, b + PAD], lane)
                        store(src, g, a + PAD, b + PAD, lane, cap)
                        store(dst, g, a + PAD, b + PAD, lane, cap)
                        _stamp_near(stamps, keys, queue, g, a, b, tick, listed, _LIFT, old)
        for k, g in ti.ndrange(cells.shape[0], pen.shape[0]):
            for lane in range(width):
                a, b = window_cell(origins, cells, k, g, lane)
                if 0 <= a < rows and 0 <= b < cols and penalties[k] <= MAX_COST:
                    freed = ti.min(freed, freed_key(src, header, cap, g, a, b, lane))
        for k, g in ti.ndrange(cells.shape[0], pen.shape[0]):
            for lane in range(width):
                a, b = window_cell(origins, cells, k, g, lane)
                if 0 <= a < rows and 0 <= b < cols and penalties[k] <= MAX_COST:
                    _stamp_near(stamps, keys, queue, g, a, b, tick, listed, _LOWER, freed)

    return SimpleNamespace(paint_cells=paint_cells)


def _edit_kernels(kernel, cell: SimpleNamespace, t: _KernelTypes) -> None:
    """Editing: ``paint`` (cells occupied or freed, the tiles around them woken with keys) and ``stamp_cells``
    (tiles woken for iterations after a goal move)."""
    window_cell, width, paint_cells = cell.window_cell, cell.width, _paint_rules(cell).paint_cells

    @kernel
    def paint(src: t.values, dst: t.values, pen: t.penalties, stamps: t.stamps, keys: t.keys, header: t.ints,
              queue: t.queue, origins: t.cells, cells: t.cells, penalties: t.costs, cap: ti.f32, run: t.ints):
        """``paint_cells`` (``run``: a _PaintRun). A few cells per edit: cheaper than waking the threads. One outer
        loop, so that its three passes all run on the calling thread (a loop config holds for the next loop only:
        the later two woke the threads, twice, 0.2 ms of a small edit's 0.25)."""
        ti.loop_config(serialize=True)
        for _ in range(1):
            paint_cells(src, dst, pen, stamps, keys, header, queue, origins, cells, penalties, cap, run[_PAINT.tick],
                        run[_PAINT.listed])

    @kernel
    def stamp_cells(stamps: t.stamps, pen: t.penalties, origins: t.cells, cells: t.cells, tick: ti.i32):
        """Activate for iteration ``tick`` the tiles that have one of ``cells`` (grid coordinates) within reach
        (see ``_stamp_near``; ``pen`` gives the layers' shape): for iterations only (a converge after a goal move
        starts afresh)."""
        rows, cols = pen.shape[1] - 2 * PAD, pen.shape[2] - 2 * PAD
        ti.loop_config(serialize=True)  # a few cells: cheaper than waking the threads
        for k, g in ti.ndrange(cells.shape[0], stamps.shape[0]):
            for lane in range(width):
                a, b = window_cell(origins, cells, k, g, lane)
                if -PAD <= a < rows + PAD and -PAD <= b < cols + PAD:
                    _stamp_near(stamps, None, None, g, a, b, tick, 0, _LOWER, 0.0)


def _read_kernels(kernel, cell: SimpleNamespace, t: _KernelTypes) -> None:
    """Reading: ``sample`` (every layer at given cells) and ``trace`` (a layer's successors from a cell)."""
    sample_into, successor_move = _relax_rules(cell).sample_into, cell.successor_move
    moves, width = cell.moves, cell.width

    @kernel
    def sample(values: t.values, origins: t.cells, cells: t.cells, out: t.samples, cap: ti.f32):
        """Every layer of this kind at ``cells`` into out[0] (see ``sample_into``)."""
        sample_into(values, origins, cells, out, cap, 0)

    @kernel
    def trace(values: t.values, pen: t.penalties, header: t.ints, cap: ti.f32, index: ti.i32, out: t.cells):
        """Follow the successors of layer ``index`` of this kind from the cell in out[0] (padded layer coordinates)
        for at most out.shape[0] - 1 steps, into out[1:]; out[0, 0] receives the number of steps."""
        g, lane = index // width, index % width
        i, j, steps = out[0, 0], out[0, 1], 0
        ti.loop_config(serialize=True)
        for _ in range(out.shape[0] - 1):
            move = -1
            if PAD <= i < values.shape[1] - PAD and PAD <= j < values.shape[2] - PAD:
                move = successor_move(values, pen, header, cap, g, lane, i, j)
            if move >= 0:
                for k, m in ti.static(enumerate(moves)):
                    if move == k:
                        i += m.dr
                        j += m.dc
                out[steps + 1, 0] = i
                out[steps + 1, 1] = j
                steps += 1
            else:
                break
        out[0, 0] = steps


class _Kernels:
    """The kernels of one compile-time spec - ``lanes`` packed layers per cell (0: the scalar goal layer), the
    stencil's ``neighbourhood`` and corner rule, whether moves are ``weighted`` by the cells' costs, whether values
    may be ``absorbing`` (``may_absorb``) - closed over as constants, made by one factory per phase (iterate,
    settle, search or fill, set up, edit, read) and named on this object. The decorator that makes each kernel also
    records it in :attr:`all`, which :meth:`_Layers.warm_up` walks, so no kernel escapes the warm-up. Build them
    with :func:`_kernels_for`, which caches one set per spec.

    Parameter names say what they take: a layer's arrays (``src``, ``dst``, ``values``, ``pen``, ``stamps``,
    ``keys``, ``queue``, ``header``, ``origins``, see :class:`_Layers`) and its ``cap``; ``cells`` (n, 2) grid cells;
    ``out`` samples (steps, cells, 1 + nodes); ``run`` a launch's parameters (a named tuple: ``_StepRun``,
    ``_IterateRun``, ``_SettleRun``, ``_SearchRun``, ``_MendRun``, ``_PaintRun``, as :func:`_launch` makes it),
    followed by what it hands back (``_SettleResult``, ``_SearchResult``, ``_MendResult``)."""

    def __init__(self, lanes: int, neighbourhood: int, corner_cutting: bool, weighted: bool, absorbing: bool):
        init_taichi()
        self.lanes, self.weighted, self.absorbing = lanes, weighted, absorbing
        self.neighbourhood, self.corner_cutting = neighbourhood, corner_cutting
        cell = _cell_rules(lanes, stencil.moves(neighbourhood, corner_cutting), weighted, absorbing)
        types = _KernelTypes(lanes)
        made = []

        def kernel(function):
            """``ti.kernel``, and the kernel recorded in :attr:`all` (and so warmed up)."""
            made.append(_Launcher(ti.kernel(function)))
            return made[-1]

        phases = [_iterate_kernels, _settle_kernels, _setup_kernels, _edit_kernels, _read_kernels]
        for phase in phases + ([_search_kernels] if lanes == 0 else [_fill_kernels]):
            phase(kernel, cell, types)
        self.all = tuple(made)
        for made_kernel in made:
            setattr(self, made_kernel.__name__, made_kernel)
        self.warmed = False


@functools.lru_cache(maxsize=None)
def _kernels_for(lanes: int, neighbourhood: int, corner_cutting: bool, weighted: bool = False,
                 absorbing: bool = False) -> _Kernels:
    """The kernels of one compile-time spec, built once per process (Taichi compiles each on its first launch)."""
    return _Kernels(lanes, neighbourhood, corner_cutting, weighted, absorbing)


def _idle_argument(parameter: inspect.Parameter, scratch: "_Layers"):
    """A value for a kernel parameter that makes a launch touch nothing that matters: the scratch layer's array or
    cap of that name, else zeros, or a small zero array of the annotated type (IDLE_ENTRIES along each axis: no
    kernel indexes past them - ``settle_serially``'s launch array holds 13 entries; with two, as once, its result
    writes ran past the array during every warm-up and corrupted the heap)."""
    if hasattr(scratch, parameter.name):
        return getattr(scratch, parameter.name)
    kind = parameter.annotation
    if isinstance(kind, NdarrayType):
        return np.zeros((IDLE_ENTRIES,) * kind.ndim, np.int32 if kind.dtype == ti.i32 else np.float32)
    if kind == ti.i32 or kind == ti.f32:
        return 0
    raise TypeError(f"warm_up cannot launch parameter {parameter.name!r} of type {kind!r}")


# ------------------------------------------------------------------------------------------------------- host class
def _painted_array(name: str) -> property:
    """A layer's array ``name``, the edits it holds back painted into it first (:meth:`_LayerArrays.paint`)."""
    return property(lambda layer: getattr(layer._painted(), name))


class _LayerArrays:
    """One kind of layer, self-describing: the goal's (scalar, ``lanes`` = 0) or the node windows (``lanes`` packed
    per cell). It holds its kernels, two value buffers (Jacobi: ``src`` the values, ``dst`` the next), the
    penalties ``pen``, the ``header`` (CHANGED, SOURCE_ROW, SOURCE_COL), each lane's ``origins`` (grid coordinates
    of its cell (0, 0)), its ``cap``, the active-tile ``stamps`` (the last iteration or round a tile is active for)
    and ``keys`` (the smallest value that woke an active tile, inf: unknown, due at once; settling only), under the
    names the kernels' parameters use."""

    def __init__(self, kernels: _Kernels, groups: int, side: tuple[int, int], origins: np.ndarray,
                 source: tuple[int, int], cap: float, max_cost: float = 1.0):
        self.kernels = kernels
        self.lanes, (self.rows, self.cols), self.cap = kernels.lanes, side, float(cap)
        self.ring = _search_buckets(max_cost)  # the search's buckets
        self.longest_move = _longest_move(max_cost)  # ... and the most a move adds to a value, at the dearest yet
        shape = (groups, self.rows + 2 * PAD, self.cols + 2 * PAD)
        stamps = ti.ndarray(ti.i32, (groups, -(-self.rows // TILE), -(-self.cols // TILE)))
        # the arrays the kernels take, behind properties that paint the edits held back first (``paint``)
        self._arrays = SimpleNamespace(
            buffers=[self._array(shape), self._array(shape)],
            pen=ti.ndarray(ti.i32 if self.lanes else ti.f32, shape),  # packed: a bit per lane (1 blocked)
            stamps=stamps,
            keys=ti.ndarray(ti.f32, (*stamps.shape, 2)),  # lowering's and lifting's (_LOWER, _LIFT)
            queue=ti.ndarray(ti.i32, (2, math.prod(stamps.shape) + 1)),  # serial settling's work lists
            header=_device(np.array([0, source[0], source[1], *_NO_FOCUS, 0, 0, 0, 0, 0, 0], np.int32)))
        # edits (cells, penalties) the goal layer holds back for the converge that follows, which paints them in its
        # own launch (a paint launch cost as much as a small repair): ``paint``
        self.unpainted: list[tuple[np.ndarray, np.ndarray]] = []
        self.grid_origins = np.asarray(origins, np.int32)
        self.origins = _device(self.grid_origins)
        self.mirrored = True  # both buffers hold the same values wherever a tile is inactive
        self.listed = False  # the work list of round ``tick`` holds the active tiles (kept by settling and painting)
        self.round_open = False  # the last launch's allowance cut round ``tick`` short: it goes on at the next
        self.woken_unkeyed = False  # iterations woke tiles since settling or a search last keyed them: ``rekey``
        self.current = 0  # which buffer holds the values
        self.columns = slice(1, None) if self.lanes else slice(0, 1)  # this kind's columns of a sample
        # (cells as bytes, this kind's values there) sampled while idle; dropped by everything that changes values:
        # a busy iteration, converge, reset, paint
        self._idle_sample: tuple[bytes, np.ndarray] | None = None
        self.tick = 0  # number of the next iteration, never reset: stamps compare against it
        self.woken = 0  # the latest iteration the host stamped tiles for (activate_all, activate_cells)
        # A converge stopped before the fixed point (at its focus, or by max_rounds) leaves its active tiles and their
        # keys for the next converge.
        self.pending = False
        self.cut_short = False  # the last converge stopped at max_rounds or max_sweeps (not its fixed point or focus)
        self.swept = 0  # sweeps of tiles the last converge made on the calling thread
        # the successor moves read since anything last changed the values: padded cell -> index of its move (-1: none),
        # the last focused converge's at its focus (read in its last launch) and the cells traced since (``trace``)
        self.successors: dict[tuple[int, int], int] = {}
        # the values are the initial state (the cap, the source aside: edits keep it), for a search (``_search``)
        self.fresh = False
        self.links = None  # the search's buckets (``_search_rules``), made at the first search
        self.trail = None  # a mend's raised cells, then its seeds (``_raise_rules``), made at the first mend
        self.spare = None  # ... and a buffer of values at the cap everywhere, where a mend's race searches
        self.race_links = None  # ... with its own buckets and log (``_race_rules``)
        # the cells edited since the layer was last at its fixed point (None: it is not, or may not be): a converge
        # mends them cell by cell (:meth:`_mend`)
        self.edits: list[tuple[np.ndarray, np.ndarray]] | None = None
        self.restart_s: float | None = None  # seconds the last search took (``_repair``'s price of a restart)
        self.searched: int | None = None  # cells the last search to the end took (``_mend``'s price of a restart)
        self.cell_s: float | None = None  # ... and the seconds a cell of the last one that took PRICED_SEARCH or more
        self.reset_s: float | None = None  # seconds the last reset took
        self.converged_by = ""  # how the last converge ended: "search", "mend" or "rounds"
        # every tile settled (no stamp for the round, no key): a search or mend that left no frontier made them so,
        # and a mend's hand-over then sweeps none. A mend follows one of those, or rounds of tiles that reached the
        # fixed point (they clear it), with only edits since: the paint of one read before its converge clears it.
        self.tiles_settled = False
        self.depth_first = False  # whether a mend's raise takes the cell queued last first (``depth_first_raise``)
        self.activate_all()

    def reprice(self, cells: np.ndarray, costs: np.ndarray) -> None:
        """New costs for free ``cells`` of a weighted layer: each painted blocked, then free at its cost (what went
        through it is lifted, then lowered)."""
        self.paint(cells, np.full(len(cells), np.inf, np.float32))
        self.paint(cells, costs.astype(np.float32))

    def _array(self, shape: tuple[int, int, int]):
        if self.lanes:
            return _freed_when_dropped(ti.Vector.ndarray(self.lanes, ti.f32, shape))
        return ti.ndarray(ti.f32, shape)

    def _painted(self) -> SimpleNamespace:
        """The arrays, every edit held back painted into them first (``paint``)."""
        held = self._held_back()
        if held:
            self._paint_now(*held)
        return self._arrays

    def _held_back(self) -> tuple[np.ndarray, np.ndarray] | None:
        """The edits ``paint`` held back, as (cells, penalties) in order, for a launch that paints them; none now."""
        if not self.unpainted:
            return None
        held, self.unpainted = _joined(self.unpainted), []
        return held

    pen, stamps, keys, queue, header = (_painted_array(name) for name in ("pen", "stamps", "keys", "queue", "header"))

    @property
    def src(self):
        return self._painted().buffers[self.current]

    values = src

    @property
    def padded_cells(self) -> int:
        """Cells of a layer, padding included (a search's and a mend's arrays have an entry per cell); reading it
        paints no edit held back (``paint``)."""
        shape = self._arrays.buffers[0].shape
        return shape[1] * shape[2]

    @property
    def dst(self):
        return self._painted().buffers[1 - self.current]

    def changed(self) -> int:
        """Cells the last iteration changed."""
        return int(self.header[CHANGED])

    def move_source(self, source: tuple[int, int]) -> None:
        """Hold ``source`` (padded layer coordinates) at 0 from the next iteration on (the values that depended on
        the old one must rise). Work a converge left pending is dropped: it was for the old source, and finishing it
        by settling (as :meth:`iterate` finishes pending work) raised the cells cut off from the new one a step a
        round for ever where the cap is inf; the next converge restarts (``Engine.converge``), and iterations go on
        from the values as they are."""
        self.header[SOURCE_ROW], self.header[SOURCE_COL] = int(source[0]), int(source[1])
        self.successors, self.edits = {}, None
        self.pending = False

    def activate_all(self) -> None:
        """Every tile active for the next iteration or round, with no key (due at once)."""
        self.listed = False
        self.stamps.fill(self.tick)
        self.keys.fill(math.inf)
        self.woken = self.tick
        self.pending = False
        self.edits = None

    def deactivate_all(self) -> None:
        self.listed = False
        self.stamps.fill(-1)

    def activate_cells(self, cells: np.ndarray) -> None:
        """Activate the tiles near ``cells`` ((n, 2) int32 grid cells) for the next iteration."""
        self.kernels.stamp_cells(stamps=self.stamps, pen=self.pen, origins=self.origins, cells=cells, tick=self.tick)
        self.listed = False
        self.woken = self.tick
        self.edits = None

    def gather_penalties(self, grid: np.ndarray) -> None:
        """Every layer's penalties from the grid's, ``grid`` padded by PAD (0 free, inf blocked and outside)."""
        self.kernels.gather_penalties(pen=self.pen, origins=self.origins, grid=grid)

    def paint(self, cells: np.ndarray, penalties: np.ndarray) -> None:
        """Set the penalties of ``cells`` (0 free, inf occupied; a weighted layer's free cells their cost, which
        widens the search's ring if it needs more buckets: made again at the next search, and takes the absorbing
        kernels once values may reach ABSORBING: ``may_absorb``) and wake the tiles around them. The goal layer holds
        the edit back (:attr:`unpainted`): the converge that follows paints it in its own launch (a mend, or the
        first launch of rounds on the calling thread), and anything else that reads the arrays paints it first."""
        if self.kernels.weighted:
            dearest = float(np.max(penalties, where=penalties <= MAX_COST, initial=1.0))
            self.longest_move = max(self.longest_move, _longest_move(dearest))
            ring = _search_buckets(dearest)
            if ring > self.ring:
                self.ring, self.links, self.race_links = ring, None, None
            kernels = self.kernels
            if not kernels.absorbing and may_absorb(self.rows * self.cols, dearest, self.cap):
                self.kernels = _kernels_for(0, kernels.neighbourhood, kernels.corner_cutting, True, True)
        if not self.lanes:
            self.unpainted.append((cells, penalties))
        else:
            self._paint_now(cells, penalties)
        self.woken = self.tick
        self._idle_sample, self.successors = None, {}
        if self.edits is not None:
            self.edits.append((cells, penalties))

    def _paint_now(self, cells: np.ndarray, penalties: np.ndarray) -> None:
        self.tiles_settled = False  # it wakes the tiles round the cells
        self.kernels.paint(src=self.src, dst=self.dst, pen=self.pen, stamps=self.stamps, keys=self.keys,
                           header=self.header, queue=self.queue, origins=self.origins, cells=cells,
                           penalties=penalties, cap=self.cap,
                           run=_launch(_PaintRun(self.tick + int(self.round_open), int(self.listed))))  # an open
        # round goes on

    def reset(self, tiles: bool = True) -> None:
        """The values back to the initial state of eqs. 5 and 10 (the other buffer follows lazily, :meth:`iterate`);
        only the tiles within the stencil's reach of the source are active (every other cell and its inputs hold the
        cap: it cannot change before a change reaches it). ``tiles=False`` leaves the tiles' stamps and keys as they
        are and the source to the search that must follow at once (:meth:`_Layers._search`: it sets the source, and
        its hand-over every stamp and key): three launches, 0.03 ms, fewer."""
        began = time.perf_counter()
        self.rebase()
        self.tick = _first_round(self.tick)
        if self.lanes:  # the other buffer follows before the next busy iteration (``iterate``)
            self.kernels.fill_values(values=self.src, value=self.cap)
        else:
            self.src.fill(self.cap)  # a memset: 0.38 ms on 1024², where a kernel took 5
        self.mirrored = self.listed = self.round_open = False  # no round is open after a reset
        if tiles:
            self.stamps.fill(-1)
            self.keys.fill(math.inf)
            self.woken_unkeyed = False
            self.kernels.seed(src=self.src, dst=self.dst, pen=self.pen, stamps=self.stamps, header=self.header,
                              tick=self.tick)
        self.woken = self.tick
        self.pending = False
        self.fresh = True
        self._idle_sample, self.successors, self.edits = None, {}, None
        if tiles:  # a whole reset's time prices a restart (``_fills``): the leaner one would price it below its cost
            self.reset_s = time.perf_counter() - began

    def sample(self, cells: np.ndarray, out: np.ndarray) -> None:
        """Every layer of this kind at ``cells`` into out[0]."""
        self.kernels.sample(values=self.values, origins=self.origins, cells=cells, out=out, cap=self.cap)

    def trace(self, index: int, start: tuple[int, int], max_steps: int) -> list[tuple[int, int]]:
        """Cells (grid coordinates) visited following the successors of layer ``index`` of this kind from ``start``
        for at most ``max_steps`` moves, ``start`` left out."""
        origin = self.grid_origins[index] - PAD  # grid coordinates of padded layer cell (0, 0)
        out = np.empty((max_steps + 1, 2), np.int32)  # row 0: the start, then the number of steps
        out[0] = start[0] - origin[0], start[1] - origin[1]
        self.kernels.trace(values=self.values, pen=self.pen, header=self.header, cap=self.cap, index=index, out=out)
        return list(map(tuple, (out[1:1 + out[0, 0]] + origin).tolist()))

    def warm_up(self) -> None:
        """Compile every kernel of this kind (:attr:`_Kernels.all`) by launching it on a scratch layer of one cell
        with idle arguments (:func:`_idle_argument`): nothing of this layer changes. Once per spec and process."""
        if self.kernels.warmed:
            return
        scratch = _LayerArrays(self.kernels, 1, (1, 1), np.zeros((max(self.lanes, 1), 2), np.int32), (PAD, PAD), 0.0)
        # the search's and the mend's arrays as Taichi ndarrays, as every later launch passes them (a numpy array
        # compiles another kernel: the first mend compiled for 1.6 s inside a planner's tick)
        scratch.links = ti.ndarray(ti.i32, (2, IDLE_ENTRIES))
        scratch.trail = ti.ndarray(ti.i32, (_TRAIL_ROWS, IDLE_ENTRIES))
        scratch.spare = scratch.dst
        scratch.race_links = ti.ndarray(ti.i32, (3, IDLE_ENTRIES))
        for kernel in self.kernels.all:
            kernel(**{parameter.name: _idle_argument(parameter, scratch)
                      for parameter in inspect.signature(kernel).parameters.values()})
        self.kernels.warmed = True

    def idle(self) -> bool:
        """Whether the next iteration has nothing to do: the last one changed nothing and the host has stamped no
        tile since (then both buffers hold the same values, and so would every later iteration's)."""
        return self.changed() == 0 and self.woken < self.tick

    def rebase(self) -> None:
        """Renumber iterations from 0 once they pass REBASE_AT: stamps of past iterations become -1 (inactive),
        later ones keep their distance to the next iteration."""
        if self.tick < REBASE_AT:
            return
        self.listed = False
        stamps = self.stamps.to_numpy()
        self.stamps.from_numpy(np.where(stamps >= self.tick, stamps - self.tick, -1).astype(np.int32))
        self.woken = max(self.woken - self.tick, -1)
        self.tick = 0

    def _count_iterations(self, iterations: int) -> None:
        """Account for ``iterations`` done: the buffers swap roles at each."""
        self.current ^= iterations % 2
        self.tick += iterations


class _Layers(_LayerArrays):
    """A kind of layer at work: its iterations and converges (from the initial state, a search; after edits, a
    repair; with limits or lanes, rounds of tiles) and the launch policy that decides which kernel runs them,
    serially or in parallel (``_waves``)."""

    def _waves(self, count: int, serial_tiles: int, serially, in_parallel) -> tuple[int, bool]:
        """The launch policy, decided here only (module docstring): up to ``count`` waves (iterations or settling
        rounds). While at most ``_serial_limit(serial_tiles)`` tiles are active they run one after another in one
        launch on the calling thread, ``serially(first, count, limit) -> (done, finished)``; a busier wave gets a
        parallel launch of its own, ``in_parallel(first) -> finished``. Stops early once finished; returns (done,
        finished)."""
        done, finished = 0, False
        while done < count and not finished:
            ran, finished = serially(done, count - done, _serial_limit(serial_tiles))
            done += ran
            if done < count and not finished:
                finished = in_parallel(done)
                done += 1
        return done, finished

    def iterate(self, k: int, cells: np.ndarray, out: np.ndarray) -> None:
        """k synchronous iterations over the active tiles, the layers sampled at ``cells`` into out[step] after
        each; header[CHANGED] then holds the cells the last iteration changed. A converge that left work pending
        is finished first (it may have left cells below the fixed point, which iterations lift only a step at a
        time). An idle layer kind (:meth:`idle`) launches no iteration: every step reads what it holds, sampled once
        and kept while it stays idle at the same ``cells`` (a launch cost 0.1-0.2 ms through Taichi's own call, most
        of an idle tick on nav2's warehouse map; 0.03 ms or more through :class:`_Launcher`)."""
        if self.pending:  # iterations start from a fixed point: a cell below its relaxation would rise slowly
            self.converge(None)
        self.successors, self.listed, self.fresh = {}, False, False  # iterations stamp tiles without lists
        if not self.mirrored:  # settling and resets write the values' buffer only
            self.dst.copy_from(self.src)
            self.mirrored = True
        if self.idle():
            key = cells.tobytes()
            if self._idle_sample is None or self._idle_sample[0] != key:
                self.sample(cells, out)
                self._idle_sample = (key, out[0, :, self.columns].copy())
            out[:k, :, self.columns] = self._idle_sample[1]
            self._count_iterations(k)
            return
        self._idle_sample = self.edits = None  # iterations leave the values between fixed points
        self.woken_unkeyed = True

        def serially(first: int, steps: int, limit: int) -> tuple[int, bool]:
            done = self.kernels.iterate_serially(**self._relaxing(), cells=cells, out=out,
                                                 run=_launch(_IterateRun(self.tick, first, steps, limit, self.woken)))
            self._count_iterations(done)
            return done, False

        def in_parallel(first: int) -> bool:
            self.kernels.iterate(**self._relaxing(), cells=cells, out=out,
                                 run=_launch(_StepRun(self.tick, first)))
            self._count_iterations(1)
            return False

        self._waves(k, SERIAL_TILES, serially, in_parallel)

    def _relaxing(self) -> dict:
        """The arrays and cap an iteration reads and writes."""
        return dict(src=self.src, dst=self.dst, pen=self.pen, stamps=self.stamps, header=self.header,
                    origins=self.origins, cap=self.cap)

    def converge(self, max_rounds: int | None, focus: tuple[int, int] | None = None, max_sweeps: int = 0) -> int:
        """From the current values to the fixed point (with ``focus``, padded layer coordinates, as far as the
        focus needs: :meth:`_settle`); returns the rounds or buckets it took. A scalar layer's converge with no
        limits searches from the initial state (:meth:`_search`) and repairs after edits (:meth:`_repair`); every
        other converge settles rounds of tiles (:meth:`_settle`)."""
        if not self._searching(max_rounds, max_sweeps):
            return self._settle(max_rounds, focus, max_sweeps)
        return self._search(focus) if self.fresh else self._repair(focus)

    def restart(self, max_rounds: int | None, focus: tuple[int, int] | None = None, max_sweeps: int = 0) -> int:
        """:meth:`reset`, then :meth:`converge`; a search (no limits, a scalar layer) follows its reset at once, which
        then fills the values only."""
        self.reset(tiles=not self._searching(max_rounds, max_sweeps))
        return self.converge(max_rounds, focus, max_sweeps)

    def _searching(self, max_rounds: int | None, max_sweeps: int) -> bool:
        """Whether converge() with these limits searches (a scalar layer's, unlimited), from the initial state."""
        return not (self.lanes or max_rounds is not None or max_sweeps)

    def _settle(self, max_rounds: int | None, focus: tuple[int, int] | None = None, max_sweeps: int = 0) -> int:
        """Repair: from the current values to the fixed point, in time that grows with the region the edits since
        the last converge affect. Returns the rounds done, at most ``max_rounds``.

        Cells outside the active tiles are at their relaxation (an invariant of iterating, settling and editing:
        only a change wakes a tile). A cell below its relaxation - it depended on a cell that became an obstacle, or
        on one lifted since - lies in a tile with a lifting key (``paint`` and the lifts give it): settling lifts
        such a tile first, its lanes below their relaxation jumping to the cap (the raise wave, as D* Lite's
        underconsistent states), and lowers it afterwards; every other active tile is lowered. Tiles go in the
        order of their keys, as delta-stepping's buckets, so the raise and lowering waves interleave as D* Lite's
        queue orders them. The fixed point of eqs. 5 and 10 is unique, so a converge that runs to the end reaches
        the same one as from the initial state, bit for bit. A small layer's converge is one launch
        (``settle_serially``). Settling works in place in the values' buffer; the other is made equal before the
        next iteration, if any (:meth:`iterate`), not here: a planner that only converges never pays for it.

        With ``focus`` (padded layer coordinates), the tiles go in order of key plus distance from the focus and
        the converge stops once no pending tile can change the focus's value or successor chain
        (``settle_serially``): the rest stays pending (:attr:`pending`), keys and all, lifting included, for the next
        converge. So does a converge cut short by ``max_rounds`` or, on the calling thread, by ``max_sweeps`` sweeps
        of tiles (0: no limit; the rest of the round waits for the next converge); :attr:`swept` counts the sweeps it
        made on the calling thread."""
        self._idle_sample, self.fresh, self.tiles_settled = None, False, False
        if self.woken_unkeyed:  # iterations since the keys were set: the tiles they woke keyed to lift, then lower
            self.kernels.rekey(stamps=self.stamps, keys=self.keys, tick=self.tick)
            self.woken_unkeyed = False
        limit = _NEVER if max_rounds is None else max_rounds
        state = {"focused": False, "cut": False, "move": None}
        self.swept = 0
        held = self._held_back()  # the edits held back, painted by the first launch on the calling thread
        arrays = dict(values=self.values, pen=self.pen, stamps=self.stamps, keys=self.keys, header=self.header,
                      cap=self.cap)
        aim = _NO_FOCUS if focus is None else focus

        def serially(done: int, rounds: int, serial_limit: int) -> tuple[int, bool]:
            nonlocal held
            run = _launch(_SettleRun(self.tick, rounds, serial_limit, *aim, max_sweeps, int(self.listed),
                                     int(self.round_open)), _SettleResult)
            if held:
                self.kernels.settle_painting(**arrays, queue=self.queue, origins=self.origins, cells=held[0],
                                             penalties=held[1], run=run)
                held = None
            else:
                self.kernels.settle_serially(**arrays, queue=self.queue, run=run)
            outcome = _outcome(_SettleResult, run)
            self.listed = True
            self.tick += outcome.rounds
            self.swept += outcome.swept
            state["focused"], state["cut"], state["move"] = bool(outcome.focused), bool(outcome.cut), outcome.move
            self.round_open = state["cut"]
            return outcome.rounds, bool(outcome.settled or outcome.focused or outcome.cut)

        def in_parallel(done: int) -> bool:
            state["move"] = None
            pending = self.kernels.settle(**arrays, tick=self.tick)
            self.tick += 1
            self.listed = self.round_open = False
            return pending == 0

        # A focused repair stays on the calling thread (on a CPU) however many tiles wait: most of them do not move
        # (the work that cannot reach the focus piles up), and a parallel round would settle them all.
        serial_tiles = self._serial_tiles() if focus is None else _NEVER
        rounds, finished = self._waves(limit, serial_tiles, serially, in_parallel)
        if held:  # no launch ran (``max_rounds`` 0)
            self._paint_now(*held)
        self.cut_short = state["cut"] or not finished
        move = state["move"]  # the focus's successor move as the last launch left it (None: a parallel round came last)
        self.successors = {} if focus is None or move is None or self.cut_short else {focus: move}
        self.mirrored = False
        if finished and not state["focused"] and not state["cut"]:
            self.deactivate_all()
            self.pending = False
        else:
            self.pending, self.woken = True, self.tick  # the active tiles wait for the next converge or iteration
        self.edits = None if self.pending else []
        self.converged_by = "rounds"
        return rounds

    def _search(self, focus: tuple[int, int] | None) -> int:
        """converge() from the initial state: the label-setting search of ``_search_rules`` (Dial's buckets, A*'s
        order and stop with a focus) takes each cell about once however the map winds, where rounds of tiles settle
        a tile again each time the front comes back to it (a maze's corridors). A focused search hands its frontier
        over to the settling rounds of later converges (:attr:`pending`). Returns the buckets emptied."""
        self._make_links()
        arrays = dict(values=self.values, pen=self.pen, stamps=self.stamps, keys=self.keys, header=self.header,
                      links=self.links, cap=self.cap)
        if self.restart_s is None:  # compiled (if not yet) by a launch that does nothing, so the time is the search's
            self.kernels.search(**arrays, run=_launch(_SearchRun(*_NO_FOCUS, self.tick, go=0), _SearchResult))
        began = time.perf_counter()
        run = _launch(_SearchRun(*(focus or _NO_FOCUS), self.tick, go=1), _SearchResult)
        self.kernels.search(**arrays, run=run)
        self.restart_s = time.perf_counter() - began
        outcome = _outcome(_SearchResult, run)
        if not outcome.frontier:
            self.searched = outcome.taken
        if not outcome.frontier and outcome.taken >= PRICED_SEARCH:
            self.cell_s = self.restart_s / outcome.taken
        self._searched(bool(outcome.frontier), "search")
        return outcome.buckets

    def _searched(self, frontier: bool, by: str) -> None:
        """The state after a search or a mend (``by``), which left a ``frontier`` (its tiles handed over) or none."""
        self.converged_by = by
        self.fresh = self.listed = self.round_open = self.cut_short = self.mirrored = self.woken_unkeyed = False
        self.swept = 0
        self.pending, self.woken = frontier, self.tick
        self._idle_sample, self.successors = None, {}
        self.edits = None if frontier else []
        self.tiles_settled = not frontier

    def _make_links(self) -> None:
        """The search's buckets (a cell's links, then the ring's heads), made at the first search or mend."""
        if self.links is None:
            self.links = ti.ndarray(ti.i32, (2, self.padded_cells + self.ring))
            self.links.fill(_UNLISTED)

    def _mend(self, focus: tuple[int, int] | None) -> int:
        """converge() after edits on a layer at its fixed point before them: the cells the edits cut off rise to
        the cap cell by cell, then Dial's search lowers them and whatever the edits opened from the seeds around
        them (``_raise_rules``, ``_lower_rules``), so the work follows the cells that
        change - a sealed pocket's cells are raised once each, a dearer subtree lowered once each - and a small edit
        is one launch. With a focus, A*'s order and stop, the frontier handed over as a focused search's. Edits
        whose cells alone would cost more than the mend may spend (EDIT_COST each) restart at once. A search from the
        source races the mend in a spare buffer; a mend that gives up - the race finished first, or the mend passed
        its budget - lets it run to its end in the same launch (:meth:`_restarted`: a goal sealed in costs its
        pocket's search and the mend's share beside it, in one launch where a restart took two more). A mend that
        finishes leaves the restart's price as it found it (MEND_SHARE): the cells its look counted, else at least
        those it lowered (a goal let out of a pocket reaches all it lowered, where the last search took the pocket).
        Returns the buckets emptied."""
        fills = self._fills()
        restart = max(self.padded_cells if self.searched is None else self.searched + fills, 1)
        budget = int(MEND_SHARE * restart)
        cells, penalties = _joined(self.edits)
        if len(cells) * EDIT_COST > budget:
            return self.restart(None, focus)  # its reset paints the edits held back
        self.unpainted = []  # the mend paints every edit since the fixed point (one painted already: again, as it is)
        self._make_links()
        if self.trail is None:
            self.trail = ti.ndarray(ti.i32, (_TRAIL_ROWS, self.padded_cells))
            self.trail.fill(0)
            self.spare = self._array(self._arrays.buffers[0].shape)
            self.spare.fill(self.cap)
        if self.race_links is None:  # made again when the ring widens, as the search's links
            self.race_links = ti.ndarray(ti.i32, (3, self.padded_cells + self.ring))
            self.race_links.fill(_UNLISTED)
        looks = min(budget, int(CUT_SHARE * fills))
        restart_tick = _first_round(self.tick)  # a restart in the launch starts where a reset would
        seed_pass = self.padded_cells // SEED_PASS  # a race from the kept cells: its pass, in cells a search takes
        run = _launch(_MendRun(*(focus or _NO_FOCUS), self.tick, restart_tick, budget, restart, fills, looks,
                               self.longest_move, RACE_LEAD, int(RACE_HEAD_SHARE * restart), SEED_AFTER * seed_pass,
                               seed_pass, int(self.tiles_settled), int(self.depth_first), go=1), _MendResult)
        self.kernels.mend(values=self.values, pen=self.pen, stamps=self.stamps, keys=self.keys, header=self.header,
                          links=self.links, trail=self.trail, cells=cells, penalties=penalties, cap=self.cap,
                          spare=self.spare, race_links=self.race_links, run=run)
        outcome = _outcome(_MendResult, run)
        if outcome.gave_up:  # most of the layer cut off or changed: the launch searched from the source instead
            return self._restarted(outcome, restart_tick)
        if outcome.seeded:  # the race that lost had copied the cells kept into the spare buffer
            self.spare.fill(self.cap)
        if not outcome.frontier and self.searched is not None:
            self.searched = outcome.reached if outcome.reached >= 0 else max(self.searched, outcome.lowered)
        self._searched(bool(outcome.frontier), "mend")
        return outcome.buckets

    def _restarted(self, outcome: "_MendResult", tick: int) -> int:
        """After a mend that gave up and let its race search from the source in the spare buffer, as :meth:`restart`
        would (its reset's ``tick``): that buffer holds the values from now on, and the one it replaces is filled
        with the cap to be the next spare (one fill, as the reset's). A restart's prices in time (``restart_s``,
        ``cell_s``) stay the last search launch's: this one's time is the mend's too. Returns the search's buckets."""
        buffers = self._arrays.buffers
        buffers[self.current], self.spare = self.spare, buffers[self.current]
        self.spare.fill(self.cap)
        self.tick = tick
        if not outcome.frontier:
            self.searched = outcome.lowered
        self._searched(bool(outcome.frontier), "search")
        return outcome.buckets

    def _fills(self) -> int:
        """A reset's price in cells a search takes: the last whole reset's time (:meth:`reset`) over a search's per
        cell (the last that took PRICED_SEARCH cells or more), at most one per FILLS_PER_CELL cells of the layer."""
        most = self.padded_cells // FILLS_PER_CELL
        if self.reset_s is None or self.cell_s is None:
            return most
        return min(most, int(self.reset_s / self.cell_s))

    def _repair(self, focus: tuple[int, int] | None) -> int:
        """converge() after edits: cell by cell (:meth:`_mend`) when the layer was at its fixed point before them,
        else rounds of tiles (:meth:`_settle`). Unfocused, in slices, given up for a restart
        (:meth:`reset`, then :meth:`_search`) once they have taken RESTART_SHARE of the time the last search took,
        as a ski rental buys once renting has cost a share of the price: a change that lifts most of a maze (a box
        sealing off a pocket whose every cell must rise to the cap, which a search never visits) costs at most about
        (1 + RESTART_SHARE) times a restart, and a small one a slice or two. The result is the fixed point either way. A
        focused repair (the exact planner's tick) runs in one launch: slices and restarts raised its 95th percentile
        on 100 x 100 worlds from 0.8 to 1.5 ms (launches, and resets priced below their cost), and a planner that
        must bound its tick has ``max_sweeps``."""
        if self.edits:
            return self._mend(focus)
        if self.restart_s is None or focus is not None:  # no search yet to price a restart, or a planner's tick
            return self._settle(None, focus)
        allowance_s, spent_s, rounds, swept = RESTART_SHARE * self.restart_s, 0.0, 0, 0
        sweeps = sweeps_fitting(allowance_s, SLOWEST_SWEEP_S, _FEWEST_SWEEPS, _NEVER)
        while True:
            began = time.perf_counter()
            rounds += self._settle(None, focus, sweeps)
            took_s = time.perf_counter() - began
            spent_s += took_s
            swept += self.swept
            if not self.cut_short:
                self.swept = swept
                return rounds
            if spent_s >= allowance_s:
                return rounds + self.restart(None, focus)
            sweeps = sweeps_fitting(allowance_s - spent_s, took_s / max(self.swept, 1), _FEWEST_SWEEPS,
                                    SLICE_GROWTH * sweeps)

    def _serial_tiles(self) -> int:
        """Active tiles up to which converge()'s work runs on the calling thread (before ``_serial_limit``)."""
        return SERIAL_TILES if self.lanes else SERIAL_SETTLE_TILES


def _fitting(shape: tuple[int, int]) -> tuple[int, int]:
    """A map's (rows, cols) if its layers fit the engine (``MAX_MAP_SIDE``), else a ValueError naming the shape."""
    rows, cols = shape
    if max(rows, cols) > MAX_MAP_SIDE:
        raise ValueError(f"a map may have at most {MAX_MAP_SIDE} cells a side, got {rows} x {cols}")
    return rows, cols


def _float32_cap(cap: float) -> float:
    """A layer's cap as its float32 values hold it: inf past float32's largest (which no distance reaches)."""
    return float(cap) if cap <= _FLOAT32_MAX else math.inf


def _cells_array(cells) -> np.ndarray:
    """(n, 2) int32, contiguous: how kernels take cells."""
    return np.ascontiguousarray(cells, np.int32).reshape(-1, 2)


def _joined(edits: list[tuple[np.ndarray, np.ndarray]]) -> tuple[np.ndarray, np.ndarray]:
    """Edits (cells, penalties), in order, as one launch's cells (``_cells_array``) and penalties: one edit as it
    is (each is made by ``_cells_array``)."""
    if len(edits) == 1:
        return edits[0]
    cells, penalties = (np.concatenate(parts) for parts in zip(*edits))
    return _cells_array(cells), penalties


def _checked_costs(current: np.ndarray | None, count: int, costs) -> np.ndarray:
    """``costs`` (a number or one per cell) as ``count`` float32 costs of a map whose costs are ``current``; a
    ValueError for a binary map or a cost that is not a number from 1 to MAX_COST."""
    if current is None:
        raise ValueError("set_costs needs a map with costs (tdp.GridMap(..., cost=...)); this one is binary")
    try:
        given = np.asarray(costs)
        if given.dtype.kind not in "iuf":  # numpy would read "2" and True as costs
            raise TypeError(given.dtype)
        costs = np.broadcast_to(given.astype(np.float64), (count,))
    except (TypeError, ValueError):  # text, bools, ragged lists, a count that does not broadcast
        raise ValueError(f"costs must be a number or one per cell ({count}), got {checks.shown(costs)}") from None
    wrong = ~((costs >= 1) & (costs <= MAX_COST))  # NaN is wrong too
    if wrong.any():
        raise ValueError(f"costs must be between 1 and {MAX_COST:g}, got {costs[wrong][0]}")
    return costs.astype(np.float32)


def _assigned(array: np.ndarray, cells: np.ndarray, values) -> tuple[np.ndarray, np.ndarray]:
    """Write ``values`` into the map-shaped ``array`` at ``cells`` (n, 2); return what it holds there now (of a cell
    listed twice, the value numpy's assignment kept) and where that differs from what it held before."""
    where = (cells[:, 0], cells[:, 1])
    before = array[where]
    array[where] = values
    now = array[where]
    return now, before != now


def _edit(cells, occupied) -> tuple[np.ndarray, bool | np.ndarray]:
    """Cells as kernels take them and their occupancy: one flag for them all (True or False), or one per cell."""
    cells = _cells_array(cells)
    if isinstance(occupied, (bool, np.bool_)):
        return cells, bool(occupied)
    return cells, checks.flags(occupied, len(cells), "occupied")


def _freed_when_dropped(array):
    """``array`` (a Taichi vector ndarray), its memory handed back to Taichi once Python drops it. Taichi 1.7 frees
    only scalar ndarrays (taichi-dev/taichi#8763): every engine with node layers leaked its windows, 660 MB per
    navigator on nav2's warehouse map, so a long sweep's worker grew until it ran out of memory."""
    def free(handle) -> None:
        program = _taichi_impl.get_runtime().prog
        if program is not None:
            program.delete_ndarray(handle)

    weakref.finalize(array, free, array.arr).atexit = False  # at exit the process hands everything back
    return array


def _device(array: np.ndarray):
    """A Taichi ndarray holding a copy of an int32 or float32 numpy array."""
    out = ti.ndarray(ti.i32 if array.dtype == np.int32 else ti.f32, array.shape)
    out.from_numpy(np.ascontiguousarray(array))
    return out


class Engine:
    """All layers of one DP: the goal layer (cap ``goal_cap``) and one windowed layer per node (cap ``node_cap``).

    Cells are ``(row, col)``; distances are in cells. ``occupied`` is a bool (H, W) array, True = obstacle.
    ``cost`` (None, or float32 (H, W), at least 1 on free cells: :class:`tdp.GridMap`'s) weights the goal layer's
    moves, L x (cost[u] + cost[v]) / 2; node layers measure connectivity and stay unweighted (ARCHITECTURE §4).
    Map edits and goal moves take effect at the next iteration; nothing is recompiled. Each iteration relaxes
    only the tiles whose inputs changed (ARCHITECTURE §7); :meth:`activate_all` forces a dense one.
    """

    def __init__(self, occupied: np.ndarray, goal: tuple[int, int], *, goal_cap: float = math.inf,
                 nodes: np.ndarray | None = None, node_cap: float = 0.0, neighbourhood: int = 16,
                 corner_cutting: bool = False, cost: np.ndarray | None = None):
        self.occupied = np.array(occupied, dtype=bool)
        self.cost = None if cost is None else np.array(cost, np.float32)  # a copy: set_costs changes it
        self.rows, self.cols = _fitting(self.occupied.shape)
        self.neighbourhood = stencil.check_neighbourhood(neighbourhood)
        self.corner_cutting = bool(corner_cutting)
        self.goal = (int(goal[0]), int(goal[1]))
        self.goal_cap = _float32_cap(goal_cap)
        self._moves = stencil.moves(self.neighbourhood, self.corner_cutting)  # the kernels' move order
        self._move_index = {(m.dr, m.dc): index for index, m in enumerate(self._moves)}
        self.node_cap = _float32_cap(node_cap)
        self.nodes = np.zeros((0, 2), np.int32) if nodes is None else np.asarray(nodes, np.int32).reshape(-1, 2)
        self.iterations = 0

        def kernels(lanes: int, weighted: bool = False, absorbing: bool = False) -> _Kernels:
            return _kernels_for(lanes, self.neighbourhood, self.corner_cutting, weighted, absorbing)

        max_cost = 1.0 if self.cost is None else float(self.cost[~self.occupied].max(initial=1.0))
        absorbing = may_absorb(self.rows * self.cols, max_cost, self.goal_cap)
        self._goal = _Layers(kernels(0, self.cost is not None, absorbing), 1, (self.rows, self.cols),
                             np.zeros((1, 2), np.int32), (self.goal[0] + PAD, self.goal[1] + PAD), self.goal_cap,
                             max_cost)
        self._goal.depth_first = depth_first_raise(self.occupied)
        self._layers = [self._goal]
        if len(self.nodes):
            # a window reaching past the map on every side holds what a larger one would: the map, walled round
            reach = max(self.rows, self.cols)
            self.radius = reach if self.node_cap > reach else int(math.ceil(self.node_cap))
            side = 2 * self.radius + 1
            groups = -(-len(self.nodes) // LANES)
            origins = np.full((groups * LANES, 2), _FAR, np.int32)
            origins[: len(self.nodes)] = self.nodes - self.radius
            centre = self.radius + PAD
            self._windows = _Layers(kernels(LANES), groups, (side, side), origins, (centre, centre), self.node_cap)
            self._layers.append(self._windows)
        grids: dict[bool, np.ndarray] = {}  # the padded penalties by whether a kind is weighted, each built once
        for layers in self._layers:
            weighted = layers.kernels.weighted
            if weighted not in grids:
                grids[weighted] = np.full((self.rows + 2 * PAD, self.cols + 2 * PAD), np.inf, np.float32)
                grids[weighted][PAD:-PAD, PAD:-PAD] = self._penalties(layers, self.occupied, slice(None))
            layers.gather_penalties(grids[weighted])
        self.reset()
        self._goal.reset()  # again: the first compiled its launches and touched its arrays first, and a whole reset's
        # time prices the goal layer's restarts (``_Layers._fills``)

    # -- state -------------------------------------------------------------------------------------------------
    def reset(self) -> None:
        """Back to the initial state of eqs. 5 and 10 (iteration 0)."""
        for layers in self._layers:
            layers.reset()
        self.iterations = 0
        self._goal_moved = False

    def activate_all(self) -> None:
        """Make the next iteration relax every tile (a dense iteration; the result is the same)."""
        for layers in self._layers:
            layers.activate_all()

    def warm_up(self) -> None:
        """Compile every kernel that iterations, map edits, goal moves and reads of this engine use, changing nothing.

        Taichi compiles a kernel on its first launch (about a second; later processes load it from Taichi's offline
        cache), and the parallel iteration is first launched when a large change arrives: warming up in the setup
        phase keeps that pause out of the control loop. :meth:`tdp.Navigator.setup` calls it."""
        for layers in self._layers:
            layers.warm_up()

    def step(self, k: int = 1) -> None:
        """Run k synchronous iterations of every layer (only their active tiles). Once an iteration changes
        nothing and no edit is pending, every later one would change nothing either: they are counted, not run, so
        any k returns at once on a settled field."""
        nowhere = np.zeros((0, 2), np.int32)
        while k > 0:
            if all(layers.idle() for layers in self._layers):
                self.iterations += k
                return
            chunk = min(k, _CHUNK)
            self._advance(chunk, nowhere)
            k -= chunk

    def changed(self) -> int:
        """Cells changed by the last iteration, all layers together."""
        return sum(layers.changed() for layers in self._layers)

    def converge(self, max_rounds: int | None = None, focus: tuple[int, int] | None = None,
                 max_sweeps: int = 0) -> int:
        """Relax from the current values to the fixed point of the current map and goal: the setup phase, and the
        exact repair after edits. Returns the rounds (or the goal layer's search buckets) it took, the larger count
        of the two kinds of layer; ``iterations`` is 0 after it.

        The goal layer is searched cell by cell from the initial state (construction, :meth:`reset`, a goal move:
        Dijkstra's order with buckets one cell wide, A*'s with a focus) and mended cell by cell after edits when it
        was at its fixed point before them (:meth:`_Layers._mend`). Otherwise, with ``max_rounds`` or
        ``max_sweeps``, and for node layers, rounds of tiles settle in place (delta-stepping buckets, alternating
        diagonal sweeps), an unlimited repair giving way to a restart past a share of a search's price
        (:meth:`_Layers._repair`); :meth:`converged_by` says which ran. The fixed point of eqs. 5 and 10 is unique,
        so the result equals synchronous iteration's from the initial state, bit for bit.

        ``focus``, a cell (row, col): a focused repair, as D* Lite's - the goal layer stops as soon as nothing
        pending can change the cell's value or the successors from it to the goal, the rest waiting
        (:meth:`pending`); node layers always converge fully. ``max_sweeps`` (0: no limit) stops the goal layer's
        settling on the calling thread after that many sweeps of an 8 x 8 tile, mid-round if need be
        (:meth:`cut_short`; :meth:`swept` counts them): the unit of an anytime repair's budget.
        """
        focused = None if focus is None else (int(focus[0]) + PAD, int(focus[1]) + PAD)
        max_rounds = None if max_rounds is None else min(max_rounds, _NEVER)  # more than any converge takes
        max_sweeps = min(max_sweeps, _NEVER)
        goal = self._goal.restart if self._goal_moved else self._goal.converge
        self._goal_moved = False
        rounds = max([goal(max_rounds, focused, max_sweeps)] + [layers.converge(max_rounds)
                                                                 for layers in self._layers[1:]])
        self.iterations = 0
        return rounds

    def pending(self) -> bool:
        """Whether the last :meth:`converge` left work pending (it stopped at its focus, or at ``max_rounds``): the
        values are then exact only where the focus said."""
        return any(layers.pending for layers in self._layers)

    def cut_short(self) -> bool:
        """Whether the last :meth:`converge` stopped at ``max_rounds`` or ``max_sweeps`` (before its end)."""
        return any(layers.cut_short for layers in self._layers)

    def swept(self) -> int:
        """Sweeps of 8 x 8 goal-layer tiles the last :meth:`converge` made on the calling thread."""
        return self._goal.swept

    def converged_by(self) -> str:
        """How the goal layer's last :meth:`converge` went: "search", "mend" (cell by cell) or "rounds" (of tiles)."""
        return self._goal.converged_by

    def focus_successor(self, focus: tuple[int, int]) -> tuple[int, int] | None:
        """The goal layer's successor at ``focus``, read once since anything last changed the values: by the last
        converge's last launch, when that converge was focused there; else traced now, ROUTE_AHEAD moves on from
        ``focus`` (a trace is a launch: 0.03 ms, where a robot stepping along its route then reads the next cells'
        successors in microseconds). None at the goal or where no move leads down."""
        padded = (focus[0] + PAD, focus[1] + PAD)
        known = self._goal.successors
        if padded not in known:
            self._trace_ahead(focus, known)
        move = known[padded]
        if move < 0:
            return None
        m = self._moves[move]
        return focus[0] + m.dr, focus[1] + m.dc

    def _trace_ahead(self, start: tuple[int, int], known: dict[tuple[int, int], int]) -> None:
        """Add the goal layer's successor moves along the route from ``start`` (ROUTE_AHEAD moves at most) to
        ``known`` (padded cell -> move index; -1 where the route ends: the goal, or no move leads down), emptied
        first once it holds SUCCESSORS_KEPT."""
        if len(known) >= SUCCESSORS_KEPT:
            known.clear()
        route = [start, *self.trace(0, start, ROUTE_AHEAD)]
        for (r, c), (u, v) in zip(route, route[1:]):
            known[r + PAD, c + PAD] = self._move_index[u - r, v - c]
        if len(route) <= ROUTE_AHEAD:
            known[route[-1][0] + PAD, route[-1][1] + PAD] = -1

    # -- edits -------------------------------------------------------------------------------------------------
    def set_cells(self, cells: np.ndarray, occupied: bool | np.ndarray) -> int:
        """Mark ``cells`` (n, 2) as occupied or free (one bool for them all, or one per cell; a cell listed twice
        takes the state :attr:`occupied` ends with); of those, only the cells whose state changes are sent to the
        kernels (a sensor's window sent again each tick costs its changes, not its size; a node layer's cell held
        occupied by :meth:`set_node_cells` stays so while the map's cell stays free). A freed cell costs what the
        map's ``cost`` says. Returns the number of cells listed whose state changed."""
        cells, occupied = _edit(cells, occupied)
        now, changed = _assigned(self.occupied, cells, occupied)
        self._paint(self._layers, cells[changed], now[changed])
        return int(np.count_nonzero(changed))

    def set_costs(self, cells: np.ndarray, costs) -> int:
        """Set the traversal cost of ``cells`` (n, 2) to ``costs`` (a number or one per cell, 1 to MAX_COST) on a
        map with costs (an occupied cell keeps it for when it is freed; a cell listed twice takes the cost
        :attr:`cost` ends with); the goal layer repairs as after an edit, for the free cells whose cost changed.
        Returns their number.

        Raises:
            ValueError: the engine was built without costs, or a cost is not a number from 1 to MAX_COST.
        """
        cells = _cells_array(cells)
        now, changed = _assigned(self.cost, cells, _checked_costs(self.cost, len(cells), costs))
        repriced = changed & ~self.occupied[cells[:, 0], cells[:, 1]]
        self._goal.reprice(cells[repriced], now[repriced])
        return int(np.count_nonzero(repriced))

    def set_node_cells(self, cells: np.ndarray, occupied: np.ndarray) -> None:
        """Mark ``cells`` occupied or free in the node layers only (e.g. cells a box is predicted to enter); the goal
        layer and :attr:`occupied` keep the map as it is."""
        self._paint(self._layers[1:], *_edit(cells, occupied))

    def _paint(self, kinds: list, cells: np.ndarray, occupied: np.ndarray) -> None:
        if not len(cells):
            return
        for layers in kinds:
            layers.paint(cells, self._penalties(layers, occupied, (cells[:, 0], cells[:, 1])))

    def _penalties(self, layers: "_Layers", occupied: bool | np.ndarray, where) -> np.ndarray:
        """The penalties (float32, as the costs are) of the cells ``where`` selects (an index into the map) for a kind
        of layer, whose occupancy is ``occupied`` (one flag for them all, or one per cell): inf blocked; free 0, or
        the cell's cost for the weighted goal layer. One numpy call where it can: right after a converge each costs
        2-30 µs (caches cold)."""
        if occupied is True:
            return np.full(len(where[0]), _BLOCKED)
        if occupied is False:
            return self.cost[where] if layers.kernels.weighted else np.full(len(where[0]), _FREE)
        return np.where(occupied, _BLOCKED, self.cost[where] if layers.kernels.weighted else _FREE)

    def set_goal(self, goal: tuple[int, int]) -> None:
        """Move the goal layer's source; the values propagate from it from the next iteration on."""
        moved = np.array([self.goal, goal], np.int32)
        self.goal = (int(goal[0]), int(goal[1]))
        self._goal.move_source((self.goal[0] + PAD, self.goal[1] + PAD))
        self._goal.activate_cells(moved)
        self._goal_moved = True

    # -- reading -----------------------------------------------------------------------------------------------
    def goal_distances(self) -> np.ndarray:
        """The goal layer as a float32 (H, W) array."""
        return self._goal.values.to_numpy()[0, PAD:-PAD, PAD:-PAD]

    def node_distances(self, node: int) -> np.ndarray:
        """Node layer ``node`` on the full grid (H, W): its window, the cap outside it."""
        self._check_node(node)
        g, lane = divmod(node, LANES)
        window = self._windows.values.to_numpy()[g, PAD:-PAD, PAD:-PAD, lane]
        full = np.full((self.rows + 2 * self.radius, self.cols + 2 * self.radius), self.node_cap, np.float32)
        r, c = self.nodes[node]
        full[r:r + window.shape[0], c:c + window.shape[1]] = window
        return full[self.radius:self.radius + self.rows, self.radius:self.radius + self.cols]

    def sample(self, cells: np.ndarray) -> np.ndarray:
        """Every layer at each of ``cells`` (n, 2): a float32 (n, 1 + nodes) array, column 0 the goal layer."""
        cells = _cells_array(cells)
        out = np.empty((1, len(cells), 1 + len(self.nodes)), np.float32)
        for layers in self._layers:
            layers.sample(cells, out)
        return out[0]

    def advance(self, k: int, cells: np.ndarray) -> np.ndarray:
        """Run k synchronous iterations of every layer and return every layer at ``cells`` after each: a float32
        (k, n, 1 + nodes) array (as :meth:`sample` after each :meth:`step`), in one kernel launch per kind of
        layer while few tiles are active, and none for a kind with nothing to iterate that was sampled at the same
        ``cells`` before (pass the same cells from tick to tick to benefit)."""
        return self._advance(k, _cells_array(cells))

    def _advance(self, k: int, cells: np.ndarray) -> np.ndarray:
        out = np.empty((k, len(cells), 1 + len(self.nodes)), np.float32)
        for layers in self._layers:
            layers.rebase()
            layers.iterate(k, cells, out)
        self.iterations += k
        return out

    def trace(self, layer: int, start: tuple[int, int], max_steps: int) -> list[tuple[int, int]]:
        """Cells visited by following the successors of ``layer`` (0 = goal, 1 + j = node j) from ``start``.

        Stops at the layer's source, at a cell with no successor, or after ``max_steps`` moves (an integer; none
        when it is 0 or less); ``start`` itself is not included.
        """
        max_steps = min(checks.integer(max_steps, "steps"), self.rows * self.cols)  # no route has more moves
        if max_steps <= 0:
            return []
        if layer == 0:
            return self._goal.trace(0, start, max_steps)
        self._check_node(layer - 1)
        return self._windows.trace(layer - 1, start, max_steps)

    def _check_node(self, node: int) -> None:
        if not 0 <= node < len(self.nodes):
            raise ValueError(f"node index must be in [0, {len(self.nodes)}), got {node}")
