"""Parameter sweeps: many episodes (worlds x planner configurations x baselines) run serially or on Dask
distributed, each result journalled as it arrives, then tidy tables and a figure.

    spec = tdp.sweep.load_spec("study.yaml")
    rows = tdp.sweep.run_sweep(spec, Path("out"))          # a local cluster, one worker per core
    tdp.sweep.write_report(spec, rows, Path("out"))         # episodes.csv, summary.csv, ratio.png

The command line does the same: ``python -m tdp sweep study.yaml --out out``. See :mod:`tdp.sweep.spec` for the
spec's format.
"""
from .episode import TIMED, measure_episode
from .report import write_report
from .run import JOURNAL, Journal, local_workers, run_sweep
from .spec import EpisodeSpec, Spec, World, load_spec

__all__ = ["EpisodeSpec", "JOURNAL", "Journal", "Spec", "TIMED", "World", "load_spec", "local_workers",
           "measure_episode", "run_sweep", "write_report"]
