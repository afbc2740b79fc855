"""A tdp.Scenario run in PyBullet: tdp plans on the rasterised world, the robot drives by its wheels."""
from __future__ import annotations

import math
import os
import sys
import time
import warnings
from dataclasses import asdict, dataclass

import numpy as np
import pybullet as p

import tdp
from tdp import checks
from tdp.contract import Mode, TickResult, WorldFeed, detection_records, landmarks, timing_summary
from tdp.simulate import oracle_run

from .control import PurePursuit
from .robot import RADIUS_M, DiffDriveRobot
from .world import SimWorld, cell_centres


#: The farthest obstacle (metres) the clearance measures: beyond it the robot counts as CLEARANCE_M clear.
CLEARANCE_M = 1.0

#: The most pictures an episode's film keeps (:class:`_Film`): 30 s of animation at 10 frames a second.
MAX_FRAMES = 300


@dataclass(frozen=True)
class SimConfig:
    """The robot's and the simulator's settings. The world's scale comes from the scenario: a cell is its map's
    resolution (0.1 m in the named scenarios) and a tick its ``tick_s`` (0.2 s there), so the robot at
    ``max_speed`` (m/s) crosses about one cell per tick and obstacles at 0.5 cells per tick move at half its speed,
    as in the paper. Obstacles grow by the robot's radius plus ``margin_m``; moving boxes are also swept along
    their measured velocity over ``horizon_s`` seconds, so that the robot keeps out of their way between ticks.
    With ``cost_scaling_factor`` (per metre) and ``inflation_radius`` (metres), as nav2's inflation layer names
    them, the planner's map also costs more near every grown obstacle, boxes included (``252 exp(-k d)`` at d metres
    from a grown obstacle within the inflation radius less the grown radius, through NavFn's mapping; the world's
    own costs are kept where higher), and follows the boxes tick by tick."""

    physics_hz: int = 240
    control_hz: int = 20
    margin_m: float = 0.1
    horizon_s: float = 1.0
    goal_tolerance_m: float = 0.1
    max_speed: float = 0.5
    frame_every: int = 2
    cost_scaling_factor: float | None = None
    inflation_radius: float | None = None

    @property
    def inflate_m(self) -> float:
        """Obstacles grow by the robot's radius plus the margin before planning."""
        return RADIUS_M + self.margin_m

    def __post_init__(self):
        inflation = (self.cost_scaling_factor, self.inflation_radius)
        if (inflation[0] is None) != (inflation[1] is None):
            raise ValueError("cost_scaling_factor and inflation_radius go together (nav2's inflation layer); got "
                             f"{inflation[0]!r} and {inflation[1]!r}")
        optional = ("cost_scaling_factor", "inflation_radius")
        for name in ("margin_m", "horizon_s") + optional:
            value = getattr(self, name)
            if value is None and name in optional:
                continue
            checks.number(value, name, 0)
        for name in ("goal_tolerance_m", "max_speed"):  # at 0 the robot never arrives: it never moves, or never close
            checks.number(getattr(self, name), name, 0, inclusive=False)
        for name in ("physics_hz", "control_hz", "frame_every"):
            checks.integer(getattr(self, name), name, 1)
        if self.physics_hz % self.control_hz:
            raise ValueError(f"physics_hz must be a multiple of control_hz, got {self.physics_hz} and "
                             f"{self.control_hz}")

    def costs(self, occupied: np.ndarray, cell_m: float, world_cost: np.ndarray | None) -> np.ndarray | None:
        """The planner's traversal costs over ``occupied`` (the grown obstacles, cells of ``cell_m`` metres): the
        world's own (``world_cost``, or None), raised by the inflation cost when this config asks for it."""
        if self.cost_scaling_factor is None:
            return world_cost
        grid = tdp.GridMap(occupied, cell_m, cost=world_cost)
        reach_m = max(self.inflation_radius - self.inflate_m, 0.0)
        return grid.inflate(0, cost_scaling_factor=self.cost_scaling_factor, inflation_radius=reach_m).cost


def connect(gui: bool) -> int:
    """A PyBullet client: DIRECT (headless) unless ``gui``, which needs a display."""
    if gui and not os.environ.get("DISPLAY"):
        raise ValueError("--gui needs a display, and DISPLAY is not set; run headless without --gui")
    client = p.connect(p.GUI if gui else p.DIRECT)
    if client < 0:
        raise ValueError("could not open a PyBullet GUI window")
    p.setGravity(0, 0, -9.81, physicsClientId=client)
    return client


