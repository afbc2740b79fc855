"""Sweeps: specs checked up front, episodes expanded and keyed, results journalled and resumed after a kill, the
same table serially and on a real local Dask cluster, ratios against the oracle."""
import csv
import io
import json
import math
import re
import signal
import subprocess
import sys
import time
from pathlib import Path

import pytest

from tdp.__main__ import main as tdp_command
from tdp.sweep import JOURNAL, TIMED, Journal, load_spec, local_workers, run_sweep, write_report

ROOT = Path(__file__).resolve().parents[1]

SMALL = """
name: small
worlds:
  - family: crossing
    size: 60
    seeds: {first: 0, count: 2}
  - scenario: sudden-blockage
planners:
  - planner: accelerating
    updates_per_move: [1, 4]
  - planner: plain-dp
    updates_per_move: 4
  - planner: dstar-lite
    max_size: 60
"""


def spec_file(tmp_path: Path, text: str, name: str = "spec.yaml") -> Path:
    path = tmp_path / name
    path.write_text(text)
    return path


def untimed(path: Path) -> list[dict]:
    """episodes.csv without the measured times (the only columns that may differ between runs)."""
    with open(path) as file:
        return [{k: v for k, v in row.items() if k not in TIMED} for row in csv.DictReader(file)]


def test_episodes_expand_the_grid_with_one_oracle_per_world_and_stencil(tmp_path):
    spec = load_spec(spec_file(tmp_path, SMALL))
    episodes = spec.episodes()
    per_world = {}
    for e in episodes:
        per_world.setdefault(e.world.coords["world"], []).append(e.planner)
    assert per_world == {"crossing-60-0": ["oracle", "accelerating", "accelerating", "plain-dp", "dstar-lite"],
                         "crossing-60-1": ["oracle", "accelerating", "accelerating", "plain-dp", "dstar-lite"],
                         "sudden-blockage": ["oracle", "accelerating", "accelerating", "plain-dp"]}  # max_size 60
    assert len({e.key for e in episodes}) == len(episodes) == 14
    assert load_spec(spec_file(tmp_path, SMALL)).episodes()[3].key == episodes[3].key  # stable
    assert spec.columns == ("updates_per_move",)
    two_stencils = SMALL.replace("  - planner: dstar-lite\n    max_size: 60\n",
                                 "  - planner: dstar-lite\n    neighbourhood: 8\n")
    planners = [e.planner for e in load_spec(spec_file(tmp_path, two_stencils)).episodes()
                if e.world.coords["world"] == "sudden-blockage"]
    assert planners.count("oracle") == 2


def test_a_world_named_twice_is_one_world(tmp_path):
    text = ("worlds: [{family: rooms, size: 60, seeds: [3, 3, 4]}, {family: rooms, size: 60, seeds: 4}]\n"
            "planners: [{planner: plain-dp}]\n")
    spec = load_spec(spec_file(tmp_path, text))
    assert [w.coords["seed"] for w in spec.worlds] == [3, 4] and len(spec.episodes()) == 4


def test_an_entry_names_its_worlds_group_and_a_world_in_two_groups_stays_in_the_first(tmp_path):
    text = ("worlds:\n  - {family: rooms, size: 60, seeds: [3, 4]}\n"
            "  - {family: rooms, size: 60, seeds: [4, 5], group: rooms-held-out}\n"
            "  - {scenario: static, group: 7}\nplanners: [{planner: plain-dp}]\n")
    spec = load_spec(spec_file(tmp_path, text))
    assert [(w.coords["world"], w.coords["group"]) for w in spec.worlds] == [
        ("rooms-60-3", "rooms"), ("rooms-60-4", "rooms"), ("rooms-60-5", "rooms-held-out"), ("static", "7")]
    assert len(spec.episodes()) == 8
    for group, words in ((None, "worlds[0].group is empty"), ("", "worlds[0].group is empty"),
                         ([1], "worlds[0].group must be text")):
        bad = spec_file(tmp_path, f"worlds: [{{scenario: static, group: {json.dumps(group)}}}]\n"
                                  "planners: [{planner: plain-dp}]\n")
        with pytest.raises(ValueError, match=re.escape(words)):
            load_spec(bad)


