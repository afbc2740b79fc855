"""Obstacle motion from the map updates alone: the paper's closing suggestion, "obstacle motion may be extrapolated
for early blockage predictions" (ARCHITECTURE §5.7).

A box moving over the grid shows, tick by tick, a leading edge: the cells that become occupied. Those cells are
grouped into 8-connected clusters; a cluster is matched to the track whose last edge it could have come from (a
similar number of cells, moved within ``max_speed`` cells per elapsed tick: :func:`edge_shift`), and its
displacement over the ticks between them is the track's velocity. A track whose edge is not seen again within the
time it takes to move one cell (at its velocity, plus a tick) has stopped and is dropped.

The model is constant velocity in a straight line: it cannot foresee a box turning, reversing or stopping (it
learns of each from the next edge it sees, one or two ticks late; a box that turns back is then taken to come back
at the speed it went), it knows nothing of obstacles that do not move, and a new box is predicted only from its
second edge on. No world ids are used.
"""
from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

#: Offsets of the 8-neighbourhood, for clustering the cells that became occupied.
_AROUND = [(dr, dc) for dr in (-1, 0, 1) for dc in (-1, 0, 1) if (dr, dc) != (0, 0)]


#: Edges a track remembers: its velocity is the mean over them (a box at 0.3 cells per tick shows edges 3, 3 and 4
#: ticks apart; one interval alone says 0.33 or 0.25).
HISTORY = 4


@dataclass
class Track:
    """One moving obstacle: its last leading ``edge`` ((n, 2) cells), the ``tick`` it was seen, the edge's
    ``bounds`` (least row and col, then greatest: :func:`_bounds`, taken once for matching it), its ``velocity``
    (rows, cols per tick, over its last HISTORY edges; None until it has been matched once), and those edges'
    (tick, position): the first edge's centre, moved on by each :func:`edge_shift` since."""

    edge: np.ndarray
    tick: int
    bounds: tuple[int, int, int, int]
    velocity: np.ndarray | None = None
    seen: tuple = ()
    speed: float = field(init=False)  # the velocity's largest row or col component, in cells per tick (0: unknown)

    def __post_init__(self):
        self.speed = 0.0 if self.velocity is None else float(np.abs(self.velocity).max())

    @property
    def periods(self) -> tuple[tuple[float, float] | None, tuple[float, float] | None]:
        """Per axis (rows, cols) of a box slower than a cell per tick, the fewest and the most ticks a one-cell move
        along it may take as the edges seen allow (None along an axis it does not move on): n cells moved between
        edges S ticks apart, each seen at the first tick after the move, say the period P lies between (S - 1) / n
        and (S + 1) / n, that is 1 / speed give or take 1 / n. A box at 0.375 cells per tick moves every 2 or 3 ticks;
        three moves seen 3 ticks apart say 0.33, and a window of whole periods of 3 ticks missed the move that came
        after 2. With one edge since a turn, the period as it went."""
        (first, start), (last, end) = self.seen[0], self.seen[-1]
        return tuple(_periods(float(speed), float(cells), last - first)
                     for speed, cells in zip(np.abs(self.velocity), np.abs(end - start)))

    @property
    def moved_at(self) -> tuple[int, int]:
        """Per axis (rows, cols), the tick of the last edge that moved the box along it (the first edge held, where
        none did): a box going up and to the right at unequal speeds shows its rows' moves and its cols' apart, and
        its next move up is due counting from its last move up, not from its last edge."""
        return tuple(next((tick for (tick, now), (_, then) in zip(self.seen[::-1], self.seen[-2::-1])
                           if abs(now[axis] - then[axis]) >= 0.5), self.seen[0][0]) for axis in (0, 1))

    @property
    def position(self) -> np.ndarray:
        """Where the track is (rows, cols): its first edge's centre moved on by each shift seen since."""
        return self.seen[-1][1]

    def alive_at(self, tick: int, min_speed: float) -> bool:
        """Whether the obstacle is still taken to be moving at ``tick``: its next edge is due within the ticks a
        one-cell move takes at its speed (at ``min_speed`` while its speed is not known yet), plus one."""
        speed = min_speed if self.velocity is None else self.speed
        return speed > 0 and tick - self.tick <= math.ceil(1.0 / max(speed, min_speed)) + 1


