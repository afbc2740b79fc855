"""Taichi fields and kernels of the DP: every layer relaxed in parallel, on CPU threads or a GPU (eqs. 5-7, 10-12).

The only module of tdp that imports taichi. Layout (ARCHITECTURE §4):

* the goal layer is one (H + 4) x (W + 4) float32 array, two cells of padding on each side;
* node layers are windows of side 2r + 1 around their nodes, r = ceil(cap); ``LANES`` of them are packed per cell
  as a ``ti.types.vector`` so that one relaxation updates them all with SIMD (Taichi keeps them as LLVM vectors,
  ``real_matrix_scalarize=False``, which the JIT lowers to the host's widest registers). Group g, lane l is node
  g*LANES + l; unused lanes are walled in and stay at the cap;
* an obstacle holds the cap (eq. 5), written into both buffers the moment a cell becomes occupied, so a move
  into it yields at least the cap and never wins the minimum; the cells a move crosses are checked in a penalty
  array of the same shape as each layer (0 free, inf blocked, padding blocked): a move's candidate is
  ``D[Z] + |V - Z| + pen[crossed cells]``.

Iterations: each kind of layer (goal, node windows) is split into 8 x 8 tiles, relaxed only when active (their
inputs changed in the previous iteration). While few tiles are active, k iterations run one after another in a
single launch on the calling thread; a busy iteration gets a parallel launch of its own.

All kernels take ndarrays, so a kernel compiles once per (neighbourhood, corner rule, layer kind) and not once per
map. Kernels must live in a ``.py`` file: Taichi reads their source.
"""
import contextlib
import io
import logging
import math
import os

os.environ.setdefault("ENABLE_TAICHI_HEADER_PRINT", "0")  # a library's stdout belongs to its user: no banner

import numpy as np  # noqa: E402
import taichi as ti  # noqa: E402

from . import stencil

#: Node layers packed per cell: 32 float32, two AVX-512 registers (measured faster than 16 and 64 at 1024²).
LANES = 32
#: Padding around every array: the stencil's reach, so kernels never test bounds.
PAD = stencil.REACH
#: Active tiles of one kind of layer up to which iterations run one after another on the calling thread, in one
#: launch; beyond, each iteration is a parallel launch. Measured on the 2-core VM: waking the worker threads costs
#: about 55 µs a launch, and one thread relaxes a dense layer of up to about 1000 tiles as fast as two.
SERIAL_TILES = 512
#: Side of an active tile, in cells: a tile is relaxed only when its inputs changed in the previous iteration.
TILE = 8
_FAR = -(1 << 28)  # origin of an unused lane: its window lies far outside every map
_NEVER = 1 << 30  # an iteration number no tile is ever stamped for
#: Iterations handed to one launch at most (kernel arguments are 32-bit).
_CHUNK = 1 << 20
#: A layer's iteration number past which its stamps are rebased to 0, so that it never reaches _NEVER (2**30).
REBASE_AT = 1 << 29

_initialised = False
_on_cpu = True


def init_taichi() -> None:
    """Initialise Taichi once per process: ``TDP_ARCH`` (default cpu) and ``TDP_THREADS`` (default 2).

    Packed layers stay LLVM vectors (``real_matrix_scalarize=False``: Taichi's CPU optimiser otherwise targets
    generic x86-64, 4 floats wide); parallel loops hand out 32 iterations at a time (the adaptive block size gives
    at least 512, so a small map's tiles all went to one thread)."""
    global _initialised, _on_cpu
    if _initialised:
        return
    arch_name = os.environ.get("TDP_ARCH", "cpu")
    arch = getattr(ti, arch_name, None)
    if arch is None:
        raise ValueError(f"TDP_ARCH must name a Taichi arch such as cpu or cuda, got {arch_name!r}")
    threads = os.environ.get("TDP_THREADS", "2")
    if not threads.isdigit() or int(threads) < 1:
        raise ValueError(f"TDP_THREADS must be a positive integer, got {threads!r}")
    with contextlib.redirect_stdout(io.StringIO()) as said:  # ti.init prints "Starting on arch=..."
        ti.init(arch=arch, cpu_max_num_threads=int(threads), default_fp=ti.f32, log_level=ti.WARN,
                real_matrix_scalarize=False, cpu_block_dim_adaptive=False)
    logging.getLogger(__name__).debug(said.getvalue().strip())
    _initialised = True
    _on_cpu = arch == ti.cpu


def _serial_limit() -> int:
    """SERIAL_TILES on the CPU; on a GPU one thread is far slower than a launch, so every busy iteration is
    parallel there."""
    return SERIAL_TILES if _on_cpu else 0


# --------------------------------------------------------------------------------------------------- helpers (ti.func)
@ti.func
def _broadcast(value, lanes: ti.template()):
    """``value`` as a scalar (lanes == 0) or as a vector of ``lanes`` copies."""
    if ti.static(lanes == 0):
        return value
    else:
        return ti.Vector.zero(ti.f32, lanes) + value


@ti.func
def _lane(value, lane, lanes: ti.template()):
    """Component ``lane`` (a runtime index) of a packed value (the value itself for a scalar layer)."""
    out = 0.0
    if ti.static(lanes == 0):
        out = value
    else:
        out = value[lane]
    return out


