"""A sweep's runs: each one a task whose folder ``runs/<id>/`` is written
completely or not at all, run where it is executed (this process or a
Dask worker), and the pool that runs them on this machine's cores."""

import hashlib
import json
import os
import shutil
import stat
import tempfile
import time as clock
from concurrent.futures import Future, ThreadPoolExecutor, as_completed
from typing import Callable, List, Mapping, Optional, Tuple

from .. import _native
from .._errors import BlowUp, SceneError
from ._progress import Progress

#: The file a finished run's folder ends with: its row.
RESULT = "result.json"


def run_id(scene_text: str, options: Mapping[str, object]) -> str:
    """A run's id: a digest of its effective scene and its options, so the
    same run has the same folder in every sweep."""
    digest = hashlib.sha256(scene_text.encode())
    digest.update(json.dumps(options, sort_keys=True).encode())
    return digest.hexdigest()[:16]


def finished(folder: str) -> Optional[dict]:
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
    done = finished(folder)
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
                row["final"] = {name: _cell(v) for name, v in zip(names, last)}
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
            return finished(folder) or row
    except BaseException:
        shutil.rmtree(work, ignore_errors=True)
        raise
    return row



def _cell(text):
    """A cell of ``diagnostics.csv``: its number, None where it is empty,
    a name (``solver_preconditioner``) as it is."""
    if not text:
        return None
    try:
        return float(text)
    except ValueError:
        return text

#: What the sweep does with each run's outcome: its index and its future.
Finish = Callable[[int, Future], None]


def run_here(pending: List[Tuple[int, dict]], workers: int, bar: Progress,
             finish: Finish) -> None:
    """Run the ``pending`` (index, task) pairs on this machine, ``workers``
    at once, without Dask; ``finish`` takes each outcome as it comes."""

    def started(task: dict) -> dict:
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


def clear_leftovers(runs: str, tasks: List[Tuple[int, dict]]) -> None:
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