def test_a_world_file_edit_changes_the_keys_of_its_episodes(tmp_path):
    import tdp

    world = tmp_path / "w.yaml"
    world.write_text(tdp.scenarios.get("static").to_yaml())
    text = "worlds: [{world: w.yaml}]\nplanners: [{planner: plain-dp}]\n"
    before = {e.key for e in load_spec(spec_file(tmp_path, text)).episodes()}
    world.write_text(world.read_text().replace("max_ticks: 400", "max_ticks: 399"))
    after = {e.key for e in load_spec(spec_file(tmp_path, text)).episodes()}
    assert before and not before & after


@pytest.mark.parametrize("text, words", [
    ("worlds: [{family: rooms}]", "'planners'"),
    ("worlds: [{family: hallways}]\nplanners: [{planner: oracle}]", "unknown family 'hallways'"),
    ("worlds: [{family: rooms, seeds: -1}]\nplanners: [{planner: oracle}]", "worlds[0].seeds"),
    ("worlds: [{family: rooms, size: 20}]\nplanners: [{planner: oracle}]", "worlds[0].size"),
    ("worlds: [{family: rooms, size: 40000}]\nplanners: [{planner: oracle}]",
     "worlds[0].size must be an integer <= 32764"),
    ("worlds: [{family: rooms, scenario: static}]\nplanners: [{planner: oracle}]", "exactly one of"),
    ("worlds: [{world: missing.yaml}]\nplanners: [{planner: oracle}]", "missing.yaml"),
    ("worlds: [{scenario: static}]\nplanners: [{planner: plain-dp, nodes: 9}]", "'nodes' is not one of"),
    ("worlds: [{scenario: static}]\nplanners: [{planner: accelerating, nodes: [9, 0]}]", "nodes"),
    ("worlds: [{scenario: static}]\nplanners: [{planner: accelerating, speed: 2}]", "'speed'"),
    ("worlds: [{scenario: static}]\nplanners: [{planner: astar}]", "'planner' is one of"),
    ("worlds: [{scenario: static}]\ncommon: {vision: 2, colour: red}\nplanners: [{planner: oracle}]", "'colour'"),
    ("worlds: [{scenario: static}]\nplanners: [{planner: oracle}]\nmetrics: [no.such:thing]", "no.such:thing"),
    ("worlds: [{map: m.txt, start: [1, 1], goal: [1, 2]}]\nplanners: [{planner: oracle}]", "m.txt"),
    ("worlds: [{scenario: static}]\nplanners: [{planner: oracle}]\nextra: 1", "unknown key 'extra'"),
    ("worlds: [{scenario: static\n", "not valid YAML"),
    ("worlds: [{family: rooms, seeds: {count: 10000000000}}]\nplanners: [{planner: oracle}]",
     "worlds[0].seeds.count must be an integer <= 100000"),
    ("worlds: [{scenario: static}]\nplanners: [{planner: exact, budget_ms: 1e-1}]",
     "budget_ms must be a number, got '1e-1' (YAML reads 1e-1 as text"),
    ("name: {a: 1}\nworlds: [{scenario: static}]\nplanners: [{planner: oracle}]", "name must be text, got {'a': 1}"),
    ("name: .nan\nworlds: [{scenario: static}]\nplanners: [{planner: oracle}]", "name must be text, got nan"),
    ("worlds: [{scenario: static}]\nplanners: [{planner: oracle}]\nworlds: [{scenario: clearing}]",
     "'worlds' is given twice"),
    ("name: ../out\nworlds: [{scenario: static}]\nplanners: [{planner: oracle}]", "name must not hold '/'"),
    ("worlds: [{family: rooms, seeds: []}]\nplanners: [{planner: oracle}]",
     "worlds[0].seeds is an empty list: it names no world"),
    ("worlds: [{scenario: static}]\nplanners: [{planner: accelerating, nodes: []}]",
     "planners[0] (accelerating): nodes is an empty list"),
    ("worlds: [{scenario: static}]\ncommon: {updates_per_move: []}\nplanners: [{planner: plain-dp}]",
     "planners[0] (plain-dp): updates_per_move is an empty list"),
])
def test_a_bad_spec_is_a_value_error_naming_the_file_and_the_entry(tmp_path, text, words):
    path = spec_file(tmp_path, text)
    with pytest.raises(ValueError, match="sweep spec") as caught:
        load_spec(path)
    assert words in str(caught.value) and str(path) in str(caught.value)