@ti.func
def _differs(a, b, lanes: ti.template()):
    """1 if any lane of a differs from b. (Taichi 1.7's ``.any()`` of a vector comparison reads only lane 0 when
    matrices are not scalarised: the comparison is selected into integers first.)"""
    result = 0
    if ti.static(lanes == 0):
        result = ti.i32(a != b)
    else:
        result = ti.select(a != b, 1, 0).max()
    return result


@ti.func
def _best_candidate(src: ti.template(), pen: ti.template(), g, i, j, cap, lanes: ti.template(),
                    neighbourhood: ti.template(), corner_cutting: ti.template()):
    """min(cap, min over allowed moves of D[Z] + |V - Z|): the last case of eqs. 5 and 10. The minimum is a
    select: ``ti.min`` lowers to LLVM's NaN-aware minnum (a compare and a blend more per move), and no value here
    is NaN (the sums are finite or +inf)."""
    best = _broadcast(cap, lanes)
    for m in ti.static(stencil.moves(neighbourhood, corner_cutting)):
        cand = src[g, i + m.dr, j + m.dc] + ti.f32(m.cost)
        for c in ti.static(m.crossed):
            cand += pen[g, i + c[0], j + c[1]]
        best = ti.select(cand < best, cand, best)
    return best


@ti.func
def _updated(src: ti.template(), pen: ti.template(), g, i, j, sr, sc, cap, lanes: ti.template(),
             neighbourhood: ti.template(), corner_cutting: ti.template()):
    """The new value of cell (i, j) (padded coordinates): eqs. 5 and 10, obstacles before the source."""
    blocked = pen[g, i, j] > 0
    value = _best_candidate(src, pen, g, i, j, cap, lanes, neighbourhood, corner_cutting)
    if i == sr and j == sc:
        value = _broadcast(0.0, lanes)
    return ti.select(blocked, _broadcast(cap, lanes), value)


# ----------------------------------------------------------------------------------------------------------- kernels
@ti.func
def _relax_tile(src: ti.template(), dst: ti.template(), pen: ti.template(), stamps: ti.template(), g, ta, tb, tick,
                counts: ti.template(), sr, sc, cap, lanes: ti.template(), neighbourhood: ti.template(),
                corner_cutting: ti.template()):
    """One synchronous (Jacobi) iteration src -> dst of tile (g, ta, tb), if active (stamp >= ``tick``).

    A changed cell stamps its tile, and the neighbouring tiles within the stencil's reach, ``tick + 1``: only
    they can change at the next iteration. Inactive tiles hold equal values in both buffers, so skipping them is
    exact. The changed cells are added to ``counts[0]``.
    """
    if stamps[g, ta, tb] >= tick:
        rows, cols = src.shape[1] - 2 * PAD, src.shape[2] - 2 * PAD
        changed = 0
        for u, v in ti.ndrange(TILE, TILE):
            r, c = ta * TILE + u, tb * TILE + v
            if r < rows and c < cols:
                new = _updated(src, pen, g, r + PAD, c + PAD, sr, sc, cap, lanes, neighbourhood, corner_cutting)
                if _differs(new, src[g, r + PAD, c + PAD], lanes):
                    changed += 1
                    _stamp_around(stamps, g, ta, tb, u, v, tick + 1)
                dst[g, r + PAD, c + PAD] = new
        if changed:
            ti.atomic_add(counts[0], changed)


@ti.func
def _relax_kind(src: ti.template(), dst: ti.template(), pen: ti.template(), stamps: ti.template(), tick,
                counts: ti.template(), sr, sc, cap, lanes: ti.template(), neighbourhood: ti.template(),
                corner_cutting: ti.template(), serial: ti.template()):
    """One iteration of the active tiles of one kind of layer (see :func:`_relax_tile`): a parallel loop at a
    kernel's top level, ``serial`` loops inside a loop."""
    counts[0] = 0
    if ti.static(serial):  # nested loops: no division per tile (an ndrange scan is 10x slower)
        for g in range(stamps.shape[0]):
            for ta in range(stamps.shape[1]):
                for tb in range(stamps.shape[2]):
                    _relax_tile(src, dst, pen, stamps, g, ta, tb, tick, counts, sr, sc, cap, lanes, neighbourhood,
                                corner_cutting)
    else:
        for g, ta, tb in stamps:
            _relax_tile(src, dst, pen, stamps, g, ta, tb, tick, counts, sr, sc, cap, lanes, neighbourhood,
                        corner_cutting)


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


@ti.kernel
def _iterate(src: ti.types.ndarray(ndim=3), dst: ti.types.ndarray(ndim=3), pen: ti.types.ndarray(ndim=3),
             stamps: ti.types.ndarray(ndim=3), tick: ti.i32, counts: ti.types.ndarray(ndim=1), sr: ti.i32,
             sc: ti.i32, cap: ti.f32, origins: ti.types.ndarray(ndim=2), cells: ti.types.ndarray(ndim=2),
             out: ti.types.ndarray(ndim=3), step: ti.i32, lanes: ti.template(), neighbourhood: ti.template(),
             corner_cutting: ti.template()):
    """One iteration src -> dst of the active tiles of one kind of layer, the tiles shared out among the threads;
    then the layers sampled at ``cells`` into out[step] (see :func:`_sample_kind`)."""
    _relax_kind(src, dst, pen, stamps, tick, counts, sr, sc, cap, lanes, neighbourhood, corner_cutting, False)
    _sample_kind(dst, origins, cells, cap, out, step, lanes)


