"""GridMap and the map loaders: MovingAI ``.map``/``.scen``, ROS map_server ``.yaml`` + image, plain images.

Conventions (ARCHITECTURE §3): cells are ``(row, col)`` with row 0 the top row of the file or image; MovingAI's
``(x, y)`` is ``(col, row)``. ROS's origin is the pose of the lower-left pixel, so :meth:`GridMap.world_to_cell`
and :meth:`GridMap.cell_to_world` flip the rows. Occupancy is a bool array, True = obstacle.
"""
from __future__ import annotations

import math
import numbers
import warnings
from pathlib import Path
from typing import NamedTuple

import numpy as np
import yaml
from scipy import ndimage
from PIL import Image, UnidentifiedImageError

from . import checks

IMAGE_SUFFIXES = (".png", ".pgm", ".ppm", ".pbm", ".jpg", ".jpeg", ".bmp", ".gif", ".tif", ".tiff")
ROS_MODES = ("trinary", "scale", "raw")
#: The largest map read from a file, in cells (8192 x 8192): larger images are refused before they are decoded.
MAX_CELLS = 8192 * 8192
#: MovingAI terrain letters (movingai.com/benchmarks/formats.html) for a ground robot: ground ('.', 'G') and swamp
#: ('S', passable from ordinary terrain) are free; out of bounds ('@', 'O'), trees ('T') and water ('W', not
#: passable from ordinary terrain) are obstacles.
MOVINGAI_FREE = frozenset(".GS")
MOVINGAI_BLOCKED = frozenset("@OTW")
#: Pillow modes of 16-bit greyscale images: their shades are fractions of 65535 (Pillow scales a PGM's maxval).
_SIXTEEN_BIT = ("I", "I;16", "I;16B", "I;16L", "I;16N")


#: The largest traversal cost a free cell may have (``GridMap(cost=...)``); the engine takes a penalty above it for an
#: obstacle's (inf), testing against a finite bound because fast math may fold a comparison with inf away.
MAX_COST = 1e6


