"""Every parameter of a planner, checked once: :class:`NavigatorConfig`, and the planners a config can name."""
from __future__ import annotations

import math
from dataclasses import asdict, dataclass, fields

from . import checks
from .field import check_cap
from .nodes import PLACEMENTS
from .stencil import check_neighbourhood

#: The planners a config can name: exact replanning every tick (tdp.ExactPlanner), the paper's accelerating nodes and
#: its plain DP baseline (tdp.Navigator).
PLANNERS = ("exact", "accelerating", "plain-dp")
#: What each planner is called in messages and figures.
PLANNER_NAMES = {"exact": "exact replanning", "accelerating": "accelerating nodes", "plain-dp": "plain DP"}
#: How a backup ends: "evidence" (as soon as the goal layer shows a route to G no longer than the backup's, or
#: after ||Path|| iterations) or "paper" (after ||Path|| iterations only, section 4.3).
SWITCH_BACK = ("evidence", "paper")
#: The largest K, J and budget a config takes: K iterations per move (a million converge any map a robot drives),
#: J + 1 iterations' pair distances the blockage test keeps (nodes² floats each), an hour a tick (accelerating
#: nodes iterate until the budget is spent).
MAX_UPDATES_PER_MOVE, MAX_DETECT_WINDOW, MAX_BUDGET_MS = 10**6, 1000, 3.6e6

@dataclass(frozen=True)
class NavigatorConfig:
    """Every parameter of the planner.

    planner: "exact" (default: the goal layer repaired exactly every tick, :class:`tdp.ExactPlanner`; RESULTS.md's
    equal-time benchmark finds it the best for a user who does not choose), "accelerating" (the paper's accelerating
    nodes, :class:`tdp.Navigator`) or "plain-dp" (the paper's baseline: K synchronous DP iterations per move). The
    exact planner reads the stencil, ``d_max``, ``budget_ms`` (then its repair is anytime: see ExactPlanner) and
    ``avoid_boxes`` (with ``avoid_ticks`` and ``meet_ticks``);
    ``accelerating=False`` of earlier versions is ``planner="plain-dp"``.
    nodes: number of nodes of the uniform lattice (its spacing s follows from the map's area);
    spacing: lattice spacing s in cells, overriding ``nodes`` when given.
    vision: DmaxQ / s (ARCHITECTURE §5.2). updates_per_move: K, DP iterations per robot move (at most a million,
    ``MAX_UPDATES_PER_MOVE``).
    budget_ms: a time budget per tick in milliseconds instead of a fixed K: each tick runs as many DP iterations
    as fit in it, the monitor included (at least one; the number depends on the machine, so runs do too); for the
    exact planner, how long its repair may run before the robot moves on the layer as far as it got. At most an
    hour (``MAX_BUDGET_MS``).
    detect_window, detect_rise: J and U of the blockage test (U defaults to J - 1); J at most 1000
    (``MAX_DETECT_WINDOW``).
    d_max: cap of the goal layer (eq. 5): a cell farther than that from the goal reads as cut off, and a robot there
    waits (default inf). neighbourhood, corner_cutting: the stencil (ARCHITECTURE §4).
    placement: where a lattice node whose centre is on an obstacle goes: "free" (the free cell of its lattice cell
    nearest the centre), "drop" (left out, the paper) or "nudge" (a free cell within s/4); see
    :func:`tdp.nodes.place_nodes`.
    switch_back: "evidence" (leave a backup as soon as the goal layer's successors reach G by a route no longer
    than the backup's estimate, and never start one that the goal layer already beats) or "paper" (only after
    ||Path|| DP iterations, section 4.3).
    predict_ticks: obstacle prediction's horizon H in ticks (0: off; the DP planners only; ARCHITECTURE §5.7): moving
    boxes are tracked from the map updates and the node layers (not the goal layer) see the cells they are predicted
    to sweep over in the next H ticks, so the monitor flags a passage a box is about to close.
    avoid_boxes: boxes tracked as for ``predict_ticks`` (with every planner, the exact one too), the robot does not
    step into a cell a box is predicted to enter at the next tick, nor drive on where a box crossing its way will meet
    it: it yields (stays) or, if a box is about to enter its own cell, steps aside.

    The rules' thresholds (defaults as measured in RESULTS.md; tests set them directly):
    evidence_slack: with switch_back="evidence", the goal layer's route wins when it is at most this fraction longer
    than the backup's estimate (the estimate reads node layers that are at most the true lengths while they rise,
    while the route's length counts every detour the goal layer still holds around boxes moving far ahead).
    settled_cells: how far (cells) a value of the goal layer may sit below its successor's plus the move and still
    count as settled: float rounding only; a value still rising after a change is short by about a cell or more.
    avoid_ticks: with avoid_boxes, a step aside prefers cells no box is predicted to enter within this many ticks.
    meet_ticks: with avoid_boxes, how many of the robot's next moves are checked against the arrivals of boxes
    crossing its way.
    """

    planner: str = "exact"
    nodes: int = 25
    vision: float = 2.5
    updates_per_move: int = 4
    detect_window: int = 6
    detect_rise: float | None = None
    d_max: float = math.inf
    neighbourhood: int = 16
    corner_cutting: bool = False
    spacing: float | None = None
    budget_ms: float | None = None
    placement: str = "free"
    switch_back: str = "evidence"
    predict_ticks: int = 0
    avoid_boxes: bool = False
    evidence_slack: float = 0.1
    settled_cells: float = 0.25
    avoid_ticks: int = 2
    meet_ticks: int = 8

    def __post_init__(self):
        def normalised(name: str, value) -> None:  # the checked value, as a plain Python int, float or bool
            object.__setattr__(self, name, value)

        if self.planner not in PLANNERS:
            raise ValueError(f"planner must be one of {PLANNERS}, got {self.planner!r}")
        normalised("nodes", checks.integer(self.nodes, "nodes", 1))
        if self.spacing is not None:
            normalised("spacing", checks.number(self.spacing, "spacing", 1.0))
        normalised("vision", checks.number(self.vision, "vision", 0.0, inclusive=False))
        normalised("updates_per_move", checks.integer(self.updates_per_move, "updates_per_move", 1,
                                                      MAX_UPDATES_PER_MOVE))
        if self.budget_ms is not None:
            normalised("budget_ms", checks.number(self.budget_ms, "budget_ms", 0.0, inclusive=False,
                                                  high=MAX_BUDGET_MS))
        normalised("detect_window", checks.integer(self.detect_window, "detect_window", 1, MAX_DETECT_WINDOW))
        if self.detect_rise is not None:
            normalised("detect_rise", checks.number(self.detect_rise, "detect_rise", 0.0, inclusive=False))
        check_cap(self.d_max, "d_max")
        check_neighbourhood(self.neighbourhood)
        normalised("corner_cutting", checks.flag(self.corner_cutting, "corner_cutting"))
        if self.placement not in PLACEMENTS:
            raise ValueError(f"placement must be one of {PLACEMENTS}, got {self.placement!r}")
        if self.switch_back not in SWITCH_BACK:
            raise ValueError(f"switch_back must be one of {SWITCH_BACK}, got {self.switch_back!r}")
        normalised("predict_ticks", checks.integer(self.predict_ticks, "predict_ticks", 0))
        normalised("avoid_boxes", checks.flag(self.avoid_boxes, "avoid_boxes"))
        normalised("evidence_slack", checks.number(self.evidence_slack, "evidence_slack", 0.0))
        normalised("settled_cells", checks.number(self.settled_cells, "settled_cells", 0.0))
        normalised("avoid_ticks", checks.integer(self.avoid_ticks, "avoid_ticks", 1))
        normalised("meet_ticks", checks.integer(self.meet_ticks, "meet_ticks", 1))
        if self.planner == "exact" and self.predict_ticks:
            raise ValueError("predict_ticks holds predicted cells in the node layers of the DP planners: it needs "
                             "planner 'accelerating' or 'plain-dp', not 'exact' (whose goal layer stays exact; "
                             "avoid_boxes works with every planner)")

    @property
    def accelerating(self) -> bool:
        """Whether the planner is the paper's accelerating nodes."""
        return self.planner == "accelerating"

    @property
    def rise(self) -> float:
        """U: the rise over J iterations that signals a blockage."""
        return float(self.detect_window - 1) if self.detect_rise is None else float(self.detect_rise)

    def to_dict(self) -> dict:
        return asdict(self)

    def label(self) -> str:
        """The planner's name with what bounds its work per tick: K for the DP planners, or the budget."""
        return planner_label(self.to_dict())


