"""Parameter sweeps: many runs of one scene with overridden values, on
this machine's cores or on a Dask cluster, each run a task whose folder is
written completely or not at all, gathered into one ``sweep.csv``."""

import csv
import hashlib
import io
import itertools
import json
import math
import os
import shutil
import stat
import sys
import tempfile
import threading
import time as clock
from concurrent.futures import ThreadPoolExecutor, as_completed
from typing import Dict, List, Mapping, Optional, Sequence, Tuple

import numpy as np

from . import _native
from ._errors import BlowUp, SceneError, StepError

#: The columns of ``sweep.csv`` after the swept keys.
RUN_COLUMNS = ["id", "status", "message", "steps", "time", "wall_s"]
#: The file a finished run's folder ends with: its row.
RESULT = "result.json"


def latin_hypercube(ranges: Mapping[str, Tuple[float, float]], samples: int,
                    seed: int) -> List[Dict[str, float]]:
    """``samples`` points over ``ranges`` (KEY: (low, high)), a Latin
    hypercube: each range cut in ``samples`` equal strata, each stratum
    used once per key, a uniform point within it; the same points for the
    same seed."""
    if samples < 1:
        raise ValueError(f"samples = {samples}: at least 1")
    rng = np.random.default_rng(seed)
    points = [dict() for _ in range(samples)]
    for key, (low, high) in ranges.items():
        low, high = float(low), float(high)
        if not (math.isfinite(low) and math.isfinite(high) and low <= high):
            raise ValueError(f"range {key}: {low}:{high} must be finite, low <= high")
        strata = rng.permutation(samples)
        offsets = rng.random(samples)
        for point, stratum, offset in zip(points, strata, offsets):
            point[key] = low + (high - low) * (stratum + offset) / samples
    return points


def check_nesting(where: str, value: object) -> None:
    """Refuse ``value`` where its lists, tuples and dicts nest deeper than a
    scene's value may (``MAX_VALUE_DEPTH``, 32 levels), counted without
    recursion: a sweep's values are hashed into run ids and written into
    ``sweep.csv``, and neither may recurse without bound."""
    limit = _native.MAX_VALUE_DEPTH
    stack = [(value, 0)]
    while stack:
        item, depth = stack.pop()
        if isinstance(item, np.ndarray):
            # Its Python form, at the same level (as ``set=`` reads it).
            stack.append((item.tolist(), depth))
            continue
        if isinstance(item, dict):
            children = item.values()
        elif isinstance(item, (list, tuple)):
            children = item
        else:
            continue
        if depth >= limit:
            raise ValueError(f"{where}: the value nests lists or dicts more than {limit} deep, "
                             "the most a value may")
        stack.extend((child, depth + 1) for child in children)


def grid_points(grid: Mapping[str, Sequence[object]]) -> List[Dict[str, object]]:
    """Every combination of the grid's values, the first key slowest; a
    value nested deeper than a scene's value may be is refused."""
    keys = list(grid)
    for key in keys:
        if len(grid[key]) == 0:
            raise ValueError(f"grid {key}: no values")
        for n, value in enumerate(grid[key]):
            check_nesting(f"grid {key}: value {n}", value)
    return [dict(zip(keys, values)) for values in itertools.product(*(grid[k] for k in keys))]


def run_id(scene_text: str, options: Mapping[str, object]) -> str:
    """A run's id: a digest of its effective scene and its options, so the
    same run has the same folder in every sweep."""
    digest = hashlib.sha256(scene_text.encode())
    digest.update(json.dumps(options, sort_keys=True).encode())
    return digest.hexdigest()[:16]


def _finished(folder: str) -> Optional[dict]:
    """The row of a run that ended in ``folder``, or None."""
    path = os.path.join(folder, RESULT)
    try:
        # A regular file only (a FIFO there would block the open).
        if not stat.S_ISREG(os.lstat(path).st_mode):
            return None
        with open(path, encoding="utf-8") as f:
            return json.load(f)
    except (OSError, ValueError):
        return None


