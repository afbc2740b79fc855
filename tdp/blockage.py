"""Blockage monitor (paper 4.1 as reconstructed in ARCHITECTURE §5.4) and relevance to the robot's current path."""
from __future__ import annotations

from collections import deque

import numpy as np
from numpy.lib.stride_tricks import sliding_window_view


class BlockageMonitor:
    """Watches the node-pair distances D(a, b, i) iteration by iteration.

    A pair (a, b) connected J iterations ago (D < DmaxQ, ``dmax_q`` in cells) is blocked at iteration i when
    ``D(a, b, i) - D(a, b, i - J) >= rise`` (U, over ``window`` J iterations) while both its nodes were active
    (finite readings) at every one of those iterations. The node layers read up to DmaxQ + U (their cap; edges of
    the graph still need D < DmaxQ), so a pair that loses its connection always shows a rise of at least U, while a
    pair that is only just connected and crosses DmaxQ because a box passes by shows only the rise the box really
    caused: there is no separate "reached DmaxQ" test to flicker. A pair is reported once, on the first iteration
    its condition holds, and again only after the condition has cleared. An inactive node (covered by an obstacle,
    or still settling after being uncovered) reads inf: its pairs' histories restart J iterations after it is active
    again, so covering and uncovering alone never look like a blockage.
    """

    def __init__(self, dmax_q: float, window: int = 8, rise: float = 7.0):
        self.dmax_q = float(dmax_q)
        self.window = int(window)
        self.rise = float(rise)
        self._history: deque[np.ndarray] = deque(maxlen=self.window + 1)
        self._blocked: np.ndarray | None = None

    @property
    def blocked(self) -> np.ndarray | None:
        """bool (n x n): the pairs whose blockage condition holds at the last iteration (None before any)."""
        return self._blocked

    def observe(self, pairs: np.ndarray) -> list[tuple[int, int]]:
        """Record one iteration's pair distances (n x n; inf where a node is inactive); return the pairs (a < b)
        that became blocked at this iteration."""
        return [pair for _, pair in self.observe_iterations(np.asarray(pairs)[None])]

    def observe_iterations(self, pairs: np.ndarray) -> list[tuple[int, tuple[int, int]]]:
        """Record k iterations' pair distances at once ((k, n, n), oldest first), as k calls of :meth:`observe`
        would; return (index in ``pairs``, (a, b)) for each pair that became blocked, in order."""
        new = np.asarray(pairs, np.float64)
        if self._blocked is None:
            self._blocked = np.zeros(new.shape[1:], bool)
        history = np.concatenate([np.stack(self._history), new]) if self._history else new
        self._history.extend(new)
        now = np.arange(max(0, self.window - len(history) + len(new)), len(new)) + len(history) - len(new)
        if not len(now):
            return []
        before = history[now - self.window]
        watched = before < self.dmax_q
        finite = np.isfinite(history)
        if not finite.all():  # a window is history[now - J .. now]
            watched &= sliding_window_view(finite, self.window + 1, axis=0)[now - self.window].all(axis=-1)
        rise = np.subtract(history[now], before, out=np.zeros_like(before), where=watched)
        blocked = watched & (rise >= self.rise)
        both_ways = blocked | blocked.transpose(0, 2, 1)
        fresh = blocked & ~np.concatenate([self._blocked[None], both_ways[:-1]])
        self._blocked = both_ways[-1]
        if not fresh.any():
            return []
        index, a, b = np.nonzero(np.triu(fresh, k=1))
        first = len(new) - len(now)
        return [(int(k) + first, (int(i), int(j))) for k, i, j in zip(index, a, b)]


def segment_near_path(a: np.ndarray, b: np.ndarray, path: np.ndarray, reach: float) -> bool:
    """Whether the segment a-b passes within ``reach`` cells (Euclidean) of any cell of ``path`` (m, 2)."""
    if len(path) == 0:
        return False
    a, b, path = np.asarray(a, float), np.asarray(b, float), np.asarray(path, float)
    ab = b - a
    length2 = float(ab @ ab)
    t = np.zeros(len(path)) if length2 == 0 else np.clip((path - a) @ ab / length2, 0.0, 1.0)
    nearest = a + t[:, None] * ab
    return bool((np.hypot(*(path - nearest).T) <= reach).any())


def polyline_cells(corners: list[tuple[int, int]]) -> list[tuple[int, int]]:
    """The cells along the straight legs between consecutive ``corners`` (cells), each leg's ends included."""
    cells = []
    for a, b in zip(corners, corners[1:]):
        steps = int(max(abs(b[0] - a[0]), abs(b[1] - a[1]))) + 1
        cells += [tuple(cell) for cell in np.rint(np.linspace(a, b, steps)).astype(int)]
    return cells