class MotionPredictor:
    """Tracks moving obstacles from the cells that become occupied each tick and predicts the cells they enter.

    ``max_speed`` and ``min_speed``: the fastest and slowest obstacles to track, in cells per tick (a faster one is
    seen as a new obstacle each tick, a slower one as one that stopped, and neither is predicted)."""

    def __init__(self, shape: tuple[int, int], max_speed: float = 2.0, min_speed: float = 0.25):
        self.shape = (int(shape[0]), int(shape[1]))
        self.max_speed, self.min_speed = float(max_speed), float(min_speed)
        self.tracks: list[Track] = []

    def observe(self, tick: int, became_occupied: np.ndarray) -> None:
        """Take the cells ((n, 2) row, col) that became occupied at ``tick`` (ticks must not go back)."""
        previous = [track for track in self.tracks if track.alive_at(tick, self.min_speed)]
        matched: set[int] = set()
        tracks = []
        for edge in clusters(np.asarray(became_occupied, np.int64).reshape(-1, 2)):
            bounds = _bounds(edge)
            index = self._match(edge, bounds, tick, previous, matched)
            velocity, seen = None, ((tick, edge.sum(axis=0) / len(edge)),)  # the centre, without np.mean's dispatch
            if index is not None:
                matched.add(index)
                track = previous[index]
                expected = None if track.velocity is None else track.velocity * (tick - track.tick)
                velocity, seen = _continued(track, tick, edge_shift(track.bounds, bounds, expected))
            tracks.append(Track(edge, tick, bounds, velocity, seen))
        self.tracks = tracks + [track for i, track in enumerate(previous) if i not in matched]

    def _match(self, edge: np.ndarray, bounds: tuple[int, int, int, int], tick: int, previous: list[Track],
               taken: set[int]) -> int | None:
        """The previous track this edge (its cells and their ``bounds``) most plausibly continues - the nearest by
        :func:`edge_shift` within the reach of ``max_speed``, of a similar size -, or None."""
        best, best_distance = None, math.inf
        for i, track in enumerate(previous):
            elapsed = tick - track.tick
            if i in taken or elapsed <= 0 or not 0.5 <= len(edge) / len(track.edge) <= 2.0:
                continue
            distance = float(np.abs(edge_shift(track.bounds, bounds)).max())
            if 0 < distance <= self.max_speed * elapsed + 0.5 and distance < best_distance:
                best, best_distance = i, distance
        return best

    def arrivals(self, tick: int, ahead: int, across: np.ndarray | None = None,
                 near: tuple[tuple[int, int], float] | None = None) -> dict[tuple[int, int], int]:
        """For each cell (inside the map) a tracked box may move into within ``ahead`` ticks after ``tick``, the
        first such tick (1 = the next) over every box. A box slower than a cell per tick moves a cell at a time
        along each axis, rows and cols apart, every P ticks, P within what its edges allow (:attr:`Track.periods`):
        its k-th move along an axis after its last edge comes floor(k P) ticks after it at the earliest (a box seen
        every other tick is not expected every tick), a move overdue (no edge seen since it was due) from the next
        tick on, and a cell is flagged from the first tick both its rows' and its cols' moves fit (a diagonal box
        keeps one pace on both); a faster one sweeps as in
        :meth:`entering`. With ``across`` (a direction, rows and cols), only the boxes that move across it (at more
        than 45 degrees to it either way); with ``near`` (a cell and a radius in cells), only those that may come
        within the radius of the cell (:meth:`may_reach`): the cells it leaves out all lie beyond it."""
        moves = [(track.edge, *self._moves(track, tick - track.tick, ahead))
                 for track in self._moving(tick, ahead, near) if across is None or _crosses(track.velocity, across)]
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

    def may_reach(self, tick: int, ahead: int, cell: tuple[int, int], radius: float) -> bool:
        """Whether a tracked box may come within ``radius`` cells (in rows and in cols) of ``cell`` in the ``ahead``
        ticks after ``tick`` (:func:`_may_reach`)."""
        return bool(self._moving(tick, ahead, (cell, radius)))

    def _moving(self, tick: int, ahead: int = 0, near: tuple[tuple[int, int], float] | None = None) -> list[Track]:
        """The tracks with a velocity that are still taken to be moving at ``tick``; with ``near`` (a cell and a
        radius), those that may come within the radius of the cell by ``tick + ahead`` (:func:`_may_reach`)."""
        return [track for track in self.tracks
                if track.velocity is not None and track.alive_at(tick, self.min_speed)
                and (near is None or _may_reach(track, tick + ahead, *near))]

    def _inside(self, cells: np.ndarray) -> np.ndarray:
        """Which rows of ``cells`` lie inside the map (a bool per row)."""
        return (cells >= 0).all(axis=1) & (cells[:, 0] < self.shape[0]) & (cells[:, 1] < self.shape[1])

    @staticmethod
    def _moves(track: Track, waited: int, ahead: int) -> tuple[np.ndarray, np.ndarray]:
        """The offsets ((m, 2) cells) a track's edge may move by in the next ``ahead`` ticks, ``waited`` ticks after
        its last edge was seen, and the tick (1 = the next) of each. A slow box's moves are counted along each axis
        from the last edge that moved it along that axis (:func:`_steps_by_count`); one seen not to move since (a
        move overdue: its period is not a whole number of ticks, or it slowed) has made none of its moves yet: they
        are counted from now on at the least."""
        if track.speed >= 1.0:
            elapsed = waited + np.arange(1, ahead + 1)[:, None]
            offsets, segment = _swept_offsets(track.velocity * (elapsed - 1), track.velocity * elapsed)
            return offsets, segment + 1
        first, last = zip(*(_steps_by_count(periods, waited + track.tick - moved, ahead)
                            for periods, moved in zip(track.periods, track.moved_at)))
        earliest = np.maximum.outer(*first)  # a box's rows and cols move apart (a diagonal box rounds each its way),
        possible = earliest <= np.minimum.outer(*last)  # but at one pace: both counts must fit the same tick
        signs = np.sign(track.velocity).astype(np.int64)
        rows, cols = np.nonzero(possible)
        keep = (rows > 0) | (cols > 0)  # (0, 0), where the edge is, left out
        return np.column_stack([rows[keep] * signs[0], cols[keep] * signs[1]]), earliest[rows[keep], cols[keep]]

    def entering(self, tick: int, horizon: int) -> np.ndarray:
        """Cells ((n, 2), inside the map) that the tracked obstacles' leading edges are predicted to sweep over
        after ``tick`` up to ``tick + horizon``, at constant velocity; the edges' current cells left out."""
        found = []
        for track in self._moving(tick) if horizon >= 1 else []:
            offsets, _ = _swept_offsets(track.velocity[None] * (tick - track.tick),
                                        track.velocity[None] * (tick + horizon - track.tick))
            found.append(_shifted(track.edge, offsets))
        if not found:
            return np.zeros((0, 2), np.int64)
        cells = np.unique(np.vstack(found), axis=0)
        return cells[self._inside(cells)]