def inflated_scenario(scenario: tdp.Scenario, margin_cells: float) -> tdp.Scenario:
    """The scenario as the planner sees it: the static map inflated by a disk of ``margin_cells`` (as the run's),
    boxes grown by that rounded up to whole cells on each side."""
    cells = math.ceil(margin_cells)
    boxes = [tdp.Obstacle(box=(o.box[0] - cells, o.box[1] - cells, o.box[2] + cells, o.box[3] + cells),
                          waypoints=[(r - cells, c - cells) for r, c in o.waypoints], speed=o.speed,
                          appear_at=o.appear_at, vanish_at=o.vanish_at) for o in scenario.obstacles]
    return tdp.Scenario(scenario.grid.inflate(margin_cells), scenario.start, scenario.goal, obstacles=boxes,
                        target_waypoints=scenario.target_waypoints, target_speed=scenario.target_speed,
                        name=scenario.name, max_ticks=scenario.max_ticks)


def episode_ticks(scenario: tdp.Scenario, sim: SimConfig) -> int:
    """The ticks a PyBullet episode of ``scenario`` may last: the world's ``max_ticks`` where it sets them; else its
    grid-level limit (``tick_limit``, 4 (H + W): about a cell a tick) stretched by the ticks the robot needs per cell
    at ``sim.max_speed``. On a map of 1 m cells with 0.2 s ticks the robot crosses a cell in 10 ticks: the grid's
    limit ended a 745 m route through a 512 x 512 map of rooms after 406 m."""
    cells_per_tick = sim.max_speed * scenario.tick_s / scenario.grid.resolution
    if scenario.max_ticks:
        return scenario.tick_limit
    return math.ceil(scenario.tick_limit / min(1.0, cells_per_tick))


def grown_oracle(scenario: tdp.Scenario, config: tdp.NavigatorConfig, margin_cells: float,
                 max_ticks: int) -> dict | None:
    """The oracle's run (:func:`tdp.simulate.oracle_run`) on :func:`inflated_scenario`, or None where that has no
    room for the start or the goal (a box's growth rounded up to whole cells on a coarse map covers one the run's
    exact margin leaves free): the episode then has no oracle, rather than losing its metrics at the end."""
    try:
        grown = inflated_scenario(scenario, margin_cells)
    except ValueError:
        return None
    return oracle_run(grown, config, max_ticks)


