"""Obstacle prediction: the tracker on hand-made motions, and the navigator with prediction on."""
import math

import numpy as np
import pytest
from hypothesis import assume, given, settings
from hypothesis import strategies as st

import tdp
from benchmarks.common import run_navigator, turn_and_closest, unblocked_route
from tdp.contract import Mode, WorldFeed
from tdp.lookout import step_aside
from tdp.predict import GAP_MOST, MotionPredictor, Track, clusters
from tdp.random_worlds import make_world
from tdp.simulate import oracle_run


def column(col: int, rows=range(4, 7)) -> np.ndarray:
    return np.array([(r, col) for r in rows])


def row(at: int, cols) -> np.ndarray:
    return np.array([(at, c) for c in cols])


def cells_of(array: np.ndarray) -> set:
    return set(map(tuple, array.tolist()))


def test_clusters_are_8_connected_groups():
    found = clusters(np.array([(0, 0), (1, 1), (5, 5), (5, 6), (9, 0)]))
    assert sorted(cells_of(group).__len__() for group in found) == [1, 2, 2]
    assert {frozenset(cells_of(g)) for g in found} == {frozenset({(0, 0), (1, 1)}), frozenset({(5, 5), (5, 6)}),
                                                       frozenset({(9, 0)})}


def test_a_box_moving_one_cell_a_tick_is_predicted_along_its_way():
    """A 3-cell edge at column 10 at tick 1, column 11 at tick 2: velocity (0, 1); over the next two ticks it
    enters columns 12 and 13, rows 4-6 (hand-computed)."""
    predictor = MotionPredictor((20, 30))
    predictor.observe(1, column(10))
    assert len(predictor.entering(1, 2)) == 0  # one edge: direction unknown
    predictor.observe(2, column(11))
    np.testing.assert_allclose(predictor.tracks[0].velocity, [0.0, 1.0])
    assert cells_of(predictor.entering(2, 2)) == cells_of(np.vstack([column(12), column(13)]))
    assert cells_of(predictor.entering(2, 1)) == cells_of(column(12))


def test_a_slow_box_is_tracked_across_the_ticks_it_does_not_move_and_dropped_once_it_stops():
    predictor = MotionPredictor((20, 30))
    predictor.observe(2, column(10))
    predictor.observe(3, np.zeros((0, 2)))
    predictor.observe(4, column(9))  # half a cell per tick, to the left
    np.testing.assert_allclose(predictor.tracks[0].velocity, [0.0, -0.5])
    predictor.observe(5, np.zeros((0, 2)))
    assert cells_of(column(8)) <= cells_of(predictor.entering(5, 1))
    for tick in range(6, 9):
        predictor.observe(tick, np.zeros((0, 2)))
    assert predictor.tracks == [] and len(predictor.entering(8, 4)) == 0  # no edge for 4 ticks: it stopped


def test_a_box_seen_every_other_tick_is_expected_within_the_periods_its_edges_allow():
    """Edges at columns 10, 11, 12 at ticks 2, 4, 6: two moves in four ticks, each seen at the first tick after it,
    say a period between 1.5 and 2.5 ticks (a box at 0.4-0.67 cells per tick shows those edges). Right after tick
    6 its next move may come at tick 7 (floor 1.5 ticks after the last), its second not before tick 9 (floor 3):
    column 13 from tick 7, column 14 from tick 9 - not a cell a tick (hand-computed)."""
    predictor = MotionPredictor((20, 30))
    for tick, col in ((2, 10), (4, 11), (6, 12)):
        predictor.observe(tick, column(col))
        predictor.observe(tick + 1, np.zeros((0, 2)))
    np.testing.assert_allclose(predictor.tracks[0].velocity, [0.0, 0.5])
    assert predictor.tracks[0].periods == (None, (1.5, 2.5))
    assert predictor.arrivals(6, 2) == {cell: 1 for cell in cells_of(column(13))}
    assert predictor.arrivals(6, 3) == {**{cell: 1 for cell in cells_of(column(13))},
                                        **{cell: 3 for cell in cells_of(column(14))}}
    assert predictor.arrivals(7, 1) == {cell: 1 for cell in cells_of(column(13))}


def test_boxes_in_step_either_way_are_each_expected_their_own_way():
    """Two boxes of the test above, one going right from column 10 and one going left from column 30, edges at the
    same ticks: the same periods and ticks since their last moves, apart only in their ways. The moves a slow box
    makes are kept for the next box or tick that asks with the same arguments (``_paced_moves``): each box is
    expected its own way - columns 13 and 14, 27 and 26 (hand-computed) - whichever is asked about first."""
    predictor = MotionPredictor((20, 40))
    for tick, (right, left) in ((2, (10, 30)), (4, (11, 29)), (6, (12, 28))):
        predictor.observe(tick, np.vstack([column(right), column(left)]))
        predictor.observe(tick + 1, np.zeros((0, 2)))
    expected = {**{cell: 1 for cell in cells_of(np.vstack([column(13), column(27)]))},
                **{cell: 3 for cell in cells_of(np.vstack([column(14), column(26)]))}}
    for tracks in (predictor.tracks[:], predictor.tracks[::-1]):
        predictor.tracks = tracks
        assert predictor.arrivals(6, 3) == expected


def test_a_box_whose_speed_its_edges_read_low_is_expected_as_early_as_they_allow():
    """A box at 0.37 cells per tick (a move every 2.7 ticks) shows edges at ticks 1, 4, 7 and 10 and its next at
    tick 12. Three moves in nine ticks read 1/3 cell per tick; a window of whole periods of 3 ticks expected the
    next only at tick 13, and a robot stepped in front of it at tick 11 (crossing worlds with avoid_boxes). The
    edges allow a period between 8/3 and 10/3 ticks: column 14 from tick 12 (floor 8/3 ticks after the last),
    column 15 from tick 15 (floor 16/3) (hand-computed)."""
    predictor = MotionPredictor((20, 30))
    for tick, col in ((1, 10), (4, 11), (7, 12), (10, 13)):
        predictor.observe(tick, column(col))
    np.testing.assert_allclose(predictor.tracks[0].velocity, [0.0, 1 / 3])
    assert predictor.arrivals(10, 5) == {**{cell: 2 for cell in cells_of(column(14))},
                                         **{cell: 5 for cell in cells_of(column(15))}}