def _periods(speed: float, cells: float, ticks: int) -> tuple[float, float] | None:
    """The fewest and most ticks a move along an axis may take (:attr:`Track.periods`) for a box seen to move
    ``cells`` along it in ``ticks`` at ``speed`` cells per tick; None where it does not move along it."""
    if speed <= 0.0:
        return None
    period = 1.0 / speed
    if ticks == 0 or cells < 1.0:
        return period, period
    return round(max(1.0, period - 1.0 / cells), 9), round(period + 1.0 / cells, 9)  # whole periods stay whole


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
    made_most = [min(_most_moves(waited + step, fewest), 1 + _most_moves(step - 1, fewest)) for step in steps]
    counts = np.arange(made_most[-1] + 1)
    first = np.where(counts > 0, np.searchsorted(made_most, counts) + 1, 0)
    last = np.searchsorted(np.floor(steps / most), counts, side="right")
    return first.astype(np.int64), last.astype(np.int64)


def _most_moves(ticks: int, period: float) -> int:
    """The most one-cell moves a box that takes at least ``period`` ticks a move makes in the ``ticks`` ticks after
    one: its c-th move is seen floor(c period) ticks after it at the earliest."""
    return math.ceil((ticks + 1) / period) - 1


def _may_reach(track: Track, until: int, cell: tuple[int, int], radius: float) -> bool:
    """Whether the box of ``track`` may come within ``radius`` cells (in rows and in cols) of ``cell`` by tick
    ``until``: its edge moves at most max(speed, 1) cells a tick in each since it was seen (a slow box a cell at a
    time), and a cell more where a world rounds its place up."""
    reach = max(track.speed, 1.0) * (until - track.tick) + 1.0
    r0, c0, r1, c1 = track.bounds  # the distance to the edge's bounds is at most the distance to its nearest cell
    return max(r0 - cell[0], cell[0] - r1, c0 - cell[1], cell[1] - c1, 0) <= radius + reach


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


