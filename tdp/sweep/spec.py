"""Sweep specs: a YAML file naming worlds and a grid of planner parameters, expanded into episodes.

A spec (every key but ``worlds`` and ``planners`` optional)::

    name: rooms-nodes-k
    worlds:
      - family: [rooms, corridor]    # random worlds (tdp.random_worlds): families, sizes and seeds
        size: [100, 200]
        seeds: {first: 0, count: 10}  # or a list of seeds, or one
      - scenario: sudden-blockage    # a named scenario
      - world: my-world.yaml         # a world file (relative to the spec)
      - map: warehouse.yaml          # a quick world on a map file: shuttling boxes from each seed
        start: [20, 30]
        goal: [400, 900]
        boxes: 4
        seeds: [0, 1, 2]
        blockage: true
        cost_scaling_factor: 3.0     # optional: nav2's inflation cost (with inflation_radius, metres)
        inflation_radius: 0.6
    common: {neighbourhood: 16}      # NavigatorConfig fields for every planner
    planners:
      - planner: exact               # exact replanning every tick; budget_ms: [0.3, 1] makes it anytime
      - planner: accelerating        # NavigatorConfig fields; a list sweeps the field
        nodes: [9, 25, 49]
        updates_per_move: [1, 4]
      - planner: plain-dp
        updates_per_move: [1, 4]
      - planner: dstar-lite
        max_size: 100                # only on worlds whose larger side is at most 100 cells
    metrics: [benchmarks.worlds:truth_metrics]   # extra per-episode metrics, module:function

The oracle (exact distances every tick) runs on every world for each stencil in the spec, listed or not: ratios
are taken against it, on the world of the same name: worlds that would share a name but differ (two ``map``
entries on one map with other cells or boxes, two world files of one name) are told apart by a suffix, ``#1``,
``#2``, ... in the order of the spec. An episode's key is a hash of everything that decides its result (the
world's recipe and file contents, the planner, its whole configuration, the extra metrics), so a rerun skips what
is done and a changed spec reruns only what changed.
"""
from __future__ import annotations

import hashlib
import importlib
import itertools
import json
from dataclasses import dataclass
from pathlib import Path

import yaml

from .. import checks
from ..config import CONFIG_FIELDS, PLANNERS, STENCIL_FIELDS, NavigatorConfig, fields_read
from ..engine import MAX_MAP_SIDE

#: What a sweep's planners entry may name: the planners of a config, D* Lite and the oracle.
SWEEP_PLANNERS = ("exact", "accelerating", "plain-dp", "dstar-lite", "oracle")
WORLD_KINDS = ("family", "scenario", "world", "map")
#: The most seeds one entry of ``worlds`` may count (seeds: {first, count}): each is a world kept in the spec's list.
MAX_SEEDS = 100_000


@dataclass(frozen=True)
class World:
    """One world of a sweep: ``recipe`` says how to build it (plain JSON values: a worker builds it from them),
    ``coords`` are its columns in the results (world, group, size, seed)."""

    recipe: dict
    coords: dict

    def build(self):
        """The :class:`~tdp.world.Scenario` of this world."""
        import tdp
        from ..random_worlds import boxes_on_map, make_world

        kind = self.recipe["kind"]
        if kind == "family":
            return make_world(self.recipe["family"], self.recipe["size"], self.recipe["seed"])
        if kind == "scenario":
            return tdp.scenarios.get(self.recipe["scenario"])
        if kind == "world":
            return tdp.load_world(self.recipe["path"])
        grid = tdp.load_map(self.recipe["path"], **self.recipe["options"])
        scenario = boxes_on_map(grid, tuple(self.recipe["start"]), tuple(self.recipe["goal"]), self.recipe["boxes"],
                                self.recipe["seed"], self.recipe["blockage"])
        scenario.name = self.coords["world"]
        return scenario


@dataclass(frozen=True)
class EpisodeSpec:
    """One run: a planner with one configuration on one world. ``config`` holds every NavigatorConfig field the
    planner reads (all of them for accelerating nodes and plain DP, the stencil for D* Lite and the oracle);
    ``metrics`` names the extra metric functions."""

    world: World
    planner: str
    config: dict
    metrics: tuple[str, ...] = ()

    @property
    def key(self) -> str:
        """A hash of everything that decides this episode's result."""
        text = json.dumps([self.world.recipe, self.planner, self.config, list(self.metrics)], sort_keys=True)
        return hashlib.sha1(text.encode()).hexdigest()[:16]


