"""Obstacle motion from the map updates alone: the paper's closing suggestion, "obstacle motion may be extrapolated
for early blockage predictions" (ARCHITECTURE §5.7).

A box moving over the grid shows, tick by tick, a leading edge: the cells that become occupied. Those cells are
grouped into 8-connected clusters; a cluster is matched to the track whose last edge it could have come from (a
similar number of cells, moved within NEAR_SPEED cells per elapsed tick - up to ``max_speed`` where it may be a fast
box's edge: :func:`edge_shift`, :func:`_fast`), and its displacement over the ticks between them is the track's
velocity. A box moving across rows and cols at once moves them on different ticks: each axis keeps its own moves
(the edges that moved the box along it), from which come the ticks a move along it takes, and the face its last move
along it showed (the box's top row, for one going up), which is moved along with it; the cells ahead are those of
its last edge and its faces. A track with no move along any axis within the most ticks its edges allow a move along
it has stopped and is dropped.

The model is constant velocity in a straight line: it cannot foresee a box turning, reversing or stopping (it
learns of each from the next edge it sees, one or two ticks late; a box that turns is then taken to come back at the
velocity it went, each axis's next move due at the box's speed), and it knows nothing of obstacles that do not
move. A box seen once (a new box, or one whose edge no track could have shown: a box turning back at the end of its
run shows its far face) has no velocity yet: the cells it enters are predicted from its second edge on, and until
then it may step a cell either way along the axes its edge's shape shows (:meth:`MotionPredictor.arrivals`). No world
ids are used.
"""
from __future__ import annotations

import math
from dataclasses import dataclass, field
from functools import cached_property, lru_cache

import numpy as np

#: Offsets of the 8-neighbourhood, for clustering the cells that became occupied.
_AROUND = [(dr, dc) for dr in (-1, 0, 1) for dc in (-1, 0, 1) if (dr, dc) != (0, 0)]
#: The farthest from a moving box, in cells, that :meth:`MotionPredictor.box_gaps` tells apart.
GAP_MOST = 2
#: The most cells :meth:`MotionPredictor.box_gaps` takes off a fast box's gaps: one less than the cells it may cover
#: in a tick (a box tracked at up to 4 cells a tick).
FAST_REACH = 3
_NEAR = GAP_MOST + FAST_REACH
_NEAR_OFFSETS = np.array([(dr, dc) for dr in range(-_NEAR, _NEAR + 1) for dc in range(-_NEAR, _NEAR + 1)], np.int64)
_NEAR_GAPS = np.abs(_NEAR_OFFSETS).max(axis=1)


#: Edges a track remembers, and moves along each axis: its velocity is the mean over its last edges (a box at 0.3
#: cells per tick shows edges 3, 3 and 4 ticks apart; one interval alone says 0.33 or 0.25), the ticks a move along an
#: axis takes come from its last moves along it (Track.periods).
HISTORY = 4
#: The most cells an edge may lie from where a track's velocity expects it for the pair to be taken before those that
#: do not fit (:meth:`MotionPredictor._assign`): a box's place rounds to whole cells either way, and its edges by a
#: cell.
FIT = 1.0
#: Cells per elapsed tick within which an edge and a track are matched first (:meth:`MotionPredictor._assign`); pairs
#: further apart, up to ``max_speed``, match only the edges and tracks left over. Read at 4 cells a tick from the
#: start, two boxes shuttling across each other's lanes at half a cell a tick swapped tracks and one drove onto the
#: robot (crossing-60-431, -100-511 of the held-out seeds); read at 2, boxes at 2-3 cells a tick were new boxes every
#: tick, never predicted (RESULTS §8).
NEAR_SPEED = 2.0


