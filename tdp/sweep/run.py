"""Running a sweep: the episodes not yet in the journal, serially or on Dask distributed, each result appended to
the journal the moment it arrives, with progress and an ETA on stderr."""
from __future__ import annotations

import json
import logging
import math
import os
import sys
import tempfile
import time
from pathlib import Path
from typing import Iterable, TextIO

from .. import checks
from .episode import measure_episode
from .spec import EpisodeSpec, Spec

JOURNAL = "episodes.jsonl"
#: The most worker processes a local cluster may have per core: each runs one episode at a time, so more only queue,
#: and each is a process that holds Taichi and its kernels.
MAX_WORKERS_PER_CORE = 4


class Journal:
    """The sweep's record on disk: one JSON line per finished episode, ``{"key", "row"}`` or ``{"key", "error"}``,
    flushed and synced as it is written, so a crash, a kill or Ctrl-C loses at most the episodes still running.
    Strict JSON, which any reader takes: a value that is not a finite number (an extra metric's nan) is null, in the
    row kept in memory as in the line written, so a sweep resumed from the journal has the rows an unbroken one has.
    Reading it back skips a line torn by a kill; a later line for a key replaces an earlier one (a rerun's result
    replaces a recorded error)."""

    def __init__(self, path: Path, log: TextIO | None = None):
        self.path, self.log = Path(path), sys.stderr if log is None else log
        self.rows: dict[str, dict] = {}
        self.errors: dict[str, str] = {}
        if self.path.exists():
            self._read()

    def _read(self) -> None:
        data = self.path.read_bytes()
        whole = data[:data.rfind(b"\n") + 1]
        if len(whole) < len(data):  # the last line was being written when the sweep was killed
            self.path.write_bytes(whole)
        for line in whole.decode().splitlines():
            try:
                entry = json.loads(line)
            except ValueError:
                continue
            if isinstance(entry, dict) and "key" in entry and ("row" in entry or "error" in entry):
                self._take(entry)

    def _take(self, entry: dict) -> None:
        if "row" in entry:
            self.rows[entry["key"]] = entry["row"]
            self.errors.pop(entry["key"], None)
        else:
            self.errors[entry["key"]] = entry["error"]

    def rows_of(self, episodes: list[EpisodeSpec]) -> list[dict]:
        """The rows of those of ``episodes`` that are done, in their order."""
        return [self.rows[e.key] for e in episodes if e.key in self.rows]

    def add(self, key: str, row: dict | None = None, error: str | None = None) -> str | None:
        """Record an episode's row, or the error that ended it; return the error recorded (a row with a value JSON
        cannot hold, which an extra metric may return, is recorded as that episode's error: the sweep goes on)."""
        try:
            entry = {"key": key, "row": _plain(row)} if error is None else {"key": key, "error": error}
        except TypeError as problem:
            entry = {"key": key, "error": f"TypeError: {problem}"}
        self._take(entry)
        try:
            self._append(_line(entry))
        except OSError as problem:  # keep going: the results must outlive an output problem
            self.path = Path(tempfile.mkdtemp(prefix="tdp-sweep-")) / JOURNAL
            print(f"warning: cannot write the journal ({problem}); writing it to {self.path} instead",
                  file=self.log, flush=True)
            self._append("".join(_line({"key": k, "row": r}) for k, r in self.rows.items()))
        return entry.get("error")

    def _append(self, text: str) -> None:
        with open(self.path, "a") as file:
            file.write(text)
            file.flush()
            os.fsync(file.fileno())


def _line(entry: dict) -> str:
    return json.dumps(entry, allow_nan=False) + "\n"


def _plain(value):
    """``value`` as JSON's types: numpy scalars and arrays (which extra metrics may return) as Python's, a float
    that is not finite as None. A TypeError for anything else JSON cannot hold."""
    if hasattr(value, "tolist"):
        value = value.tolist()
    if isinstance(value, dict):
        return {_key(k): _plain(v) for k, v in value.items()}
    if isinstance(value, (list, tuple)):
        return [_plain(v) for v in value]
    if isinstance(value, float):
        return value if math.isfinite(value) else None
    if value is None or isinstance(value, (bool, int, str)):
        return value
    raise TypeError(f"cannot write {type(value).__name__} in a sweep row")


def _key(name) -> str:
    if not isinstance(name, str):
        raise TypeError(f"a sweep row's names must be text, got {name!r}")
    return name


