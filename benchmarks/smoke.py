"""Every benchmark script's --quick run, one after another in one process: a check that the scripts still work.

    python -m benchmarks.smoke [--out DIR] [SCRIPT ...]

Each script's ``main()`` runs as ``python -m benchmarks.SCRIPT --quick`` runs it, and writes its JSON and figure to
results/ as that would; its printed output and its outcome go to DIR/SCRIPT.json (default DIR:
results/smoke-quick): ``status`` (0; the number it exited with; 1 for an exception or an exit with a message),
``stdout``, ``error`` (the traceback, or the message) and ``seconds``. One process for all of them because a fresh
one parses and loads again every Taichi kernel it uses (about ten seconds of each run on the 2-core VM;
``benchmarks.startup``): the fourteen runs took about seven minutes of one core as fourteen processes. The
scripts' own children (the kernel's and the backends' workers, the start-up's fresh processes, the sweep's Dask
workers) still start as they do. Prints one line per script as it ends and exits with 1 if any failed.
"""
from __future__ import annotations

import argparse
import contextlib
import importlib
import io
import json
import sys
import time
import traceback
from pathlib import Path

from benchmarks.common import RESULTS

#: Every benchmark script, the longest smoke runs first (convergence 57 s ... ab 14 s as processes of their own on
#: the 2-core VM, warm cache, the twenty-eighth session).
SCRIPTS = ("convergence", "worlds", "sweep", "costs", "predict", "warehouse", "blockage", "paper", "backends",
           "budget", "kernel", "equal_time", "startup", "ab")
OUT = RESULTS / "smoke-quick"


def run_script(script: str) -> dict:
    """Run ``benchmarks.<script>``'s main() with --quick in this process; its outcome, output and seconds."""
    began, output, status, error = time.perf_counter(), io.StringIO(), 0, ""
    argv = sys.argv
    sys.argv = [f"benchmarks.{script}", "--quick"]
    try:
        with contextlib.redirect_stdout(output):
            importlib.import_module(f"benchmarks.{script}").main()
    except SystemExit as exit_:  # sys.exit(): None or 0 a success, another number its status, a message 1
        code = 0 if exit_.code is None else exit_.code
        status, error = (code, "") if isinstance(code, int) else (1, str(code))
    except Exception:  # a script's failure is its result here; the next script still runs
        status, error = 1, traceback.format_exc()
    finally:
        sys.argv = argv
    return {"script": script, "status": status, "stdout": output.getvalue(), "error": error,
            "seconds": time.perf_counter() - began}


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("scripts", nargs="*", metavar="SCRIPT", help=f"scripts to run (default: all: {SCRIPTS})")
    parser.add_argument("--out", type=Path, default=OUT, help=f"folder of the outcomes (default: {OUT})")
    args = parser.parse_args()
    unknown = sorted(set(args.scripts) - set(SCRIPTS))
    if unknown:
        parser.error(f"no benchmark script named {', '.join(unknown)}; the scripts: {', '.join(SCRIPTS)}")
    args.out.mkdir(parents=True, exist_ok=True)
    failed = []
    for script in args.scripts or SCRIPTS:
        outcome = run_script(script)
        (args.out / f"{script}.json").write_text(json.dumps(outcome, indent=2))
        print(f"{script}: {'ok' if outcome['status'] == 0 else 'FAILED'} in {outcome['seconds']:.1f} s", flush=True)
        if outcome["status"] != 0:
            failed.append(script)
            print(outcome["error"][-2000:], file=sys.stderr)
    if failed:
        raise SystemExit(f"failed: {', '.join(failed)}")


if __name__ == "__main__":
    main()