@pytest.mark.parametrize("asked, cores, episodes, workers", [
    (None, 2, 200, 2), (None, 16, 3, 3), (3, 2, 200, 3), (8, 2, 200, 8), (5, 2, 2, 2), (None, 2, 0, 1)])
def test_a_local_cluster_has_the_workers_asked_or_one_a_core_and_no_more_than_episodes(asked, cores, episodes,
                                                                                        workers):
    assert local_workers(asked, cores, episodes) == workers


@pytest.mark.parametrize("asked, words", [(9, "workers: at most 8 on this machine's 2 cores (4 a core), got 9"),
                                          (0, "workers must be an integer >= 1"), (2.5, "workers must be an integer")])
def test_a_local_cluster_of_more_workers_than_four_a_core_is_refused(tmp_path, asked, words):
    """--workers 1000 on the 2-core VM started 1000 processes that each load Taichi, until memory ran out."""
    with pytest.raises(ValueError, match=re.escape(words)):
        local_workers(asked, 2, 100)
    with pytest.raises(ValueError, match="workers"):
        run_sweep(load_spec(spec_file(tmp_path, SMALL)), tmp_path / "out", workers=10_000)
    assert not (tmp_path / "out").exists()


def test_bad_spec_on_the_command_line_is_one_error_line(tmp_path):
    done = subprocess.run([sys.executable, "-m", "tdp", "sweep", str(tmp_path / "none.yaml")], cwd=ROOT,
                          capture_output=True, text=True, timeout=120)
    assert done.returncode == 2 and done.stderr.startswith("error: sweep spec") and "Traceback" not in done.stderr


def test_journal_skips_a_torn_line_and_a_result_replaces_an_error(tmp_path):
    path = tmp_path / JOURNAL
    path.write_text(json.dumps({"key": "a", "error": "boom"}) + "\n" + json.dumps({"key": "b", "row": {"x": 1}})
                    + "\n" + '{"key": "c", "ro')
    journal = Journal(path)
    assert journal.rows == {"b": {"x": 1}} and journal.errors == {"a": "boom"}
    assert path.read_text().endswith("}\n")  # the torn line is cut off, so the next line starts cleanly
    journal.add("a", {"x": 2})
    again = Journal(path)
    assert again.rows == {"b": {"x": 1}, "a": {"x": 2}} and not again.errors


def test_journal_is_strict_json_and_a_row_it_cannot_hold_is_that_episodes_error(tmp_path):
    """An extra metric's nan was written as NaN, which Python reads and strict JSON readers refuse; a value JSON
    cannot hold stopped the sweep with a TypeError from deep inside json."""
    import numpy as np

    def strict(text):
        return json.loads(text, parse_constant=lambda name: pytest.fail(f"{name} in the journal"))

    path = tmp_path / JOURNAL
    journal = Journal(path)
    assert journal.add("a", {"closest": math.nan, "far": -math.inf, "mean": np.float32(1.5),
                             "cells": np.arange(2), "reached": np.bool_(True), "pair": (1, 2)}) is None
    expected = {"closest": None, "far": None, "mean": 1.5, "cells": [0, 1], "reached": True, "pair": [1, 2]}
    assert [strict(line) for line in path.read_text().splitlines()] == [{"key": "a", "row": expected}]
    assert journal.rows == Journal(path).rows == {"a": expected}  # resumed or not, the same rows
    for bad, words in (({"cells": {1, 2}}, "cannot write set"), ({"by": {(0, 1): 2}}, "names must be text")):
        assert words in journal.add("b", bad)
        assert "b" not in journal.rows and words in Journal(path).errors["b"]


