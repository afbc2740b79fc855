"""8-neighbour DP without corner cutting reproduces MovingAI's published optimal lengths."""
import numpy as np
import pytest

import tdp
from conftest import DATA, shared_file


def check_problems(grid, problems):
    by_goal = {}
    for problem in problems:
        by_goal.setdefault(problem.goal, []).append(problem)
    for goal, group in by_goal.items():
        field = tdp.DistanceField(grid, goal, neighbourhood=8)
        field.converge()
        d = field.distances()
        for problem in group:
            assert d[problem.start] == pytest.approx(problem.optimal_length, rel=1e-5, abs=1e-4), problem


@pytest.mark.parametrize("name", ["arena", "den312d"])
def test_every_problem_of_the_small_maps(name):
    grid = tdp.load_map(DATA / f"{name}.map")
    problems = tdp.load_scenarios(DATA / f"{name}.map.scen", grid)
    assert len(problems) == {"arena": 160, "den312d": 320}[name]
    check_problems(grid, problems)


@pytest.mark.parametrize("name", ["maze512-32-0", "random512-10-0", "8room_000"])
def test_a_sample_of_each_large_map(name):
    grid = tdp.load_map(shared_file("movingai", f"{name}.map"))
    problems = tdp.load_scenarios(shared_file("movingai", f"{name}.map.scen"), grid)
    picks = np.linspace(0, len(problems) - 1, 12).astype(int)  # short to longest buckets
    check_problems(grid, [problems[i] for i in picks])