def test_a_move_overdue_is_expected_from_the_next_tick():
    """Edges at columns 10, 11 at ticks 2, 4: one move in two ticks says a period between 1 and 3 ticks, so the
    next move is due at tick 5 at the earliest and 7 at the latest. At tick 6 no edge came: column 12 is expected
    at tick 7, not skipped for column 13, which may follow a tick later (hand-computed)."""
    predictor = MotionPredictor((20, 30))
    for tick, col in ((2, 10), (4, 11)):
        predictor.observe(tick, column(col))
        predictor.observe(tick + 1, np.zeros((0, 2)))
    predictor.observe(6, np.zeros((0, 2)))
    assert predictor.arrivals(6, 1) == {cell: 1 for cell in cells_of(column(12))}
    assert predictor.arrivals(6, 3) == {**{cell: 1 for cell in cells_of(column(12))},
                                        **{cell: 2 for cell in cells_of(column(13))},
                                        **{cell: 3 for cell in cells_of(column(14))}}


def test_a_box_that_turns_back_is_expected_back_at_its_speed():
    """A 3-cell-wide box moving right half a cell per tick (leading edges at columns 10, 11, 12 at ticks 2, 4, 6)
    turns back at tick 8: the cells that become occupied are column 9, on its other side. It is expected back at
    half a cell per tick (column 8 at tick 10), not taken to barely move (the mean over the last four edges says
    -1/6 cells per tick) (hand-computed)."""
    predictor = MotionPredictor((20, 30))
    for tick, col in ((2, 10), (4, 11), (6, 12), (8, 9)):
        predictor.observe(tick, column(col))
        predictor.observe(tick + 1, np.zeros((0, 2)))
    np.testing.assert_allclose(predictor.tracks[0].velocity, [0.0, -0.5])
    assert predictor.arrivals(8, 2) == {cell: 2 for cell in cells_of(column(8))}


def test_a_box_seen_once_may_step_a_cell_either_way_along_the_axis_its_edge_shows():
    """A 3 x 3 box standing at columns 10-12 (rows 4-6, never seen to move) starts to move left at tick 4: column 9
    becomes occupied, an edge no track continues: a box seen once. Its way is not known, so at the next tick it may
    step a cell either way along its columns, into column 8 or 10 (which it covers); 6 ticks without an edge later it
    has stopped. Before, a box was predicted only from its second edge: a box turning back at full speed (whose far
    face no track reached then) drove onto a robot at column 8 beside it (passing-60-70) (hand-computed)."""
    predictor = MotionPredictor((20, 30))
    predictor.observe(4, column(9))
    seen_once = [track for track in predictor.tracks if track.velocity is None]
    assert [cells_of(track.edge) for track in seen_once] == [cells_of(column(9))]
    arrivals = predictor.arrivals(4, 3)
    assert all(arrivals.get(cell) == 1 for cell in cells_of(column(8)) | cells_of(column(10)))
    assert not cells_of(column(8)) & cells_of(predictor.entering(4, 3))  # node layers hold what a velocity says
    for tick in range(5, 11):
        predictor.observe(tick, np.zeros((0, 2)))
    assert predictor.arrivals(10, 3) == {}


def test_a_box_that_turns_back_at_full_speed_keeps_its_track_and_is_expected_back_at_the_next_tick():
    """A 3 x 3 box going right a cell a tick (edges at columns 10, 11, 12 at ticks 1-3) turns back at tick 4: column
    9 becomes occupied, its far face, 3 cells behind its last edge and beyond a track's reach (2.5 cells at 2 cells a
    tick). Read as the box turned back, it keeps its track at a cell a tick leftwards and is expected in column 8 at
    the next tick, 7 and 6 after (hand-computed); seen as a new box, it was predicted only from its second edge
    (passing-60-70)."""
    predictor = MotionPredictor((20, 30))
    for tick, col in ((1, 10), (2, 11), (3, 12), (4, 9)):
        predictor.observe(tick, column(col))
    np.testing.assert_allclose(predictor.tracks[0].velocity, [0.0, -1.0])
    expected = {cell: step for step, col in ((1, 8), (2, 7), (3, 6)) for cell in cells_of(column(col))}
    assert predictor.arrivals(4, 3) == expected


def test_a_box_that_turns_back_beside_another_keeps_its_track_and_leaves_the_other_its_own():
    """Box A (rows 14-15) goes right half a cell a tick (edges at columns 18, 19 at ticks 1, 3); box B (rows 16-18, the
    next lane) a cell a tick (columns 22, 23, 24 at ticks 1-3), and turns back at tick 4: its far face, column 21,
    lies 3 cells behind its last edge, beyond a track's reach, but 2 from A's. Taken nearest, it took A's track
    (read as a box turning down and across) and A moved on unseen (passing-60-90, -219); as B's face turned back it
    takes B's track, and A keeps its own (hand-computed)."""
    predictor = MotionPredictor((40, 40))
    a, b = range(14, 16), range(16, 19)
    for tick, edges in ((1, [column(18, a), column(22, b)]), (2, [column(23, b)]), (3, [column(19, a), column(24, b)]),
                        (4, [column(21, b)])):
        predictor.observe(tick, np.vstack(edges))
    moving = {frozenset(cells_of(track.edge)): tuple(track.velocity) for track in predictor.tracks
              if track.velocity is not None}
    assert moving == {frozenset(cells_of(column(21, b))): (0.0, -1.0), frozenset(cells_of(column(19, a))): (0.0, 0.5)}


@pytest.mark.parametrize("cells", [[(5, 5)], [(r, c) for r in range(5, 8) for c in range(3, 6)]])
def test_a_cell_or_a_block_seen_once_is_not_expected_to_move(cells):
    """A single cell, or a whole block that appeared at once (a door closing), shows no axis it moved along: nothing
    is expected of it."""
    predictor = MotionPredictor((20, 30))
    predictor.observe(1, np.array(cells))
    assert predictor.arrivals(1, 3) == {}


def test_the_velocity_is_the_mean_over_the_last_edges():
    """Edges 3, 3 and 4 ticks apart (0.3 cells per tick): the velocity is 3 cells over 10 ticks, not the last
    interval's 1/4."""
    predictor = MotionPredictor((20, 30))
    for tick, col in ((1, 10), (4, 11), (7, 12), (11, 13)):
        predictor.observe(tick, column(col))
    np.testing.assert_allclose(predictor.tracks[0].velocity, [0.0, 0.3])