@dataclass(frozen=True)
class Spec:
    """A loaded sweep spec: its name, worlds, the planner configurations, the fields it sets (the columns of the
    results besides the world's) and the extra metric functions."""

    name: str
    worlds: tuple[World, ...]
    runs: tuple[tuple[str, dict, int | None], ...]  # planner, config, max_size
    columns: tuple[str, ...]
    metrics: tuple[str, ...]

    def episodes(self) -> list[EpisodeSpec]:
        """Every episode, world by world in the spec's order: the oracle once per stencil, then each run; repeats
        (the same planner and configuration from two entries) once."""
        stencils = list(dict.fromkeys(tuple(config[f] for f in STENCIL_FIELDS) for _, config, _ in self.runs))
        oracles = [("oracle", dict(zip(STENCIL_FIELDS, stencil)), None) for stencil in stencils]
        out: dict[str, EpisodeSpec] = {}
        for world in self.worlds:
            for planner, config, max_size in oracles + [run for run in self.runs if run[0] != "oracle"]:
                if max_size is None or world.coords["size"] <= max_size:
                    episode = EpisodeSpec(world, planner, config, self.metrics)
                    out.setdefault(episode.key, episode)
        return list(out.values())


def load_spec(path: str | Path) -> Spec:
    """Read and check a sweep spec; ValueError names the file, the entry and what is wrong with it."""
    path = checks.path(path, "path")
    try:
        text = path.read_text()
    except FileNotFoundError:
        raise ValueError(f"sweep spec {path} does not exist") from None
    except (OSError, UnicodeDecodeError) as error:
        raise ValueError(f"sweep spec {path}: cannot read it ({error})") from None
    try:
        data = checks.yaml_data(text)
    except yaml.YAMLError as error:
        raise ValueError(f"sweep spec {path}: not valid YAML ({error})") from None
    try:
        return _spec(data, path)
    except ValueError as error:
        raise ValueError(f"sweep spec {path}: {error}") from None


def _spec(data, path: Path) -> Spec:
    if not isinstance(data, dict):
        raise ValueError("must be a mapping with 'worlds' and 'planners'")
    _only(data, ("name", "worlds", "common", "planners", "metrics"), "the spec")
    for key in ("worlds", "planners"):
        if not isinstance(data.get(key), list) or not data[key]:
            raise ValueError(f"'{key}' must be a non-empty list")
    common = data.get("common") or {}
    if not isinstance(common, dict):
        raise ValueError("'common' must be a mapping of NavigatorConfig fields")
    for name in common:
        if name not in CONFIG_FIELDS:
            raise ValueError(f"common: {name!r} is not a NavigatorConfig field ({', '.join(CONFIG_FIELDS)})")
    entries = enumerate(data["worlds"])
    worlds = _named_apart(w for i, entry in entries for w in _worlds(entry, f"worlds[{i}]", path.parent))
    runs, columns = [], dict.fromkeys(k for k in common if k in CONFIG_FIELDS)
    for i, entry in enumerate(data["planners"]):
        planner_runs, named = _runs(entry, common, f"planners[{i}]")
        runs += planner_runs
        columns.update(dict.fromkeys(named))
    metrics = data.get("metrics") or []
    if not isinstance(metrics, list):
        raise ValueError("'metrics' must be a list of module:function names")
    for name in metrics:
        metric_function(name)
    return Spec(_name(data.get("name"), path.stem), worlds, tuple(runs), tuple(columns), tuple(metrics))


def _name(value, default: str) -> str:
    """The spec's name: text that names a folder of its own (the default output is ``sweep-NAME``)."""
    name = checks.text(value, "name", default)
    if any(c in name for c in "/\\\0"):
        raise ValueError(f"name must not hold '/', '\\' or a NUL (it names the folder sweep-NAME), got {name!r}")
    return name


def _only(entry: dict, allowed: tuple[str, ...], where: str) -> None:
    unknown = [k for k in entry if k not in allowed]
    if unknown:
        raise ValueError(f"{where}: unknown key {unknown[0]!r}; allowed: {', '.join(allowed)}")


def _listed(value) -> list:
    return value if isinstance(value, list) else [value]


