"""Each benchmark script runs in its --quick form and writes its JSON and figure (so the scripts keep working).

The smoke runs take about seven minutes of one core (each process parses and loads the kernels it uses again),
and the rest of the suite leaves most of the second core idle (it is mostly Python on the calling thread): so once
the suite is collected, ``conftest.py`` moves these tests to the end and starts the runs, one at a time, longest
first, in a background thread; each test waits for its script's. Their figures are not timings that matter."""
import json
import subprocess
import sys
from concurrent.futures import Future, ThreadPoolExecutor
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
RESULTS = ROOT / "benchmarks" / "results"
#: Each script and the key its JSON must fill, the longest runs first (convergence 57 s ... ab 14 s on the 2-core VM,
#: warm cache, the twenty-eighth session).
SCRIPTS = {"convergence": "results", "worlds": "summary", "sweep": "rows", "costs": "rows", "predict": "summary",
           "warehouse": "rows", "blockage": "rows", "paper": "rows", "backends": "rows", "budget": "rows",
           "kernel": "results", "equal_time": "summary", "startup": "rows", "ab": "rows"}


#: A smoke run's limit, for a run that hangs: on a machine whose Taichi cache is cold, the first runs compile every
#: kernel they use beside the suite's own process (sweep, backends and predict took over 300 s each so on the 2-core VM
#: at half speed, the twenty-fourth session; 35 s at most warm).
SMOKE_RUN_S = 1200


def _smoke_run(script: str) -> subprocess.CompletedProcess:
    return subprocess.run([sys.executable, "-m", f"benchmarks.{script}", "--quick"], cwd=ROOT, capture_output=True,
                          text=True, timeout=SMOKE_RUN_S)


class SmokeRuns:
    """Every script's --quick run, started once (:meth:`start`) in one background thread, longest first."""

    def __init__(self):
        self._runs: dict[str, Future] = {}

    def start(self) -> None:
        if not self._runs:
            pool = ThreadPoolExecutor(max_workers=1, thread_name_prefix="smoke-run")
            self._runs = {script: pool.submit(_smoke_run, script) for script in SCRIPTS}
            pool.shutdown(wait=False)

    def result(self, script: str) -> subprocess.CompletedProcess:
        self.start()  # a run of this module alone, without conftest's start
        return self._runs[script].result()


SMOKE_RUNS = SmokeRuns()


@pytest.mark.parametrize("script", SCRIPTS)
def test_quick_benchmark_runs(script):
    done = SMOKE_RUNS.result(script)
    assert done.returncode == 0, done.stderr[-2000:]
    assert "|" in done.stdout  # the table
    payload = json.loads((RESULTS / f"{script}-quick.json").read_text())
    assert payload[SCRIPTS[script]] and payload["machine"]["cores"] >= 1
    figure = RESULTS / ("paper-curves-quick.png" if script == "paper" else f"{script}-quick.png")
    assert figure.stat().st_size > 1000