def test_a_box_moving_up_and_right_shows_rows_and_columns_and_keeps_its_direction():
    """A 3 x 3 box going up and to the right a cell at a time, rows and cols in turn: its leading edge is its right
    column (rows 9-11, col 13) after a move right, its top row (row 8, cols 11-13) after a move up. The edges' centres
    lie half the box apart - (10, 13), then (8, 12): read from them, it went back up-left and turned back every tick.
    The corners that move least say (0, 1), (-1, 0), (0, 1): 1 row up and 2 cols right over the 3 ticks after its
    first edge (hand-computed), and the next cells ahead of it, row 7 and col 15, are expected."""
    predictor = MotionPredictor((20, 30))
    edges = [[(9, c) for c in range(10, 13)], [(r, 13) for r in range(9, 12)], [(8, c) for c in range(11, 14)],
             [(r, 14) for r in range(8, 11)]]
    for tick, edge in enumerate(edges, start=1):
        predictor.observe(tick, np.array(edge))
    np.testing.assert_allclose(predictor.tracks[0].velocity, [-1 / 3, 2 / 3])
    arrivals = predictor.arrivals(4, 3)
    assert {(8, 15), (9, 15), (10, 15)} <= set(arrivals) and {(7, 14), (7, 15)} & set(arrivals)
    assert not set(arrivals) & {(r, c) for r in range(11, 20) for c in range(30)}  # nothing below it


def test_a_box_moving_up_slower_than_right_is_expected_up_counting_from_its_last_move_up():
    """A 2 x 2 box (corner at row 10, col 10 at tick 0) moves right at ticks 2, 4, 6, 8, 10 and up at 3 and 7 (half a
    cell per tick right, a quarter up); its next move is up, at tick 11. At tick 10 its edge is its right column
    (rows 8-9, col 16) and its velocity (-0.25, 0.5). Moved by the direction's whole-cell steps, (-1, 1) or (0, 1),
    counted from that edge, the edge never went straight up: a robot beside the box's top corner was driven over
    (crossing worlds with avoid_boxes). Rows and cols move apart: its moves up, at ticks 3 and 7, say 3 to 5 ticks a
    row, so the next may come at tick 11; its last four moves right, at ticks 4 to 10, 5/3 to 7/3 ticks a col, the
    last at tick 10, so at tick 11 too: the edge is expected shifted (-1, 0), (0, 1) and (-1, 1)
    at tick 11 (hand-computed), and so is cell (7, 15), which the box also enters then: its top row (row 8, cols
    15-16), seen at its move up at tick 7 and brought right with it since, moved up."""
    predictor = MotionPredictor((30, 40))
    row, col, before = 10, 10, set()
    for tick in range(11):
        col, row = col + (tick % 2 == 0 and tick > 0), row - (tick % 4 == 3)
        box = {(r, c) for r in (row, row + 1) for c in (col, col + 1)}
        predictor.observe(tick, np.array(sorted(box - before)))
        before = box
    np.testing.assert_allclose(predictor.tracks[0].velocity, [-0.25, 0.5])
    assert predictor.tracks[0].moved_at == (7, 10)
    np.testing.assert_allclose(predictor.tracks[0].periods, [(3, 5), (5 / 3, 7 / 3)])
    assert predictor.arrivals(10, 1) == {cell: 1 for cell in [(7, 15), (7, 16), (8, 16), (8, 17), (9, 17), (7, 17)]}


def test_a_diagonal_box_s_first_two_edges_are_read_the_way_its_l_leans():
    """A 3 x 3 box (corner at row 40, col 40) moves right at tick 1 - its new right column, col 43, rows 40-42 - and
    up and right at tick 3: an L, row 39 at cols 42-44 and col 44 at rows 40-41. The edges' least cols moved -1, their
    greatest +1, and with no velocity yet neither is the nearer guess (the one that moved least read a box going up
    and to the left). The L's long arms lie on its least row and greatest col, the way the box moves: it went (-1, 1)
    in two ticks (hand-computed), and the cells ahead of it lie above and to the right."""
    predictor = MotionPredictor((80, 80))
    predictor.observe(1, np.array([(r, 43) for r in range(40, 43)]))
    predictor.observe(3, np.array([(39, c) for c in range(42, 45)] + [(40, 44), (41, 44)]))
    np.testing.assert_allclose(predictor.tracks[0].velocity, [-0.5, 0.5])
    ahead = set(predictor.arrivals(3, 2))
    assert {(38, 45), (39, 45)} <= ahead and all(r <= 41 and c >= 42 for r, c in ahead)


def test_a_diagonal_box_keeps_one_pace_on_its_rows_and_its_cols():
    """A 2 x 2 box going down and to the right, a row and a col every two ticks (edges at ticks 2, 4, 6, 8, its
    corner at (14, 14) after the last): three cells in six ticks on each axis say 5/3 to 7/3 ticks a move. Eight ticks
    ahead its rows and its cols may each have made 0 to 5 moves, but not apart: four cols while no row would need the
    cols at the fastest pace and the rows at less than the slowest. Hand-computed: (18, 18), its edge moved (3, 3),
    from tick 13 (the third move 5 ticks after the last at the earliest); (15, 16), moved (0, 1), from tick 9; (15,
    19) and (19, 15), moved (0, 4) and (4, 0), never (each axis on its own flagged them at tick 14)."""
    predictor = MotionPredictor((40, 40))
    before = set()
    for tick in range(9):
        corner = 10 + tick // 2
        box = {(r, c) for r in (corner, corner + 1) for c in (corner, corner + 1)}
        predictor.observe(tick, np.array(sorted(box - before)).reshape(-1, 2))
        before = box
    np.testing.assert_allclose(predictor.tracks[0].periods, [(5 / 3, 7 / 3)] * 2)
    arrivals = predictor.arrivals(8, 8)
    assert arrivals[(18, 18)] == 5 and arrivals[(15, 16)] == 1
    assert not {(15, 19), (19, 15), (14, 19), (19, 14)} & set(arrivals)