class GridMap:
    """An occupancy grid: ``occupied`` bool (H, W), True = obstacle; ``resolution`` in metres per cell;
    ``origin`` the (x, y, yaw) pose in metres and radians of the lower-left cell's outer corner (ROS convention);
    ``cost`` None (every free cell costs 1: plain ground) or a float (H, W) array of traversal costs, between 1 and
    MAX_COST (1e6) on every free cell (its values on obstacles are ignored): a move of length L from cell u to cell
    v costs L x (cost[u] + cost[v]) / 2, and distances are in those units.

    Raises:
        ValueError: ``occupied`` not a non-empty 2-D bool array; a bad resolution or origin; ``cost`` not a float
            array of the map's shape, or NaN, infinite, below 1 or above MAX_COST on a free cell.
    """

    def __init__(self, occupied: np.ndarray, resolution: float = 1.0, origin: tuple[float, ...] = (0.0, 0.0),
                 cost: np.ndarray | None = None):
        occupied = np.asarray(occupied)
        if occupied.ndim != 2 or occupied.shape[0] < 1 or occupied.shape[1] < 1:
            raise ValueError(f"occupied must be a non-empty 2-D array, got shape {occupied.shape}")
        if occupied.dtype != bool:
            raise ValueError(f"occupied must be a bool array (True = obstacle), got dtype {occupied.dtype}")
        resolution = checks.number(resolution, "resolution (metres per cell)", 0.0, inclusive=False)
        if not (isinstance(origin, (tuple, list, np.ndarray)) and len(origin) in (2, 3) and all(
                isinstance(v, numbers.Real) and not isinstance(v, bool) and math.isfinite(v) for v in origin)):
            raise ValueError(f"origin must be finite (x, y) or (x, y, yaw), got {checks.shown(origin)}")
        origin = tuple(float(v) for v in origin)
        self._occupied = occupied.copy()
        self._occupied.flags.writeable = False
        self._cost = None if cost is None else _checked_cost(cost, occupied)
        self.resolution = float(resolution)
        self.origin = origin if len(origin) == 3 else origin + (0.0,)

    @property
    def occupied(self) -> np.ndarray:
        """Read-only bool (H, W) array, True = obstacle."""
        return self._occupied

    @property
    def cost(self) -> np.ndarray | None:
        """Read-only float32 (H, W) traversal costs (1 on obstacles), or None for a binary map."""
        return self._cost

    @property
    def shape(self) -> tuple[int, int]:
        """(rows, cols)."""
        return self._occupied.shape

    def __repr__(self) -> str:
        costs = "" if self._cost is None else f", cost {float(self._cost.min()):g}-{float(self._cost.max()):g}"
        return (f"GridMap(shape={self.shape}, obstacles={int(self._occupied.sum())}, "
                f"resolution={self.resolution}, origin={self.origin}{costs})")

    def inflate(self, radius_cells: float, *, cost_scaling_factor: float | None = None,
                inflation_radius: float | None = None) -> GridMap:
        """A new map whose obstacles grow by a disk: a cell is occupied if an obstacle's centre lies within
        ``radius_cells`` (Euclidean, in cells) of its centre - the robot's inscribed radius.

        With ``cost_scaling_factor`` (per metre) and ``inflation_radius`` (metres), as nav2's inflation layer names
        them, the free cells within ``inflation_radius`` of an obstacle also get nav2's inflation cost,
        ``252 exp(-cost_scaling_factor (d - radius))`` at d metres from the nearest obstacle cell (radius: the
        inscribed radius, ``radius_cells`` in metres), turned into a traversal cost by :func:`costmap_cost`; costs the
        map had already are kept where they are higher. Distances come from scipy's exact Euclidean transform.

        Raises:
            ValueError: a radius or factor that is not a finite number >= 0, or only one of the two cost parameters.
        """
        radius_cells = checks.number(radius_cells, "radius_cells", 0.0)
        if (cost_scaling_factor is None) != (inflation_radius is None):
            raise ValueError("cost_scaling_factor and inflation_radius go together (nav2's inflation layer); got "
                             f"{cost_scaling_factor!r} and {inflation_radius!r}")
        away = np.full(self.shape, np.inf)  # cells from the nearest obstacle cell's centre
        if self._occupied.any():
            away = ndimage.distance_transform_edt(~self._occupied)
        grown = self._occupied | (np.rint(away ** 2) <= radius_cells * radius_cells)  # squared: exact, as integers
        cost = self._cost
        if cost_scaling_factor is not None:
            factor = checks.number(cost_scaling_factor, "cost_scaling_factor", 0.0)
            reach_m = checks.number(inflation_radius, "inflation_radius", 0.0)
            away_m, inscribed_m = away * self.resolution, radius_cells * self.resolution
            # metres beyond the inscribed radius, kept finite: 252 within it, no cost past the reach either way
            beyond_m = np.clip(away_m - inscribed_m, 0.0, reach_m + 1.0)
            inflation = costmap_cost(np.where(away_m <= reach_m, 252.0 * np.exp(-factor * beyond_m), 0.0))
            cost = inflation if cost is None else np.maximum(cost, inflation)
        return GridMap(grown, self.resolution, self.origin, None if cost is None else np.asarray(cost, np.float64))

    def contains(self, cell: tuple[int, int]) -> bool:
        """Whether ``cell`` lies inside the map."""
        return 0 <= cell[0] < self.shape[0] and 0 <= cell[1] < self.shape[1]

    def check_free_cell(self, cell, name: str) -> tuple[int, int]:
        """Return ``cell`` as a (row, col) tuple of ints if it is inside the map and free, else raise ValueError."""
        row, col = checks.cell(cell, self.shape, name)
        if self._occupied[row, col]:
            raise ValueError(f"{name} {(row, col)} is on an obstacle")
        return row, col

    def world_to_cell(self, x: float, y: float) -> tuple[int, int]:
        """The (row, col) of the cell containing world point (x, y) in metres (may lie outside the map).

        Raises:
            ValueError: x or y not a finite number.
        """
        x, y = checks.number(x, "x"), checks.number(y, "y")
        ox, oy, yaw = self.origin
        dx, dy = x - ox, y - oy
        u = math.cos(yaw) * dx + math.sin(yaw) * dy
        v = -math.sin(yaw) * dx + math.cos(yaw) * dy
        col = math.floor(u / self.resolution)
        row_from_bottom = math.floor(v / self.resolution)
        return self.shape[0] - 1 - row_from_bottom, col

    def cell_to_world(self, row: float, col: float) -> tuple[float, float]:
        """World (x, y) in metres of the centre of cell (row, col) (may lie outside the map).

        Raises:
            ValueError: row or col not a finite number.
        """
        row, col = checks.number(row, "row"), checks.number(col, "col")
        ox, oy, yaw = self.origin
        u = (col + 0.5) * self.resolution
        v = (self.shape[0] - 1 - row + 0.5) * self.resolution
        return ox + math.cos(yaw) * u - math.sin(yaw) * v, oy + math.sin(yaw) * u + math.cos(yaw) * v


