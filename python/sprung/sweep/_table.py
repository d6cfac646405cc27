"""``sweep.csv``: a row per run, the swept values first, then the run's
columns and its last diagnostics row as ``final.NAME``."""

import csv
import io
import os
from typing import Any, Dict, List, Mapping, Sequence

from .. import _native

#: The columns of ``sweep.csv`` after the swept keys.
RUN_COLUMNS = ["id", "status", "message", "steps", "time", "wall_s"]


def flat(keys: Sequence[str], point: Mapping[str, object], row: Mapping[str, Any]) -> dict:
    """A row of ``sweep.csv`` as a dict: the swept values, the run's
    columns, its last diagnostics row as ``final.NAME``."""
    values = {key: point.get(key) for key in keys}
    values.update({name: row.get(name) for name in RUN_COLUMNS})
    values.update({f"final.{name}": v for name, v in row.get("final", {}).items()})
    return values


def write_table(path: str, keys: Sequence[str], points: Sequence[Mapping[str, object]],
                rows: Sequence[Mapping[str, Any]]) -> None:
    """Write ``sweep.csv`` completely or not at all."""
    flat_rows: List[Dict[str, object]] = [flat(keys, p, r) for p, r in zip(points, rows)]
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