#: Every NavigatorConfig field but ``planner``.
CONFIG_FIELDS = tuple(f.name for f in fields(NavigatorConfig) if f.name != "planner")
#: The fields every planner reads: the moves allowed.
STENCIL_FIELDS = ("neighbourhood", "corner_cutting")
#: The fields of box avoidance (every planner reads them).
AVOID_FIELDS = ("avoid_boxes", "avoid_ticks", "meet_ticks")
#: The fields only accelerating nodes read: the node lattice and the blockage test.
NODE_FIELDS = ("nodes", "spacing", "vision", "detect_window", "detect_rise", "placement", "switch_back")


def fields_read(planner: str) -> tuple[str, ...]:
    """The :class:`NavigatorConfig` fields besides ``planner`` that ``planner`` (one of PLANNERS) reads: the
    stencil, ``d_max``, ``budget_ms`` and box avoidance for exact replanning, all but the node lattice's for plain
    DP, all for accelerating nodes. Sweep specs and command lines refuse the others rather than ignore them."""
    return {"exact": STENCIL_FIELDS + ("d_max", "budget_ms") + AVOID_FIELDS,
            "plain-dp": tuple(f for f in CONFIG_FIELDS if f not in NODE_FIELDS)}.get(planner, CONFIG_FIELDS)


def planner_label(config: dict) -> str:
    """:meth:`NavigatorConfig.label` of a config written as a dict (an episode's, a run's metrics)."""
    if config.get("budget_ms") is not None:
        return f"{PLANNER_NAMES[config['planner']]}, {config['budget_ms']:g} ms"
    return PLANNER_NAMES[config["planner"]] + ("" if config["planner"] == "exact" else
                                               f", K = {config['updates_per_move']}")