def _continued(track: Track, tick: int, shift: np.ndarray) -> tuple[np.ndarray, tuple]:
    """The velocity and edge history of ``track`` once its next edge is seen at ``tick``, ``shift`` from its last
    (:func:`edge_shift`): the mean velocity over its last HISTORY edges; a box whose edge moved against its velocity
    turned back, and is taken to come back at the speed it went, its history starting again from this edge (a mean
    over edges on both sides of the turn says it barely moves)."""
    position = track.position + shift
    if track.velocity is not None and float(np.dot(shift, track.velocity)) < 0:
        return -track.velocity, ((tick, position),)
    seen = (track.seen + ((tick, position),))[-HISTORY:]
    return (seen[-1][1] - seen[0][1]) / (seen[-1][0] - seen[0][0]), seen


def _bounds(edge: np.ndarray) -> tuple[int, int, int, int]:
    """The least row and col of ``edge``'s cells, then the greatest."""
    low, high = edge.min(axis=0), edge.max(axis=0)
    return int(low[0]), int(low[1]), int(high[0]), int(high[1])


def edge_shift(before: tuple[int, int, int, int], after: tuple[int, int, int, int],
               expected: np.ndarray | None = None) -> np.ndarray:
    """How far a box moved (rows, cols) from one leading edge to the next, given by their bounds (least row and
    col, then greatest): the shift of one of the four corners or of the middle - the one nearest ``expected`` (the
    track's velocity times the ticks between), or with none expected the corner that moved least. A box moving
    across rows and cols at once shows a row of cells on one tick and a column on another (its top edge as it rises,
    its right edge as it goes right), whose middles lie half the box apart: read from the middles, a box going up
    and to the right turned back every tick. The corner towards which it moves is the same cell of the box on both."""
    (r0, c0, r1, c1), (s0, d0, s1, d1) = before, after
    corners = [(s0 - r0, d0 - c0), (s0 - r0, d1 - c1), (s1 - r1, d0 - c0), (s1 - r1, d1 - c1)]
    if expected is None:
        return np.array(min(corners, key=lambda shift: max(abs(shift[0]), abs(shift[1]))), np.float64)
    middle = ((s0 + s1 - r0 - r1) / 2, (d0 + d1 - c0 - c1) / 2)
    return np.array(min(corners + [middle], key=lambda shift: max(abs(shift[0] - expected[0]),
                                                                   abs(shift[1] - expected[1]))), np.float64)


def _crosses(velocity: np.ndarray, direction: np.ndarray) -> bool:
    """Whether ``velocity`` points at more than 45 degrees to the line of ``direction`` (either way along it)."""
    along = abs(float(np.dot(velocity, direction)))
    return along * along < 0.5 * float(np.dot(velocity, velocity)) * float(np.dot(direction, direction))
