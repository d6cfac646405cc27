"""What a sweep adds to its runs: 100 short runs of the 2D gas ball (200
steps each) swept on this machine and, with --scheduler ADDRESS, on a
Dask cluster; the overhead per run is the sweep's wall time, times its
parallelism, less the runs' own (their `wall_s`), over the runs.

    python python/benchmarks/sweep_overhead.py OUT_DIR [--scheduler ADDRESS] [--threads N]
"""

import argparse
import shutil
import time
from pathlib import Path

import sprung

SCENE = Path(__file__).resolve().parents[2] / "scenes" / "ball2d.toml"

parser = argparse.ArgumentParser()
parser.add_argument("out")
parser.add_argument("--scheduler")
parser.add_argument("--threads", type=int, default=1)
args = parser.parse_args()
shutil.rmtree(args.out, ignore_errors=True)
grid = {"body.ball.gas.nrt": [50.0 + k for k in range(100)]}
start = time.perf_counter()
rows = sprung.sweep(SCENE, grid=grid, steps=200, out=args.out, scheduler=args.scheduler,
                    threads=args.threads, progress=False)
wall = time.perf_counter() - start
own = sum(r["wall_s"] for r in rows)
workers = args.threads
if args.scheduler:
    from dask.distributed import Client
    with Client(args.scheduler) as client:
        workers = sum(w["nthreads"] for w in client.scheduler_info()["workers"].values())
where = f"Dask at {args.scheduler}, {workers} worker threads" if args.scheduler else f"{workers} thread(s), no Dask"
print(f"{len(rows)} runs on {where}: sweep {wall:.3f} s, runs' own {own:.3f} s: "
      f"{(wall * workers - own) / len(rows) * 1000:.1f} ms overhead a run")
