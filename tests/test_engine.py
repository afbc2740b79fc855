"""The engine's windowed node layers against full-grid layers, cell for cell, through map changes."""
import gc
import math
from pathlib import Path

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from conftest import recorded
from reference import assert_distances_match, distances_to
from tdp import engine as engine_module
from tdp.engine import LANES, Engine


def random_map(rows, cols, density, seed):
    occupied = np.random.default_rng(seed).random((rows, cols)) < density
    occupied[0, 0] = False
    return occupied


@pytest.mark.parametrize("node_cap", [40.0, 1e6, 1e300, math.inf])
def test_a_node_cap_past_the_map_clips_the_windows_to_it(node_cap):
    """A node layer is a Dijkstra from its node capped at ``node_cap``: a cap of a million asked Taichi for windows
    of 2,000,001 cells a side (a RuntimeError from its memory pool); one past float32 warned of an overflow."""
    occupied = random_map(12, 17, 0.25, 3)
    nodes = np.array([[5, 7], [11, 16]])
    occupied[tuple(nodes.T)] = False
    engine = Engine(occupied, (0, 0), nodes=nodes, node_cap=node_cap)
    engine.converge()
    assert engine.radius == (17 if node_cap > 17 else math.ceil(node_cap))
    cap = np.float32(node_cap) if node_cap < 1e38 else np.float32(np.inf)
    for k, node in enumerate(nodes):
        ours, expected = engine.node_distances(k), distances_to(occupied, tuple(node))
        assert (ours <= cap).all()
        assert_distances_match(np.where(ours < cap, ours, np.float32(np.inf)),
                               np.where(expected < cap, expected, np.inf), 1e-5)