def assert_never_expected_late(velocity: tuple[float, float], phase: tuple[float, float], rows: int, cols: int,
                               since: int = 8):
    """A box of ``rows`` x ``cols`` cells at a constant ``velocity`` (rows, cols per tick), its corner rounded as the
    worlds round it at any ``phase``, seen only by the cells it newly covers (as a planner sees a box on the map from
    the start): from tick ``since`` on, every cell it newly covers in the next 8 ticks is flagged at or before the
    tick it enters."""
    def corner(tick):  # a millionth of a cell on the phase: round-off must not move 0.1 - 3 x 0.2 + 0.5 below 0
        return tuple(40 + math.floor(start + 1e-6 + tick * speed + 0.5) for start, speed in zip(phase, velocity))

    def box(tick):
        top, left = corner(tick)
        return {(top + i, left + j) for i in range(rows) for j in range(cols)}

    predictor = MotionPredictor((80, 80))
    before = box(0)
    for tick in range(1, since + 16):
        now = box(tick)
        predictor.observe(tick, np.array(sorted(now - before)).reshape(-1, 2))
        before = now
        if tick < since:
            continue
        assert len(predictor.tracks) == 1
        arrivals = predictor.arrivals(tick, 8)
        for step in range(1, 9):
            for cell in box(tick + step) - box(tick + step - 1) - now:
                assert arrivals.get(cell, math.inf) <= step, (tick, step, cell)


@settings(max_examples=60, deadline=None)
@given(st.floats(0.26, 0.95), st.floats(-0.5, 0.49), st.integers(1, 3), st.integers(1, 3),
       st.sampled_from([(0, 1), (0, -1), (1, 0), (-1, 0)]))
def test_a_slow_box_along_an_axis_is_never_expected_later_than_it_enters_a_cell(speed, phase, rows, cols, way):
    """A box below a cell a tick along a row or a column (:func:`assert_never_expected_late`; whole periods of the
    speed read from its edges missed 3,304 of 83,550 such cells on 400 random boxes, 543 of them never flagged)."""
    assert_never_expected_late((way[0] * speed, way[1] * speed), (phase, phase), rows, cols)


@settings(max_examples=80, deadline=None)
@given(st.floats(0.2, 0.95), st.floats(0.2, 0.95), st.sampled_from([-1, 1]), st.sampled_from([-1, 1]),
       st.floats(-0.5, 0.49), st.floats(-0.5, 0.49), st.sampled_from([(1, 1), (1, 2), (2, 1), (2, 2), (2, 3), (3, 2),
                                                                      (3, 3)]))
def test_a_slow_diagonal_box_is_never_expected_later_than_it_enters_a_cell(row_speed, col_speed, down, right,
                                                                           row_phase, col_phase, shape):
    """A box at any angle, its rows and its cols each at 0.2-0.95 cells a tick (the faster at least 0.27, above the
    slowest tracked) and so moving along them on different ticks, of sides within a factor 2
    (:func:`assert_never_expected_late`), from tick 12 on (an axis at 0.2 may show its first move, whose way its
    first edge cannot tell, at tick 5, and its second at tick 10). The tracker that counted both axes from its last
    four edges, read its shift by the corner nearest its velocity, dropped it by the speed of its first two edges
    and knew it by its last edge alone flagged 7,575 of the 40,808 cells 400 such random boxes covered anew late or
    never (from tick 8 on; a box going up and to the right, last seen moving right, covers its whole top row on its
    next move up)."""
    assume(max(row_speed, col_speed) >= 0.27)
    assert_never_expected_late((down * row_speed, right * col_speed), (row_phase, col_phase), *shape, since=12)


def test_a_door_that_closes_once_is_never_predicted():
    predictor = MotionPredictor((20, 30))
    predictor.observe(1, np.array([(r, c) for r in range(5, 7) for c in range(3, 9)]))
    for tick in range(2, 6):
        predictor.observe(tick, np.zeros((0, 2)))
        assert len(predictor.entering(tick, 5)) == 0


def test_two_boxes_passing_each_other_keep_their_own_velocities():
    predictor = MotionPredictor((30, 30))
    predictor.observe(1, np.vstack([column(5, range(2, 4)), column(20, range(10, 12))]))
    predictor.observe(2, np.vstack([column(6, range(2, 4)), column(19, range(10, 12))]))
    velocities = sorted(tuple(t.velocity) for t in predictor.tracks)
    assert velocities == [(0.0, -1.0), (0.0, 1.0)]
    assert cells_of(predictor.entering(2, 1)) == cells_of(np.vstack([column(7, range(2, 4)),
                                                                     column(18, range(10, 12))]))


def test_an_edge_continues_the_track_whose_velocity_expects_it_not_the_nearest():
    """A box going right at two cells a tick, its edge at col 12 (rows 5-7), and at the next tick a new box's edge
    beside where it was (col 11): a cell from the track's last edge, where the box's own edge (col 14) lies two on, as
    its velocity expects. Taken nearest first, the new edge took the track - a box that turned back - and the box's
    own edge started a track with no velocity: nothing was expected ahead of it (hand-computed)."""
    predictor = MotionPredictor((30, 40))
    predictor.observe(1, column(10, range(5, 8)))
    predictor.observe(2, column(12, range(5, 8)))
    predictor.observe(3, np.vstack([column(14, range(5, 8)), column(11, range(5, 8))]))
    moving = [track for track in predictor.tracks if track.velocity is not None]
    assert [(cells_of(track.edge), tuple(track.velocity)) for track in moving] == [
        (cells_of(column(14, range(5, 8))), (0.0, 2.0))]
    assert cells_of(predictor.entering(3, 1)) == cells_of(np.vstack([column(15, range(5, 8)),
                                                                     column(16, range(5, 8))]))


def test_predictions_stay_inside_the_map():
    predictor = MotionPredictor((10, 10))
    predictor.observe(1, column(8, range(0, 2)))
    predictor.observe(2, column(9, range(0, 2)))
    assert len(predictor.entering(2, 5)) == 0


@pytest.mark.parametrize("bad", [-1, 1.5, True, "4"])
def test_predict_ticks_must_be_a_non_negative_integer(bad):
    with pytest.raises(ValueError, match="predict_ticks"):
        tdp.NavigatorConfig(planner="accelerating", predict_ticks=bad)


@pytest.mark.parametrize("bad", [1, "yes", None])
def test_avoid_boxes_must_be_a_bool(bad):
    with pytest.raises(ValueError, match="avoid_boxes"):
        tdp.NavigatorConfig(planner="accelerating", avoid_boxes=bad)


def test_the_goal_layer_never_sees_a_prediction():
    """Two navigators fed the same moving boxes, one predicting: their goal layers are equal at every tick."""
    scenario = make_world("crossing", 100, 1)
    grid = tdp.GridMap(scenario.occupancy(0))
    plain, predicting = (tdp.Navigator(grid, scenario.start, scenario.goal,
                                       tdp.NavigatorConfig(planner="accelerating", predict_ticks=h))
                         for h in (0, 6))
    feeds = [WorldFeed(scenario.occupancy(0), scenario.goal) for _ in range(2)]
    for navigator in (plain, predicting):
        navigator.setup()
    for tick in range(1, 40):
        for navigator, feed in zip((plain, predicting), feeds):
            feed.update(navigator, scenario.occupancy(tick), scenario.goal)
            navigator.tick()
        np.testing.assert_array_equal(plain.engine.goal_distances(), predicting.engine.goal_distances())
    assert len(predicting.lookout.predictor.tracks) > 0