def run_task(task: dict) -> dict:
    """One run of a sweep, where it is executed (this process or a Dask
    worker): build the effective scene, run it, and write
    ``runs/<id>/`` (``scene.toml``, ``diagnostics.csv``, ``result.json``)
    into a temporary folder renamed into place at the end, so a run cut
    short is never taken for a finished one. Returns the run's row; a
    refused scene or a blow-up is a row, not an exception."""
    folder = task["folder"]
    done = _finished(folder)
    if done is not None:
        return done
    os.makedirs(os.path.dirname(folder), exist_ok=True)
    work = tempfile.mkdtemp(prefix=os.path.basename(folder) + ".partial-",
                            dir=os.path.dirname(folder))
    row = {"id": task["id"], "status": "ok", "message": "", "steps": 0, "time": 0.0,
           "final": {}}
    start = clock.perf_counter()
    try:
        with open(os.path.join(work, "scene.toml"), "w", encoding="utf-8") as f:
            f.write(task["scene"])
        try:
            # Errors name the run's own scene.toml, where its lines are.
            world = _native.loads(task["scene"], folder, None, "scene.toml")
            # steps, time and every are in the effective scene.
            csv_text, error = _native.run(world, None, None, None, None, work,
                                          task.get("frames"))
        except SceneError as e:
            row.update(status="error", message=str(e))
        except ValueError as e:
            row.update(status="error", message=str(e))
        else:
            if error is not None:
                status = "blew_up" if isinstance(error, BlowUp) else "error"
                row.update(status=status, message=str(error))
            lines = csv_text.splitlines()
            if len(lines) > 1:
                names, last = lines[0].split(","), lines[-1].split(",")
                row["final"] = {name: (float(v) if v else None) for name, v in zip(names, last)}
            row["steps"] = world.steps
            row["time"] = world.time
        row["wall_s"] = clock.perf_counter() - start
        with open(os.path.join(work, RESULT), "w", encoding="utf-8") as f:
            json.dump(row, f)
        try:
            os.rename(work, folder)
        except OSError:
            # Another attempt finished first (a task run twice after a
            # worker was lost): its folder stands.
            shutil.rmtree(work, ignore_errors=True)
            return _finished(folder) or row
    except BaseException:
        shutil.rmtree(work, ignore_errors=True)
        raise
    return row


class _Progress:
    """A one-line progress report on a terminal: runs done, running,
    failed, time left."""

    def __init__(self, total: int, enabled: bool):
        self.total, self.enabled = total, enabled and sys.stderr.isatty()
        self.done = self.failed = self.running = 0
        self.start = clock.perf_counter()
        self.lock = threading.Lock()

    def update(self, done=0, failed=0, running=0):
        with self.lock:
            self.done += done
            self.failed += failed
            self.running += running
            if not self.enabled:
                return
            elapsed = clock.perf_counter() - self.start
            left = (elapsed / self.done * (self.total - self.done)) if self.done else float("nan")
            sys.stderr.write(f"\r{self.done}/{self.total} runs done, {self.running} running, "
                             f"{self.failed} failed, {left:.0f} s left   ")
            sys.stderr.flush()

    def close(self):
        if self.enabled:
            sys.stderr.write("\n")


def _client(scheduler):
    """A Dask client for ``scheduler``: a ``Client`` as it is, or an address."""
    if hasattr(scheduler, "submit"):
        return scheduler, False
    try:
        from dask.distributed import Client
    except ImportError as e:
        raise ImportError("a sweep on a Dask cluster needs dask[distributed] "
                          "(pip install 'sprung[sweep]')") from e
    return Client(scheduler), True