def test_ratios_are_lengths_over_the_oracle_of_the_same_world(tmp_path):
    spec = load_spec(spec_file(tmp_path, SMALL))
    rows = run_sweep(spec, tmp_path, serial=True, log=io.StringIO())
    assert len(rows) == len(spec.episodes())
    write_report(spec, rows, tmp_path)
    with open(tmp_path / "episodes.csv") as file:
        table = list(csv.DictReader(file))
    oracle = {r["world"]: float(r["length"]) for r in rows if r["planner"] == "oracle"}
    for row in table:
        expected = float(row["length"]) / oracle[row["world"]] if row["reached"] == "True" else math.nan
        assert float(row["ratio"]) == pytest.approx(expected, nan_ok=True)
    blockage = {r["planner"]: float(r["ratio"]) for r in table if r["world"] == "sudden-blockage"
                and r["updates_per_move"] in ("", "4")}
    assert blockage["oracle"] == 1.0 and blockage["plain-dp"] > 1.05 > blockage["accelerating"]
    with open(tmp_path / "summary.csv") as file:
        summary = list(csv.DictReader(file))
    assert {(s["group"], s["planner"], s["updates_per_move"]) for s in summary} == {
        (r["group"], r["planner"], r["updates_per_move"]) for r in table}
    assert (tmp_path / "ratio.png").stat().st_size > 1000


def test_two_worlds_on_one_map_get_their_own_names_and_oracles(tmp_path):
    """Two map entries on one map with other start and goal cells: both were named map-0, and the ratio of one read
    the oracle of the other (mean ratios of 1.9-2.1 on den312d and arena, where they are 1.00-1.003)."""
    (tmp_path / "m.map").write_text("type octile\nheight 12\nwidth 12\nmap\n" + "\n".join(["." * 12] * 12) + "\n")
    text = ("worlds:\n"
            "  - {map: m.map, start: [0, 0], goal: [0, 11], boxes: 0}\n"
            "  - {map: m.map, start: [0, 0], goal: [11, 11], boxes: 0}\n"
            "  - {map: m.map, start: [0, 0], goal: [11, 11], boxes: 0}\n"
            "planners: [{planner: plain-dp}]\n")
    spec = load_spec(spec_file(tmp_path, text))
    assert [w.coords["world"] for w in spec.worlds] == ["m-0#1", "m-0#2"]  # the third is the second again
    assert {w.coords["group"] for w in spec.worlds} == {"m"}
    rows = run_sweep(spec, tmp_path, serial=True, log=io.StringIO())
    write_report(spec, rows, tmp_path)
    with open(tmp_path / "episodes.csv") as file:
        table = list(csv.DictReader(file))
    assert len(table) == 4 and all(float(row["ratio"]) == pytest.approx(1.0) for row in table)
    lengths = {row["world"]: float(row["length"]) for row in table}
    assert lengths == pytest.approx({"m-0#1": 11.0, "m-0#2": 11.0 * 2 ** 0.5})