def _seeds(value, where: str) -> list[int]:
    """Seeds as a list, one integer, or {first, count}."""
    if isinstance(value, dict):
        _only(value, ("first", "count"), f"{where}.seeds")
        first = checks.integer(value.get("first", 0), f"{where}.seeds.first", 0)
        count = checks.integer(value.get("count"), f"{where}.seeds.count", 1, MAX_SEEDS)
        return list(range(first, first + count))
    seeds = [checks.integer(s, f"{where}.seeds", 0) for s in _listed(value)]
    if not seeds:
        raise ValueError(f"{where}.seeds is an empty list: it names no world")
    return seeds


def _file(value, where: str, folder: Path) -> tuple[Path, str]:
    if not isinstance(value, str):
        raise ValueError(f"{where}: a file name, got {value!r}")
    file = (folder / value).resolve()
    try:
        return file, hashlib.sha1(file.read_bytes()).hexdigest()
    except OSError as error:
        raise ValueError(f"{where}: cannot read {file} ({error.strerror})") from None


def _worlds(entry, where: str, folder: Path) -> list[World]:
    """The worlds of one entry of ``worlds``, checked, in the entry's ``group`` where it names one (held-out seeds
    of a family apart from the seeds a study tuned on, say; by default the family, scenario or file)."""
    if not isinstance(entry, dict) or "group" not in entry:
        return _kind_worlds(entry, where, folder)
    group = checks.text(entry["group"], f"{where}.group", "")
    if not group:
        raise ValueError(f"{where}.group is empty: name the group or leave the key out")
    return [World(world.recipe, {**world.coords, "group": group})
            for world in _kind_worlds({k: v for k, v in entry.items() if k != "group"}, where, folder)]


def _kind_worlds(entry, where: str, folder: Path) -> list[World]:
    """The worlds of one entry of ``worlds`` but its group, checked (families and sizes by name, files by loading
    them)."""
    import tdp
    from ..random_worlds import FAMILIES, GENERATION

    if not isinstance(entry, dict) or sum(k in entry for k in WORLD_KINDS) != 1:
        raise ValueError(f"{where}: a mapping with exactly one of {', '.join(WORLD_KINDS)}")
    kind = next(k for k in WORLD_KINDS if k in entry)
    if kind == "family":
        _only(entry, ("family", "size", "seeds"), where)
        families = _listed(entry["family"])
        for family in families:
            if family not in FAMILIES:
                raise ValueError(f"{where}: unknown family {family!r}; choose one of {', '.join(FAMILIES)}")
        sizes = [checks.integer(s, f"{where}.size", 60, MAX_MAP_SIDE) for s in _listed(entry.get("size", 100))]
        return [World({"kind": kind, "family": family, "size": size, "seed": seed, "generation": GENERATION},
                      {"world": f"{family}-{size}-{seed}", "group": family, "size": size, "seed": seed})
                for family in families for size in sizes for seed in _seeds(entry.get("seeds", 0), where)]
    if kind == "scenario":
        _only(entry, ("scenario",), where)
        name = entry["scenario"]
        size = max(tdp.scenarios.get(name).grid.shape)
        return [World({"kind": kind, "scenario": name}, {"world": name, "group": name, "size": size, "seed": None})]
    if kind == "world":
        _only(entry, ("world",), where)
        file, digest = _file(entry["world"], where, folder)
        scenario = tdp.load_world(file)
        return [World({"kind": kind, "path": str(file), "sha1": digest},
                      {"world": file.stem, "group": file.stem, "size": max(scenario.grid.shape), "seed": None})]
    _only(entry, ("map", "start", "goal", "boxes", "seeds", "blockage") + _MAP_OPTIONS, where)
    file, digest = _file(entry["map"], where, folder)
    options = _map_options(entry, where)
    grid = tdp.load_map(file, **options)
    start = grid.check_free_cell(_cell(entry.get("start"), f"{where}.start"), f"{where}.start")
    goal = grid.check_free_cell(_cell(entry.get("goal"), f"{where}.goal"), f"{where}.goal")
    boxes = checks.integer(entry.get("boxes", 3), f"{where}.boxes", 0)
    blockage = checks.flag(entry.get("blockage", False), f"{where}.blockage")
    return [World({"kind": kind, "path": str(file), "sha1": digest, "options": options, "start": list(start),
                   "goal": list(goal), "boxes": boxes, "seed": seed, "blockage": blockage},
                  {"world": f"{file.stem}-{seed}", "group": file.stem, "size": max(grid.shape), "seed": seed})
            for seed in _seeds(entry.get("seeds", 0), where)]