#: NavFn's mapping from a nav2 costmap's values to traversal costs: a free cell costs COST_NEUTRAL (50), a cell of
#: cost c costs COST_NEUTRAL + COST_FACTOR (0.8) x c; relative to free ground, 1 + 0.016 c (1 to 5.03 for 0-252).
NAVFN_NEUTRAL, NAVFN_FACTOR = 50.0, 0.8


def costmap_cost(values: np.ndarray) -> np.ndarray:
    """Traversal costs (1 = free ground) of nav2 costmap values 0-252 by NavFn's mapping, 1 + 0.8 c / 50."""
    return 1.0 + NAVFN_FACTOR * np.asarray(values, np.float64) / NAVFN_NEUTRAL


def costmap_grid(costmap: np.ndarray, resolution: float = 1.0, origin: tuple[float, ...] = (0.0, 0.0), *,
                 unknown_is_free: bool = False) -> GridMap:
    """A GridMap from a nav2 costmap array (uint8 or ints 0-255, row 0 the top row): 254 (lethal) and 253
    (inscribed) are obstacles, 255 (unknown) too unless ``unknown_is_free``, and 0-252 are free with the cost of
    :func:`costmap_cost`.

    Raises:
        ValueError: not a 2-D integer array of values 0-255.
    """
    unknown_is_free = checks.flag(unknown_is_free, "unknown_is_free")
    try:
        costmap = np.asarray(costmap)
    except ValueError:  # rows of unequal lengths
        raise ValueError(f"costmap must be a 2-D integer array, got {checks.shown(costmap)}") from None
    if costmap.ndim != 2 or not np.issubdtype(costmap.dtype, np.integer):
        raise ValueError(f"costmap must be a 2-D integer array, got {costmap.dtype} of shape {costmap.shape}")
    if costmap.size and (costmap.min() < 0 or costmap.max() > 255):
        raise ValueError(f"costmap values must be 0-255, got values from {int(costmap.min())} to {int(costmap.max())}")
    occupied = (costmap == 253) | (costmap == 254) | ((costmap == 255) & (not unknown_is_free))
    return GridMap(occupied, resolution, origin, costmap_cost(np.where(costmap > 252, 0, costmap)))


def occupancy_costmap(values: np.ndarray) -> np.ndarray:
    """nav2 costmap values (uint8, 0-255) of occupancy values (-1 unknown, 0-100, as map_server publishes them) as
    nav2's static layer reads them with ``trinary_costmap: false`` and its default ``lethal_threshold`` of 100:
    unknown 255, 100 lethal (254), v of 0-99 the truncated v / 100 x 254 (0-251)."""
    values = np.asarray(values, np.int16)
    scaled = np.trunc(np.clip(values, 0, 100) / 100.0 * 254.0)
    return np.where(values < 0, 255, np.where(values >= 100, 254, scaled)).astype(np.uint8)