def test_a_whole_map_sent_again_each_tick_changes_no_layer_and_no_prediction():
    """A navigator fed the whole map every tick (a sensor's view, mostly as it was) against one fed the changes: the
    same node layers, goal layer and moves at every tick - prediction's held cells included (a map cell sent again as
    free must not free a node layer's cell held occupied)."""
    scenario = make_world("crossing", 60, 1)
    grid = tdp.GridMap(scenario.occupancy(0))
    config = tdp.NavigatorConfig(planner="accelerating", predict_ticks=6, updates_per_move=2)
    fed, resent = (tdp.Navigator(grid, scenario.start, scenario.goal, config) for _ in range(2))
    feed = WorldFeed(scenario.occupancy(0), scenario.goal)
    everything = np.ones(grid.shape, bool)
    for navigator in (fed, resent):
        navigator.setup()
    for tick in range(1, 30):
        feed.update(fed, scenario.occupancy(tick), scenario.goal)
        resent.update_map(everything, scenario.occupancy(tick)[everything])
        moves = [navigator.tick().next_cell for navigator in (fed, resent)]
        assert moves[0] == moves[1]
        for navigator in (fed, resent):
            navigator.move_robot(moves[0] or navigator.robot)
        np.testing.assert_array_equal(fed.engine.goal_distances(), resent.engine.goal_distances())
        cells = np.argwhere(everything)
        np.testing.assert_array_equal(fed.engine.sample(cells), resent.engine.sample(cells))
    assert fed.lookout.predicted.any() and np.array_equal(fed.lookout.predicted, resent.lookout.predicted)


@pytest.mark.parametrize("planner, size, seed", [("accelerating", 100, 0), ("exact", 60, 1)])
def test_avoiding_boxes_keeps_the_robot_out_of_their_way(planner, size, seed):
    """A sliding box drives onto the robot and sits on it (cluttered-100-0, accelerating nodes at K = 4: 26 ticks;
    cluttered-60-1, the exact planner - the oracle -: 7); with avoid_boxes the robot yields or steps aside and is
    never hit, and reaches the goal."""
    scenario = make_world("cluttered", size, seed)
    hits, modes = {}, {}
    for avoid in (False, True):
        record, _ = run_navigator(scenario, tdp.NavigatorConfig(planner=planner, avoid_boxes=avoid), 400)
        assert record["reached"] and record["collisions"] == 0
        hits[avoid], modes[avoid] = record["hits"], set(record["modes"])
    assert hits[False] > 0 and hits[True] == 0
    assert tdp.Mode.YIELD in modes[True] and tdp.Mode.YIELD not in modes[False]


@pytest.mark.parametrize("planner", ["exact", "accelerating", "plain-dp"])
def test_every_planner_steps_aside_from_a_box_on_a_tick_that_gives_no_move(planner):
    """No way to the goal (its corner walled off): every tick waits, and a box driving along the robot's row sat on
    it for 4 ticks; the lookout vetted only moves. A budgeted repair not yet at the robot gives such ticks too (on
    moving-target 200² at 0.3 ms: 53 hit ticks on two worlds, none now)."""
    occupied = np.zeros((20, 20), bool)
    occupied[0:3, 16] = occupied[3, 16:] = True
    box = tdp.Obstacle(box=(9, 0, 11, 2), waypoints=[(9, 18)], speed=0.5)
    scenario = tdp.Scenario(tdp.GridMap(occupied), (10, 10), (0, 19), obstacles=[box], max_ticks=60)
    hits, stepped = {}, {}
    for avoid in (False, True):
        record, _ = run_navigator(scenario, tdp.NavigatorConfig(planner=planner, avoid_boxes=avoid))
        hits[avoid] = record["hits"]
        path = record["trajectory"]
        stepped[avoid] = {mode for mode, here, there in zip(record["modes"], path, path[1:]) if here != there}
    assert hits == {False: 4, True: 0} and stepped == {False: set(), True: {Mode.YIELD}}


def test_avoiding_boxes_leaves_the_exact_planner_on_the_oracles_way_where_no_box_comes_near():
    scenario = make_world("rooms", 100, 1)  # doors that close, no box that moves
    record, _ = run_navigator(scenario, tdp.NavigatorConfig(avoid_boxes=True))
    assert record["reached"] and record["trajectory"] == oracle_run(scenario, tdp.NavigatorConfig(), 600)["trajectory"]


def test_a_misread_move_faster_than_a_cell_a_tick_leaves_the_axis_pace_unknown_not_impossible():
    """An L-shaped first edge (rows 20-22, cols 10-14: it moved the box along both axes), then a row 2 rows up and 4
    cols left (read as one move of 4 cols in 2 ticks - another box's cells, say), then the row moving up a cell a
    tick (rows 17, 16, 15). The cols' window said 4 cells in 2 ticks: a move every 0.75 ticks at most, less than the
    fewest (1), so no tick allowed the cols to stay and nothing the box enters was expected (hand-computed: rows 14
    and 13, cols 6-10, at the next tick and the one after). Faster than a cell a tick is a misread: the cols' pace is
    unknown, and the box may keep to its cols."""
    predictor = MotionPredictor((40, 40))
    predictor.observe(1, np.vstack([row(20, range(10, 15)), [(21, 14), (22, 14)]]))
    predictor.observe(2, np.zeros((0, 2)))
    for tick, at in ((3, 18), (4, 17), (5, 16), (6, 15)):
        predictor.observe(tick, row(at, range(6, 11)))
    arrivals = predictor.arrivals(6, 2)
    assert all(arrivals.get((14, col), math.inf) <= 1 and arrivals.get((13, col), math.inf) <= 2
               for col in range(6, 11))