class _Run:
    """State of one episode: world, robot, planner (``navigator``: whichever the config names), controller and the
    record."""

    def __init__(self, scenario: tdp.Scenario, config: tdp.NavigatorConfig, sim: SimConfig, client: int):
        self.scenario, self.config, self.sim, self.client = scenario, config, sim, client
        p.setTimeStep(1.0 / sim.physics_hz, physicsClientId=client)
        self.cell_m, self.tick_s = scenario.grid.resolution, scenario.tick_s
        if config.budget_ms is not None and config.budget_ms > 1e3 * self.tick_s:
            raise ValueError(f"budget_ms {config.budget_ms} is longer than the control period, a tick of "
                             f"{1e3 * self.tick_s:g} ms")
        if round(self.tick_s * sim.physics_hz) < 1:  # a tick of no physics step: the robot would never move
            raise ValueError(f"the world's tick, {self.tick_s:g} s, is shorter than half a physics step "
                             f"(1/{sim.physics_hz} s): lengthen tick_s or raise SimConfig.physics_hz")
        self.world = SimWorld(client, scenario, self.cell_m, self.tick_s)
        self.grid = self.world.grid
        self.static = scenario.grid.inflate(sim.inflate_m / self.cell_m).occupied
        mask = self.static | self.world.moving_footprints(sim.inflate_m, 0.0, sim.horizon_s)
        for name, cell in (("start", scenario.start), ("goal", scenario.goal)):
            if mask[cell]:
                raise ValueError(f"{name} {cell} is within {sim.inflate_m} m of an obstacle: no room for the robot")
        cost = sim.costs(mask, self.cell_m, scenario.grid.cost)  # the world's costs and the inflation's, if any
        self.navigator = tdp.make_planner(tdp.GridMap(mask, cost=cost), scenario.start, scenario.goal, config)
        self.feed = WorldFeed(mask, scenario.goal, cost)
        self.navigator.setup()
        x, y = self.grid.cell_to_world(*scenario.start)
        gx, gy = self.grid.cell_to_world(*scenario.goal)
        self.robot = DiffDriveRobot(client, x, y, math.atan2(gy - y, gx - x))
        self.controller = PurePursuit(max_v=sim.max_speed)
        self.trace: list[tuple[float, float, Mode]] = [(x, y, Mode.EXACT if config.planner == "exact" else Mode.DP)]
        self.length_m = 0.0
        self.contact_steps = 0
        self.min_clearance = math.inf
        self.clearances: list[float] = []
        self.planner_s: list[float] = []
        self.results: list[TickResult] = []

    def robot_cell(self) -> tuple[int, int]:
        x, y, _ = self.robot.pose()
        r, c = self.grid.world_to_cell(x, y)
        return min(max(r, 0), self.grid.shape[0] - 1), min(max(c, 0), self.grid.shape[1] - 1)

    def plan(self, tick: int) -> TickResult:
        """Rasterise, send the changed cells and the target's move, run the planner's tick."""
        now = self.static | self.world.moving_footprints(self.sim.inflate_m, (tick - 1) * self.tick_s,
                                                         self.sim.horizon_s)
        cost = None  # the world's own costs stay; the inflation's follow the boxes
        if self.sim.cost_scaling_factor is not None:
            cost = self.sim.costs(now, self.cell_m, self.scenario.grid.cost)
        self.feed.update(self.navigator, now, self.scenario.target(tick), cost)
        self.navigator.move_robot(self.robot_cell())
        began = time.perf_counter()
        result = self.navigator.tick()
        self.planner_s.append(time.perf_counter() - began)
        self.results.append(result)
        return result

    def landmark_points(self) -> tuple[tuple[float, float] | None, tuple[float, float] | None]:
        """Where the robot was (x, y in metres) when it turned (A) and when it switched back (B)."""
        return tuple(self.trace[t - 1][:2] if t else None for t in landmarks(self.results))

    def drive(self, tick: int, result) -> None:
        """Physics for one tick, steering at control_hz along the planner's route."""
        sim = self.sim
        route = self._route(result)
        steps_per_control = sim.physics_hz // sim.control_hz
        control_dt = 1.0 / sim.control_hz
        steps = round(self.tick_s * sim.physics_hz)
        last = self.robot.pose()
        for step in range(steps):
            if step % steps_per_control == 0:
                if not route:
                    v, w = self.controller.stop(control_dt)
                else:
                    v, w = self.controller.steer(last, route, control_dt)
                self.robot.command(v, w)
                self._measure_clearance()
            self.world.update(((tick - 1) * steps + step + 1) / sim.physics_hz)
            p.stepSimulation(physicsClientId=self.client)
            now = self.robot.pose()
            self.length_m += math.hypot(now[0] - last[0], now[1] - last[1])
            last = now
            self._count_contacts()
        self.trace.append((last[0], last[1], result.mode))

    def _route(self, result: TickResult) -> list[tuple[float, float]]:
        """The points (x, y in metres) to steer along this tick, none to stop: out of the inflated obstacles the
        nearest free cell, else the centres of :func:`steering_cells`."""
        escape = self._escape()
        if escape is not None:
            return [escape]
        move = result.next_cell
        route = [] if move is None else self.navigator.route(12)  # a tick without a move steers along none
        cells = steering_cells(self.robot_cell(), self.feed.target, move, route)
        return [self.grid.cell_to_world(*cell) for cell in cells]

    def _escape(self) -> tuple[float, float] | None:
        """Inside the inflated obstacles (a box came too close) the planner has no successor: head for the
        nearest free cell instead of waiting to be hit. None when the robot's cell is free."""
        if not self.feed.occupied[self.robot_cell()]:
            return None
        if self.feed.occupied.all():
            return None
        x, y, _ = self.robot.pose()
        cx, cy = cell_centres(self.grid)
        distance = np.where(self.feed.occupied, np.inf, np.hypot(cx - x, cy - y))
        nearest = np.unravel_index(np.argmin(distance), distance.shape)
        return float(cx[nearest]), float(cy[nearest])

    def _count_contacts(self) -> None:
        touching = any(self.world.is_obstacle(c[2]) for c in p.getContactPoints(bodyA=self.robot.body,
                                                                                physicsClientId=self.client))
        self.contact_steps += int(touching)

    def _measure_clearance(self) -> None:
        """The robot's distance to the nearest obstacle now (metres, up to CLEARANCE_M): its minimum and its
        samples, one per control step. Only the obstacles whose bounding boxes come within CLEARANCE_M of the
        robot's are asked."""
        nearest = CLEARANCE_M
        low, high = p.getAABB(self.robot.body, physicsClientId=self.client)
        for link in range(p.getNumJoints(self.robot.body, physicsClientId=self.client)):
            link_low, link_high = p.getAABB(self.robot.body, link, physicsClientId=self.client)
            low, high = np.minimum(low, link_low), np.maximum(high, link_high)
        reach = np.array([CLEARANCE_M, CLEARANCE_M, 0.0])
        for body in self.world.obstacles_near(tuple(low - reach), tuple(high + reach)):
            for point in p.getClosestPoints(self.robot.body, body, CLEARANCE_M, physicsClientId=self.client):
                nearest = min(nearest, point[8])
        self.min_clearance = min(self.min_clearance, nearest)
        self.clearances.append(nearest)

    def reached(self) -> bool:
        x, y, _ = self.robot.pose()
        gx, gy = self.grid.cell_to_world(*self.feed.target)
        return math.hypot(gx - x, gy - y) <= self.sim.goal_tolerance_m


