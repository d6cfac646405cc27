"""A sweep's runs on a Dask cluster: each run a task, retried where a
worker is lost (a run's folder is whole or absent, so a retry is safe)."""

from typing import List, Tuple

from . import _runs
from ._progress import Progress


def client(scheduler):
    """A Dask client for ``scheduler`` (a ``Client`` as it is, or an
    address) and whether this sweep opened it (and so closes it)."""
    if hasattr(scheduler, "submit"):
        return scheduler, False
    try:
        from dask.distributed import Client
    except ImportError as e:
        raise ImportError("a sweep on a Dask cluster needs dask[distributed] "
                          "(pip install 'sprung[sweep]')") from e
    return Client(scheduler), True


def run_on_cluster(pending: List[Tuple[int, dict]], scheduler, bar: Progress,
                   finish: _runs.Finish) -> None:
    """Send the ``pending`` (index, task) pairs to the cluster of
    ``scheduler``; ``finish`` takes each outcome as it comes."""
    dask, own = client(scheduler)
    try:
        from dask.distributed import as_completed
        futures = {}
        for k, task in pending:
            futures[dask.submit(_runs.run_task, task, key=f"sprung-run-{task['id']}",
                                pure=False, retries=2)] = k
            # Sent to the cluster: counted as running from then on.
            bar.update(running=1)
        for future in as_completed(list(futures)):
            finish(futures[future], future)
    finally:
        if own:
            dask.close()