def test_two_boxes_whose_edges_touch_as_they_pass_keep_their_own_tracks():
    """Box A (rows 10-12) going right and box B (rows 13-15) going left, a cell a tick each, in touching lanes: at
    tick 6 both leading columns are at col 10, one cluster of 6 cells. It continued B's track alone, and A's, coasting,
    expected col 11 at the second tick ahead, where A enters it at the first (hand-computed). Split between the
    tracks' expected fronts, each box keeps its track: col 11 (rows 10-12) and col 9 (rows 13-15) at the next tick."""
    predictor = MotionPredictor((30, 30))
    for tick in range(1, 7):
        predictor.observe(tick, np.vstack([column(4 + tick, range(10, 13)), column(16 - tick, range(13, 16))]))
    arrivals = predictor.arrivals(6, 2)
    assert [arrivals.get((r, 11)) for r in range(10, 13)] == [1, 1, 1]
    assert [arrivals.get((r, 9)) for r in range(13, 16)] == [1, 1, 1]
    assert len(predictor.tracks) == 2


def test_a_cell_two_boxes_drive_into_arrives_at_the_earlier_of_their_ticks_whichever_box_is_tracked_first():
    """Two boxes closing on row 5's column 15 from either side: the one on the left at a cell a tick gets there at
    the fourth tick, the one on the right at two cells a tick at the third (hand-computed). The first box in the
    tracks' list set the tick, so with the slow one first the cell was expected a tick late."""
    predictor = MotionPredictor((20, 40))
    predictor.observe(1, np.vstack([column(10), column(23)]))
    predictor.observe(2, np.vstack([column(11), column(21)]))
    for tracks in (predictor.tracks[:], predictor.tracks[::-1]):
        predictor.tracks = tracks
        arrivals = predictor.arrivals(2, 4)
        assert [arrivals[(5, col)] for col in (12, 15, 17, 19)] == [1, 3, 2, 1]


def test_arrivals_near_a_cell_are_the_arrivals_within_its_radius():
    """The filter that spares the lookout its work far from the robot (``near``) leaves out no cell within the
    radius: the boxes of test_a_box_moving_one_cell_a_tick..., and one coming down at 2 cells a tick."""
    predictor = MotionPredictor((40, 40))
    for tick, (col, row) in enumerate([(10, 30), (11, 28)], start=1):
        predictor.observe(tick, np.vstack([column(col), [(row, c) for c in range(20, 24)]]))
    for ahead in (1, 2, 5):
        every = predictor.arrivals(2, ahead)
        assert every
        for cell in [(5, 12), (5, 20), (20, 21), (35, 5), (0, 39)]:
            for radius in (0, 2, 6):
                within = {c: t for c, t in every.items() if max(abs(c[0] - cell[0]), abs(c[1] - cell[1])) <= radius}
                near = predictor.arrivals(2, ahead, near=(cell, radius))
                assert {c: t for c, t in near.items() if c in within} == within
                assert predictor.may_reach(2, ahead, cell, radius) or not within
    assert not predictor.may_reach(2, 1, (35, 5), 2) and predictor.may_reach(2, 1, (5, 14), 1)


@pytest.mark.parametrize("planner", ["accelerating", "exact"])
@pytest.mark.parametrize("box_col", [12, 16])
def test_a_robot_yields_to_a_box_driving_across_its_way_instead_of_escorting_it(box_col, planner):
    """Open ground, the robot driving east along row 20, a 6 x 6 box driving south across its way at half a cell
    per tick. With avoid_boxes the robot waits for the box to pass and keeps to its row (within a cell); checking
    only its next cell, it stepped aside along the box's front, a cell per yield, down to row 43 (86 cells of path
    against 55)."""
    box = tdp.Obstacle((12, box_col, 18, box_col + 6), waypoints=((40, box_col),), speed=0.5)
    scenario = tdp.Scenario(tdp.GridMap(np.zeros((44, 60), bool)), (20, 2), (20, 57), obstacles=[box])
    config = tdp.NavigatorConfig(planner=planner, avoid_boxes=True, **({} if planner == "exact" else
                                                                       {"updates_per_move": 1}))
    record, _ = run_navigator(scenario, config, 300)
    rows = [row for row, _ in record["trajectory"]]
    assert record["reached"] and record["collisions"] == 0 and record["hits"] == 0
    assert 19 <= min(rows) and max(rows) <= 21 and record["length"] < 56.0


def test_a_diagonal_box_may_turn_back_into_the_cell_diagonally_behind_its_corner():
    """A 3 x 3 box going down and to the right a cell a tick along both axes (rows and cols t..t + 2 at tick t): at
    tick 3 it covers rows and cols 3-5, and turned back it enters row 2 (cols 2-4), col 2 (rows 2-4) and, by its
    corner, the cell (2, 2) diagonally behind it, which neither axis's walk back reaches (hand-computed)."""
    predictor = MotionPredictor((20, 20))
    occupied = np.zeros((20, 20), bool)
    for tick in (1, 2, 3):
        box = np.zeros((20, 20), bool)
        box[tick:tick + 3, tick:tick + 3] = True
        predictor.observe(tick, np.argwhere(box & ~occupied))
        occupied = box
    assert (2, 2) in cells_of(predictor.behind(3, occupied))
    assert cells_of(predictor.behind(3, occupied)) <= {(2, c) for c in range(2, 6)} | {(r, 2) for r in range(2, 6)}


@pytest.mark.parametrize("planner", ["exact", "accelerating"])
@pytest.mark.parametrize("end_col", [10, 11, 12])
@pytest.mark.parametrize("speed", [0.5, 1.0])
def test_a_robot_crossing_a_lane_does_not_step_in_right_behind_a_box_that_may_turn_back(speed, end_col, planner):
    """Open ground, the robot going down column 10 across a lane where a 3 x 3 box (rows 8-10) shuttles between
    columns 0 and ``end_col`` + 2. With the box turning back at columns 11-13 at half a cell a tick, the robot
    stepped into the lane right behind it (column 10) and was driven over as it turned (6 hit ticks): the box was
    expected only ahead of it. With avoid_boxes no box may be on the robot, whatever the lane's end and speed."""
    box = tdp.Obstacle((8, 0, 11, 3), waypoints=((8, end_col), (8, 0)) * 6, speed=speed)
    scenario = tdp.Scenario(tdp.GridMap(np.zeros((20, 24), bool)), (1, 10), (18, 10), obstacles=[box], max_ticks=200)
    config = tdp.NavigatorConfig(planner=planner, avoid_boxes=True, **({} if planner == "exact" else
                                                                       {"updates_per_move": 1}))
    record, _ = run_navigator(scenario, config)
    assert record["reached"] and record["hits"] == 0