@ti.kernel
def _iterate_serially(a: ti.types.ndarray(ndim=3), b: ti.types.ndarray(ndim=3), pen: ti.types.ndarray(ndim=3),
                      stamps: ti.types.ndarray(ndim=3), tick: ti.i32, counts: ti.types.ndarray(ndim=1), sr: ti.i32,
                      sc: ti.i32, cap: ti.f32, origins: ti.types.ndarray(ndim=2), cells: ti.types.ndarray(ndim=2),
                      out: ti.types.ndarray(ndim=3), first: ti.i32, steps: ti.i32, limit: ti.i32, woken: ti.i32,
                      lanes: ti.template(), neighbourhood: ti.template(), corner_cutting: ti.template()) -> ti.i32:
    """Up to ``steps`` iterations of one kind of layer on the calling thread, each sampled into out[first + step],
    for as long as at most ``limit`` tiles are active: below that, waking the worker threads costs more than they
    save. ``a`` holds the values and ``b`` receives the next ones; they swap at each iteration. Returns the
    iterations done.

    An iteration is idle, and skipped, when the previous one changed nothing (counts[0] == 0) and the host has
    stamped no tile for it or later (``woken``, the latest iteration it stamped for, is earlier): then no tile is
    active and both buffers hold the same values."""
    done = 0
    while done < steps:
        busy = counts[0] > 0 or woken >= tick + done
        if busy:
            if _active_tiles(stamps, tick + done) > limit:
                break
        if done % 2 == 0:
            if busy:
                _relax_kind(a, b, pen, stamps, tick + done, counts, sr, sc, cap, lanes, neighbourhood, corner_cutting,
                            True)
            _sample_kind(b, origins, cells, cap, out, first + done, lanes)
        else:
            if busy:
                _relax_kind(b, a, pen, stamps, tick + done, counts, sr, sc, cap, lanes, neighbourhood, corner_cutting,
                            True)
            _sample_kind(a, origins, cells, cap, out, first + done, lanes)
        done += 1
    return done


@ti.func
def _stamp_around(stamps: ti.template(), g, ta, tb, u, v, value):
    """Stamp tile (ta, tb) and the neighbours that cell (u, v) of it reaches with the stencil."""
    for da in ti.static(range(-1, 2)):
        for db in ti.static(range(-1, 2)):
            near_a = da == 0 or (da < 0 and u < PAD) or (da > 0 and u >= TILE - PAD)
            near_b = db == 0 or (db < 0 and v < PAD) or (db > 0 and v >= TILE - PAD)
            a, b = ta + da, tb + db
            if near_a and near_b and 0 <= a < stamps.shape[1] and 0 <= b < stamps.shape[2]:
                stamps[g, a, b] = value


@ti.kernel
def _stamp_cells(stamps: ti.types.ndarray(ndim=3), cells: ti.types.ndarray(ndim=2),
                 origins: ti.types.ndarray(ndim=2), lanes: ti.template(), rows: ti.i32, cols: ti.i32, tick: ti.i32):
    """Activate for iteration ``tick`` the tiles that have one of ``cells`` (grid coordinates) within reach.

    ``origins`` (one per lane) maps grid to layer coordinates; a layer of rows x cols cells sees a cell up to PAD
    outside it.
    """
    for k, g in ti.ndrange(cells.shape[0], stamps.shape[0]):
        for lane in range(max(lanes, 1)):
            a = cells[k, 0] - origins[g * max(lanes, 1) + lane, 0]
            b = cells[k, 1] - origins[g * max(lanes, 1) + lane, 1]
            if -PAD <= a < rows + PAD and -PAD <= b < cols + PAD:
                for da in ti.static(range(-PAD, PAD + 1, PAD)):
                    for db in ti.static(range(-PAD, PAD + 1, PAD)):
                        ta, tb = (a + da) // TILE, (b + db) // TILE
                        if 0 <= ta < stamps.shape[1] and 0 <= tb < stamps.shape[2]:
                            stamps[g, ta, tb] = ti.max(stamps[g, ta, tb], tick)


@ti.func
def _settle_tile(arr: ti.template(), pen: ti.template(), stamps: ti.template(), g, ta, tb, tick, sr, sc, cap,
                 lanes: ti.template(), neighbourhood: ti.template(), corner_cutting: ti.template()):
    """Asynchronous relaxation in place of tile (g, ta, tb), if active (stamp >= ``tick``): sweep its cells,
    alternately forwards and backwards, until they stop changing (in cache), stamping ``tick + 1`` on the
    neighbouring tiles that its changed border cells reach. Returns 1 if the tile changed.

    From the initial caps values only fall and every value read is the length of some path to the source, so
    races between threads are benign and the tiles settle to the unique fixed point of eqs. 5 and 10.
    """
    touched = 0
    if stamps[g, ta, tb] >= tick:
        rows, cols = arr.shape[1] - 2 * PAD, arr.shape[2] - 2 * PAD
        passes, changed_here = 0, 1
        while changed_here and passes < 4 * TILE:
            changed_here = 0
            for k in range(TILE * TILE):
                kk = k if passes % 2 == 0 else TILE * TILE - 1 - k
                u, v = kk // TILE, kk % TILE
                r, c = ta * TILE + u, tb * TILE + v
                if r < rows and c < cols:
                    new = _updated(arr, pen, g, r + PAD, c + PAD, sr, sc, cap, lanes, neighbourhood, corner_cutting)
                    if _differs(new, arr[g, r + PAD, c + PAD], lanes):
                        arr[g, r + PAD, c + PAD] = new
                        changed_here = 1
                        if u < PAD or u >= TILE - PAD or v < PAD or v >= TILE - PAD:
                            _stamp_around(stamps, g, ta, tb, u, v, tick + 1)
            passes += 1
        if passes > 1:
            touched = 1
        if changed_here:
            stamps[g, ta, tb] = tick + 1
    return touched


