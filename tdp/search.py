"""Uniform-cost search over the node graph (paper 4.2)."""
from __future__ import annotations

import heapq
from typing import Callable, Iterable


def uniform_cost_search(neighbours: Callable[[int], Iterable[tuple[int, float]]], start: int,
                        goal: int) -> tuple[list[int], float] | None:
    """Cheapest path from ``start`` to ``goal``: (vertices from start to goal, cost), or None if there is none.

    ``neighbours(v)`` yields (vertex, non-negative weight). Ties between equal costs go to the lower vertex id,
    so results are deterministic.
    """
    frontier = [(0.0, start)]
    best = {start: 0.0}
    parent: dict[int, int] = {}
    done = set()
    while frontier:
        cost, vertex = heapq.heappop(frontier)
        if vertex in done:
            continue
        if vertex == goal:
            path = [goal]
            while path[-1] != start:
                path.append(parent[path[-1]])
            return path[::-1], cost
        done.add(vertex)
        for other, weight in neighbours(vertex):
            if weight < 0:
                raise ValueError(f"edge {vertex}-{other} has negative weight {weight}")
            candidate = cost + weight
            if other not in done and candidate < best.get(other, float("inf")):
                best[other] = candidate
                parent[other] = vertex
                heapq.heappush(frontier, (candidate, other))
    return None