def test_a_box_three_cells_a_tick_is_tracked_and_its_next_cells_predicted():
    """A 3 x 3 box going right 3 cells a tick (cols 0-2, 3-5, 6-8 at ticks 1-3: each tick's new cells are the whole
    box): one track at 3 cells a tick, the cells it sweeps at the next tick (cols 9-11 of rows 10-12) predicted.
    Tracked up to 2 cells a tick (the default before), each edge was a new box: three tracks, no velocity, nothing
    predicted."""
    def watched(predictor):
        for tick, col in ((1, 0), (2, 3), (3, 6)):
            predictor.observe(tick, np.array([(row, c) for row in range(10, 13) for c in range(col, col + 3)]))
        return predictor

    tracked = watched(MotionPredictor((30, 40)))
    assert [track.velocity.tolist() for track in tracked.tracks] == [[0.0, 3.0]]
    next_tick = {cell for cell, tick in tracked.arrivals(3, 1).items() if tick == 1}
    assert {(row, col) for row in range(10, 13) for col in range(9, 12)} <= next_tick
    before = watched(MotionPredictor((30, 40), max_speed=2.0))
    assert len(before.tracks) == 3 and not before.arrivals(3, 1)


def test_an_edge_beyond_a_slow_tracks_reach_does_not_take_it():
    """A column of 3 cells going right half a cell a tick (col 10, 11, 12 at ticks 1, 3, 5); at tick 6 another box's
    column appears 4 cells behind it, a row lower. Within the 4 cells a tick that fast boxes are tracked at, but
    beyond NEAR_SPEED's 2 and not where the track's velocity expects it: it starts a track of its own, and the slow
    track keeps its velocity. Read at 4 cells a tick from the start, it took the slow track (as a box turned back),
    as boxes crossing each other's lanes swapped tracks on held-out worlds and one drove onto the robot."""
    def column(col, top):
        return np.array([(row, col) for row in range(top, top + 3)])

    predictor = MotionPredictor((30, 40))
    for tick, col in ((1, 10), (3, 11), (5, 12)):
        predictor.observe(tick, column(col, 5))
    predictor.observe(6, column(8, 6))
    velocities = {track.bounds: None if track.velocity is None else track.velocity.tolist()
                  for track in predictor.tracks}
    assert velocities == {(5, 12, 7, 12): [0.0, 0.5], (6, 8, 8, 8): None}


def test_a_face_carried_past_the_maps_edge_is_walked_back_from_inside_the_map_alone():
    """A box going right a cell a tick along rows 6-9, its edge at col 58 of a 60-column map, carries a row face that
    a misread cluster gave it (two touching boxes read as one L, then moved on with the box: seen at 6x the
    families' speed) to cols 58-60, past the map's edge. ``behind`` indexed the map with it (IndexError; a face at a
    negative row would have read the map's last row instead); it walks back from the front's cells inside the map
    alone: col 54 of rows 6-9, behind the box, and (5, 57) behind the face (hand-computed)."""
    edge = np.array([(row, 58) for row in range(6, 10)])
    face = np.array([(5, col) for col in range(58, 61)])
    track = Track(edge, 23, (6, 58, 9, 58), np.array([0.0, 1.0]),
                  ((22, np.array([7.5, 57.0])), (23, np.array([7.5, 58.0]))),
                  (22, np.array([7.5, 57.0]), (False, True)), ((), ((23, 58.0),)), (face, edge))
    predictor = MotionPredictor((60, 60))
    predictor.tracks = [track]
    occupied = np.zeros((60, 60), bool)
    occupied[6:10, 55:59] = occupied[5, 58:60] = True
    assert cells_of(predictor.behind(23, occupied)) == {(5, 57)} | {(row, 54) for row in range(6, 10)}


def test_a_moving_box_may_turn_back_into_the_cell_behind_it():
    """A 3 x 3 box going right (edges at columns 10, 11, 12 at ticks 1-3) covers columns 10-12 of rows 4-6: if it
    turns back, it enters column 9 at the next tick, the first free cell behind its front, walked back through the
    box (hand-computed). Two cells past it lies a wall, which is not walked through. A box that stopped (7 ticks
    without an edge) turns back into nothing. Near a cell, only the cells within the radius of it count."""
    predictor = MotionPredictor((20, 30))
    occupied = np.zeros((20, 30), bool)
    occupied[4:7, 10:13] = occupied[:, 5:8] = True
    for tick, col in ((1, 10), (2, 11), (3, 12)):
        predictor.observe(tick, column(col))
    assert cells_of(predictor.behind(3, occupied)) == cells_of(column(9))
    assert cells_of(predictor.behind(3, occupied, near=((5, 8), 1))) == cells_of(column(9))
    assert cells_of(predictor.behind(3, occupied, near=((2, 9), 2))) == {(4, 9)}  # the cells within the radius
    assert predictor.behind(3, occupied, near=((5, 28), 2)).size == 0  # no box behind which it could turn back
    occupied[4:7, 8:10] = True  # the box 5 cells deep, against the wall
    assert cells_of(predictor.behind(3, occupied)) == set()
    for tick in range(4, 11):
        predictor.observe(tick, np.zeros((0, 2)))
    occupied[4:7, 8:10] = False
    assert predictor.behind(10, occupied).size == 0


def test_prediction_turns_the_robot_earlier_when_a_box_moves_into_its_passage():
    scenario = tdp.scenarios.get("moving-blockage")
    route = unblocked_route(scenario)
    turns = {}
    for horizon in (0, 4):
        config = tdp.NavigatorConfig(planner="accelerating", updates_per_move=1, predict_ticks=horizon)
        record, _ = run_navigator(scenario, config)
        assert record["reached"]
        turns[horizon] = turn_and_closest(scenario, record["trajectory"], route)["turn_after"]
    assert turns[4] <= turns[0] - 3


def test_a_box_that_turned_keeps_the_turns_pace_along_the_axis_it_has_not_moved_on_since():
    """A one-cell box going down and to the right, a row and a col in turn (ticks 1-5), turns: a move left at tick
    6 (its track restarts, taken to come back up and to the left), a move up at tick 7. Its next move left may come
    at tick 8: the turn's velocity is kept along the cols its edges have not moved since, and its pace there is the
    box's speed (a third and two thirds of a cell a tick over its last edges: 0.75), counted from the turn. Read
    from the move up alone, it was going straight up, and the cell to its left, where a robot stood, was flagged by
    nothing (wandering-60-61 of the tuning seeds)."""
    predictor = MotionPredictor((30, 30))
    for tick, cell in enumerate([(10, 10), (11, 10), (11, 11), (12, 11), (12, 12), (12, 11), (11, 11)], start=1):
        predictor.observe(tick, np.array([cell]))
    track, = predictor.tracks
    assert track.velocity[1] < 0 and track.turn_speed == pytest.approx(math.hypot(1 / 3, 2 / 3))
    arrivals = predictor.arrivals(7, 2)
    assert arrivals.get((11, 10)) == 1 and arrivals.get((10, 11)) == 1  # left, or up again, at the next tick