def _checked_cost(cost, occupied: np.ndarray) -> np.ndarray:
    """``cost`` as a read-only float32 array, 1 on obstacles, or a ValueError naming what is wrong."""
    if not isinstance(cost, np.ndarray) or not np.issubdtype(cost.dtype, np.floating):
        raise ValueError(f"cost must be a float numpy array of traversal costs (1 = plain ground), got "
                         f"{getattr(cost, 'dtype', type(cost).__name__)}; a nav2 costmap's 0-255 values: "
                         f"tdp.costmap_grid(values)")
    if cost.shape != occupied.shape:
        raise ValueError(f"cost must have the map's shape {occupied.shape}, got {cost.shape}")
    free = cost[~occupied].astype(np.float64)  # float16 cannot hold MAX_COST to compare with
    for wrong, what in ((np.isnan(free), "NaN"), (np.isinf(free), "infinite"), (free < 1, "below 1"),
                        (free > MAX_COST, f"above {MAX_COST:g}")):
        if wrong.any():
            row, col = np.argwhere(~occupied)[int(np.argmax(wrong))]
            raise ValueError(f"cost must be between 1 and {MAX_COST:g} on free cells: {what} at cell "
                             f"{(int(row), int(col))} ({float(cost[row, col])})")
    checked = np.where(occupied, 1.0, cost).astype(np.float32)
    checked.flags.writeable = False
    return checked


def rectangles(occupied: np.ndarray) -> list[tuple[int, int, int, int]]:
    """Cover the occupied cells with few (r0, c0, r1, c1) rectangles: runs per row, merged down equal runs."""
    open_runs: dict[tuple[int, int], int] = {}
    done = []
    for r in range(occupied.shape[0] + 1):
        runs = set()
        if r < occupied.shape[0]:
            row = np.concatenate([[False], occupied[r], [False]])
            edges = np.flatnonzero(row[1:] != row[:-1])
            runs = {(int(a), int(b)) for a, b in zip(edges[::2], edges[1::2])}
        for run in list(open_runs):
            if run not in runs:
                done.append((open_runs.pop(run), run[0], r, run[1]))
        for run in runs:
            open_runs.setdefault(run, r)
    return sorted(done)


class Problem(NamedTuple):
    """One line of a MovingAI ``.scen``: start and goal cells (row, col) and the published optimal length."""

    start: tuple[int, int]
    goal: tuple[int, int]
    optimal_length: float


# --------------------------------------------------------------------------------------------------------- loading
def load_map(path: str | Path, *, unknown_is_free: bool = False, threshold: float = 0.5,
             trinary_costmap: bool = True, cost_scaling_factor: float | None = None,
             inflation_radius: float | None = None) -> GridMap:
    """Load a MovingAI ``.map``, a ROS map_server ``.yaml`` or an image, chosen by the file's suffix.

    ``unknown_is_free`` applies to ROS maps (unknown cells are obstacles by default); ``threshold`` to plain
    images (a pixel darker than ``threshold`` of full brightness is an obstacle). ``trinary_costmap=False`` reads a
    ROS map's graded values as nav2's static layer does with that parameter (:func:`occupancy_costmap`), into
    traversal costs (:func:`costmap_cost`): a ``scale`` or ``raw`` map's 1-99 become costs instead of unknown.
    ``cost_scaling_factor`` (per metre) and ``inflation_radius`` (metres), together, add nav2's inflation cost
    around the obstacles (:meth:`GridMap.inflate` without growing them).

    Raises:
        FileNotFoundError: no such file (or a ROS map's image).
        ValueError: an unknown format, a malformed file, ``trinary_costmap=False`` for a map that is not ROS's,
            one of the two inflation parameters without the other.
    """
    grid = _load(checks.path(path, "path"), checks.flag(unknown_is_free, "unknown_is_free"), threshold,
                 checks.flag(trinary_costmap, "trinary_costmap"))
    if cost_scaling_factor is None and inflation_radius is None:
        return grid
    return grid.inflate(0, cost_scaling_factor=cost_scaling_factor, inflation_radius=inflation_radius)


def _load(path: Path, unknown_is_free: bool, threshold: float, trinary_costmap: bool) -> GridMap:
    """The map file at ``path`` by its suffix (see :func:`load_map`)."""
    suffix = checks.existing_file(path, "map file").suffix.lower()
    if suffix in (".yaml", ".yml"):
        return _load_ros(path, unknown_is_free, trinary_costmap)
    if not trinary_costmap:
        raise ValueError(f"{path}: trinary_costmap=False reads a ROS map_server map's graded values; a {suffix!r} "
                         "file has none")
    if suffix == ".map":
        return _load_movingai(path)
    if suffix in IMAGE_SUFFIXES:
        return _load_image(path, threshold)
    raise ValueError(f"{path}: unknown map format {suffix!r}; expected .map, .yaml or an image "
                     f"({', '.join(IMAGE_SUFFIXES)})")


