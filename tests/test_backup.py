"""The backup rules (tdp/backup.py) driven by hand-built readings: states, node graphs and layer values written out
here, no seeded world."""
import math
from types import SimpleNamespace

import numpy as np
import pytest

from tdp.backup import (Backup, BackupState, Follow, Step, after_search, cells_near, cost_from_robot, driven_search,
                        goal_route_wins, iterated, next_step, plan_backup, switched_back, without_route)
import tdp.navigator as navigator_module
from tdp.navigator import MOST_PER_CALL, iterations_within
from tdp.nodes import NodeGraph, Vertices, choose_subgoal

DMAX_Q = 10.0
FOLLOWING = BackupState(Follow.BACKUP, Backup((3, 0, 1, 4), 12.0, 1, {0: 8.0, 1: 4.0, 4: 0.0}), path_cost=12.0,
                        since_detection=5)


def graph_from(robot_readings, goal_readings, pairs, robot_goal=np.inf):
    """A node graph over len(robot_readings) nodes (R = n, G = n + 1) from the layers' values written out."""
    n = len(robot_readings)
    samples = np.full((n + 2, n + 1), np.inf, np.float32)
    samples[:n, 1:] = pairs
    samples[n, 1:], samples[n + 1, 1:] = robot_readings, goal_readings
    samples[n, 0] = robot_goal
    return NodeGraph(samples, DMAX_Q, np.ones(n, bool))


# Three nodes in a row, 4 cells apart (0-2: 9); R reads node 0 at 3 and node 1 at 8.5, node 2 out of sight; G is 2
# from node 2 and 9 from node 1. Paths R..G: 3,0,1,2,4 = 3 + 4 + 4 + 2 = 13; 3,0,2,4 = 14; 3,1,2,4 = 14.5.
ROW = np.array([[0, 4, 9], [4, 0, 4], [9, 4, 0]], float)
R_READS, G_READS = [3, 8.5, 20], [20, 9, 2]


@pytest.mark.parametrize("state, relevant, subgoal_at_robot, expected", [
    (BackupState(), False, math.inf, Step.KEEP),                          # following the goal layer, all quiet
    (BackupState(), True, math.inf, Step.SEARCH),                         # a relevant blockage: search
    (FOLLOWING, True, 2.0, Step.SEARCH),                                  # a new one while on a backup: search anew
    (BackupState(Follow.NO_ROUTE), False, math.inf, Step.RETRY),          # no route last tick: try again
    (FOLLOWING, False, 6.0, Step.KEEP),                                   # on the way to the subgoal
    (FOLLOWING, False, 4.9, Step.RESEARCH),                               # within DmaxQ / 2 of it: search again
    (BackupState(Follow.BACKUP, FOLLOWING.route, 12.0, 12), False, 6.0, Step.SWITCH_BACK),  # ||Path|| iterations
])
def test_next_step_follows_the_papers_rules(state, relevant, subgoal_at_robot, expected):
    assert next_step(state, relevant, subgoal_at_robot, DMAX_Q) is expected


def test_a_search_for_a_detection_restarts_the_count_and_takes_the_new_cost():
    found = Backup((3, 2, 4), 9.0, 2, {2: 3.0, 4: 0.0})
    state = after_search(FOLLOWING, found, Step.SEARCH)
    assert state == BackupState(Follow.BACKUP, found, path_cost=9.0, since_detection=0)
    assert state.subgoal == 2


def test_a_search_near_the_subgoal_keeps_the_backups_path_cost_and_count():
    found = Backup((3, 1, 4), 7.0, 1, {1: 4.0, 4: 0.0})
    assert after_search(FOLLOWING, found, Step.RESEARCH) == BackupState(Follow.BACKUP, found, 12.0, 5)
    assert after_search(BackupState(Follow.NO_ROUTE, None, 3.0, 5), found, Step.RETRY).path_cost == 7.0


def test_a_failed_search_leaves_the_robot_on_the_goal_layer_searching_every_tick():
    state = after_search(FOLLOWING, None, Step.RESEARCH)
    assert state.follow is Follow.NO_ROUTE and state.route is None and state.subgoal is None
    assert state.path_cost == 12.0 and state.since_detection == 5
    assert after_search(FOLLOWING, None, Step.SEARCH).since_detection == 0
    assert next_step(state, False, math.inf, DMAX_Q) is Step.RETRY