def margin_floor_m(cell_m: float) -> float:
    """The least ``SimConfig.margin_m`` (metres) that covers a grid of ``cell_m``-metre cells: obstacles grow centre
    to centre, so a free cell's centre may lie up to half a cell's diagonal nearer an obstacle's edge than the growth
    says (0.071 m on 0.1 m cells)."""
    return cell_m * math.sqrt(2) / 2


def _check_episode(scenario, config, sim, gui, frames) -> None:
    """:func:`run_episode`'s arguments are of their kinds, else a ValueError naming the first that is not; a
    UserWarning where the margin leaves the robot less room than the grid promises (``margin_floor_m``)."""
    for value, kind, name, called in ((scenario, tdp.Scenario, "scenario", "tdp.Scenario"),
                                      (config, tdp.NavigatorConfig, "config", "tdp.NavigatorConfig"),
                                      (sim, SimConfig, "sim", "sim.episode.SimConfig")):
        if not isinstance(value, kind):
            raise ValueError(f"{name} must be a {called}, got {type(value).__name__}")
    checks.flag(gui, "gui")
    if frames is not None and not isinstance(frames, list):
        raise ValueError(f"frames must be a list (the pictures are appended to it) or None, got "
                         f"{type(frames).__name__}")
    floor_m = margin_floor_m(scenario.grid.resolution)
    if sim.margin_m < floor_m:
        enough_m = math.ceil(floor_m * 1000) / 1000
        warnings.warn(f"margin_m {sim.margin_m:g} is less than half a cell's diagonal ({floor_m:.3g} m on this map's "
                      f"{scenario.grid.resolution:g} m cells): the planners may route the robot through gaps it does "
                      f"not fit, and it may touch obstacles; give SimConfig(margin_m={enough_m:g}) "
                      f"(--margin {enough_m:g} on the command line) or more, or a finer map", UserWarning, stacklevel=3)


class TopCamera:
    """The simulator's camera straight above the map's centre, seeing the whole map (TinyRenderer: works headless)."""

    def __init__(self, client: int, grid: tdp.GridMap, pixels: int = 360):
        self.client, self.pixels = client, pixels
        width, height = grid.shape[1] * grid.resolution, grid.shape[0] * grid.resolution
        centre = (width / 2, height / 2, 0.0)
        fov = 40.0
        eye_height = 0.55 * max(width, height) / math.tan(math.radians(fov / 2))
        self.view = p.computeViewMatrix((centre[0], centre[1], eye_height), centre, (0, 1, 0), physicsClientId=client)
        self.projection = p.computeProjectionMatrixFOV(fov, 1.0, eye_height * 0.5, eye_height * 1.5,
                                                       physicsClientId=client)

    def picture(self) -> np.ndarray:
        """An RGB picture (pixels x pixels x 3, uint8) of the world now."""
        _, _, rgba, _, _ = p.getCameraImage(self.pixels, self.pixels, self.view, self.projection,
                                            renderer=p.ER_TINY_RENDERER, physicsClientId=self.client)
        return np.asarray(rgba, np.uint8).reshape(self.pixels, self.pixels, 4)[:, :, :3].copy()


class _Film:
    """The camera's pictures of an episode, appended to ``frames``: after every ``every``-th tick from the first and
    at the end. At most MAX_FRAMES of them: beyond that every other picture is dropped and the rest come half as
    often, so a long episode's film stays evenly spaced and its memory bounded (a picture is 0.4 MB: a 1,500 s
    episode on a 512 x 512 map took 3,700 of them at every second tick)."""

    def __init__(self, frames: list, camera: TopCamera, every: int):
        self.frames, self.camera, self.every = frames, camera, every
        self.first, self.ticks = len(frames), []  # the ticks of this film's pictures

    def shoot(self, tick: int) -> None:
        """After ``tick`` (from 1): a picture if it is one of the film's."""
        if (tick - 1) % self.every:
            return
        self.frames.append(self.camera.picture())
        self.ticks.append(tick)
        if len(self.ticks) > MAX_FRAMES:
            self.frames[self.first:] = self.frames[self.first::2]
            self.ticks = self.ticks[::2]
            self.every *= 2

    def finish(self, tick: int) -> None:
        """At the end, after ``tick`` ticks: the last state, where no picture shows it."""
        if not self.ticks or self.ticks[-1] != tick:
            self.frames.append(self.camera.picture())