def test_killed_sweep_resumes_without_redoing_finished_episodes(tmp_path, capsys):
    """Killed after three episodes and run again: the rest run, the journal's first lines kept. One planner kind,
    so that the killed process compiles one set of kernels; the command's main() runs again in this process."""
    spec = spec_file(tmp_path, "worlds: [{family: crossing, size: 60, seeds: {first: 0, count: 4}}]\n"
                               "planners: [{planner: exact}]\n")
    out = tmp_path / "out"
    command = [sys.executable, "-m", "tdp", "sweep", str(spec), "--serial", "--out", str(out)]
    process = subprocess.Popen(command, cwd=ROOT, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    journal = out / JOURNAL
    deadline = time.monotonic() + 240
    while time.monotonic() < deadline and process.poll() is None:
        if journal.exists() and journal.read_text().count("\n") >= 3:
            break
        time.sleep(0.05)
    process.send_signal(signal.SIGKILL)
    process.wait()
    before = journal.read_text().splitlines()
    total = len(load_spec(spec).episodes())
    assert 3 <= len(before) < total, "the sweep was not caught halfway"
    assert tdp_command(command[3:]) == 0
    assert f"{len(before)} of {total} episodes done before, skipped" in capsys.readouterr().err
    after = journal.read_text().splitlines()
    assert after[:len(before)] == before  # finished episodes were kept, not redone
    keys = [json.loads(line)["key"] for line in after]
    assert len(keys) == len(set(keys)) == total
    assert len(untimed(out / "episodes.csv")) == total


def test_a_sweep_on_an_existing_dask_scheduler_gives_the_serial_table(tmp_path):
    """On a cluster the sweep did not start (its scheduler's address), whose worker is a thread of this process
    (a worker process would load every kernel again: 39 s against 5); a local cluster of the sweep's own, with
    worker processes (``workers``), is the sweep benchmark's smoke run (tests/test_benchmarks.py), which compares
    the tables too."""
    distributed = pytest.importorskip("dask.distributed")
    spec = load_spec(spec_file(tmp_path, SMALL))
    serial, cluster = tmp_path / "serial", tmp_path / "cluster"
    serial.mkdir()
    cluster.mkdir()
    write_report(spec, run_sweep(spec, serial, serial=True, log=io.StringIO()), serial)
    with distributed.LocalCluster(n_workers=1, threads_per_worker=1, processes=False,
                                  dashboard_address=None) as local:
        rows = run_sweep(spec, cluster, scheduler=local.scheduler_address, log=io.StringIO())
    write_report(spec, rows, cluster)
    assert untimed(serial / "episodes.csv") == untimed(cluster / "episodes.csv")
    assert len(untimed(cluster / "episodes.csv")) == len(spec.episodes())


def test_exact_planner_entries_sweep_budgets_and_match_the_oracle_unbudgeted(tmp_path):
    """``planner: exact`` reads the stencil, d_max and budget_ms; unbudgeted it drives the oracle's path (ratio 1),
    and a node field for it is refused with the fields it reads named."""
    text = """
worlds: [{family: rooms, size: 60, seeds: [3]}]
planners:
  - {planner: exact, budget_ms: [null, 0.3]}
"""
    spec = load_spec(spec_file(tmp_path, text))
    assert [(e.planner, e.config.get("budget_ms")) for e in spec.episodes()] == [
        ("oracle", None), ("exact", None), ("exact", 0.3)]
    rows = run_sweep(spec, tmp_path, serial=True, log=io.StringIO())
    lengths = {(r["planner"], r["config"].get("budget_ms")): r["length"] for r in rows}
    assert lengths[("exact", None)] == lengths[("oracle", None)]
    assert all(r["reached"] and r["collisions"] == 0 for r in rows)
    with pytest.raises(ValueError, match="'nodes' is not one of its fields.*budget_ms"):
        load_spec(spec_file(tmp_path, "worlds: [{scenario: static}]\nplanners: [{planner: exact, nodes: 9}]",
                            "bad.yaml"))


def test_a_map_entry_with_nav2s_inflation_cost_runs_on_a_costed_map_and_half_of_it_is_refused(tmp_path):
    arena = Path(__file__).parent / "data" / "arena.map"
    entry = f"  - {{map: {arena}, start: [1, 3], goal: [47, 46], boxes: 0, cost_scaling_factor: 0.5%s}}\n"
    spec = load_spec(spec_file(tmp_path, "worlds:\n" + entry % ", inflation_radius: 6.0" +
                               "planners: [{planner: exact}]\n"))
    world = spec.worlds[0].build()
    assert world.grid.cost is not None and world.grid.cost.max() > 3  # 252 exp(-0.5) at 1 m: 3.4
    rows = run_sweep(spec, tmp_path, serial=True, log=io.StringIO())
    assert all(row["reached"] for row in rows) and len(rows) == 2  # the exact planner and the oracle
    with pytest.raises(ValueError, match="go together"):
        load_spec(spec_file(tmp_path, "worlds:\n" + entry % "" + "planners: [{planner: exact}]\n"))