@dataclass
class Track:
    """One moving obstacle: its last leading ``edge`` ((n, 2) cells), the ``tick`` it was seen, the edge's
    ``bounds`` (least row and col, then greatest: :func:`_bounds`, taken once for matching it), its ``velocity``
    (rows, cols per tick, over its last HISTORY edges; None until it has been matched once), those edges'
    (tick, position): the first edge's centre, moved on by each :func:`edge_shift` since, the ``origin``: the (tick,
    position) of the edge the track (re)started from and the axes it surely moved the box along
    (:func:`_moved_along`), per axis (rows, cols) the (tick, place along it) of the last HISTORY edges since then that
    moved the box along it, per axis the ``faces``: the last edge that moved the box along it, brought along with
    the box since (None before the first), the slowest speed tracked (``min_speed``, cells per tick) and, for a track
    that restarted at a turn, the box's speed then (``turn_speed``, its velocity's length; 0 for a track that started
    with no velocity)."""

    edge: np.ndarray
    tick: int
    bounds: tuple[int, int, int, int]
    velocity: np.ndarray | None = None
    seen: tuple = ()
    origin: tuple = ()
    axis_moves: tuple = ((), ())
    faces: tuple = (None, None)
    min_speed: float = 0.25
    turn_speed: float = 0.0
    speed: float = field(init=False)  # the velocity's largest row or col component, in cells per tick (0: unknown)

    def __post_init__(self):
        self.speed = 0.0 if self.velocity is None else float(np.abs(self.velocity).max())

    @cached_property
    def periods(self) -> tuple[tuple[float, float] | None, tuple[float, float] | None]:
        """Per axis (rows, cols) of a box no faster than a cell per tick, the fewest and the most ticks a one-cell move
        along it may take as the edges seen allow (None along an axis it does not move on), from the edges that
        moved it along that axis (:attr:`axis_moves`; a diagonal box moves its rows and its cols on different ticks,
        and an edge that moved only its cols says nothing of when its rows moved): n cells moved between edges S
        ticks apart, each seen at the first tick after the move, say the period P lies between (S - 1) / n and
        (S + 1) / n. A box at 0.375 cells per tick moves every 2 or 3 ticks; three moves seen 3 ticks apart say 0.33,
        and a window of whole periods of 3 ticks missed the move that came after 2. The edge the track started from
        counts as a move along the axis where its shape says it moved the box along it (:func:`_moved_along`). With
        one move, a tick or more (the first reads of a diagonal box, before its direction is known, may have taken a
        move along one axis for none: a single cell, then a row of two, may be a move up or up and left); with
        none since the start, 1 / speed and up to a tick more, but since a turn from 1 / ``turn_speed`` on: a box
        turning at any angle may put all its speed on either axis, at a phase its old moves do not give (a one-cell
        box going down and to the right turned up and to the left, a move left, then up, then left a tick later, and
        drove onto the robot beside it: wandering-60-61 of the tuning seeds)."""
        start_tick, start, start_moved = self.origin
        return tuple(_periods(abs(speed), (start_tick, place), moves, moved, self.turn_speed)
                     for speed, place, moves, moved in zip(self.velocity.tolist(), start.tolist(), self.axis_moves,
                                                           start_moved))

    @cached_property
    def moved_at(self) -> tuple[int, int]:
        """Per axis (rows, cols), the tick of the last edge that moved the box along it (the edge the track started
        from, where none did): a box going up and to the right at unequal speeds shows its rows' moves and its cols'
        apart, and its next move up is due counting from its last move up, not from its last edge."""
        return tuple(moves[-1][0] if moves else self.origin[0] for moves in self.axis_moves)

    @cached_property
    def signs(self) -> np.ndarray:
        """Per axis (rows, cols), the way the box moves along it (-1, 0 or 1): that of its last move along it, or of
        its velocity where it has made none since the track started (a box moving right with a slow drift up shows
        no move up in most of its last HISTORY edges)."""
        return np.array([np.sign(moves[-1][1] - (moves[-2][1] if len(moves) > 1 else self.origin[1][axis]))
                         if moves else np.sign(self.velocity[axis]) for axis, moves in enumerate(self.axis_moves)],
                        np.int64)

    @cached_property
    def front(self) -> np.ndarray:
        """The cells ((n, 2)) the box leads with: its last edge and its faces (:class:`Track`). A box going up and to
        the right shows its right column after a move right, and its next move up covers its whole top row, which
        that column shifted up does not: the face its last move up showed, brought right with it, does."""
        faces = [face for face in self.faces if face is not None and face is not self.edge]
        return np.vstack([self.edge] + faces) if faces else self.edge  # a cell twice is flagged once

    @cached_property
    def front_bounds(self) -> tuple[int, int, int, int]:
        """The least row and col of :attr:`front`'s cells, then the greatest."""
        return _bounds(self.front)

    @cached_property
    def sizes(self) -> tuple[int, int]:
        """The fewest and the most cells of the track's last edge and faces."""
        sizes = [len(self.edge)] + [len(face) for face in self.faces if face is not None]
        return min(sizes), max(sizes)

    @property
    def position(self) -> np.ndarray:
        """Where the track is (rows, cols): its first edge's centre moved on by each shift seen since."""
        return self.seen[-1][1]

    @cached_property
    def moving_until(self) -> int:
        """The last tick the obstacle is still taken to be moving: along some axis, its next move is due within the
        most ticks a one-cell move along it may take (:attr:`periods`, rounded up; at most 1 / ``min_speed``, and
        that and a tick more while its velocity is not known yet), counted from its last move along that axis
        (:attr:`moved_at`). Not from its velocity: a diagonal box at a third of a cell a tick may show its first two
        edges a tick apart, a move down and then one right, and read a cell a tick."""
        slowest = 1.0 / self.min_speed
        if self.velocity is None:
            return self.tick + math.ceil(slowest) + 1
        return max((moved + math.ceil(min(periods[1], slowest))
                    for periods, moved in zip(self.periods, self.moved_at) if periods is not None), default=-1)