def sweep(scene, grid=None, samples=None, ranges=None, seed=0, steps=None, time=None,
          every=None, out="out/sweep", scheduler=None, threads=None, progress=True,
          frames=None):
    """Run ``scene`` once per point of a grid or of a Latin hypercube.

    Args:
        scene: a scene file (TOML).
        grid: ``{KEY: [values...]}``: every combination (dotted keys of
            ``--set``: ``"sim.dt"``, ``"body.ball.gas.nrt"``, ...).
        samples, ranges, seed: ``samples`` points of a Latin hypercube over
            ``ranges`` (``{KEY: (low, high)}``), the same for the same seed.
            With a grid too, every sample is run at every grid point.
        steps, time, every: as ``sprung.run``.
        out: the sweep's folder: ``runs/<id>/`` per run and ``sweep.csv``.
        scheduler: None to run on this machine's cores without Dask; a
            ``dask.distributed.Client`` or a scheduler's address
            (``tcp://HOST:PORT``) to run each run as a task there.
        threads: runs at once on this machine (default: every core).

    Returns:
        The rows of ``sweep.csv`` as a list of dicts. A run that blows up
        or whose values are refused is a row (``status`` ``blew_up`` or
        ``error``); a rerun with the same ``out`` skips every run that ended.
    """
    path = os.fspath(scene)
    # Through the command line's gate: a scene that is not a regular file,
    # too large or not UTF-8 is refused (SceneError) before any run.
    text = _native.read_scene(path)
    points = grid_points(grid) if grid else [{}]
    if samples is not None or ranges:
        if samples is None or not ranges:
            raise ValueError("samples and ranges go together")
        points = [{**p, **s} for p in points for s in latin_hypercube(ranges, samples, seed)]
    keys = list(points[0]) if points else []
    options = {"steps": steps, "time": time, "every": every, "frames": frames}
    runs = os.path.join(os.fspath(out), "runs")
    tasks, rows = [], [None] * len(points)
    for k, point in enumerate(points):
        try:
            # The run's length and records are written into the scene:
            # its scene.toml alone runs it again.
            effective = _native.effective_scene(text, path, list(point.items()),
                                                steps, time, every)
        except (SceneError, ValueError) as e:
            # Values the scene cannot take: a row of its own, no run.
            effective, refused = None, str(e)
        else:
            refused = None
        digest = run_id(effective if effective is not None else text + json.dumps(point, default=str),
                        options)
        if refused is not None:
            rows[k] = {"id": digest, "status": "error", "message": refused, "steps": 0,
                       "time": 0.0, "wall_s": 0.0, "final": {}}
            continue
        tasks.append((k, {"id": digest, "scene": effective,
                          "folder": os.path.abspath(os.path.join(runs, digest)),
                          "frames": frames}))
    bar = _Progress(len(points), progress)
    bar.update(done=sum(r is not None for r in rows))
    pending = []
    for k, task in tasks:
        done = _finished(task["folder"])
        if done is not None:
            rows[k] = done
            bar.update(done=1, failed=int(done["status"] != "ok"))
        else:
            pending.append((k, task))

    def finish(k, future):
        try:
            row = future.result()
        except Exception as e:  # noqa: BLE001 (a failed run is a row, never a lost sweep)
            task = dict(tasks)[k]
            row = {"id": task["id"], "status": "error", "message": f"{type(e).__name__}: {e}",
                   "steps": 0, "time": 0.0, "wall_s": 0.0, "final": {}}
        rows[k] = row
        bar.update(done=1, failed=int(row["status"] != "ok"), running=-1)

    if scheduler is None:
        workers = threads or os.cpu_count() or 1

        def started(task):
            bar.update(running=1)
            return run_task(task)

        pool = ThreadPoolExecutor(max_workers=workers)
        try:
            futures = {pool.submit(started, task): k for k, task in pending}
            for future in as_completed(futures):
                finish(futures[future], future)
        except BaseException:
            # Ctrl-C: the runs not started are dropped; those running end
            # (each between steps) and their folders stand or go whole.
            pool.shutdown(wait=False, cancel_futures=True)
            bar.close()
            raise
        pool.shutdown()
    else:
        client, own = _client(scheduler)
        try:
            from dask.distributed import as_completed as dask_completed
            futures = {}
            for k, task in pending:
                futures[client.submit(run_task, task, key=f"sprung-run-{task['id']}",
                                      pure=False, retries=2)] = k
                # Sent to the cluster: counted as running from then on.
                bar.update(running=1)
            for future in dask_completed(list(futures)):
                finish(futures[future], future)
        finally:
            if own:
                client.close()
    bar.close()
    _clear_leftovers(runs, tasks)
    write_table(os.path.join(os.fspath(out), "sweep.csv"), keys, points, rows)
    return [flat(keys, point, row) for point, row in zip(points, rows)]