def test_switching_back_and_counting_iterations():
    assert switched_back(FOLLOWING) == BackupState(Follow.GOAL, None, 12.0, 5)
    assert without_route(FOLLOWING).follow is Follow.NO_ROUTE
    assert iterated(FOLLOWING, 4).since_detection == 9


def test_the_backups_cost_from_the_robot_is_the_subgoals_layer_plus_the_rest_of_the_path():
    assert cost_from_robot(FOLLOWING, 2.5) == 2.5 + 4.0
    assert cost_from_robot(BackupState(), 2.5) == math.inf
    assert cost_from_robot(BackupState(Follow.NO_ROUTE), 2.5) == math.inf


def test_subgoal_is_q2_or_q1_when_q2_is_out_of_sight_or_the_last_point():
    pairs = np.array([[0, 4, 10], [4, 0, 4], [10, 4, 0]], float)  # DmaxQ = 10
    graph = graph_from([3, 6, 10], [10, 10, 2], pairs)
    assert choose_subgoal([3, 0, 1, 2, 4], graph) == 1      # Q2, within sight (6 < 10)
    graph = graph_from([3, 12, 10], [10, 10, 2], pairs)
    assert choose_subgoal([3, 0, 1, 2, 4], graph) == 0      # Q2 out of sight: Q1
    assert choose_subgoal([3, 2, 4], graph) == 2            # R, Q1, G with G out of sight: Q1
    assert choose_subgoal([3, 4], graph) == 4               # R, G: the last point
    near_goal = graph_from([3, 12, 10], [10, 10, 2], pairs, robot_goal=7.0)
    assert choose_subgoal([3, 2, 4], near_goal) == 4        # R, Q1, G with G in sight: G
    graph = graph_from([0, 6, 8], [10, 10, 2], pairs)
    assert choose_subgoal([3, 0, 1, 2, 4], graph) == 2      # standing on Q1: skip it


def test_plan_backup_takes_the_cheapest_driven_path_and_its_subgoal():
    graph = graph_from(R_READS, G_READS, ROW)
    found = plan_backup(graph, graph.weight)
    assert found.path == (3, 0, 1, 2, 4) and found.cost == pytest.approx(13.0)
    assert found.subgoal == 1  # Q2, within sight of R (8.5 < DmaxQ)
    assert found.cost_to_goal == pytest.approx({4: 0.0, 2: 2.0, 1: 6.0, 0: 10.0, 3: 13.0})


def test_plan_backup_goes_round_an_edge_whose_layer_does_not_drive_it():
    graph = graph_from(R_READS, G_READS, ROW)  # node 1's layer does not lead from node 0 to node 1 yet
    found = plan_backup(graph, lambda a, b: math.inf if (a, b) == (0, 1) else graph.weight(a, b))
    assert found.path == (3, 0, 2, 4) and found.cost == pytest.approx(14.0)


def test_plan_backup_heads_for_q1_when_q2s_layer_does_not_drive_the_robot_there():
    graph = graph_from(R_READS, G_READS, ROW)
    found = plan_backup(graph, lambda a, b: math.inf if (a, b) == (3, 1) else graph.weight(a, b))
    assert found.path == (3, 0, 1, 2, 4) and found.subgoal == 0


def test_driven_search_reweights_each_leg_by_the_length_driven_and_finds_none_when_nothing_drives():
    graph = graph_from(R_READS, G_READS, ROW)
    path, cost = driven_search(graph, lambda a, b: 7.5 if (a, b) == (0, 1) else graph.weight(a, b))
    assert path == [3, 0, 2, 4] and cost == pytest.approx(14.0)  # 3 + 7.5 + 4 + 2 = 16.5 lost to 3 + 9 + 2
    assert graph.weight(0, 1) == 7.5
    graph = graph_from(R_READS, G_READS, ROW)
    assert driven_search(graph, lambda a, b: math.inf) is None
    assert plan_backup(graph_from(R_READS, G_READS, ROW), lambda a, b: math.inf) is None


def test_driven_search_keeps_driven_costs_past_dmaxq_as_on_a_map_with_traversal_costs():
    graph = graph_from(R_READS, G_READS, ROW)  # every driven cost 3x the cells read: ground of cost 3
    path, cost = driven_search(graph, lambda a, b: 3 * graph.weight(a, b))
    assert path == [3, 0, 1, 2, 4] and cost == pytest.approx(39.0)  # 9 + 12 + 12 + 6, two legs past DmaxQ (10)