@pytest.mark.parametrize("neighbourhood, corner_cutting", [(16, False), (8, True), (4, False)])
@pytest.mark.parametrize("shape", [(30, 41), (12, 41), (12, 9)])  # maps wider and narrower than the 17-cell windows
def test_windowed_node_layers_equal_full_grid_layers_through_map_changes(neighbourhood, corner_cutting, shape):
    """Node windows (LANES + 2 nodes: a full group, every lane's penalty bit in use, and a second group) equal goal
    layers of the full grid with the node as source, through iterations and map edits, after a converge, and in
    the successors their traces follow."""
    rng = np.random.default_rng(3)
    occupied = random_map(*shape, 0.2, 1)
    nodes = np.array([[0, 0], [5, 6], [15, 20], [29, 40], [14, 39], [28, 2]] * 6)[: LANES + 2]  # two groups
    nodes = nodes + np.arange(len(nodes))[:, None] % 3  # distinct-ish positions, some on obstacles
    nodes = np.clip(nodes, 0, np.array(shape) - 1)
    cap = 7.5
    engine = Engine(occupied, (0, 0), nodes=nodes, node_cap=cap, neighbourhood=neighbourhood,
                    corner_cutting=corner_cutting)
    # The same layers on the full grid: a goal layer with the node as source and cap DmaxQ.
    full = [Engine(occupied, (r, c), goal_cap=cap, neighbourhood=neighbourhood, corner_cutting=corner_cutting)
            for r, c in nodes]
    for iteration in range(40):
        if iteration % 7 == 3:
            cells = np.argwhere(rng.random(occupied.shape) < 0.05)
            value = bool(iteration % 2)
            engine.set_cells(cells, value)
            for layer in full:
                layer.set_cells(cells, value)
        engine.step()
        for layer in full:
            layer.step()
        for j, layer in enumerate(full):
            np.testing.assert_array_equal(engine.node_distances(j), layer.goal_distances(),
                                          err_msg=f"node {j} at iteration {iteration}")
    engine.set_cells(np.argwhere(rng.random(occupied.shape) < 0.05), True)
    engine.converge()
    start = tuple(np.array(shape) // 2)
    for j, (r, c) in enumerate(nodes):
        layer = Engine(engine.occupied, (r, c), goal_cap=cap, neighbourhood=neighbourhood,
                       corner_cutting=corner_cutting)
        layer.converge()
        np.testing.assert_array_equal(engine.node_distances(j), layer.goal_distances(), err_msg=f"node {j}")
        assert engine.trace(1 + j, start, 20) == layer.trace(0, start, 20), f"node {j}"


def test_node_on_an_obstacle_stays_at_the_cap_and_sample_reads_every_layer():
    occupied = np.zeros((20, 20), bool)
    occupied[10, 10] = True
    nodes = np.array([[10, 10], [5, 5], [5, 9]])
    engine = Engine(occupied, (0, 0), nodes=nodes, node_cap=6.0)
    engine.converge()
    assert (engine.node_distances(0) == 6.0).all()
    values = engine.sample([[5, 5], [0, 0]])
    assert values.shape == (2, 4)
    assert values[0, 0] == pytest.approx(5 * math.sqrt(2), rel=1e-6)
    assert values[0, 1] == 6.0 and values[0, 2] == 0.0 and values[0, 3] == 4.0
    assert values[1, 0] == 0.0 and values[1, 2] == 6.0  # (0, 0) is 7.07 from (5, 5): beyond the cap


def test_trace_follows_a_node_layer_to_its_node():
    engine = Engine(np.zeros((30, 30), bool), (0, 0), nodes=np.array([[15, 15]]), node_cap=10.0)
    engine.converge()
    path = engine.trace(1, (15, 22), 50)
    assert path[-1] == (15, 15)
    assert engine.trace(1, (0, 0), 50) == []  # outside its vision


@pytest.mark.parametrize("serial_tiles", [0, 3, 10**6])  # rounds in parallel launches, mixed, all in one launch
def test_converge_equals_synchronous_iteration_for_node_layers_too(monkeypatch, serial_tiles):
    occupied = random_map(25, 25, 0.25, 5)
    nodes = np.argwhere(~occupied)[::37]
    swept = Engine(occupied, tuple(np.argwhere(~occupied)[0]), nodes=nodes, node_cap=9.0)
    monkeypatch.setattr(engine_module, "SERIAL_TILES", serial_tiles)
    assert swept.converge() > 1
    monkeypatch.undo()
    jacobi = Engine(occupied, tuple(np.argwhere(~occupied)[0]), nodes=nodes, node_cap=9.0)
    jacobi.step()
    while jacobi.changed():
        jacobi.step()
    np.testing.assert_array_equal(swept.goal_distances(), jacobi.goal_distances())
    for j in range(len(nodes)):
        np.testing.assert_array_equal(swept.node_distances(j), jacobi.node_distances(j))


@pytest.mark.parametrize("seed", range(3))
def test_active_tiles_are_exact_through_edits_and_goal_moves(seed):
    """Relaxing only the tiles whose inputs changed gives, bit for bit, what relaxing every tile gives."""
    rng = np.random.default_rng(seed)
    occupied = random_map(37, 45, 0.15, seed)
    nodes = np.argwhere(~occupied)[rng.choice(int((~occupied).sum()), 20, replace=False)]
    goal = tuple(np.argwhere(~occupied)[0])
    tiled = Engine(occupied, goal, nodes=nodes, node_cap=11.0)
    dense = Engine(occupied, goal, nodes=nodes, node_cap=11.0)
    tiled.converge()
    dense.converge()
    for iteration in range(60):
        if iteration % 9 == 4:
            cells = np.argwhere(rng.random(occupied.shape) < 0.01)
            value = bool(rng.integers(2))
            tiled.set_cells(cells, value)
            dense.set_cells(cells, value)
        if iteration % 13 == 6:
            free = np.argwhere(~tiled.occupied)
            goal = tuple(free[rng.integers(len(free))])
            tiled.set_goal(goal)
            dense.set_goal(goal)
        dense.activate_all()
        tiled.step()
        dense.step()
        assert tiled.changed() == dense.changed()
        np.testing.assert_array_equal(tiled.goal_distances(), dense.goal_distances())
        for j in range(len(nodes)):
            np.testing.assert_array_equal(tiled.node_distances(j), dense.node_distances(j))


def test_a_converged_engine_with_no_change_relaxes_nothing():
    engine = Engine(random_map(40, 40, 0.2, 9), (0, 0), nodes=np.array([[20, 20]]), node_cap=10.0)
    engine.converge()
    engine.step(3)
    assert engine.changed() == 0
    engine.set_cells([[20, 21]], True)
    engine.step()
    assert engine.changed() > 0


@pytest.mark.parametrize("serial_tiles", [0, 12, 10**6])  # always parallel launches, mixed, always one launch
def test_advance_equals_single_parallel_steps_and_samples(monkeypatch, serial_tiles):
    """advance(k) gives exactly what k parallel single iterations, each followed by sample(), give, through map
    edits and goal moves, whether its iterations run in one serial launch, in parallel launches or mixed, and while
    one kind of layer or both are idle (the small node windows settle first; k = 40 lets everything settle),
    and after a converge that moved the goal while both were idle."""
    rng = np.random.default_rng(serial_tiles)
    occupied = random_map(40, 50, 0.2, 1)
    nodes = np.argwhere(~occupied)[::97]
    fused = Engine(occupied, (0, 0), nodes=nodes, node_cap=9.0)
    stepped = Engine(occupied, (0, 0), nodes=nodes, node_cap=9.0)
    goal_only = Engine(occupied, (0, 0))
    cells = np.vstack([nodes, [[5, 5]]])
    for tick, k in enumerate((1, 4, 3, 4, 2, 4, 4, 1, 4, 40, 4, 4, 40, 4, 4, 4)):
        if tick in (2, 5, 8, 11):
            edited = np.argwhere(rng.random(occupied.shape) < 0.01)
            for engine in (fused, stepped, goal_only):
                engine.set_cells(edited, bool(tick % 2))
        if tick in (4, 14):
            for engine in (fused, stepped, goal_only):
                engine.set_goal((39, 49) if tick == 4 else (0, 0))
        if tick == 14:  # after an idle tick: values change in converge alone
            for engine in (fused, stepped, goal_only):
                engine.converge()
        monkeypatch.setattr(engine_module, "SERIAL_TILES", serial_tiles)
        samples = fused.advance(k, cells)
        goal_samples = goal_only.advance(k, cells)
        monkeypatch.setattr(engine_module, "SERIAL_TILES", 0)
        for s in range(k):
            stepped.step()
            np.testing.assert_array_equal(samples[s], stepped.sample(cells))
            np.testing.assert_array_equal(goal_samples[s], stepped.sample(cells)[:, :1])
        assert fused.changed() == stepped.changed()
    assert fused.iterations == stepped.iterations
    np.testing.assert_array_equal(fused.goal_distances(), stepped.goal_distances())
    for j in range(len(nodes)):
        np.testing.assert_array_equal(fused.node_distances(j), stepped.node_distances(j))


def test_warm_up_changes_nothing():
    occupied = random_map(30, 30, 0.2, 4)
    nodes = np.argwhere(~occupied)[::60]
    warmed, plain = (Engine(occupied, (0, 0), nodes=nodes, node_cap=8.0) for _ in range(2))
    for engine in (warmed, plain):
        engine.step(3)
    warmed.warm_up()
    assert warmed.changed() == plain.changed() > 0
    assert warmed.iterations == plain.iterations
    cells = np.argwhere(~occupied)[::7]
    np.testing.assert_array_equal(warmed.sample(cells), plain.sample(cells))
    for engine in (warmed, plain):
        engine.set_cells([[10, 10], [11, 11]], True)
    np.testing.assert_array_equal(warmed.advance(4, cells), plain.advance(4, cells))
    for j in range(len(nodes)):
        np.testing.assert_array_equal(warmed.node_distances(j), plain.node_distances(j))


def test_node_layers_of_new_caps_compile_no_fill_kernel():
    """A reset fills the node windows with their cap by the engine's own kernel: Taichi's fill of a vector ndarray
    compiles a kernel for every value it is given (632 of them in one run of this suite)."""
    from taichi import _kernels

    engine_module.init_taichi()  # (ti.init starts the kernels' instances afresh)
    taichis_fill = _kernels.fill_ndarray_matrix._primal
    before = len(taichis_fill.compiled_kernels)
    occupied = random_map(20, 20, 0.2, 5)
    nodes = np.argwhere(~occupied)[::40]
    for cap in (5.0, 6.5, 8.0):
        engine = Engine(occupied, (0, 0), nodes=nodes, node_cap=cap)
        engine.converge()
        ours, expected = engine.node_distances(0), distances_to(occupied, tuple(nodes[0]))
        assert_distances_match(np.where(ours < cap, ours, np.inf), np.where(expected < cap, expected, np.inf), 1e-5)
    assert len(taichis_fill.compiled_kernels) == before


def test_the_quickened_taichi_front_end_reads_and_wraps_as_taichi_does():
    """The engine memoises three steps of Taichi 1.7's front end (a function's source lines, each AST node's debug
    message, a line wrapped at 80 columns): what they return is what Taichi's own steps return, for every node of a
    function's source and again from the memo, in another file or at another line too, and a caller's changes to
    a result do not reach the next."""
    import ast
    import inspect
    import textwrap
    from types import SimpleNamespace

    import taichi as ti
    from taichi.lang import _wrap_inspect, kernel_impl
    from taichi.lang.ast import ast_transformer_utils

    engine_module.init_taichi()
    if tuple(ti.__version__[:2]) != (1, 7):
        pytest.skip("the front end is quickened on Taichi 1.7 only")
    assert ast_transformer_utils.TextWrapper is not textwrap.TextWrapper
    lines = inspect.getsource(engine_module).splitlines()
    for line in lines[::7] + ["", " " * 90 + "^" * 30, "x" * 200]:
        wrapped = ast_transformer_utils.TextWrapper(width=80).wrap(line)
        assert wrapped == textwrap.TextWrapper(width=80).wrap(line)
        wrapped.append("changed")
        assert ast_transformer_utils.TextWrapper(width=80).wrap(line) == textwrap.TextWrapper(width=80).wrap(line)
    function = engine_module._cell_rules
    source, first = kernel_impl.getsourcelines(function)
    assert (source, first) == _wrap_inspect.getsourcelines(function)
    source.clear()
    assert kernel_impl.getsourcelines(function) == _wrap_inspect.getsourcelines(function)
    position = ast_transformer_utils.ASTTransformerContext.get_pos_info
    taichis = position.__wrapped__
    source, first = _wrap_inspect.getsourcelines(function)
    source = [textwrap.fill(line, tabsize=4, width=9999) for line in source]  # as Taichi's _get_tree_and_ctx
    nodes = [node for node in ast.walk(ast.parse(textwrap.dedent("\n".join(source))))
             if isinstance(node, (ast.stmt, ast.expr))]
    assert len(nodes) > 100 and any(node.lineno != node.end_lineno for node in nodes)
    for file, offset in (("engine.py", first - 1), ("engine.py", first - 1), ("other.py", first - 1),
                         ("engine.py", first + 4)):
        context = SimpleNamespace(file=file, lineno_offset=offset, func=SimpleNamespace(func=function), src=source,
                                  indent=len(source[0]) - len(source[0].lstrip()))
        assert [position(context, node) for node in nodes] == [taichis(context, node) for node in nodes]


@pytest.mark.parametrize("serial_tiles", [0, 10**6])
def test_iterations_after_a_converge_cut_short_finish_it_first(monkeypatch, serial_tiles):
    """A converge stopped early may leave values below the fixed point's (a raise wave under way), which synchronous
    iterations would lift one step at a time: the next iteration finishes the converge first."""
    occupied = random_map(40, 40, 0.3, 8)
    nodes = np.argwhere(~occupied)[::53]
    goal = tuple(np.argwhere(~occupied)[0])
    full = Engine(occupied, goal, nodes=nodes, node_cap=12.0)
    full.converge()
    cut = Engine(occupied, goal, nodes=nodes, node_cap=12.0)
    cut.converge()
    monkeypatch.setattr(engine_module, "SERIAL_TILES", serial_tiles)
    wall = np.array([(20, c) for c in range(40)])
    for engine in (full, cut):
        engine.set_cells(wall, np.ones(len(wall), bool))
    full.converge()
    assert cut.converge(max_rounds=1) == 1
    assert cut.pending()
    cut.step()
    assert not cut.pending()
    assert cut.changed() == 0
    np.testing.assert_array_equal(cut.goal_distances(), full.goal_distances())
    for j in range(len(nodes)):
        np.testing.assert_array_equal(cut.node_distances(j), full.node_distances(j))


def test_iteration_numbers_rebase_without_changing_anything(monkeypatch):
    """Tile stamps are renumbered before they could overflow 32 bits; with a tiny rebase point the tiled engine
    still equals dense iterations through edits and goal moves."""
    monkeypatch.setattr(engine_module, "REBASE_AT", 5)
    rng = np.random.default_rng(11)
    occupied = random_map(30, 33, 0.15, 11)
    nodes = np.argwhere(~occupied)[::41]
    tiled, dense = (Engine(occupied, (0, 0), nodes=nodes, node_cap=8.0) for _ in range(2))
    for iteration in range(40):
        if iteration % 6 == 2:
            cells = np.argwhere(rng.random(occupied.shape) < 0.02)
            for engine in (tiled, dense):
                engine.set_cells(cells, bool(iteration % 4))
        dense.activate_all()
        for engine in (tiled, dense):
            engine.step()
        np.testing.assert_array_equal(tiled.goal_distances(), dense.goal_distances())
        for j in range(len(nodes)):
            np.testing.assert_array_equal(tiled.node_distances(j), dense.node_distances(j))


@pytest.mark.skipif(not Path("/proc/self/statm").exists(), reason="reads the process's memory from Linux's /proc")
def test_dropped_engines_hand_their_node_windows_back():
    """Taichi 1.7 never freed vector ndarrays (taichi-dev/taichi#8763): every engine leaked its node windows, here
    three arrays of 601 x 601 cells x 32 lanes (139 MB) each time."""
    def resident_mb() -> float:
        return int(Path("/proc/self/statm").read_text().split()[1]) * 4096 / 1e6

    def build_and_drop() -> None:
        Engine(np.zeros((64, 64), bool), (0, 0), nodes=np.array([[32, 32]]), node_cap=300.0)
        gc.collect()

    build_and_drop()
    before = resident_mb()
    for _ in range(4):
        build_and_drop()
    assert resident_mb() - before < 139


def test_sweeps_fitting_is_what_fits_between_its_bounds():
    """A slice's size (the exact planner's budgeted ticks and the engine's repairs share it): the sweeps that fit
    in the time left at the rate given, never fewer than ``fewest`` (also when no time is left) nor more than
    ``most``."""
    assert engine_module.sweeps_fitting(1e-3, 2e-6, 16, 10**6) == 500
    assert engine_module.sweeps_fitting(1e-3, 2e-6, 16, 100) == 100
    assert engine_module.sweeps_fitting(-1e-3, 2e-6, 16, 100) == 16
    assert engine_module.sweeps_fitting(1e9, 1e-9, 16, 2**40) == engine_module._NEVER


def test_warm_up_compiles_every_kernel_a_field_then_launches():
    """Each distinct argument type compiles a kernel anew (a numpy array and a Taichi ndarray differ): the warm-up
    must launch each kernel as later launches do, or the first search or mend compiles inside a planner's tick (the
    mend's first launch took 1.6 s there). Every launch below - a search, paint, a mend, rounds of tiles, a focused
    and a sliced converge, iterations, samples, traces - compiles nothing the warm-up did not."""
    from tdp.engine import _kernels_for

    occupied = np.zeros((40, 40), bool)
    engine = Engine(occupied, (0, 0), cost=np.ones((40, 40)))
    engine.warm_up()
    kernels = _kernels_for(0, 16, False, True).all
    compiled = [len(kernel.kernel._primal.compiled_kernels) for kernel in kernels]
    engine.converge()
    engine.set_cells(np.array([(5, 5), (6, 6)]), np.array([True, True]))
    engine.set_costs(np.array([(9, 9)]), 3.0)
    engine.converge()
    engine.set_cells(np.array([(20, 5)]), np.array([True]))
    engine.converge(focus=(39, 39))
    engine.converge(max_sweeps=4)
    engine.step(3)
    engine.sample(np.array([(1, 1)]))
    engine.trace(0, (39, 39), 10)
    engine.set_goal((10, 10))
    engine.converge(focus=(0, 0))
    assert [len(kernel.kernel._primal.compiled_kernels) for kernel in kernels] == compiled


def _every_kind_of_launch(nodes):
    """A run through every kind of launch an engine makes - a search, paints, a mend, rounds focused and cut short,
    iterations parallel and serial (a returned count), samples, traces, cost edits, a goal move - and what each
    left: the goal layer and every node layer, the samples, the trace and the counts."""
    occupied = random_map(48, 56, 0.2, 7)
    engine = Engine(occupied, (1, 1), nodes=nodes, node_cap=40.0, cost=np.ones((48, 56)))
    seen = [engine.converge()]
    engine.set_cells(np.array([(10, 10), (11, 11), (30, 30)]), np.array([True, True, True]))
    engine.set_costs(np.array([(20, 20), (21, 20)]), 4.0)
    seen += [engine.converge(), engine.converged_by()]
    engine.set_cells(np.array([(12, 12)]), np.array([True]))
    seen += [engine.converge(focus=(47, 55)), engine.pending(), engine.converge(max_sweeps=3), engine.cut_short()]
    engine.set_cells(np.array([(10, 10)]), np.array([False]))
    engine.step(2)
    seen += [engine.changed(), engine.advance(3, np.array([(5, 5), (40, 50)])), engine.sample(np.array([(2, 3)]))]
    engine.step(200)
    seen += [engine.trace(0, (47, 55), 30), engine.goal_distances()]
    engine.set_goal((40, 40))
    seen += [engine.converge(), engine.goal_distances()]
    seen += [engine.node_distances(node) for node in range(len(nodes))]
    return seen


@pytest.mark.parametrize("nodes", [np.zeros((0, 2), int), np.array([(5, 5), (24, 30), (40, 50)])])
def test_direct_launches_give_what_taichis_calls_give(monkeypatch, nodes):
    """The launcher sets a kernel's arguments straight into Taichi's launch context after the first launch of each
    kind of arguments: the same runs through every kind of launch, by that path and by Taichi's own calls, leave
    the same values bit for bit, and the direct path is the one taken (Taichi's call runs once per kind)."""
    runs = []
    for direct, held in ((False, False), (True, False), (True, True)):
        monkeypatch.setattr(engine_module, "DIRECT_LAUNCH", direct)
        monkeypatch.setattr(engine_module, "HOLD_CONTEXTS", held)
        runs.append(_every_kind_of_launch(nodes))
    for by_taichi, *by_launcher in zip(*runs):
        for seen in by_launcher:
            np.testing.assert_array_equal(np.asarray(by_taichi), np.asarray(seen))
    calls = []
    for lanes in (0, LANES):
        for launcher in engine_module._kernels_for(lanes, 16, False, True).all:
            monkeypatch.setattr(launcher, "kernel", recorded(launcher.kernel, launcher.__name__, calls))
    _every_kind_of_launch(nodes)
    assert calls == []


def test_a_held_launch_context_is_reused_only_with_the_same_ndarrays(monkeypatch):
    """A launcher keeps its last context: mends of the same field set no ndarray again; a field of the same shape made
    after the first is dropped (its arrays freed, perhaps at the same addresses) gets contexts of its own and the
    values a fresh converge gives."""
    set_again = []
    host_array = engine_module._set_host_array
    monkeypatch.setattr(engine_module, "_set_host_array", lambda *a: set_again.append(a[2]) or host_array(*a))
    occupied = random_map(30, 30, 0.2, 3)
    for _ in range(2):
        engine = Engine(occupied, (0, 0))
        engine.converge()
        for cell in [(5, 5), (6, 6), (5, 5)]:
            engine.set_cells(np.array([cell]), np.array([not occupied[cell]]))
            engine.converge()
            occupied[cell] = not occupied[cell]
            fresh = Engine(occupied, (0, 0))
            fresh.converge()
            np.testing.assert_array_equal(engine.goal_distances(), fresh.goal_distances())
            for toggle in range(4):  # the same mend's launches: after the first two, nothing is set again
                if toggle == 2:
                    set_again.clear()
                engine.set_cells(np.array([(20, 20)]), np.array([occupied[20, 20] == (toggle % 2 == 1)]))
                engine.converge()
            assert set_again == [] or not engine_module._on_cpu
        del engine, fresh


_SHAPE = (13, 17)
_CELL = st.tuples(st.integers(0, _SHAPE[0] - 1), st.integers(0, _SHAPE[1] - 1))
_OPERATION = st.one_of(
    st.tuples(st.just("edit"), st.lists(_CELL, min_size=1, max_size=6), st.booleans()),
    st.tuples(st.just("cost"), st.lists(_CELL, min_size=1, max_size=4), st.integers(1, 9)),
    st.tuples(st.just("converge"), st.one_of(st.none(), _CELL), st.sampled_from([0, 1, 3])),
    st.tuples(st.just("step"), st.integers(1, 3), st.none()),
    st.tuples(st.just("goal"), _CELL, st.none()),
    st.tuples(st.just("reset"), st.none(), st.none()))


@settings(max_examples=60, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(st.integers(0, 2**16), st.sampled_from([(16, False), (8, True), (4, False)]),
       st.lists(st.tuples(_OPERATION, st.lists(_CELL, max_size=3)), min_size=1, max_size=12),
       st.lists(_CELL, min_size=1, max_size=3))
def test_focus_successors_read_once_are_what_a_trace_reads_now(seed, stencil_spec, operations, watched):
    """focus_successor keeps the successors it has read (the focused converge's, the routes traced ahead) until the
    values change: through edits, cost changes, converges (focused, cut short, whole), iterations, goal moves and
    resets, every cell it is asked about - walking along the route from it, as a robot does, and the ``watched``
    cells after every operation, whose routes it has read before - gets what a trace from that cell reads now."""
    neighbourhood, corner_cutting = stencil_spec
    rng = np.random.default_rng(seed)
    occupied = random_map(*_SHAPE, 0.25, seed)
    engine = Engine(occupied, (0, 0), neighbourhood=neighbourhood, corner_cutting=corner_cutting,
                    cost=rng.integers(1, 4, _SHAPE).astype(np.float32))
    engine.converge()
    for (kind, first, second), asked in operations:
        if kind == "edit":
            engine.set_cells(np.array(first), np.full(len(first), second))
        elif kind == "cost":
            engine.set_costs(np.array(first), second)
        elif kind == "converge":
            engine.converge(focus=first, max_sweeps=second)
        elif kind == "step":
            engine.step(first)
        elif kind == "goal" and not engine.occupied[first]:
            engine.set_goal(first)
        elif kind == "reset":
            engine.reset()
        for cell in [first] * (kind == "converge" and first is not None) + asked + watched:
            for _ in range(4):  # along the route: the cells after the first come from the route traced ahead
                traced = engine.trace(0, cell, 1)
                successor = engine.focus_successor(cell)
                assert successor == (traced[0] if traced else None), (kind, cell)
                if successor is None:
                    break
                cell = successor


def test_iterations_drop_the_successors_read_before_them():
    """The goal sealed in, a successor read, then iterations raising the values round the seal: the successor read
    again is the new one (the iterations dropped the one kept)."""
    engine = Engine(np.zeros((9, 9), bool), (0, 0))
    engine.converge()
    engine.set_cells(np.array([(1, 1), (1, 0), (0, 1)]), True)
    assert engine.focus_successor((4, 4)) == (3, 3)
    engine.step(2)
    assert engine.trace(0, (4, 4), 1) == [(3, 4)]
    assert engine.focus_successor((4, 4)) == (3, 4)


def test_the_successors_kept_stay_bounded(monkeypatch):
    """Asked about every cell of a map with nothing changing, focus_successor keeps at most SUCCESSORS_KEPT moves
    (and a route's worth more), each still what a trace reads."""
    monkeypatch.setattr(engine_module, "SUCCESSORS_KEPT", 40)
    occupied = random_map(20, 30, 0.2, 4)
    engine = Engine(occupied, (0, 0))
    engine.converge()
    for cell in np.argwhere(~occupied):
        cell = tuple(int(v) for v in cell)
        traced = engine.trace(0, cell, 1)
        assert engine.focus_successor(cell) == (traced[0] if traced else None)
        assert len(engine._goal.successors) <= 40 + engine_module.ROUTE_AHEAD + 1
