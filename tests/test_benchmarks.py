"""Each benchmark script runs in its --quick form and writes its JSON and figure (so the scripts keep working).

The smoke runs go one after another in one process (``benchmarks.smoke``: a fresh process per script parsed and
loaded its kernels again, about seven minutes of one core for the fourteen), and the rest of the suite leaves most
of the second core idle (it is mostly Python on the calling thread): so once the suite is collected, ``conftest.py``
moves these tests to the end and starts that process in the background; each test reads its script's outcome once
it has ended. Their figures are not timings that matter."""
import json
import shutil
import subprocess
import sys
from concurrent.futures import Future, ThreadPoolExecutor
from pathlib import Path
from types import SimpleNamespace

import pytest

from benchmarks.common import RESULTS
from benchmarks.smoke import OUT as OUTCOMES, SCRIPTS, run_script

ROOT = Path(__file__).resolve().parents[1]
#: The key each script's JSON must fill.
FILLED = {"convergence": "results", "worlds": "summary", "sweep": "rows", "costs": "rows", "predict": "summary",
          "warehouse": "rows", "blockage": "rows", "paper": "rows", "backends": "rows", "budget": "rows",
          "kernel": "results", "equal_time": "summary", "startup": "rows", "ab": "rows"}
#: The rows of a script's JSON that each say whether its field equals a reference (``equal``): a quick run that finds
#: one unequal fails, as the full run would be wrong.
EQUAL_ROWS = {"convergence": "results", "costs": "edits"}
#: The smoke process's limit, for a run that hangs: on a machine whose Taichi cache is cold, it compiles every kernel
#: the scripts use beside the suite's own process (sweep, backends and predict took over 300 s each so on the 2-core
#: VM at half speed, the twenty-fourth session, as processes of their own; all fourteen 315-355 s warm in one): the
#: limit is near CI's 90 minutes, so that a hang still ends as a failed test before CI stops the run.
SMOKE_RUN_S = 80 * 60


def _smoke_run() -> subprocess.CompletedProcess:
    """The smoke process, at a lower priority where ``nice`` is at hand: the suite's own process is the longer."""
    shutil.rmtree(OUTCOMES, ignore_errors=True)  # no outcome of an earlier run is read as this one's
    nice = ["nice", "-n", "10"] if shutil.which("nice") else []
    return subprocess.run([*nice, sys.executable, "-m", "benchmarks.smoke", "--out", str(OUTCOMES)], cwd=ROOT,
                          capture_output=True, text=True, timeout=SMOKE_RUN_S)


class SmokeRuns:
    """Every script's --quick run, in one process (``benchmarks.smoke``) started once (:meth:`start`) from a
    background thread."""

    def __init__(self):
        self._run: Future | None = None

    def start(self) -> None:
        if self._run is None:
            pool = ThreadPoolExecutor(max_workers=1, thread_name_prefix="smoke-run")
            self._run = pool.submit(_smoke_run)
            pool.shutdown(wait=False)

    def result(self, script: str) -> dict:
        """``script``'s outcome (``benchmarks.smoke``'s JSON) once the smoke process has ended."""
        self.start()  # a run of this module alone, without conftest's start
        done = self._run.result()
        outcome = OUTCOMES / f"{script}.json"
        assert outcome.exists(), f"no outcome for {script}; the smoke process said:\n{done.stderr[-2000:]}"
        return json.loads(outcome.read_text())


SMOKE_RUNS = SmokeRuns()


def test_every_script_has_a_smoke_check():
    """Every benchmark module with a main() (but the smoke runner) is a script that the smoke process runs."""
    scripts = {path.stem for path in (ROOT / "benchmarks").glob("*.py") if "\ndef main(" in path.read_text()}
    assert set(FILLED) == set(SCRIPTS) == scripts - {"smoke"}


@pytest.mark.parametrize("ends, status, error", [
    (lambda: None, 0, ""), (lambda: sys.exit(), 0, ""), (lambda: sys.exit(3), 3, ""),
    (lambda: sys.exit("no map"), 1, "no map"), (lambda: 1 / 0, 1, "ZeroDivisionError")])
def test_the_smoke_runner_keeps_each_scripts_output_and_outcome(monkeypatch, capsys, ends, status, error):
    """A script's table and its end - returned, sys.exit with nothing, a number or a message, an exception - as
    benchmarks.smoke records them, its command line as ``python -m benchmarks.SCRIPT --quick`` gives it."""
    def main():
        print(f"| {' '.join(sys.argv)} |")
        ends()
    monkeypatch.setitem(sys.modules, "benchmarks.fake", SimpleNamespace(main=main))
    outcome = run_script("fake")
    assert outcome["status"] == status and error in outcome["error"] and (error or not outcome["error"])
    assert outcome["stdout"] == "| benchmarks.fake --quick |\n" and capsys.readouterr().out == ""
    assert sys.argv[0] != "benchmarks.fake"  # put back


@pytest.mark.parametrize("script", SCRIPTS)
def test_quick_benchmark_runs(script):
    outcome = SMOKE_RUNS.result(script)
    assert outcome["status"] == 0, outcome["error"][-2000:]
    assert "|" in outcome["stdout"]  # the table
    payload = json.loads((RESULTS / f"{script}-quick.json").read_text())
    assert payload[FILLED[script]] and payload["machine"]["cores"] >= 1
    if script in EQUAL_ROWS:
        rows = payload[EQUAL_ROWS[script]]
        assert rows and all(row["equal"] for row in rows), [row for row in rows if not row["equal"]][:3]
    figure = RESULTS / ("paper-curves-quick.png" if script == "paper" else f"{script}-quick.png")
    assert figure.stat().st_size > 1000