def _read_lines(path: Path) -> list[str]:
    try:
        return path.read_text(encoding="ascii").splitlines()
    except UnicodeDecodeError as error:
        raise ValueError(f"{path}: not an ASCII text file ({error.reason} at byte {error.start})") from None


def _header_value(path: Path, lines: list[str], index: int, key: str) -> str:
    if index >= len(lines):
        raise ValueError(f"{path}: truncated header, expected '{key} ...' on line {index + 1}")
    parts = lines[index].split()
    if not parts or parts[0] != key:
        raise ValueError(f"{path}, line {index + 1}: expected '{key} ...', got {lines[index]!r}")
    return " ".join(parts[1:])


def _positive_int(path: Path, line: int, key: str, text: str) -> int:
    if not text.isdigit() or int(text) < 1:
        raise ValueError(f"{path}, line {line}: {key} must be a positive integer, got {text!r}")
    return int(text)


def _load_movingai(path: Path) -> GridMap:
    """MovingAI ``.map``: the terrain letters of :data:`MOVINGAI_FREE` are free, those of
    :data:`MOVINGAI_BLOCKED` obstacles; any other character is an error naming its line and column."""
    lines = _read_lines(path)
    _header_value(path, lines, 0, "type")
    height = _positive_int(path, 2, "height", _header_value(path, lines, 1, "height"))
    width = _positive_int(path, 3, "width", _header_value(path, lines, 2, "width"))
    if height * width > MAX_CELLS:
        raise ValueError(f"{path}: {height} x {width} cells is more than the {MAX_CELLS} cells tdp reads")
    if _header_value(path, lines, 3, "map") != "":
        raise ValueError(f"{path}, line 4: expected 'map', got {lines[3]!r}")
    rows = lines[4:4 + height]
    if len(rows) < height:
        raise ValueError(f"{path}: truncated, header says height {height} but only {len(rows)} rows follow")
    for number, row in enumerate(rows, start=5):
        if len(row) != width:
            raise ValueError(f"{path}, line {number}: row has {len(row)} cells, header says width {width}")
        unknown = set(row) - MOVINGAI_FREE - MOVINGAI_BLOCKED
        if unknown:
            column = min(row.index(ch) for ch in unknown)
            raise ValueError(f"{path}, line {number}, column {column + 1}: unknown terrain {row[column]!r}; "
                             f"expected one of {''.join(sorted(MOVINGAI_FREE | MOVINGAI_BLOCKED))}")
    if any(line.strip() for line in lines[4 + height:]):
        raise ValueError(f"{path}: more than the {height} rows the header announces")
    chars = np.array([list(row) for row in rows])
    return GridMap(~np.isin(chars, sorted(MOVINGAI_FREE)))


def load_scenarios(path: str | Path, grid: GridMap | None = None) -> list[Problem]:
    """Read a MovingAI ``.scen`` file into a list of :class:`Problem` (start and goal as (row, col)).

    Tolerates CRLF, a missing final newline, and blank lines with any text after them (reading stops at the first
    blank line). With ``grid``, checks that each problem's map size matches and its cells are free.
    """
    path = checks.existing_file(checks.path(path, "path"), "scenario file")
    lines = _read_lines(path)
    if not lines or not lines[0].startswith("version"):
        raise ValueError(f"{path}, line 1: expected a 'version ...' header")
    problems = []
    for number, line in enumerate(lines[1:], start=2):
        if not line.strip():
            break
        problems.append(_scenario_row(path, number, line, grid))
    return problems


