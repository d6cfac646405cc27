"""``python -m sprung.sweep SCENE --grid KEY=V1,V2 ... --out DIR``: a
parameter sweep from the command line (``sprung.sweep`` from Python)."""

import argparse
import os
import sys
from typing import List, Optional

from .. import _native
from . import sweep


def parse_value(text: str) -> object:
    """A command line's value as ``--set`` reads it: a TOML value (``1e-4``,
    ``true``, ``"text"``, ``[0, 1]``), else a bare word as a string."""
    return _native.parse_value(text.strip())


def main(argv: Optional[List[str]] = None) -> int:
    """``python -m sprung.sweep``: see ``--help``; the exit status."""
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
    counts: dict = {}
    for row in rows:
        counts[row["status"]] = counts.get(row["status"], 0) + 1
    summary = ", ".join(f"{n} {status}" for status, n in sorted(counts.items()))
    print(f"{len(rows)} runs ({summary}): {os.path.join(args.out, 'sweep.csv')}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