def _clear_leftovers(runs: str, tasks) -> None:
    """Remove the ``<id>.partial-*`` folders that attempts at this sweep's
    runs left where their worker died mid-run (a killed process cannot
    remove its own): every run has ended by now, its own folder whole. An
    attempt still going somewhere finds its folder gone and yields to the
    finished one, as when another attempt finished first."""
    ids = {os.path.basename(task["folder"]) for _, task in tasks}
    try:
        names = os.listdir(runs)
    except OSError:
        return
    for name in names:
        stem, partial, _ = name.partition(".partial-")
        if partial and stem in ids:
            shutil.rmtree(os.path.join(runs, name), ignore_errors=True)


def flat(keys, point, row) -> dict:
    """A row of ``sweep.csv`` as a dict: the swept values, the run's
    columns, its last diagnostics row as ``final.NAME``."""
    values = {key: point.get(key) for key in keys}
    values.update({name: row.get(name) for name in RUN_COLUMNS})
    values.update({f"final.{name}": v for name, v in row.get("final", {}).items()})
    return values


def write_table(path: str, keys, points, rows) -> None:
    """Write ``sweep.csv`` completely or not at all."""
    flat_rows = [flat(keys, p, r) for p, r in zip(points, rows)]
    columns = list(keys) + RUN_COLUMNS
    for row in flat_rows:
        columns += [c for c in row if c.startswith("final.") and c not in columns]
    buffer = io.StringIO()
    writer = csv.writer(buffer, lineterminator="\n")
    writer.writerow(columns)
    for row in flat_rows:
        writer.writerow(["" if row.get(c) is None else
                         (repr(row[c]) if isinstance(row[c], float) else row[c]) for c in columns])
    os.makedirs(os.path.dirname(path) or ".", exist_ok=True)
    # Whole or not at all, and never through a link, FIFO or device.
    _native.write_output(path, buffer.getvalue())


def main(argv=None) -> int:
    """``python -m sprung.sweep``: see ``--help``."""
    import argparse
    parser = argparse.ArgumentParser(
        prog="python -m sprung.sweep",
        description="Run a scene once per point of a grid or a Latin hypercube, "
                    "on this machine or a Dask cluster; results in OUT/sweep.csv.")
    parser.add_argument("scene")
    parser.add_argument("--grid", action="append", default=[], metavar="KEY=V1,V2,...")
    parser.add_argument("--samples", type=int)
    parser.add_argument("--range", action="append", default=[], metavar="KEY=LO:HI",
                        dest="ranges")
    parser.add_argument("--seed", type=int, default=0)
    length = parser.add_mutually_exclusive_group()
    length.add_argument("--steps", type=int)
    length.add_argument("--time", type=float)
    parser.add_argument("--every", type=int)
    parser.add_argument("--scheduler", metavar="ADDRESS")
    parser.add_argument("--threads", type=int)
    parser.add_argument("--format", choices=["vtu", "vtk", "obj"],
                        help="also write each run's frames (runs/<id>/frames/)")
    parser.add_argument("--out", required=True)
    args = parser.parse_args(argv)
    try:
        grid = {}
        for item in args.grid:
            key, _, values = item.partition("=")
            if not key or not values:
                parser.error(f"--grid {item}: expected KEY=V1,V2,...")
            grid[key] = [parse_value(v) for v in values.split(",")]
        ranges = {}
        for item in args.ranges:
            key, _, span = item.partition("=")
            low, _, high = span.partition(":")
            try:
                ranges[key] = (float(low), float(high))
            except ValueError:
                parser.error(f"--range {item}: expected KEY=LO:HI")
        rows = sweep(args.scene, grid=grid or None, samples=args.samples, ranges=ranges or None,
                     seed=args.seed, steps=args.steps, time=args.time, every=args.every,
                     out=args.out, scheduler=args.scheduler, threads=args.threads,
                     frames=args.format)
    except (OSError, ValueError, ImportError) as e:
        print(f"error: {e}", file=sys.stderr)
        return 1
    counts = {}
    for row in rows:
        counts[row["status"]] = counts.get(row["status"], 0) + 1
    summary = ", ".join(f"{n} {status}" for status, n in sorted(counts.items()))
    print(f"{len(rows)} runs ({summary}): {os.path.join(args.out, 'sweep.csv')}")
    return 0


def parse_value(text: str):
    """A command line's value as ``--set`` reads it: a TOML value (``1e-4``,
    ``true``, ``"text"``, ``[0, 1]``), else a bare word as a string."""
    return _native.parse_value(text.strip())