def test_cells_near_counts_the_moves_to_cover_a_distance():
    steps = np.array([1.0, math.sqrt(2), 1.0, 1.0, math.sqrt(5)])
    assert cells_near(steps, 1.0) == 1
    assert cells_near(steps, 2.0) == 2  # 1 + 1.41 = 2.41 >= 2
    assert cells_near(steps, 100.0) == 6  # past the end: the whole chain


STEPS = np.array([1.0, 1.0, 1.0, 1.0])  # a straight chain of four moves from R to G


@pytest.mark.parametrize("values, budget, settled_route, wins", [
    ([4.0, 3.0, 2.0], 5.0, True, True),          # settled, shorter than the backup
    ([4.0, 3.0, 2.0], 3.9, False, False),        # longer than the backup's estimate with slack
    ([4.0, 3.0, 2.2], 5.0, False, True),         # 3.0 under 2.2 + 1 by 0.2: settled within settled_cells (0.25)
    ([4.0, 3.0, 2.5], 5.0, False, False),        # 3.0 under 2.5 + 1 by 0.5: a change still arriving
    ([5.0, 3.0, 2.0], 5.0, False, True),         # R's value above its successor's plus the move: no rise arriving
    ([0.5, -0.5, -1.5], 5.0, False, True),       # starting a backup: the route's length need not match R's value
    ([0.5, -0.5, -1.5], 5.0, True, False),       # leaving one: length 4 is 3.5 over R's value > U = 3
])
def test_the_goal_layers_route_wins_only_when_short_enough_and_settled(values, budget, settled_route, wins):
    assert goal_route_wins(STEPS, np.array(values), budget, settled_route, rise=3.0, settled_cells=0.25) is wins


def test_iterations_within_a_budget_run_at_least_one_and_no_budget_runs_k(monkeypatch):
    """On a clock of its own (k iterations take k x 0.1 ms): the test slept instead, and a loaded machine's sleep
    of 0.1 ms past 20 ms made it fail."""
    calls, now = [], [0.0]
    monkeypatch.setattr(navigator_module, "time", SimpleNamespace(perf_counter=lambda: now[0]))

    def iterate(k):
        calls.append(k)
        now[0] += k * 1e-4

    assert iterations_within(iterate, 4, None) == 4 and calls == [4]
    calls.clear()
    assert iterations_within(iterate, 4, 1e-6) == 1 and calls == [1]  # the budget is spent after one
    calls.clear()
    done = iterations_within(iterate, 4, 20.0)  # 20 ms: doubling calls, then what the rest of the budget fits
    assert done == sum(calls) == 200 and calls == [1, 2, 4, 8, 16, 32, 64, 73]


def test_iterations_within_run_at_most_a_call_of_iterations_at_once():
    """An idle layer's iterations cost next to nothing: an absurd budget grew a call to 262,144 of them, whose
    samples and pair distances took 1.2 GB; K = 10**6 took 4.7 GB in one call."""
    calls = []
    assert iterations_within(calls.append, 2 * MOST_PER_CALL + 5, None) == 2 * MOST_PER_CALL + 5
    assert calls == [MOST_PER_CALL, MOST_PER_CALL, 5]
    calls.clear()
    done = iterations_within(calls.append, 4, 30.0)  # free iterations: as many calls as 30 ms hold
    assert done == sum(calls) and max(calls) == MOST_PER_CALL


def test_vertex_ids_convert_to_layers_and_cells_in_one_place():
    vertices = Vertices(np.array([[1, 2], [5, 6]]))
    assert (vertices.robot, vertices.goal) == (2, 3)
    assert vertices.layer(0) == 1 and vertices.layer(1) == 2 and vertices.layer(vertices.goal) == 0
    assert vertices.cell(1, (9, 9), (0, 0)) == (5, 6)
    assert vertices.cell(vertices.robot, (9, 9), (0, 0)) == (9, 9)
    assert vertices.cell(vertices.goal, (9, 9), (0, 0)) == (0, 0)
    assert vertices.cells((9, 9), (0, 0)).tolist() == [[1, 2], [5, 6], [9, 9], [0, 0]]