def test_a_cells_gap_to_a_moving_box_is_measured_to_the_box_as_the_map_shows_it():
    """A 2 x 2 box going right a cell a tick (rows 5-6; its leading column at col 10, then 11) covers cols 10-11;
    a wall cell lies at (5, 20). Gaps (hand-computed): 0 at (5, 10), in it; 1 at (4, 10) above it, (7, 12) by its
    corner and (6, 9) behind it; 2 at (5, 13) and (3, 11); 3 - further than GAP_MOST - at (5, 14) and at (4, 20),
    by the wall, which lies beyond the box's reach. Once the box stops (no edge for 6 ticks) no cell is near a
    moving box."""
    predictor = MotionPredictor((20, 30))
    predictor.observe(1, column(10, range(5, 7)))
    predictor.observe(2, column(11, range(5, 7)))
    occupied = np.zeros((20, 30), bool)
    occupied[5:7, 10:12] = occupied[5, 20] = True
    cells = [(5, 10), (4, 10), (7, 12), (6, 9), (5, 13), (3, 11), (5, 14), (4, 20)]
    assert GAP_MOST == 2 and predictor.box_gaps(2, occupied, cells).tolist() == [0, 1, 1, 1, 2, 2, 3, 3]
    for tick in range(3, 9):
        predictor.observe(tick, np.zeros((0, 2)))
    assert (predictor.box_gaps(8, occupied, cells) == 3).all() and predictor.box_gaps(8, occupied, []).size == 0


@pytest.mark.parametrize("turn_col", [14, 17])
def test_a_robot_keeps_clear_of_a_box_passing_beside_it_that_turns_onto_its_way(turn_col):
    """Open ground, the robot driving east along row 10, a 2 x 2 box driving west along rows 11-12 at half a cell a
    tick, beside the robot's row, then turning north across it at ``turn_col``. Nothing predicted the box's cells
    on row 10 before it turned: the robot drove next to the box and was driven over (col 17: 4 hit ticks, with
    avoidance or without). Kept off the cells beside a moving box it is never hit - if it also steps off such a cell
    once the box comes beside it: only kept from stepping onto one, it waited beside the box as it passed and was
    driven over at col 14 (4 hit ticks; none without avoidance)."""
    box = tdp.Obstacle(box=(11, 24, 13, 26), waypoints=[(11, turn_col), (2, turn_col)], speed=0.5)
    scenario = tdp.Scenario(tdp.GridMap(np.zeros((24, 32), bool)), (10, 2), (10, 29), obstacles=[box], max_ticks=120)
    for avoid in (False, True):
        record, _ = run_navigator(scenario, tdp.NavigatorConfig(avoid_boxes=avoid))
        assert record["reached"] and record["collisions"] == 0
        assert (record["hits"] > 0) == (not avoid and turn_col == 17)


def test_a_robot_stepping_off_a_cell_next_to_a_box_steps_away_from_it_rather_than_escort_it():
    """crossing-60-418 of the held-out seeds, accelerating nodes at K = 1: a 3 x 3 box shuttles diagonally across
    the robot's way. Stepping off each cell the box came beside to the clear cell nearest the goal, the robot kept
    just ahead of the box's corner and escorted it, back and forth, for 250 ticks (334 against the oracle's 53);
    away from the box first, it lets the box pass (84)."""
    scenario = make_world("crossing", 60, 418)
    config = tdp.NavigatorConfig(planner="accelerating", updates_per_move=1, avoid_boxes=True)
    record, _ = run_navigator(scenario, config, 400)
    oracle = oracle_run(scenario, tdp.NavigatorConfig(), 400)
    assert record["reached"] and record["hits"] == 0
    assert record["ticks"] <= 2 * (len(oracle["trajectory"]) - 1)


def test_a_fast_boxs_gaps_shrink_by_the_cells_it_may_cover_beyond_one_in_a_tick():
    """The 2 x 2 box of the test above going right at 3 cells a tick (its leading column at col 8, then 11; it
    covers cols 10-11): (5, 14) is 3 cells from it, less the 2 cells beyond one that it may cover in a tick: 1, next
    to it; (5, 15) 2; (5, 17), 6 cells away, further than GAP_MOST (hand-computed). At a cell a tick or less nothing
    is taken off (the test above)."""
    predictor = MotionPredictor((20, 30))
    predictor.observe(1, column(8, range(5, 7)))
    predictor.observe(2, column(11, range(5, 7)))
    occupied = np.zeros((20, 30), bool)
    occupied[5:7, 10:12] = True
    assert predictor.tracks[0].speed == 3.0
    assert predictor.box_gaps(2, occupied, [(5, 14), (5, 15), (5, 17)]).tolist() == [1, 2, 3]


def test_a_step_aside_takes_a_clear_cell_the_cheapest_when_driven_onto_and_the_furthest_when_only_beside():
    """``step_aside`` on hand-made options (cell, cost, first arrival, gap to a box). Clear cells (no arrival within
    2 ticks, not next to a box) come first. A robot a box is about to drive onto takes the cheapest of them; one a box
    only came beside takes the furthest from the boxes (toward the goal it escorted a box shuttling across its way),
    and stays where none is clear; driven onto with none clear, it takes the cheapest that no box enters at the next
    tick."""
    cells = [(0, 0), (0, 1), (0, 2), (0, 3)]
    costs = np.array([5.0, 3.0, 1.0, 2.0])
    arrivals = [math.inf, math.inf, 2, math.inf]
    gaps = np.array([3, 2, 3, 1])
    assert step_aside(cells, costs, arrivals, gaps, 2, entered=True) == (0, 1)
    assert step_aside(cells, costs, arrivals, gaps, 2, entered=False) == (0, 0)
    assert step_aside(cells[2:], costs[2:], arrivals[2:], gaps[2:], 2, entered=False) is None
    assert step_aside(cells[2:], costs[2:], arrivals[2:], gaps[2:], 2, entered=True) == (0, 2)
