import functools
from pathlib import Path

import pytest

DATA = Path(__file__).parent / "data"
SHARED = Path(__file__).resolve().parents[2] / "shared" / "data"


@pytest.fixture
def data_dir() -> Path:
    return DATA


def shared_file(*parts: str) -> Path:
    """A file of ../shared/data, skipping the test when the checkout has no shared/ beside it."""
    path = SHARED.joinpath(*parts)
    if not path.exists():
        pytest.skip(f"{path} not present (large third-party data lives in ../shared/data)")
    return path


def recorded(kernel, name: str, calls: list):
    """``kernel`` (called by keywords) with each call's ``name`` appended to ``calls`` before it runs; its
    attributes kept (the engine's launcher reads the Taichi kernel's)."""
    @functools.wraps(kernel)
    def call(**arguments):
        calls.append(name)
        return kernel(**arguments)
    return call


def pytest_collection_modifyitems(session, config, items):
    """Move the benchmarks' smoke tests to the end of the run and start their scripts now, in the background
    (``tests/test_benchmarks.py``): they overlap the rest of the suite instead of following it."""
    smoke = [item for item in items if item.path.name == "test_benchmarks.py"]
    if smoke:
        items[:] = [item for item in items if item not in smoke] + smoke
        smoke[0].module.SMOKE_RUNS.start()