class MotionPredictor:
    """Tracks moving obstacles from the cells that become occupied each tick and predicts the cells they enter.

    ``max_speed`` and ``min_speed``: the fastest and slowest obstacles to track, in cells per tick (a faster one is
    seen as a new obstacle each tick, a slower one as one that stopped, and neither is predicted); one faster than
    NEAR_SPEED is tracked where no nearer edge takes its track."""

    def __init__(self, shape: tuple[int, int], max_speed: float = 4.0, min_speed: float = 0.25):
        self.shape = (int(shape[0]), int(shape[1]))
        self.max_speed, self.min_speed = float(max_speed), float(min_speed)
        self.tracks: list[Track] = []

    def observe(self, tick: int, became_occupied: np.ndarray) -> None:
        """Take the cells ((n, 2) row, col) that became occupied at ``tick`` (ticks must not go back)."""
        previous = [track for track in self.tracks if tick <= track.moving_until]
        expected = _expected_fronts(previous, tick)
        edges, bounds = [], []
        for cluster in clusters(np.asarray(became_occupied, np.int64).reshape(-1, 2)):
            around = _bounds(cluster)
            pieces = _split_by_fronts(cluster, around, expected)
            edges += pieces
            bounds += [around] if len(pieces) == 1 else [_bounds(piece) for piece in pieces]  # one piece: all of it
        continues = self._assign(edges, bounds, tick, previous)
        tracks = []
        for k, edge in enumerate(edges):
            if k in continues:
                i, shift = continues[k]
                tracks.append(_continued(previous[i], edge, tick, bounds[k], shift))
            else:
                centre = edge.sum(axis=0) / len(edge)  # without np.mean's dispatch
                tracks.append(_started(edge, tick, bounds[k], centre, None, self.min_speed))
        matched = {i for i, _ in continues.values()}
        self.tracks = tracks + [track for i, track in enumerate(previous) if i not in matched]

    def _assign(self, edges: list[np.ndarray], bounds: list[tuple[int, int, int, int]], tick: int,
                previous: list[Track]) -> dict[int, tuple[int, np.ndarray]]:
        """Which previous track each new edge (its cells and their ``bounds``) continues, by index, and the edge's
        shift from the track's last (:func:`_reading`): every pair within the reach of NEAR_SPEED and of a similar
        size (half the smallest to twice the largest of the track's last edge and faces: a 5 x 7 box going diagonally
        shows edges of 5, 7 and 11 cells), taken first those within ``FIT`` of where the track's velocity expects its
        edge (:func:`_reading`), the best fit first, then those where the box may have turned back
        (:func:`_turned_back`: its far face, up to twice the face's length further than a track's reach), then the
        rest nearest first, each edge and each track at most once; then, in the same order, the pairs within the
        reach of ``max_speed`` that :func:`_fast` allows, among the edges and tracks left. Without the second rank a
        box that turned back at full speed lay beyond its track's reach, and its far face took a box's track in the
        next lane. Taken edge by edge, nearest first, an edge read first could take another box's track, whose own
        edge, a velocity's move on, then started a track of its own."""
        pairs = []
        for k, (edge, bound) in enumerate(zip(edges, bounds)):
            for i, track in enumerate(previous):
                elapsed = tick - track.tick
                if elapsed <= 0 or not 0.5 * track.sizes[0] <= len(edge) <= 2.0 * track.sizes[1]:
                    continue
                turned = 2 * len(edge)  # the most a far face turned back lies past the reach
                if _gap(track.bounds, bound) > self.max_speed * elapsed + 0.5 + turned:  # a shift is at least the gap
                    continue
                distance = float(np.abs(edge_shift(track.bounds, bound)).max())
                turned *= _turned_back(track, edge, bound)
                far = distance > NEAR_SPEED * elapsed + 0.5 + turned
                if 0 < distance <= self.max_speed * elapsed + 0.5 + turned:
                    shift, miss = _reading(track, edge, bound, tick)
                    if far and not _fast(track, edge, bound, shift, miss):
                        continue
                    rank = (0, miss) if miss <= FIT else (1 if turned else 2, distance)
                    pairs.append(((far,) + rank, k, i, shift))
        continues: dict[int, tuple[int, np.ndarray]] = {}
        taken: set[int] = set()
        for _, k, i, shift in sorted(pairs, key=lambda pair: pair[:3]):
            if k not in continues and i not in taken:
                continues[k] = i, shift
                taken.add(i)
        return continues

    def arrivals(self, tick: int, ahead: int, across: np.ndarray | None = None,
                 near: tuple[tuple[int, int], float] | None = None) -> dict[tuple[int, int], int]:
        """For each cell (inside the map) a tracked box may move into within ``ahead`` ticks after ``tick``, the
        first such tick (1 = the next) over every box. A box no faster than a cell per tick moves a cell at a time
        along each axis, rows and cols apart, every P ticks, P within what its edges allow (:attr:`Track.periods`):
        its k-th move along an axis after its last edge comes floor(k P) ticks after it at the earliest (a box seen
        every other tick is not expected every tick), a move overdue (no edge seen since it was due) from the next
        tick on, and a cell is flagged from the first tick both its rows' and its cols' moves fit (a diagonal box
        keeps one pace on both); a faster one sweeps as in :meth:`entering`; one seen once, whose way is not known
        yet, a cell either way at the next tick along each axis its edge's shape says it moved along (a box turning
        back at the end of its run shows its far face, which no track's velocity expects). With ``across`` (a
        direction, rows and cols), only the boxes that move across it (at more than 45 degrees to it either way; not
        those seen once, whose one tick ahead the next cell's test covers); with ``near`` (a cell and a radius in
        cells), only those that may come within the radius of the cell (:func:`_may_reach`): the cells it leaves out
        all lie beyond it."""
        moves = [(track.front, *self._moves(track, tick - track.tick, ahead))
                 for track in self._moving(tick, ahead, near, seen_once=True)
                 if across is None or track.velocity is not None and _crosses(track.velocity, across)]
        if not moves:
            return {}
        cells = np.vstack([_shifted(edge, offsets) for edge, offsets, _ in moves])
        steps = np.concatenate([np.repeat(steps, len(edge)) for edge, _, steps in moves])
        inside = self._inside(cells)
        flat, steps = cells[inside, 0] * self.shape[1] + cells[inside, 1], steps[inside]
        by_step = np.argsort(steps, kind="stable")
        first, index = np.unique(flat[by_step], return_index=True)  # a cell's first place: its earliest step
        rows, cols = np.divmod(first, self.shape[1])
        return dict(zip(zip(rows.tolist(), cols.tolist()), steps[by_step][index].tolist()))

    def behind(self, tick: int, occupied: np.ndarray, near: tuple[tuple[int, int], float] | None = None
               ) -> np.ndarray:
        """Cells ((n, 2), inside the map) that the boxes moving at ``tick`` would enter at the next tick if they
        turned back: along each axis a box moves on (and diagonally, where it moves on both: :func:`_ways_back`), the
        first cell free in ``occupied`` ((H, W) bool, the map now) behind its front (:attr:`Track.front`; its cells
        inside the map), walked back through the box - at most twice its largest edge or face deep. With ``near`` (a
        cell and a radius in cells), only those within the radius of the cell (in rows and in cols), and only the
        walks that pass there are made.
        The constant-velocity model learns that a box turned back from its next edge: a robot that stepped in right
        behind one was driven over as it turned (passing-60-423, -469), and one diagonally behind a diagonal box's
        corner (crossing-60-23 with its boxes at twice their speed)."""
        fronts, ways, depths = [], [], []
        for track in self._moving(tick):
            depth = 2 * track.sizes[1]
            if near is not None and not _may_reach(track, tick, near[0], near[1] + depth + track.sizes[1]):
                continue  # its faces lie within a box's side of its edge, the cells behind within depth of those
            back = -np.sign(track.velocity).astype(np.int64)
            for way in _ways_back(back):
                fronts.append(track.front)
                ways.append(way)
                depths.append(depth)
        if not fronts:
            return np.zeros((0, 2), np.int64)
        counts = [len(front) for front in fronts]
        cells = np.vstack(fronts)
        ways, depths = np.repeat(np.array(ways, np.int64), counts, axis=0), np.repeat(depths, counts)
        # where the box still is; a face moved on with its box may lie past the map's edge (a misread cluster)
        _, walked = self._occupied_at(occupied, cells)
        if near is not None:
            walked &= _within(cells + ways, cells + ways * depths[:, None], *near)
        found = self._first_free(cells[walked], ways[walked], depths[walked], occupied)
        if near is not None:
            found = found[_within(found, found, *near)]
        flat = np.unique(found[:, 0] * self.shape[1] + found[:, 1])
        return np.column_stack(np.divmod(flat, self.shape[1]))

    def box_gaps(self, tick: int, occupied: np.ndarray, cells: list[tuple[int, int]]) -> np.ndarray:
        """How far each of ``cells`` (row, col pairs inside the map) lies from a box moving at ``tick``, in cells (rows
        and cols; 0 inside it, 1 next to it; GAP_MOST + 1 where further): from the nearest cell occupied in
        ``occupied`` ((H, W) bool, the map now) within the box's largest edge or face of its front
        (:attr:`Track.front`), either way - the box as the map shows it, since the tracker sees its leading edges
        alone (an obstacle that close to it counts too) -, less the cells beyond one that a box faster than a cell a
        tick may cover in one (ceil(speed) - 1, FAST_REACH at most; never below 0). A box turning at any angle drives
        onto a robot next to it - a fast one onto a robot within its tick's reach - a tick after its edge shows the
        turn."""
        gaps = np.full(len(cells), GAP_MOST + 1, np.int64)
        if not cells:
            return gaps
        cells = np.asarray(cells, np.int64)
        asked = _bounds(cells)
        zones = [(track.front_bounds, track.sizes[1], min(FAST_REACH, max(math.ceil(track.speed) - 1, 0)))
                 for track in self._moving(tick)]
        zones = [zone for zone in zones if _gap(zone[0], asked) <= zone[1] + GAP_MOST + zone[2]]
        if not zones:
            return gaps
        around = cells[:, None, :] + _NEAR_OFFSETS[None]
        _, taken = self._occupied_at(occupied, around)
        for (r0, c0, r1, c1), depth, reach in zones:
            boxed = (taken & (around[..., 0] >= r0 - depth) & (around[..., 0] <= r1 + depth)
                     & (around[..., 1] >= c0 - depth) & (around[..., 1] <= c1 + depth))
            near = np.where(boxed, np.maximum(_NEAR_GAPS[None] - reach, 0), GAP_MOST + 1)
            gaps = np.minimum(gaps, near.min(axis=1))
        return gaps

    def _first_free(self, cells: np.ndarray, ways: np.ndarray, depths: np.ndarray, occupied: np.ndarray
                    ) -> np.ndarray:
        """For each of ``cells`` ((n, 2)), the first cell free in ``occupied`` within its ``depths`` steps of one
        cell the way of its row of ``ways`` ((n, 2), a unit step along an axis or diagonally), where there is one
        before the map's edge (m <= n rows): every cell's walk in one set of array operations, as deep as the
        deepest."""
        if not len(cells):
            return cells
        steps = np.arange(1, int(depths.max()) + 1)
        line = cells[:, None, :] + ways[:, None, :] * steps[None, :, None]
        on_map, taken = self._occupied_at(occupied, line)
        inside = on_map & (steps[None, :] <= depths[:, None])
        free = inside & ~taken
        first = np.argmax(free | ~inside, axis=1)  # the walk ends at a free cell, its depth or the map's edge
        rows = np.arange(len(cells))
        return line[rows, first][free[rows, first]]

    def may_reach(self, tick: int, ahead: int, cell: tuple[int, int], radius: float) -> bool:
        """Whether a tracked box may come within ``radius`` cells (in rows and in cols) of ``cell`` in the ``ahead``
        ticks after ``tick`` (:func:`_may_reach`)."""
        return bool(self._moving(tick, ahead, (cell, radius)))

    def _moving(self, tick: int, ahead: int = 0, near: tuple[tuple[int, int], float] | None = None,
                seen_once: bool = False) -> list[Track]:
        """The tracks with a velocity (and with ``seen_once``, those seen once, which have none yet) that are still
        taken to be moving at ``tick``; with ``near`` (a cell and a radius), those that may come within the radius
        of the cell by ``tick + ahead`` (:func:`_may_reach`)."""
        return [track for track in self.tracks
                if (seen_once or track.velocity is not None) and tick <= track.moving_until
                and (near is None or _may_reach(track, tick + ahead, *near))]

    def _inside(self, cells: np.ndarray) -> np.ndarray:
        """Which of ``cells`` ((..., 2) row, col) lie inside the map (a bool per cell)."""
        return (cells >= 0).all(axis=-1) & (cells[..., 0] < self.shape[0]) & (cells[..., 1] < self.shape[1])

    def _occupied_at(self, occupied: np.ndarray, cells: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """Which of ``cells`` ((..., 2) row, col, any of them off the map) lie inside the map, and which of those
        are occupied in ``occupied`` ((H, W) bool): a bool per cell each."""
        inside = self._inside(cells)
        clipped = np.minimum(np.maximum(cells, 0), np.array(self.shape) - 1)
        return inside, inside & occupied[clipped[..., 0], clipped[..., 1]]

    @staticmethod
    def _moves(track: Track, waited: int, ahead: int) -> tuple[np.ndarray, np.ndarray]:
        """The offsets ((m, 2) cells) a track's edge may move by in the next ``ahead`` ticks, ``waited`` ticks after
        its last edge was seen, and the tick (1 = the next) of each. A slow box's moves are counted along each axis
        from the last edge that moved it along that axis (:func:`_steps_by_count`); one seen not to move since (a
        move overdue: its period is not a whole number of ticks, or it slowed) has made none of its moves yet: they
        are counted from now on at the least. A box seen once, a cell either way along each axis its first edge's
        shape says it moved along (:func:`_moved_along`), at the next tick."""
        if track.velocity is None:
            ways = [(-1, 0, 1) if along else (0,) for along in track.origin[2]]
            offsets = np.array([(r, c) for r in ways[0] for c in ways[1] if r or c], np.int64).reshape(-1, 2)
            return offsets, np.ones(len(offsets), np.int64)
        if track.speed > 1.0:
            elapsed = waited + np.arange(1, ahead + 1)[:, None]
            offsets, segment = _swept_offsets(track.velocity * (elapsed - 1), track.velocity * elapsed)
            return offsets, segment + 1
        since = tuple(waited + track.tick - moved for moved in track.moved_at)
        return _paced_moves(track.periods, since, tuple(track.signs.tolist()), ahead)

    def entering(self, tick: int, horizon: int) -> np.ndarray:
        """Cells ((n, 2), inside the map) that the tracked obstacles' leading edges are predicted to sweep over
        after ``tick`` up to ``tick + horizon``, at constant velocity; the edges' current cells left out."""
        found = []
        for track in self._moving(tick) if horizon >= 1 else []:
            offsets, _ = _swept_offsets(track.velocity[None] * (tick - track.tick),
                                        track.velocity[None] * (tick + horizon - track.tick))
            found.append(_shifted(track.front, offsets))
        if not found:
            return np.zeros((0, 2), np.int64)
        cells = np.unique(np.vstack(found), axis=0)
        return cells[self._inside(cells)]


def _periods(speed: float, start: tuple[int, float], moves: tuple, start_moved: bool, turn_speed: float = 0.0
             ) -> tuple[float, float] | None:
    """The fewest and most ticks a move along an axis may take (:attr:`Track.periods`) for a box moving at ``speed``
    cells per tick along it over its last edges, from the (tick, place along the axis) of the edge it started from,
    those of its ``moves`` along it since (the last HISTORY), whether that start is known to have moved it along
    the axis, and the box's speed when its track restarted at a turn (0: it did not); None where it does not move
    along it. With one move (or moves that cancel out), from 1 tick, with no bound above, and so where the moves are
    faster than a cell a tick (more cells than ticks and one: an edge misread, another box's cells taken for this
    one's - the bounds were then a most below the fewest, and no count of moves fit any tick); with none since the
    start, 1 / speed and a tick more, from 1 / ``turn_speed`` (a tick at least) after a turn."""
    counted = (start,) + moves if start_moved and len(moves) < HISTORY else moves  # the start still in the history
    ticks = counted[-1][0] - counted[0][0] if counted else 0
    cells = sum(abs(after - before) for (_, before), (_, after) in zip(counted, counted[1:]))  # back and forth too
    if cells > ticks + 1 + 1e-6:  # an edge misread: no pace known
        return 1.0, math.inf
    if cells >= 1.0:
        return round(max(1.0, (ticks - 1) / cells), 9), round((ticks + 1) / cells, 9)  # whole periods stay whole
    if moves:  # the move before the one seen came at any time (the first reads of a track may have missed it)
        return 1.0, math.inf
    if speed <= 0.0:
        return None
    return max(1.0, 1.0 / max(turn_speed, speed)), 1.0 / speed + 1.0


@lru_cache(maxsize=4096)
def _paced_moves(periods: tuple, since: tuple[int, int], signs: tuple[int, int], ahead: int
                 ) -> tuple[np.ndarray, np.ndarray]:
    """:meth:`MotionPredictor._moves` of a box no faster than a cell a tick: the offsets ((m, 2) cells, read-only)
    its edge may move by in the next ``ahead`` ticks and the tick of each, from its ``periods`` and, per axis, the
    ticks ``since`` its last move along it and the way (``signs``) it moves. Kept for the next call with the same
    arguments: a box at a steady pace comes back to the same ones every few ticks, and the lookout asks twice a
    tick (:class:`tdp.lookout.BoxLookout`); a call cost about 40 µs of numpy (RESULTS §8)."""
    first, last = zip(*(_steps_by_count(axis_periods, ticks, ahead) for axis_periods, ticks in zip(periods, since)))
    earliest = np.maximum.outer(*first)  # a box's rows and cols move apart (a diagonal box rounds each its way),
    possible = earliest <= np.minimum.outer(*last)  # but at one pace: both counts must fit the same tick
    rows, cols = np.nonzero(possible)
    keep = (rows > 0) | (cols > 0)  # (0, 0), where the edge is, left out
    offsets = np.column_stack([rows[keep] * signs[0], cols[keep] * signs[1]])
    steps = earliest[rows[keep], cols[keep]]
    offsets.flags.writeable = steps.flags.writeable = False
    return offsets, steps


def _steps_by_count(periods: tuple[float, float] | None, waited: int, ahead: int) -> tuple[np.ndarray, np.ndarray]:
    """For 0, 1, 2 ... one-cell moves along an axis, the first and the last of the next ``ahead`` ticks (1 = the
    next; 0 for none) at which a box whose moves take ``periods`` (fewest, most ticks) may have made that many and
    no more, ``waited`` ticks after its last edge that moved it along the axis. The c-th comes floor(c fewest) ticks
    after that edge at the earliest; one overdue (no edge since it was due: the period is not a whole number of
    ticks, or the box slowed) comes from the next tick on, and the ones after it are counted from there. At the
    most's pace, counted from now (the least it can have made), floor(s / most) are made by tick s."""
    if periods is None:
        return np.zeros(1, np.int64), np.full(1, ahead, np.int64)
    fewest, most = periods
    steps = np.arange(1, ahead + 1)
    made_most = np.minimum(_most_moves(waited + steps, fewest), 1 + _most_moves(steps - 1, fewest))
    counts = np.arange(made_most[-1] + 1)
    first = np.where(counts > 0, np.searchsorted(made_most, counts) + 1, 0)
    last = np.searchsorted(np.floor(steps / most), counts, side="right")
    return first.astype(np.int64), last.astype(np.int64)


def _most_moves(ticks: np.ndarray, period: float) -> np.ndarray:
    """The most one-cell moves a box that takes at least ``period`` ticks a move makes in each of ``ticks`` (ints)
    ticks after one: its c-th move is seen floor(c period) ticks after it at the earliest."""
    return np.ceil((ticks + 1) / period).astype(np.int64) - 1


def _may_reach(track: Track, until: int, cell: tuple[int, int], radius: float) -> bool:
    """Whether the box of ``track`` may come within ``radius`` cells (in rows and in cols) of ``cell`` by tick
    ``until``: its edge moves at most max(speed, 1) cells a tick in each since it was seen (a slow box a cell at a
    time), and a cell more where a world rounds its place up."""
    reach = max(track.speed, 1.0) * (until - track.tick) + 1.0
    # the distance to the edge's bounds is at most the distance to its nearest cell
    return _gap(track.bounds, (cell[0], cell[1], cell[0], cell[1])) <= radius + reach


def _ways_back(back: np.ndarray) -> list[tuple[int, int]]:
    """The unit steps a box whose velocity's signs are ``-back`` (rows, cols) takes if it turns back: along each axis
    it moves on, and diagonally where it moves on both (its corner then enters the cell behind it diagonally, which
    neither axis's step reaches)."""
    ways = [(int(back[0]), 0)] if back[0] else []
    ways += [(0, int(back[1]))] if back[1] else []
    return ways + ([(int(back[0]), int(back[1]))] if back.all() else [])


def _within(ends: np.ndarray, others: np.ndarray, cell: tuple[int, int], radius: float) -> np.ndarray:
    """Which of the rectangles spanned by ``ends`` and ``others`` ((n, 2) cells each; a walk's first and last cells)
    come within ``radius`` cells (in rows and in cols) of ``cell``: a bool per row."""
    low, high = np.minimum(ends, others), np.maximum(ends, others)
    return ((low <= np.add(cell, radius)) & (high >= np.subtract(cell, radius))).all(axis=1)


def _shifted(edge: np.ndarray, offsets: np.ndarray) -> np.ndarray:
    """The cells ((m n, 2)) of an ``edge`` ((n, 2) cells) shifted by each of ``offsets`` ((m, 2)) in turn."""
    return (edge[None] + offsets[:, None]).reshape(-1, 2)


def _swept_offsets(now: np.ndarray, then: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """The whole-cell offsets an edge displaced from ``now[s]`` to ``then[s]`` ((S, 2) cells, fractional: S
    segments) may occupy on the way: both the floor and the ceiling of each coordinate at points along the segment,
    since a world may round either way; (0, 0), where the edge is, left out. Returns the offsets (m, 2), each
    segment's distinct and the segments in order, and the segment of each (m,)."""
    points_per = 2 * np.maximum(1, np.ceil(np.abs(then - now).max(axis=1))).astype(np.int64)[:, None]
    fractions = np.minimum(np.arange(points_per.max() + 1), points_per) / points_per  # the last point repeated
    points = now[:, None] + (then - now)[:, None] * fractions[:, :, None]
    corners = np.concatenate([np.stack([rows(points[..., 0]), cols(points[..., 1])], axis=-1)
                              for rows in (np.floor, np.ceil) for cols in (np.floor, np.ceil)], axis=1)
    segment = np.repeat(np.arange(len(now)), corners.shape[1])
    found = np.unique(np.column_stack([segment, corners.reshape(-1, 2).astype(np.int64)]), axis=0)
    found = found[found[:, 1:].any(axis=1)]
    return found[:, 1:], found[:, 0]


#: A track's expected front (:func:`_expected_fronts`): its bounds (least row and col, then greatest), the track and
#: the move (rows, cols) from its last edge.
_Front = tuple[tuple[int, int, int, int], Track, np.ndarray]


def _expected_fronts(tracks: list[Track], tick: int) -> list[_Front]:
    """Where each track with a velocity expects its front at ``tick`` (:attr:`Track.front` moved on by the velocity,
    rounded): the front's bounds (least row and col, then greatest) moved on, the track and the move (rows, cols)."""
    fronts = []
    for track in tracks:
        if track.velocity is not None:
            shift = np.rint(track.velocity * (tick - track.tick)).astype(np.int64)
            r0, c0, r1, c1 = track.front_bounds
            dr, dc = int(shift[0]), int(shift[1])
            fronts.append(((r0 + dr, c0 + dc, r1 + dr, c1 + dc), track, shift))
    return fronts


def _split_by_fronts(edge: np.ndarray, bounds: tuple[int, int, int, int], fronts: list[_Front]) -> list[np.ndarray]:
    """``edge`` ((n, 2) cells of one cluster, within ``bounds``) split between the tracks' expected ``fronts``
    (:func:`_expected_fronts`) within a cell of it, each cell to the nearest (in rows and cols), where two or more
    are: two boxes whose new edges touch come as one cluster, which continued one track while the other coasted, its
    next move expected a tick late. A front that shares a cell with another's (two tracks of one box) splits nothing.
    Otherwise ``[edge]``."""
    near = [k for k, (around, _, _) in enumerate(fronts) if _gap(bounds, around) <= 1]
    if len(near) < 2:
        return [edge]
    distance = {k: np.abs(edge[:, None, :] - (fronts[k][1].front + fronts[k][2])[None]).max(axis=2).min(axis=1)
                for k in near}
    near = [k for k in near if distance[k].min() <= 1 and not _overlapped(k, fronts)]
    if len(near) < 2:
        return [edge]
    nearest = np.argmin(np.stack([distance[k] for k in near]), axis=0)
    return [edge[nearest == k] for k in range(len(near)) if (nearest == k).any()]


def _gap(a: tuple[int, int, int, int], b: tuple[int, int, int, int]) -> int:
    """How many cells apart (in rows and in cols; 0 where they overlap) the rectangles of two bounds (least row and
    col, then greatest) lie."""
    return max(a[0] - b[2], b[0] - a[2], a[1] - b[3], b[1] - a[3], 0)


def _overlapped(k: int, fronts: list[_Front]) -> bool:
    """Whether another track's expected front shares a cell with the ``k``-th's of ``fronts``."""
    around, track, shift = fronts[k]
    mine = None
    for j, (other, other_track, other_shift) in enumerate(fronts):
        if j != k and _gap(around, other) == 0:
            mine = _flat_cells(track.front + shift) if mine is None else mine
            if mine & _flat_cells(other_track.front + other_shift):
                return True
    return False


def _flat_cells(cells: np.ndarray) -> set[int]:
    """``cells`` ((n, 2), any sign) as a set of ints, one per cell."""
    return set((cells[:, 0] * (1 << 20) + cells[:, 1]).tolist())


def clusters(cells: np.ndarray) -> list[np.ndarray]:
    """The 8-connected groups of ``cells`` ((n, 2) row, col), each as an (m, 2) array."""
    left = set(map(tuple, np.asarray(cells, np.int64).reshape(-1, 2).tolist()))
    groups = []
    while left:
        frontier = [left.pop()]
        group = list(frontier)
        while frontier:
            r, c = frontier.pop()
            for dr, dc in _AROUND:
                near = (r + dr, c + dc)
                if near in left:
                    left.remove(near)
                    frontier.append(near)
                    group.append(near)
        groups.append(np.array(sorted(group), np.int64))
    return groups


def _started(edge: np.ndarray, tick: int, bounds: tuple[int, int, int, int], position: np.ndarray,
             velocity: np.ndarray | None, min_speed: float, shifted=(False, False)) -> Track:
    """A track (re)starting from ``edge`` (seen at ``tick``, within ``bounds``) at ``position``: its history and its
    origin that edge, its faces the edge along the axes its shape says it moved the box along (:func:`_moved_along`)
    or its shift from the box's last edge did (``shifted``, per axis: a turn), no move along either axis yet. With a
    ``velocity`` (a turn), the history holds the place the box came from at that velocity a tick before: its next
    edges' mean velocity keeps the turn's along an axis they do not move it on yet (from one interval alone, a
    diagonal box's first move up after a turn read as going straight up, and its next move left went unforeseen)."""
    moved = tuple(bool(a or b) for a, b in zip(_moved_along(edge, bounds), shifted))
    seen, turn_speed = ((tick, position),), 0.0
    if velocity is not None:
        seen, turn_speed = ((tick - 1, position - velocity), (tick, position)), float(np.hypot(*velocity))
    return Track(edge, tick, bounds, velocity, seen, (tick, position, moved), ((), ()),
                 tuple(edge if along else None for along in moved), min_speed, turn_speed)


def _continued(track: Track, edge: np.ndarray, tick: int, bounds: tuple[int, int, int, int],
               shift: np.ndarray) -> Track:
    """``track`` once its next ``edge`` (within ``bounds``) is seen at ``tick``, ``shift`` from its last
    (:func:`edge_shift`): the mean velocity over its last HISTORY edges; per axis it moved along, the move and the
    edge as its face, the other faces moved on by the shift. A box whose edge moved against its velocity turned (back,
    or at any other angle), and is taken to come back at the velocity it went, its track starting again from this
    edge (a mean over edges on both sides of the turn says it barely moves); the edge's shift says which axes it moved
    the box along."""
    position, along = track.position + shift, np.abs(shift) >= 0.5
    if track.velocity is not None and float(np.dot(shift, track.velocity)) < 0:
        return _started(edge, tick, bounds, position, -track.velocity, track.min_speed, along)
    seen = (track.seen + ((tick, position),))[-HISTORY:]
    velocity = np.round((seen[-1][1] - seen[0][1]) / (seen[-1][0] - seen[0][0]), 9)  # a cell a tick stays 1
    axis_moves = tuple((moves + ((tick, float(place)),))[-HISTORY:] if moved else moves
                       for moves, moved, place in zip(track.axis_moves, along, position))
    offset = np.rint(shift).astype(np.int64)
    faces = tuple(edge if moved else None if face is None else face + offset for face, moved in zip(track.faces, along))
    return Track(edge, tick, bounds, velocity, seen, track.origin, axis_moves, faces, track.min_speed, track.turn_speed)


def _bounds(edge: np.ndarray) -> tuple[int, int, int, int]:
    """The least row and col of ``edge``'s cells, then the greatest."""
    low, high = edge.min(axis=0), edge.max(axis=0)
    return int(low[0]), int(low[1]), int(high[0]), int(high[1])


def _fast(track: Track, edge: np.ndarray, bounds: tuple[int, int, int, int], shift: np.ndarray, miss: float) -> bool:
    """Whether ``edge`` (its cells within ``bounds``, ``shift`` and ``miss`` from ``track``: :func:`_reading`), beyond
    NEAR_SPEED's reach of the track, may be its fast box's: where the track's velocity expects it; before the track
    has a velocity, an edge of the same rows and cols as its last, shifted along the axis its shape says it moved
    along where it is a line (a box's front moving across rows is a row: :func:`_moved_along`). A slow track's box
    is not a fast one, nor one whose line of an edge moved sideways: the far edges of other boxes took such tracks
    (cluttered-60-417, crossing-60-431, passing-60-401 of the held-out seeds)."""
    if track.velocity is not None:
        return miss <= FIT
    if _span(bounds) != _span(track.bounds):
        return False
    along = _moved_along(edge, bounds)
    return along[0] == along[1] or not shift[1 if along[0] else 0]


def _span(bounds: tuple[int, int, int, int]) -> tuple[int, int]:
    """How many rows and cols ``bounds`` (least row and col, then greatest) span."""
    return bounds[2] - bounds[0] + 1, bounds[3] - bounds[1] + 1


def _moved_along(edge: np.ndarray, bounds: tuple[int, int, int, int]) -> tuple[bool, bool]:
    """Which axes (rows, cols) a leading ``edge`` ((n, 2) cells, within ``bounds``) surely moved its box along, from
    its shape: a row of cells (one row, more than one col) a move along rows (a move along cols alone shows a column
    as tall as the box), a column one along cols, an L (part of a rectangle of more than one row and col) both; a
    single cell or a whole rectangle (a box that appeared), neither surely."""
    height, width = _span(bounds)
    if height == 1 or width == 1:
        return height == 1 < width, width == 1 < height
    return (len(edge) < height * width,) * 2


def _turned_back(track: Track, edge: np.ndarray, bounds: tuple[int, int, int, int]) -> bool:
    """Whether ``edge`` (its cells within ``bounds``) may be the far face of ``track``'s box, turned back: the track
    moves along one axis alone, and the edge has as many cells as its last edge, spans the same rows (cols) across
    that axis and lies behind it along the axis."""
    if track.velocity is None or len(edge) != len(track.edge) or np.count_nonzero(track.velocity) != 1:
        return False
    along = int(np.flatnonzero(track.velocity)[0])
    across = 1 - along
    return (bounds[across] == track.bounds[across] and bounds[across + 2] == track.bounds[across + 2]
            and (bounds[along] - track.bounds[along]) * track.velocity[along] < 0)


def _lean(edge: np.ndarray) -> np.ndarray:
    """Per axis (rows, cols), the way a leading ``edge`` ((n, 2) cells) leans: 1 where more of its cells lie on its
    greatest row (col) than on its least, -1 where fewer, else 0. A box moving down and to the right shows its new
    right column and bottom row: an L with its long arms on the greatest row and col; a row or a column alone leans
    nowhere."""
    low, high = edge.min(axis=0), edge.max(axis=0)
    return np.sign((edge == high).sum(axis=0) - (edge == low).sum(axis=0))


def _reading(track: Track, edge: np.ndarray, bounds: tuple[int, int, int, int], tick: int
             ) -> tuple[np.ndarray, float]:
    """The shift (rows, cols) of ``edge`` (its cells and their ``bounds``), seen at ``tick``, from ``track``'s last
    edge (:func:`edge_shift`, each axis read the way the track moves along it, or before it has a velocity the way
    its last edge and this one lean: :func:`_lean`), and how far, in cells (the larger of rows and cols), the edge
    lies from where the track's velocity expects it (infinite before it has one)."""
    if track.velocity is None:
        return edge_shift(track.bounds, bounds, None, np.sign(_lean(track.edge) + _lean(edge))), math.inf
    expected = track.velocity * (tick - track.tick)
    shift = edge_shift(track.bounds, bounds, expected, track.signs)
    return shift, float(np.abs(shift - expected).max())


def edge_shift(before: tuple[int, int, int, int], after: tuple[int, int, int, int],
               expected: np.ndarray | None = None, signs: np.ndarray = (0, 0)) -> np.ndarray:
    """How far a box moved (rows, cols) from one leading edge to the next, given by their bounds (least row and
    col, then greatest), along each axis on its own: the shift of the edges' greatest row (col) where the box moves
    that way along it (``signs``: -1, 0 or 1 per axis), of their least where it moves the other way - unless the
    least's, the greatest's or the middle's is more than a cell nearer ``expected`` (the track's velocity times the
    ticks between: two boxes whose edges touch are one cluster, whose bounds reach a box further on one side); where
    it is not known to move, whichever of the three is nearest ``expected``, or with none expected the least's or the
    greatest's, whichever moved less. A box moving across rows and cols at once shows a row of cells on one tick and
    a column on another (its top edge as it rises, its right edge as it goes right), whose middles lie half the box
    apart: read from the middles, a box going up and to the right turned back every tick. The corner towards which
    it moves is the same cell of the box on both (a box at 45 degrees has it, its middles and its other corners
    equally near what its velocity expects)."""
    shifts = []
    for axis, sign in enumerate(signs):
        low, high = after[axis] - before[axis], after[axis + 2] - before[axis + 2]
        towards = high if sign > 0 else low
        if expected is None:
            shifts.append(towards if sign else min(low, high, key=abs))
            continue
        misses = {shift: abs(shift - expected[axis]) for shift in (low, high, (low + high) / 2)}
        nearest = min(misses, key=misses.get)
        shifts.append(towards if sign and misses[towards] <= misses[nearest] + 1.0 else nearest)
    return np.array(shifts, np.float64)


def _crosses(velocity: np.ndarray, direction: np.ndarray) -> bool:
    """Whether ``velocity`` points at more than 45 degrees to the line of ``direction`` (either way along it)."""
    along = abs(float(np.dot(velocity, direction)))
    return along * along < 0.5 * float(np.dot(velocity, velocity)) * float(np.dot(direction, direction))
