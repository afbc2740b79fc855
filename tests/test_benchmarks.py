"""Each benchmark script runs in its --quick form and writes its JSON and figure (so the scripts keep working).

The smoke runs go two at a time (one per core of the CI machine): their figures are not timings that matter, and in
turn they took three and a half minutes of the suite."""
import json
import subprocess
import sys
from concurrent.futures import ThreadPoolExecutor
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
RESULTS = ROOT / "benchmarks" / "results"
#: Each script and the key its JSON must fill, the longest runs first (sweep 38 s ... costs 7 s on the 2-core VM).
SCRIPTS = {"sweep": "rows", "predict": "summary", "worlds": "summary", "kernel": "results", "warehouse": "rows",
           "blockage": "rows", "budget": "rows", "equal_time": "summary", "paper": "rows", "convergence": "results",
           "costs": "rows"}


def _smoke_run(script: str) -> subprocess.CompletedProcess:
    return subprocess.run([sys.executable, "-m", f"benchmarks.{script}", "--quick"], cwd=ROOT, capture_output=True,
                          text=True, timeout=300)


@pytest.fixture(scope="module")
def smoke_runs() -> dict[str, subprocess.CompletedProcess]:
    """Every script's --quick run, two at a time, longest first."""
    with ThreadPoolExecutor(max_workers=2) as pool:
        return dict(zip(SCRIPTS, pool.map(_smoke_run, SCRIPTS)))


@pytest.mark.parametrize("script", SCRIPTS)
def test_quick_benchmark_runs(script, smoke_runs):
    done = smoke_runs[script]
    assert done.returncode == 0, done.stderr[-2000:]
    assert "|" in done.stdout  # the table
    payload = json.loads((RESULTS / f"{script}-quick.json").read_text())
    assert payload[SCRIPTS[script]] and payload["machine"]["cores"] >= 1
    figure = RESULTS / ("paper-curves-quick.png" if script == "paper" else f"{script}-quick.png")
    assert figure.stat().st_size > 1000