def steering_cells(robot: tuple[int, int], target: tuple[int, int], move: tuple[int, int] | None,
                   route: list[tuple[int, int]]) -> list[tuple[int, int]]:
    """The cells the robot steers through this tick, given its cell, the target's, the tick's move (None: stay) and
    the planner's route from the robot: the target's cell once there; none where the tick gives no move (waiting,
    yielding to a box, a budgeted repair not yet at the robot: the robot stops); the route where it starts with the
    move (the controller looks ahead along it); else the move alone (a step aside from a box's way)."""
    if robot == target:
        return [target]
    if move is None:
        return []
    return route if route and route[0] == move else [move]


def run_episode(scenario: tdp.Scenario, config: tdp.NavigatorConfig = tdp.NavigatorConfig(),
                sim: SimConfig = SimConfig(), gui: bool = False, progress: bool = False,
                frames: list | None = None) -> dict:
    """Run ``scenario`` in PyBullet and return its metrics (lengths in metres, times in seconds). With ``frames``
    (a list), the simulator's own camera looks down on the world every ``sim.frame_every`` ticks and at the end
    (a run that starts at its goal has that picture alone), and each picture (an (H, W, 3) uint8 array) is appended
    to it; a long episode's pictures are thinned to at most MAX_FRAMES, evenly spaced.

    Raises:
        ValueError: an argument of the wrong kind; no room for the robot at the start or the goal; a budget longer
            than a tick; a tick shorter than half a physics step (no step would run); ``gui`` without a display.

    Warns:
        UserWarning: ``sim.margin_m`` below half a cell's diagonal (``margin_floor_m``), where the robot may not fit
            the gaps the planners route it through.
    """
    _check_episode(scenario, config, sim, gui, frames)
    client = connect(gui)
    try:
        run = _Run(scenario, config, sim, client)
        film = _Film(frames, TopCamera(client, run.grid), sim.frame_every) if frames is not None else None
        max_ticks = episode_ticks(scenario, sim)
        tick = 0
        began = time.perf_counter()
        while tick < max_ticks and not run.reached():
            tick += 1
            result = run.plan(tick)
            run.drive(tick, result)
            if film:
                film.shoot(tick)
            if progress and tick % 25 == 0:
                x, y, _ = run.robot.pose()
                print(f"  [{scenario.name}] t = {tick * run.tick_s:5.1f} s: robot at ({x:.2f}, {y:.2f}) m, "
                      f"{result.mode}", file=sys.stderr, flush=True)
        wall_s = time.perf_counter() - began
        reached = run.reached()
        if film:
            film.finish(tick)
    finally:
        p.disconnect(physicsClientId=client)
    oracle = grown_oracle(scenario, config, sim.inflate_m / run.cell_m, max_ticks)
    oracle_reached = None if oracle is None else bool(oracle["reached"])
    oracle_m = oracle["length"] * run.cell_m if oracle_reached else None  # no route's length where none reached
    turn_point, switch_back_point = run.landmark_points()
    return {
        "scenario": scenario.name, "planner": config.planner, "updates_per_move": config.updates_per_move,
        "reached": reached, "time_s": tick * run.tick_s, "wall_s": wall_s, "ticks": tick, "max_ticks": max_ticks,
        "path_length_m": run.length_m, "oracle_reached": oracle_reached, "oracle_length_m": oracle_m,
        "ratio": run.length_m / oracle_m if oracle_m and reached else None,  # as the grid's: both reached
        "contacts": run.contact_steps,
        "min_clearance_m": run.min_clearance, "mean_clearance_m": float(np.mean(run.clearances or [math.nan])),
        "detections": detection_records(run.results),
        "planner_ms_per_tick": timing_summary(run.planner_s),
        "trace": run.trace, "modes": [result.mode for result in run.results], "nodes": run.navigator.nodes.tolist(),
        "turn_point": turn_point, "switch_back_point": switch_back_point,
        "oracle_trajectory": [] if oracle is None else oracle["trajectory"], "config": config.to_dict(),
        "sim": {**asdict(sim), "cell_m": run.cell_m, "tick_s": run.tick_s},
    }