@ti.func
def _settle_kind(arr: ti.template(), pen: ti.template(), stamps: ti.template(), tick, sr, sc, cap,
                 lanes: ti.template(), neighbourhood: ti.template(), corner_cutting: ti.template(),
                 serial: ti.template()):
    """One round of :func:`_settle_tile` over every tile of one kind of layer: a parallel loop at a kernel's top
    level, ``serial`` loops inside a loop. Returns the number of tiles that changed."""
    touched = 0
    if ti.static(serial):
        for g in range(stamps.shape[0]):
            for ta in range(stamps.shape[1]):
                for tb in range(stamps.shape[2]):
                    touched += _settle_tile(arr, pen, stamps, g, ta, tb, tick, sr, sc, cap, lanes, neighbourhood,
                                            corner_cutting)
    else:
        for g, ta, tb in stamps:
            touched += _settle_tile(arr, pen, stamps, g, ta, tb, tick, sr, sc, cap, lanes, neighbourhood,
                                    corner_cutting)
    return touched


@ti.kernel
def _settle(arr: ti.types.ndarray(ndim=3), pen: ti.types.ndarray(ndim=3), stamps: ti.types.ndarray(ndim=3),
            tick: ti.i32, sr: ti.i32, sc: ti.i32, cap: ti.f32, lanes: ti.template(), neighbourhood: ti.template(),
            corner_cutting: ti.template()) -> ti.i32:
    """One round of settling, the tiles shared out among the threads; returns the number of tiles that changed."""
    return _settle_kind(arr, pen, stamps, tick, sr, sc, cap, lanes, neighbourhood, corner_cutting, False)


@ti.kernel
def _settle_serially(arr: ti.types.ndarray(ndim=3), pen: ti.types.ndarray(ndim=3), stamps: ti.types.ndarray(ndim=3),
                     tick: ti.i32, sr: ti.i32, sc: ti.i32, cap: ti.f32, rounds: ti.i32, limit: ti.i32,
                     result: ti.types.ndarray(ndim=1), lanes: ti.template(), neighbourhood: ti.template(),
                     corner_cutting: ti.template()):
    """Up to ``rounds`` rounds of settling on the calling thread, until one changes no tile or more than ``limit``
    tiles are active. result[0] = the rounds done, result[1] = the tiles the last of them changed (0: settled)."""
    done, touched = 0, 1
    while done < rounds and touched > 0:
        if _active_tiles(stamps, tick + done) > limit:
            break
        touched = _settle_kind(arr, pen, stamps, tick + done, sr, sc, cap, lanes, neighbourhood, corner_cutting,
                               True)
        done += 1
    result[0] = done
    result[1] = touched


@ti.kernel
def _reset(arr: ti.types.ndarray(ndim=3), pen: ti.types.ndarray(ndim=3), sr: ti.i32, sc: ti.i32, cap: ti.f32,
           lanes: ti.template()):
    """The initial state of eqs. 5 and 10: 0 at a free source, the cap everywhere else."""
    for g, i, j in arr:
        value = _broadcast(cap, lanes)
        if i == sr and j == sc:
            value = ti.select(pen[g, i, j] > 0, value, _broadcast(0.0, lanes))
        arr[g, i, j] = value


@ti.kernel
def _gather_window_pen(grid_pen: ti.types.ndarray(ndim=3), window_pen: ti.types.ndarray(ndim=3),
                       origins: ti.types.ndarray(ndim=2), lanes: ti.template()):
    """Fill each node window's penalties from the grid's (inf outside the grid and in the window's padding)."""
    rows, cols = grid_pen.shape[1] - 2 * PAD, grid_pen.shape[2] - 2 * PAD
    side = window_pen.shape[1] - 2 * PAD
    for g, i, j in window_pen:
        value = _broadcast(ti.math.inf, lanes)
        for k in ti.static(range(lanes)):
            r = origins[g * lanes + k, 0] + i - PAD
            c = origins[g * lanes + k, 1] + j - PAD
            inside = PAD <= i < side + PAD and PAD <= j < side + PAD and 0 <= r < rows and 0 <= c < cols
            if inside:
                value[k] = grid_pen[0, r + PAD, c + PAD]
        window_pen[g, i, j] = value


@ti.func
def _store(arr: ti.template(), g, i, j, lane, value, lanes: ti.template()):
    """Write ``value`` into component ``lane`` of arr[g, i, j] (the whole cell for a scalar layer), storing only
    that component: other lanes of the cell may be written by other threads at the same time."""
    if ti.static(lanes == 0):
        arr[g, i, j] = value
    else:
        arr[g, i, j][lane] = value