#: A map entry's options for tdp.load_map: nav2's inflation cost and a ROS map's graded values as costs.
_MAP_OPTIONS = ("cost_scaling_factor", "inflation_radius", "trinary_costmap")


def _map_options(entry: dict, where: str) -> dict:
    """The load_map options of a map entry, checked (the inflation parameters go together)."""
    options = {key: checks.number(entry[key], f"{where}.{key}", 0.0)
               for key in _MAP_OPTIONS[:2] if key in entry}
    if len(options) == 1:
        raise ValueError(f"{where}: cost_scaling_factor and inflation_radius go together (nav2's inflation layer)")
    if "trinary_costmap" in entry:
        options["trinary_costmap"] = checks.flag(entry["trinary_costmap"], f"{where}.trinary_costmap")
    return options


def _named_apart(worlds) -> tuple[World, ...]:
    """The worlds, each once (a seed listed twice, or in two entries, is one world, in the first entry's group),
    those that share a name with a different world renamed ``name#k`` (k: 1, 2, ... in order of first appearance):
    results are keyed by name, and the oracle's length of one must not be read for the other."""
    worlds = list(worlds)
    recipes: dict[str, list[dict]] = {}
    for world in worlds:
        same = recipes.setdefault(world.coords["world"], [])
        if world.recipe not in same:
            same.append(world.recipe)
    out: dict[str, World] = {}
    for world in worlds:
        name, same = world.coords["world"], recipes[world.coords["world"]]
        if len(same) > 1:
            world = World(world.recipe, {**world.coords, "world": f"{name}#{same.index(world.recipe) + 1}"})
        out.setdefault(json.dumps([world.recipe, world.coords["world"]], sort_keys=True), world)  # the first group
    return tuple(out.values())


def _cell(value, where: str) -> tuple:
    if not isinstance(value, list) or len(value) != 2:
        raise ValueError(f"{where}: [row, col] is needed, got {value!r}")
    return tuple(value)


def _runs(entry, common: dict, where: str) -> tuple[list[tuple[str, dict, int | None]], list[str]]:
    """The (planner, full config, max_size) of one ``planners`` entry (the product of its listed values) and the
    fields it names."""
    if not isinstance(entry, dict) or entry.get("planner") not in SWEEP_PLANNERS:
        raise ValueError(f"{where}: a mapping whose 'planner' is one of {', '.join(SWEEP_PLANNERS)}")
    planner = entry["planner"]
    allowed = fields_read(planner) if planner in PLANNERS else STENCIL_FIELDS  # D* Lite, the oracle: the stencil
    given = {k: v for k, v in entry.items() if k not in ("planner", "max_size")}
    max_size = checks.optional_integer(entry.get("max_size"), f"{where}.max_size", 1)
    for name in given:
        if name not in allowed:
            raise ValueError(f"{where} ({planner}): {name!r} is not one of its fields "
                             f"({', '.join(allowed + ('max_size',))})")
    settings = {**{k: v for k, v in common.items() if k in allowed}, **given}
    names = list(settings)
    for name in names:
        if settings[name] == []:
            raise ValueError(f"{where} ({planner}): {name} is an empty list: it sweeps no value")
    runs = []
    for values in itertools.product(*(_listed(settings[n]) for n in names)):
        try:
            config = NavigatorConfig(planner=config_planner(planner), **dict(zip(names, values))).to_dict()
        except ValueError as error:
            hint = next((hint for hint in map(checks.yaml_text_hint, values) if hint), "")
            raise ValueError(f"{where} ({planner}): {error}{hint}") from None
        runs.append((planner, {k: config[k] for k in allowed}, max_size))
    return runs, names


def config_planner(kind: str) -> str:
    """The NavigatorConfig ``planner`` of a sweep's planner name: the name itself for the planners a config names,
    "exact" for the oracle (the exact planner, unbudgeted) and D* Lite (which reads only the stencil)."""
    return kind if kind in PLANNERS else "exact"


def metric_function(name: str):
    """The function ``module:function`` names: ``function(scenario, record, planner, config) -> dict`` of extra
    metrics of an episode (record: :func:`tdp.simulate.run_planner`'s; config: the NavigatorConfig)."""
    module_name, _, function_name = str(name).partition(":")
    try:
        function = getattr(importlib.import_module(module_name), function_name)
    except (ImportError, AttributeError, ValueError) as error:
        raise ValueError(f"metrics: cannot find {name!r} (module:function; {error})") from None
    if not callable(function):
        raise ValueError(f"metrics: {name!r} is not a function")
    return function