def _scenario_row(path: Path, number: int, line: str, grid: GridMap | None) -> Problem:
    fields = line.split("\t")
    if len(fields) != 9:
        raise ValueError(f"{path}, line {number}: expected 9 tab-separated fields, got {len(fields)}")
    try:
        width, height, sx, sy, gx, gy = (int(v) for v in fields[2:8])
        optimal = float(fields[8])
    except ValueError:
        raise ValueError(f"{path}, line {number}: fields 3-8 must be integers and field 9 a number") from None
    if not (math.isfinite(optimal) and optimal >= 0):
        raise ValueError(f"{path}, line {number}: the optimal length must be a finite number >= 0, "
                         f"got {fields[8]!r}")
    start, goal = (sy, sx), (gy, gx)
    if grid is not None:
        if (height, width) != grid.shape:
            raise ValueError(f"{path}, line {number}: map size {width} x {height} (w x h) does not match the map "
                             f"({grid.shape[1]} x {grid.shape[0]})")
        grid.check_free_cell(start, f"{path}, line {number}: start")
        grid.check_free_cell(goal, f"{path}, line {number}: goal")
    return Problem(start, goal, optimal)


def _load_image(path: Path, threshold: float) -> GridMap:
    """A plain image: a pixel whose brightness is below ``threshold`` (0-1) is an obstacle."""
    threshold = checks.number(threshold, "threshold (0-1)", 0.0, inclusive=False, high=1.0)
    shade, _ = _read_shade(path, with_alpha=False)
    return GridMap(shade < threshold)


def _read_shade(path: Path, with_alpha: bool) -> tuple[np.ndarray, np.ndarray | None]:
    """Brightness in [0, 1] averaged over the colour channels (and alpha when ``with_alpha``, as map_server's
    trinary mode does), plus the alpha channel in [0, 1] if the image has one. Shades are fractions of the image's
    full scale whatever its depth (255 for 8 bits, 65535 for 16; a PGM's maxval is scaled by Pillow)."""
    unreadable = (UnidentifiedImageError, OSError, SyntaxError, ValueError, Image.DecompressionBombError,
                  Image.DecompressionBombWarning)
    try:
        with warnings.catch_warnings():
            warnings.simplefilter("error", Image.DecompressionBombWarning)
            image = Image.open(path)
    except FileNotFoundError:
        raise FileNotFoundError(f"image file not found: {path}") from None
    except unreadable as error:
        raise ValueError(f"{path}: cannot read image ({error})") from None
    with image:
        if image.width * image.height > MAX_CELLS:
            raise ValueError(f"{path}: {image.width} x {image.height} pixels is more than the {MAX_CELLS} cells "
                             f"tdp reads")
        try:
            image.load()
        except unreadable as error:
            raise ValueError(f"{path}: cannot read image ({error})") from None
        has_alpha = image.mode in ("RGBA", "LA", "PA") or "transparency" in image.info
        rgba = _rgba(path, image)
    channels = rgba if (with_alpha and has_alpha) else rgba[..., :3]
    return channels.mean(axis=2), (rgba[..., 3] if has_alpha else None)


def _rgba(path: Path, image: Image.Image) -> np.ndarray:
    """(H, W, 4) float64 in [0, 1] from an 8- or 16-bit image."""
    if image.mode in _SIXTEEN_BIT:
        grey = np.asarray(image, dtype=np.float64)
        if grey.size and (grey.min() < 0 or grey.max() > 65535):
            raise ValueError(f"{path}: 32-bit integer pixels are not a map image (values beyond 0-65535)")
        grey = grey / 65535.0
        return np.stack([grey, grey, grey, np.ones_like(grey)], axis=2)
    if image.mode == "F":
        raise ValueError(f"{path}: floating-point pixels are not a map image; save it as 8- or 16-bit greyscale")
    return np.asarray(image.convert("RGBA"), dtype=np.float64) / 255.0