@ti.kernel
def _paint(pen: ti.types.ndarray(ndim=3), buffer_a: ti.types.ndarray(ndim=3), buffer_b: ti.types.ndarray(ndim=3),
           origins: ti.types.ndarray(ndim=2), cells: ti.types.ndarray(ndim=2), values: ti.types.ndarray(ndim=1),
           cap: ti.f32, lanes: ti.template(), rows: ti.i32, cols: ti.i32):
    """Write changed cells' penalties into every layer that contains them (``origins``, one per lane, maps grid to
    layer coordinates of a rows x cols layer); a newly occupied cell takes its obstacle value, the cap, at once."""
    for k, g in ti.ndrange(cells.shape[0], pen.shape[0]):
        for lane in range(max(lanes, 1)):
            a = cells[k, 0] - origins[g * max(lanes, 1) + lane, 0]
            b = cells[k, 1] - origins[g * max(lanes, 1) + lane, 1]
            if 0 <= a < rows and 0 <= b < cols:
                _store(pen, g, a + PAD, b + PAD, lane, values[k], lanes)
                if values[k] > 0:
                    _store(buffer_a, g, a + PAD, b + PAD, lane, cap, lanes)
                    _store(buffer_b, g, a + PAD, b + PAD, lane, cap, lanes)


@ti.func
def _successor_move(arr: ti.template(), pen: ti.template(), g, lane, i, j, sr, sc, cap, lanes: ti.template(),
                    neighbourhood: ti.template(), corner_cutting: ti.template()):
    """Index of the argmin move from (i, j) (eqs. 7 and 12), first in tie order; -1 at the source or at the cap."""
    best = cap
    found = -1
    index = 0
    for m in ti.static(stencil.moves(neighbourhood, corner_cutting)):
        cand = _lane(arr[g, i + m.dr, j + m.dc] + ti.f32(m.cost), lane, lanes)
        for c in ti.static(m.crossed):
            cand += _lane(pen[g, i + c[0], j + c[1]], lane, lanes)
        if cand < best:
            best = cand
            found = index
        index += 1
    if i == sr and j == sc:
        found = -1
    return found


@ti.kernel
def _trace(arr: ti.types.ndarray(ndim=3), pen: ti.types.ndarray(ndim=3), g: ti.i32, lane: ti.i32, i0: ti.i32,
           j0: ti.i32, sr: ti.i32, sc: ti.i32, cap: ti.f32, out: ti.types.ndarray(ndim=2), lanes: ti.template(),
           neighbourhood: ti.template(), corner_cutting: ti.template()):
    """Follow successors from (i0, j0) (padded coordinates) for at most out.shape[0] - 1 steps, into out[1:];
    out[0, 0] receives the number of steps."""
    i, j, steps = i0, j0, 0
    ti.loop_config(serialize=True)
    for _ in range(out.shape[0] - 1):
        move = -1
        if PAD <= i < arr.shape[1] - PAD and PAD <= j < arr.shape[2] - PAD:
            move = _successor_move(arr, pen, g, lane, i, j, sr, sc, cap, lanes, neighbourhood, corner_cutting)
        if move >= 0:
            for index, m in ti.static(enumerate(stencil.moves(neighbourhood, corner_cutting))):
                if move == index:
                    i += m.dr
                    j += m.dc
            out[steps + 1, 0] = i
            out[steps + 1, 1] = j
            steps += 1
        else:
            break
    out[0, 0] = steps


@ti.func
def _sample_kind(arr: ti.template(), origins: ti.template(), cells: ti.template(), cap, out: ti.template(), step,
                 lanes: ti.template()):
    """out[step, k, column] = each layer of one kind at cells[k]: column 0 for the goal layer (lanes == 0),
    1 + node for a node layer (its cap outside its window). ``origins`` maps grid to layer coordinates."""
    rows, cols = arr.shape[1] - 2 * PAD, arr.shape[2] - 2 * PAD
    ti.loop_config(serialize=True)  # a few hundred reads: cheaper than waking the threads
    for k, g in ti.ndrange(cells.shape[0], arr.shape[0]):
        for lane in range(max(lanes, 1)):
            layer = g * max(lanes, 1) + lane
            column = layer + ti.static(0 if lanes == 0 else 1)
            if column < out.shape[2]:
                a = cells[k, 0] - origins[layer, 0]
                b = cells[k, 1] - origins[layer, 1]
                value = cap
                if 0 <= a < rows and 0 <= b < cols:
                    value = _lane(arr[g, a + PAD, b + PAD], lane, lanes)
                out[step, k, column] = value


@ti.kernel
def _sample(arr: ti.types.ndarray(ndim=3), origins: ti.types.ndarray(ndim=2), cells: ti.types.ndarray(ndim=2),
            cap: ti.f32, out: ti.types.ndarray(ndim=3), lanes: ti.template()):
    _sample_kind(arr, origins, cells, cap, out, 0, lanes)


