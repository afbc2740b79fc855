"""Blockage monitor (paper 4.1 as reconstructed in ARCHITECTURE §5.4) and relevance to the robot's current path."""
from __future__ import annotations

from collections import deque

import numpy as np


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
        pairs = np.array(pairs, np.float64)
        self._history.append(pairs)
        if self._blocked is None:
            self._blocked = np.zeros(pairs.shape, bool)
        if len(self._history) <= self.window:
            return []
        before = self._history[0]
        watched = np.isfinite(np.stack(self._history)).all(axis=0) & (before < self.dmax_q)
        rise = np.subtract(pairs, before, out=np.zeros_like(pairs), where=watched)
        blocked = watched & (rise >= self.rise)
        fresh = blocked & ~self._blocked
        self._blocked = blocked | blocked.T
        a, b = np.nonzero(np.triu(fresh, k=1))
        return [(int(i), int(j)) for i, j in zip(a, b)]


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
