"""The input contract of every public entry point: cells, flags and numbers, each refused with a ValueError that
names the argument and what was wrong.

A cell is a pair (row, col) of integers (Python or numpy integers; never a float, which would be silently
truncated, nor a bool). A flag is a ``bool``. Counts and ticks are integers, never bools or floats.
"""
from __future__ import annotations

import math
import numbers
import os
from pathlib import Path

import numpy as np
import yaml

#: A grid cell: (row, col).
Cell = tuple[int, int]


def shown(value, most: int = 60) -> str:
    """``value``'s repr for an error message, cut to ``most`` characters (a text file read as a world file is one
    long string)."""
    text = repr(value)
    return text if len(text) <= most else text[:most - 3] + "..."


def yaml_text_hint(value) -> str:
    """A hint for a number that YAML read as text (YAML 1.1 wants a dot in a float: ``1e-3`` is a string, ``1.0e-3``
    a number) when ``value`` is such a string, for a file's error message; else ""."""
    if isinstance(value, str):
        try:
            float(value)
        except ValueError:
            return ""
        return f" (YAML reads {value} as text: write it with a dot and a signed exponent, as 1.0e+3)"
    return ""


class _UniqueKeys(yaml.SafeLoader):
    """PyYAML's safe loader, except that a key given twice in one mapping is an error (PyYAML keeps the last)."""

    def construct_mapping(self, node, deep=False):
        seen = set()
        for key_node, _ in node.value:
            if key_node.tag == "tag:yaml.org,2002:merge":
                continue
            key = self.construct_object(key_node, deep=deep)
            if isinstance(key, (str, int, float, bool)) or key is None:
                if (type(key), key) in seen:
                    raise yaml.constructor.ConstructorError(None, None, f"{key!r} is given twice",
                                                            key_node.start_mark)
                seen.add((type(key), key))
        return super().construct_mapping(node, deep)


def yaml_data(text: str):
    """The data of a YAML document of the project's own (a world file, a sweep spec), as ``yaml.safe_load`` reads
    it, but a key given twice in one mapping - which PyYAML would read as the last one, silently - raises
    ``yaml.YAMLError`` naming the key and its line."""
    return yaml.load(text, Loader=_UniqueKeys)


def path(value, name: str, kind: str = "file") -> Path:
    """``value`` as a Path if it is a str or path-like; ``kind`` ("file", "folder") names what it should lead to."""
    if not isinstance(value, (str, os.PathLike)):
        raise ValueError(f"{name} must be a {kind} path (a str or a pathlib.Path), got {shown(value)}")
    return Path(value)


def existing_file(path: Path, what: str) -> Path:
    """``path`` if it leads to a file; else a FileNotFoundError saying that the ``what`` (e.g. "map file") was not
    found there, and that it is a folder where it is one."""
    if not path.is_file():
        raise FileNotFoundError(f"{what} not found: {path}" + (" is a folder" if path.is_dir() else ""))
    return path


def text(value, name: str, default: str) -> str:
    """A name or a description read from a file: text, or a finite number YAML read from unquoted digits, as text;
    ``default`` where it is absent or empty."""
    if value is None or value == "":
        return default
    if isinstance(value, bool) or not isinstance(value, (str, int, float)) or (
            isinstance(value, float) and not math.isfinite(value)):
        raise ValueError(f"{name} must be text, got {shown(value)}")
    return str(value)


def integer(value, name: str, low: int | None = None, high: int | None = None) -> int:
    """``value`` as an int if it is an integer (numpy integers included, bools not) >= ``low`` and <= ``high``."""
    if isinstance(value, bool) or not isinstance(value, numbers.Integral):
        raise ValueError(f"{name} must be an integer, got {value!r}")
    if low is not None and value < low:
        raise ValueError(f"{name} must be an integer >= {low}, got {value!r}")
    if high is not None and value > high:
        raise ValueError(f"{name} must be an integer <= {high}, got {value!r}")
    return int(value)


def optional_integer(value, name: str, low: int | None = None) -> int | None:
    """None, or ``value`` checked by :func:`integer`."""
    return None if value is None else integer(value, name, low)


def number(value, name: str, low: float | None = None, *, inclusive: bool = True, finite: bool = True,
           high: float | None = None) -> float:
    """``value`` as a float if it is a real number (not a bool, never NaN) >= ``low`` (> when not inclusive) and at
    most ``high``."""
    if isinstance(value, bool) or not isinstance(value, numbers.Real) or math.isnan(value):
        raise ValueError(f"{name} must be a number, got {value!r}")
    if finite and not math.isfinite(value):
        raise ValueError(f"{name} must be a finite number, got {value!r}")
    if low is not None and (value < low or (value == low and not inclusive)):
        raise ValueError(f"{name} must be a number {'>=' if inclusive else '>'} {low}, got {value!r}")
    if high is not None and value > high:
        raise ValueError(f"{name} must be a number <= {high:g}, got {value!r}")
    return float(value)


def flag(value, name: str) -> bool:
    """``value`` if it is True or False (numpy bools included)."""
    if not isinstance(value, (bool, np.bool_)):
        raise ValueError(f"{name} must be True or False, got {value!r}")
    return bool(value)


def flags(value, count: int, name: str) -> np.ndarray:
    """``value`` as ``count`` bools: one flag (True or False, numpy bools included) for every cell, or a sequence or
    array of ``count`` of them, one per cell."""
    if isinstance(value, (bool, np.bool_)):
        return np.full(count, bool(value))
    array = np.asarray(value)
    if array.dtype != bool or array.shape != (count,):
        got = repr(value) if array.ndim == 0 else f"an array of shape {array.shape} and dtype {array.dtype}"
        raise ValueError(f"{name} must be True, False or one of them per cell ({count} cells), got {got}")
    return array


def pair(value, name: str) -> tuple[int, int]:
    """``value`` as a (row, col) tuple of ints: two integers, never floats."""
    try:
        items = tuple(value)
    except TypeError:
        raise ValueError(f"{name} must be a (row, col) pair of integers, got {value!r}") from None
    if len(items) != 2 or not all(isinstance(v, numbers.Integral) and not isinstance(v, bool) for v in items):
        raise ValueError(f"{name} must be a (row, col) pair of integers, got {value!r}")
    return int(items[0]), int(items[1])


def cell(value, shape: tuple[int, int], name: str) -> tuple[int, int]:
    """``value`` as a (row, col) pair of ints inside a map of ``shape``."""
    row, col = pair(value, name)
    if not (0 <= row < shape[0] and 0 <= col < shape[1]):
        raise ValueError(f"{name} {(row, col)} is outside the {shape[0]} x {shape[1]} map")
    return row, col