# ------------------------------------------------------------------------------------------------------- host class
class _Layers:
    """One kind of layer, the goal's (scalar) or the node windows (``lanes`` packed per cell): two buffers (Jacobi),
    penalties, the origin of each lane in grid coordinates, and the active-tile flags."""

    def __init__(self, groups: int, rows: int, cols: int, lanes: int, origins: np.ndarray):
        init_taichi()
        self.lanes, self.rows, self.cols = lanes, rows, cols
        shape = (groups, rows + 2 * PAD, cols + 2 * PAD)
        self.buffers = [self._array(shape), self._array(shape)]
        self.pen = self._array(shape)
        self.current = 0
        self.origins = _device(origins.astype(np.int32))
        self.stamps = ti.ndarray(ti.i32, (groups, -(-rows // TILE), -(-cols // TILE)))
        self.tick = 0  # number of the next iteration, never reset: stamps compare against it
        self.woken = 0  # the latest iteration the host stamped tiles for (activate_all, activate_cells)
        self.counts = ti.ndarray(ti.i32, (1,))  # cells the last iteration changed
        self.activate_all()

    def _array(self, shape: tuple[int, int, int]):
        if self.lanes:
            return ti.Vector.ndarray(self.lanes, ti.f32, shape)
        return ti.ndarray(ti.f32, shape)

    @property
    def values(self):
        return self.buffers[self.current]

    @property
    def other(self):
        return self.buffers[1 - self.current]

    def activate_all(self) -> None:
        self.stamps.fill(self.tick)
        self.woken = self.tick

    def deactivate_all(self) -> None:
        self.stamps.fill(-1)

    def activate_cells(self, cells: np.ndarray) -> None:
        """Activate the tiles near ``cells`` ((n, 2) int32 grid cells) for the next iteration."""
        _stamp_cells(self.stamps, cells, self.origins, self.lanes, self.rows, self.cols, self.tick)
        self.woken = self.tick

    def paint(self, cells: np.ndarray, values: np.ndarray, cap: float) -> None:
        """Set the penalties of ``cells`` to ``values`` (0 free, inf occupied) and wake the tiles around them."""
        _paint(self.pen, self.buffers[0], self.buffers[1], self.origins, cells, values, cap, self.lanes, self.rows,
               self.cols)
        self.activate_cells(cells)

    def iterate(self, k: int, sr: int, sc: int, cap: float, cells: np.ndarray, out: np.ndarray, neighbourhood: int,
                corner_cutting: bool) -> None:
        """k synchronous iterations over the active tiles, the layers sampled at ``cells`` into out[step] after
        each; ``counts[0]`` then holds the cells the last iteration changed. The iterations run in one serial launch
        while at most ``SERIAL_TILES`` tiles are active, in one parallel launch each beyond."""
        done = 0
        while done < k:
            done += self._swap(_iterate_serially(self.values, self.other, self.pen, self.stamps, self.tick,
                                                 self.counts, sr, sc, cap, self.origins, cells, out, done, k - done,
                                                 _serial_limit(), self.woken, self.lanes, neighbourhood,
                                                 corner_cutting))
            if done < k:
                _iterate(self.values, self.other, self.pen, self.stamps, self.tick, self.counts, sr, sc, cap,
                         self.origins, cells, out, done, self.lanes, neighbourhood, corner_cutting)
                done += self._swap(1)

    def settle(self, sr: int, sc: int, cap: float, max_rounds: int | None, neighbourhood: int,
               corner_cutting: bool) -> tuple[int, bool]:
        """Rounds of in-place tile settling until one changes no tile, or ``max_rounds``; returns (rounds, settled).
        Rounds run one after another in one launch while at most ``SERIAL_TILES`` tiles are active."""
        limit = _NEVER if max_rounds is None else max_rounds
        result = np.zeros(2, np.int32)
        rounds, touched = 0, 1
        while touched and rounds < limit:
            _settle_serially(self.values, self.pen, self.stamps, self.tick, sr, sc, cap, limit - rounds,
                             _serial_limit(), result, self.lanes, neighbourhood, corner_cutting)
            done, touched = int(result[0]), int(result[1])
            self.tick += done
            rounds += done
            if touched and rounds < limit:
                touched = _settle(self.values, self.pen, self.stamps, self.tick, sr, sc, cap, self.lanes,
                                  neighbourhood, corner_cutting)
                self.tick += 1
                rounds += 1
        return rounds, not touched

    def warm_up(self, neighbourhood: int, corner_cutting: bool) -> None:
        """Compile this kind's kernels by launching each on nothing (no cell, no step, no tile active at _NEVER):
        no value, stamp or count of the layers changes."""
        nowhere = np.zeros((0, 2), np.int32)
        out = np.zeros((1, 0, 1), np.float32)
        counts = ti.ndarray(ti.i32, (1,))
        _iterate(self.values, self.other, self.pen, self.stamps, _NEVER, counts, 0, 0, 0.0, self.origins, nowhere,
                 out, 0, self.lanes, neighbourhood, corner_cutting)
        _iterate_serially(self.values, self.other, self.pen, self.stamps, _NEVER, counts, 0, 0, 0.0, self.origins,
                          nowhere, out, 0, 0, 0, _NEVER, self.lanes, neighbourhood, corner_cutting)
        _paint(self.pen, self.buffers[0], self.buffers[1], self.origins, nowhere, np.zeros(0, np.float32), 0.0,
               self.lanes, self.rows, self.cols)
        _stamp_cells(self.stamps, nowhere, self.origins, self.lanes, self.rows, self.cols, _NEVER)
        _sample(self.values, self.origins, nowhere, 0.0, out, self.lanes)
        _settle(self.values, self.pen, self.stamps, _NEVER, 0, 0, 0.0, self.lanes, neighbourhood, corner_cutting)
        _settle_serially(self.values, self.pen, self.stamps, _NEVER, 0, 0, 0.0, 0, 0, np.zeros(2, np.int32),
                         self.lanes, neighbourhood, corner_cutting)
        _trace(self.values, self.pen, 0, 0, PAD, PAD, PAD, PAD, 0.0, np.zeros((1, 2), np.int32), self.lanes,
               neighbourhood, corner_cutting)

    def idle(self) -> bool:
        """Whether the next iteration has nothing to do: the last one changed nothing and the host has stamped no
        tile since (then both buffers hold the same values, and so would every later iteration's)."""
        return int(self.counts[0]) == 0 and self.woken < self.tick

    def rebase(self) -> None:
        """Renumber iterations from 0 once they pass REBASE_AT: stamps of past iterations become -1 (inactive),
        later ones keep their distance to the next iteration."""
        if self.tick < REBASE_AT:
            return
        stamps = self.stamps.to_numpy()
        self.stamps.from_numpy(np.where(stamps >= self.tick, stamps - self.tick, -1).astype(np.int32))
        self.woken = max(self.woken - self.tick, -1)
        self.tick = 0

    def _swap(self, iterations: int) -> int:
        """Account for ``iterations`` done: the buffers swap roles at each."""
        self.current ^= iterations % 2
        self.tick += iterations
        return iterations


def _cells_array(cells) -> np.ndarray:
    """(n, 2) int32, contiguous: how kernels take cells."""
    return np.ascontiguousarray(np.asarray(cells, np.int32).reshape(-1, 2))


def _device(array: np.ndarray):
    """A Taichi ndarray holding a copy of an int32 or float32 numpy array."""
    out = ti.ndarray(ti.i32 if array.dtype == np.int32 else ti.f32, array.shape)
    out.from_numpy(np.ascontiguousarray(array))
    return out


class Engine:
    """All layers of one DP: the goal layer (cap ``goal_cap``) and one windowed layer per node (cap ``node_cap``).

    Cells are ``(row, col)``; distances are in cells. ``occupied`` is a bool (H, W) array, True = obstacle.
    Map edits and goal moves take effect at the next iteration; nothing is recompiled. Each iteration relaxes
    only the tiles whose inputs changed (ARCHITECTURE §7); :meth:`activate_all` forces a dense one.
    """

    def __init__(self, occupied: np.ndarray, goal: tuple[int, int], *, goal_cap: float = math.inf,
                 nodes: np.ndarray | None = None, node_cap: float = 0.0, neighbourhood: int = 16,
                 corner_cutting: bool = False):
        self.occupied = np.array(occupied, dtype=bool)
        self.rows, self.cols = self.occupied.shape
        self.neighbourhood = stencil.check_neighbourhood(neighbourhood)
        self.corner_cutting = bool(corner_cutting)
        self.goal = (int(goal[0]), int(goal[1]))
        self.goal_cap = float(goal_cap)
        self.node_cap = float(node_cap)
        self.nodes = np.zeros((0, 2), np.int32) if nodes is None else np.asarray(nodes, np.int32).reshape(-1, 2)
        self.iterations = 0

        self._goal = _Layers(1, self.rows, self.cols, 0, np.zeros((1, 2)))
        self._goal.pen.from_numpy(self._padded_penalties())
        self._windows = None
        if len(self.nodes):
            self.radius = int(math.ceil(self.node_cap))
            side = 2 * self.radius + 1
            groups = -(-len(self.nodes) // LANES)
            origins = np.full((groups * LANES, 2), _FAR, np.int32)
            origins[: len(self.nodes)] = self.nodes - self.radius
            self._windows = _Layers(groups, side, side, LANES, origins)
            _gather_window_pen(self._goal.pen, self._windows.pen, self._windows.origins, LANES)
        self.reset()

    # -- state -------------------------------------------------------------------------------------------------
    def _padded_penalties(self) -> np.ndarray:
        pen = np.full((1, self.rows + 2 * PAD, self.cols + 2 * PAD), np.inf, np.float32)
        pen[0, PAD:-PAD, PAD:-PAD] = np.where(self.occupied, np.inf, 0.0)
        return pen

    def _kinds(self):
        """(layers, source row, source col, cap) of the goal layer and, if any, of the node windows."""
        yield self._goal, self.goal[0] + PAD, self.goal[1] + PAD, self.goal_cap
        if self._windows is not None:
            centre = self.radius + PAD
            yield self._windows, centre, centre, self.node_cap

    def reset(self) -> None:
        """Back to the initial state of eqs. 5 and 10 (iteration 0)."""
        for layers, sr, sc, cap in self._kinds():
            for buffer in layers.buffers:
                _reset(buffer, layers.pen, sr, sc, cap, layers.lanes)
            layers.rebase()
            layers.activate_all()
        self.iterations = 0

    def activate_all(self) -> None:
        """Make the next iteration relax every tile (a dense iteration; the result is the same)."""
        for layers, _, _, _ in self._kinds():
            layers.activate_all()

    def warm_up(self) -> None:
        """Compile every kernel that iterations, map edits, goal moves and reads of this engine use, changing nothing.

        Taichi compiles a kernel on its first launch (about a second; later processes load it from Taichi's offline
        cache), and the parallel iteration is first launched when a large change arrives: warming up in the setup
        phase keeps that pause out of the control loop. :meth:`tdp.Navigator.setup` calls it."""
        for layers, _, _, _ in self._kinds():
            layers.warm_up(self.neighbourhood, self.corner_cutting)

    def step(self, k: int = 1) -> None:
        """Run k synchronous iterations of every layer (only their active tiles). Once an iteration changes
        nothing and no edit is pending, every later one would change nothing either: they are counted, not run, so
        any k returns at once on a settled field."""
        nowhere = np.zeros((0, 2), np.int32)
        while k > 0:
            if all(layers.idle() for layers, _, _, _ in self._kinds()):
                self.iterations += k
                return
            chunk = min(k, _CHUNK)
            self._advance(chunk, nowhere)
            k -= chunk

    def changed(self) -> int:
        """Cells changed by the last iteration, all layers together."""
        return int(sum(layers.counts[0] for layers, _, _, _ in self._kinds()))

    def converge(self, max_rounds: int | None = None) -> int:
        """Relax from the initial state to the fixed point; return the rounds it took (the larger count of the two
        kinds of layer).

        Each round settles every active tile in place (several sweeps in cache) and wakes the neighbours its border
        changes reach; it ends when no tile changes. The fixed point of eqs. 5 and 10 is unique, so the result
        equals what synchronous iterations reach, bit for bit. While few tiles are active, rounds run one after
        another in a single launch.
        """
        self.reset()
        rounds = 0
        for layers, sr, sc, cap in self._kinds():
            done, settled = layers.settle(sr, sc, cap, max_rounds, self.neighbourhood, self.corner_cutting)
            rounds = max(rounds, done)
            layers.other.copy_from(layers.values)
            if settled:
                layers.deactivate_all()
            else:
                layers.activate_all()
        return rounds

    # -- edits -------------------------------------------------------------------------------------------------
    def set_cells(self, cells: np.ndarray, occupied: np.ndarray) -> None:
        """Mark ``cells`` (n, 2) as occupied or free (bool per cell); only those cells are sent to the kernels."""
        cells = _cells_array(cells)
        if not len(cells):
            return
        occupied = np.broadcast_to(np.asarray(occupied, bool), (len(cells),))
        self.occupied[cells[:, 0], cells[:, 1]] = occupied
        values = np.where(occupied, np.inf, 0.0).astype(np.float32)
        for layers, _, _, cap in self._kinds():
            layers.paint(cells, values, cap)

    def set_goal(self, goal: tuple[int, int]) -> None:
        """Move the goal layer's source; the values propagate from it from the next iteration on."""
        moved = np.array([self.goal, goal], np.int32)
        self.goal = (int(goal[0]), int(goal[1]))
        self._goal.activate_cells(moved)

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
        for layers, _, _, cap in self._kinds():
            _sample(layers.values, layers.origins, cells, cap, out, layers.lanes)
        return out[0]

    def advance(self, k: int, cells: np.ndarray) -> np.ndarray:
        """Run k synchronous iterations of every layer and return every layer at ``cells`` after each: a float32
        (k, n, 1 + nodes) array (as :meth:`sample` after each :meth:`step`), in one kernel launch per kind of
        layer while few tiles are active."""
        return self._advance(k, _cells_array(cells))

    def _advance(self, k: int, cells: np.ndarray) -> np.ndarray:
        out = np.empty((k, len(cells), 1 + len(self.nodes)), np.float32)
        for layers, sr, sc, cap in self._kinds():
            layers.rebase()
            layers.iterate(k, sr, sc, cap, cells, out, self.neighbourhood, self.corner_cutting)
        self.iterations += k
        return out

    def trace(self, layer: int, start: tuple[int, int], max_steps: int) -> list[tuple[int, int]]:
        """Cells visited by following the successors of ``layer`` (0 = goal, 1 + j = node j) from ``start``.

        Stops at the layer's source, at a cell with no successor, or after ``max_steps`` moves; ``start`` itself is
        not included.
        """
        if max_steps <= 0:
            return []
        if layer == 0:
            layers, g, lane, cap = self._goal, 0, 0, self.goal_cap
            sr, sc = self.goal[0] + PAD, self.goal[1] + PAD
            origin = (-PAD, -PAD)
        else:
            self._check_node(layer - 1)
            g, lane = divmod(layer - 1, LANES)
            layers, cap = self._windows, self.node_cap
            sr = sc = self.radius + PAD
            origin = tuple(int(v) for v in self.nodes[layer - 1] - self.radius - PAD)
        out = np.empty((max_steps + 1, 2), np.int32)  # row 0: the number of steps
        _trace(layers.values, layers.pen, g, lane, start[0] - origin[0], start[1] - origin[1], sr, sc, cap, out,
               layers.lanes, self.neighbourhood, self.corner_cutting)
        return [(int(r + origin[0]), int(c + origin[1])) for r, c in out[1:1 + out[0, 0]]]

    def _check_node(self, node: int) -> None:
        if not 0 <= node < len(self.nodes):
            raise ValueError(f"node index must be in [0, {len(self.nodes)}), got {node}")
