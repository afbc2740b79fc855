"""Each benchmark script runs in its --quick form and writes its JSON and figure (so the scripts keep working)."""
import json
import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
RESULTS = ROOT / "benchmarks" / "results"


@pytest.mark.parametrize("script, key", [("kernel", "results"), ("convergence", "results"), ("blockage", "rows"),
                                         ("paper", "rows"), ("worlds", "summary"), ("sweep", "rows"),
                                         ("budget", "rows"), ("predict", "summary"),
                                         ("warehouse", "rows"), ("equal_time", "summary"), ("costs", "rows")])
def test_quick_benchmark_runs(script, key):
    done = subprocess.run([sys.executable, "-m", f"benchmarks.{script}", "--quick"], cwd=ROOT, capture_output=True,
                          text=True, timeout=300)
    assert done.returncode == 0, done.stderr[-2000:]
    assert "|" in done.stdout  # the table
    payload = json.loads((RESULTS / f"{script}-quick.json").read_text())
    assert payload[key] and payload["machine"]["cores"] >= 1
    figure = RESULTS / ("paper-curves-quick.png" if script == "paper" else f"{script}-quick.png")
    assert figure.stat().st_size > 1000