class Progress:
    """Lines on ``log``: episodes done of the total, elapsed time and an ETA from this run's pace; errors always,
    other results at most every ``every_s`` seconds."""

    def __init__(self, total: int, done: int, log: TextIO, every_s: float = 2.0):
        self.total, self.done, self.log, self.every_s = total, done, log, every_s
        self.began = self.last = time.perf_counter()
        self.finished = self.failed = 0
        if done:
            print(f"sweep: {done} of {total} episodes done before, skipped", file=log, flush=True)

    def __call__(self, episode: EpisodeSpec, error: str | None) -> None:
        self.finished += 1
        self.failed += error is not None
        now = time.perf_counter()
        if error is None and now - self.last < self.every_s and self.done + self.finished < self.total:
            return
        self.last = now
        elapsed = now - self.began
        left = (self.total - self.done - self.finished) * elapsed / self.finished
        what = f"{episode.world.coords['world']} {episode.planner}"
        status = f"FAILED: {error.splitlines()[-1] if error else ''}" if error else "ok"
        print(f"sweep: {self.done + self.finished}/{self.total} episodes, {_clock(elapsed)} elapsed, ETA "
              f"{_clock(left)}{f', {self.failed} failed' if self.failed else ''} ({what}: {status})",
              file=self.log, flush=True)


def _clock(seconds: float) -> str:
    seconds = int(math.ceil(seconds))
    return f"{seconds // 3600}h{seconds // 60 % 60:02d}m{seconds % 60:02d}s" if seconds >= 3600 else \
        f"{seconds // 60}m{seconds % 60:02d}s"


def run_sweep(spec: Spec, out: Path, scheduler: str | None = None, workers: int | None = None,
              serial: bool = False, log: TextIO | None = None) -> list[dict]:
    """Run every episode of ``spec`` that the journal in ``out`` does not hold yet; return all of the spec's rows
    that are done, in the spec's order.

    ``serial``: one after another in this process. Otherwise on Dask distributed: the cluster at ``scheduler``
    (an address such as ``tcp://10.0.0.5:8786``), or a local cluster of ``workers`` processes (default: one per
    core), each running one episode at a time with cores // workers Taichi threads. Progress, the episodes a
    journal already holds and errors go to ``log`` (default: ``sys.stderr`` as it is at the call).

    Raises:
        ValueError: ``out`` is no path (a str or a pathlib.Path), or ``workers`` is not a count a local cluster
            can run (:func:`local_workers`).
    """
    episodes = spec.episodes()
    count = local_workers(workers, os.cpu_count() or 1, len(episodes))
    journal = Journal(checks.path(out, "out", "folder") / JOURNAL, log)  # its log: ``log``, else sys.stderr now
    todo = [e for e in episodes if e.key not in journal.rows]
    progress = Progress(len(episodes), len(episodes) - len(todo), journal.log)
    if todo:
        local = min(count, len(todo))
        for episode, row, error in _serially(todo) if serial else _on_dask(todo, scheduler, local):
            progress(episode, journal.add(episode.key, row, error))
    return journal.rows_of(episodes)


def local_workers(asked: int | None, cores: int, episodes: int) -> int:
    """The worker processes of a local cluster for ``episodes`` episodes on ``cores`` cores: ``asked`` (default one
    per core), no more than there are episodes (a worker is a process that loads Taichi and its kernels before its
    first episode). A ValueError where ``asked`` is not a positive integer or is more than MAX_WORKERS_PER_CORE a
    core: each worker runs one episode at a time, so more only queue, while each holds its own process in memory."""
    if asked is not None:
        most = MAX_WORKERS_PER_CORE * cores
        checks.integer(asked, "workers", 1)
        if asked > most:
            raise ValueError(f"workers: at most {most} on this machine's {cores} cores "
                             f"({MAX_WORKERS_PER_CORE} a core), got {asked}")
    return max(1, min(asked or cores, episodes))


def _serially(episodes: list[EpisodeSpec]) -> Iterable[tuple[EpisodeSpec, dict | None, str | None]]:
    for episode in episodes:
        try:
            yield episode, measure_episode(episode), None
        except Exception as error:  # one bad episode must not end a sweep of thousands; it is recorded
            yield episode, None, f"{type(error).__name__}: {error}"


def _on_dask(episodes: list[EpisodeSpec], scheduler: str | None,
             workers: int) -> Iterable[tuple[EpisodeSpec, dict | None, str | None]]:
    """Each episode's result on the cluster at ``scheduler``, or on a local cluster of ``workers`` processes."""
    try:
        from dask.distributed import Client, LocalCluster, as_completed
    except ImportError:
        raise ValueError("sweeps on a cluster need Dask: pip install 'dask[distributed]' (or run with --serial)") \
            from None
    cluster = None
    if scheduler is None:
        threads = max(1, (os.cpu_count() or 1) // workers)
        cluster = LocalCluster(n_workers=workers, threads_per_worker=1, processes=True, dashboard_address=None,
                               silence_logs=logging.ERROR, env={"TDP_THREADS": str(threads)})
    try:
        with Client(cluster or scheduler) as client:
            futures = client.map(measure_episode, episodes, key=[f"tdp-episode-{e.key}" for e in episodes])
            of = dict(zip((f.key for f in futures), episodes))
            for future in as_completed(futures):
                if future.status == "error":
                    error = future.exception()
                    yield of[future.key], None, f"{type(error).__name__}: {error}"
                else:
                    yield of[future.key], future.result(), None
                future.release()
    finally:
        if cluster is not None:
            cluster.close()