def _load_ros(path: Path, unknown_is_free: bool, trinary_costmap: bool) -> GridMap:
    """ROS map_server YAML + image, following nav2's map_io: trinary, scale and raw modes, ``negate``; graded
    values as costs unless ``trinary_costmap``."""
    meta = _read_ros_yaml(path)
    image_path = Path(meta["image"])
    if not image_path.is_absolute():
        image_path = path.parent / image_path
    try:
        found = image_path.is_file()
    except OSError as error:  # a name too long for the file system, say
        raise ValueError(f"{path}: image {checks.shown(meta['image'])}: {error.strerror}") from None
    if not found:
        raise FileNotFoundError(f"{path}: image {checks.shown(meta['image'])} not found (looked at {image_path})")
    values = ros_occupancy(image_path, meta["mode"], meta["negate"], meta["occupied_thresh"], meta["free_thresh"])
    if not trinary_costmap:
        return costmap_grid(occupancy_costmap(values), meta["resolution"], meta["origin"],
                            unknown_is_free=unknown_is_free)
    occupied = values == 100
    unknown = values < 0
    if meta["mode"] == "scale":
        unknown |= (values > 0) & (values < 100)
    if meta["mode"] == "raw":
        occupied = values > 100 * meta["occupied_thresh"]
        unknown |= ~occupied & (values >= 100 * meta["free_thresh"])
    if not unknown_is_free:
        occupied = occupied | unknown
    return GridMap(occupied, meta["resolution"], meta["origin"])


def _read_ros_yaml(path: Path) -> dict:
    try:
        meta = yaml.safe_load(path.read_text())
    except (yaml.YAMLError, UnicodeDecodeError) as error:
        raise ValueError(f"{path}: not valid YAML ({error})") from None
    if not isinstance(meta, dict):
        raise ValueError(f"{path}: expected a YAML mapping with image, resolution, origin, ...")
    for key in ("image", "resolution", "origin", "occupied_thresh", "free_thresh"):
        if key not in meta:
            raise ValueError(f"{path}: missing key {key!r}")
    if not isinstance(meta["image"], str) or not meta["image"]:
        raise ValueError(f"{path}: 'image' must be a file name, got {meta['image']!r}")
    number = (int, float)
    resolution = meta["resolution"]
    if not isinstance(resolution, number) or isinstance(resolution, bool) or not resolution > 0:
        raise ValueError(f"{path}: 'resolution' must be a positive number, got {resolution!r}")
    origin = meta["origin"]
    if not (isinstance(origin, list) and len(origin) == 3 and all(isinstance(v, number) for v in origin)):
        raise ValueError(f"{path}: 'origin' must be [x, y, yaw], got {origin!r}")
    occ, free = meta["occupied_thresh"], meta["free_thresh"]
    if not all(isinstance(v, number) for v in (occ, free)) or not 0 <= free < occ <= 1:
        raise ValueError(f"{path}: need 0 <= free_thresh < occupied_thresh <= 1, got {free!r} and {occ!r}")
    mode = meta.get("mode", "trinary")
    if mode not in ROS_MODES:
        raise ValueError(f"{path}: unknown mode {mode!r}; expected one of {ROS_MODES}")
    negate = meta.get("negate", 0)
    if negate not in (0, 1, True, False):
        raise ValueError(f"{path}: 'negate' must be 0 or 1, got {negate!r}")
    return {"image": meta["image"], "resolution": float(resolution), "origin": tuple(float(v) for v in origin),
            "occupied_thresh": float(occ), "free_thresh": float(free), "mode": mode, "negate": bool(negate)}


def ros_occupancy(image_path: Path, mode: str, negate: bool, occupied_thresh: float,
                  free_thresh: float) -> np.ndarray:
    """The int8 occupancy values (0 free, 100 occupied, -1 unknown; 1-99 in scale and raw modes) that nav2's
    map_server computes from an image, rows top-first as in the image."""
    shade, alpha = _read_shade(image_path, with_alpha=(mode == "trinary"))
    occ = shade if negate else 1.0 - shade
    values = np.full(shade.shape, -1, np.int16)
    if mode == "raw":
        percent = np.round(shade * 255)
        inside = percent <= 100
        values[inside] = percent[inside]
        return values.astype(np.int8)
    values[occ > occupied_thresh] = 100
    values[occ < free_thresh] = 0
    if mode == "scale":
        band = (occ >= free_thresh) & (occ <= occupied_thresh)
        values[band] = np.rint((occ[band] - free_thresh) / (occupied_thresh - free_thresh) * 100)
        if alpha is not None:
            values[alpha < 1.0] = -1
    return values.astype(np.int8)
