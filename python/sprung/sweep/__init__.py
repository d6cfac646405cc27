"""Parameter sweeps: many runs of one scene with overridden values, on
this machine's cores or on a Dask cluster, each run a task whose folder is
written completely or not at all, gathered into one ``sweep.csv``.

``sprung.sweep`` is the function :func:`sweep` of this module (the package
binds it by that name); ``python -m sprung.sweep`` is its command line
(``__main__.py``). The work is split by job: ``_sampling`` (where the runs
lie), ``_runs`` (one run, and the pool on this machine), ``_dask`` (the
cluster), ``_table`` (``sweep.csv``), ``_progress`` (the terminal line).
"""

import json
import os
from concurrent.futures import Future
from typing import Iterable, List, Mapping, Optional, Tuple, Union, cast

from .. import _native
from .._errors import SceneError
from . import _dask, _runs
from ._progress import Progress
from ._sampling import grid_points, latin_hypercube
from ._table import flat, write_table

__all__ = ["sweep"]

PathLike = Union[str, "os.PathLike[str]"]


def sweep(scene: PathLike, grid: Optional[Mapping[str, Iterable[object]]] = None,
          samples: Optional[int] = None,
          ranges: Optional[Mapping[str, Tuple[float, float]]] = None, seed: int = 0,
          steps: Optional[int] = None, time: Optional[float] = None,
          every: Optional[int] = None, out: PathLike = "out/sweep", scheduler=None,
          threads: Optional[int] = None, progress: bool = True,
          frames: Optional[str] = None) -> List[dict]:
    """Run ``scene`` once per point of a grid or of a Latin hypercube.

    Each run writes ``OUT/runs/<id>/`` (``scene.toml``, ``diagnostics.csv``),
    complete or not at all, and ``OUT/sweep.csv`` gets a row per run: the
    swept values, ``id``, ``status`` (``ok``, ``blew_up``, ``error``),
    ``message``, ``steps``, ``time``, ``wall_s`` and the last diagnostics
    row as ``final.*`` columns. See docs/sweeps.md.

    Args:
        scene: a scene file (TOML).
        grid: ``{KEY: [values...]}``: every combination, the first key
            slowest (dotted keys of ``--set``: ``"sim.dt"``,
            ``"body.ball.gas.nrt"``, ...).
        samples, ranges, seed: ``samples`` points of a Latin hypercube over
            ``ranges`` (``{KEY: (low, high)}``), the same for the same seed.
            With a grid too, every sample is run at every grid point.
        steps, time, every: as ``sprung.run`` (``time`` in s).
        out: the sweep's folder: ``runs/<id>/`` per run and ``sweep.csv``.
        scheduler: None to run on this machine's cores without Dask; a
            ``dask.distributed.Client`` or a scheduler's address
            (``tcp://HOST:PORT``) to run each run as a task there.
        threads: runs at once on this machine (default: every core).
        progress: a progress line on stderr where it is a terminal.
        frames: also write each run's frames (``vtu``, ``vtk``, ``obj``)
            into ``runs/<id>/frames/``.

    Returns:
        The rows of ``sweep.csv`` as a list of dicts. A run that blows up
        or whose values are refused is a row (``status`` ``blew_up`` or
        ``error``); a rerun with the same ``out`` skips every run that ended.

    Raises:
        SceneError: the scene cannot be read (not a regular file, too
            large, not UTF-8), before any run.
        ValueError: the grid or the ranges cannot be swept.
    """
    path = os.fspath(scene)
    # Through the command line's gate: a scene that is not a regular file,
    # too large or not UTF-8 is refused (SceneError) before any run.
    text = _native.read_scene(path)
    lists = None if grid is None else {key: list(values) for key, values in grid.items()}
    points = grid_points(lists) if lists else [{}]
    if samples is not None or ranges:
        if samples is None or not ranges:
            raise ValueError("samples and ranges go together")
        points = [{**p, **s} for p in points for s in latin_hypercube(ranges, samples, seed)]
    keys = list(points[0]) if points else []
    options = {"steps": steps, "time": time, "every": every, "frames": frames}
    runs = os.path.join(os.fspath(out), "runs")
    tasks: List[Tuple[int, dict]] = []
    rows: List[Optional[dict]] = [None] * len(points)
    for k, point in enumerate(points):
        effective: Optional[str]
        refused: Optional[str]
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
        digest = _runs.run_id(effective if effective is not None
                              else text + json.dumps(point, default=str), options)
        if refused is not None:
            rows[k] = {"id": digest, "status": "error", "message": refused, "steps": 0,
                       "time": 0.0, "wall_s": 0.0, "final": {}}
            continue
        tasks.append((k, {"id": digest, "scene": effective,
                          "folder": os.path.abspath(os.path.join(runs, digest)),
                          "frames": frames}))
    bar = Progress(len(points), progress)
    bar.update(done=sum(r is not None for r in rows))
    pending = []
    for k, task in tasks:
        done = _runs.finished(task["folder"])
        if done is not None:
            rows[k] = done
            bar.update(done=1, failed=int(done["status"] != "ok"))
        else:
            pending.append((k, task))

    def finish(k: int, future: Future) -> None:
        try:
            row = future.result()
        except Exception as e:  # noqa: BLE001 (a failed run is a row, never a lost sweep)
            task = dict(tasks)[k]
            row = {"id": task["id"], "status": "error", "message": f"{type(e).__name__}: {e}",
                   "steps": 0, "time": 0.0, "wall_s": 0.0, "final": {}}
        rows[k] = row
        bar.update(done=1, failed=int(row["status"] != "ok"), running=-1)

    if scheduler is None:
        _runs.run_here(pending, threads or os.cpu_count() or 1, bar, finish)
    else:
        _dask.run_on_cluster(pending, scheduler, bar, finish)
    bar.close()
    _runs.clear_leftovers(runs, tasks)
    # Every run has its row now: a run that failed is one, never a hole.
    ended = cast(List[dict], rows)
    write_table(os.path.join(os.fspath(out), "sweep.csv"), keys, points, ended)
    return [flat(keys, point, row) for point, row in zip(points, ended)]
