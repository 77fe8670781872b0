"""Sweep results on disk: the crash-safe journal and the Parquet table.

Every finished variant is appended to ``journal.jsonl`` (one JSON object per line, flushed and
fsynced) the moment its result reaches the client, so a killed run, a killed worker or a
power cut loses nothing that was finished; a half-written last line is ignored. The Parquet
table ``results.parquet`` (one row per variant of the current sweep, in sweep order) is
rewritten from the journal at the end of every run, also an interrupted one.
"""

from __future__ import annotations

import json
import math
import os
from pathlib import Path

__all__ = ["Journal", "write_table", "read_table", "column_types"]


class Journal:
    """Append-only JSON-lines record of finished variants, keyed by variant id.

    Parameters
    ----------
    path : path-like
        ``journal.jsonl`` in the sweep's output folder.
    key : str
        The column that identifies a row (``"trial"`` for an optimisation study).
    """

    def __init__(self, path, *, key: str = "variant"):
        self.path = Path(path)
        self.key = key
        self._checked = False

    def read(self) -> dict:
        """``{id: row}`` of every complete line (the last entry of an id wins)."""
        rows: dict = {}
        if not self.path.exists():
            return rows
        with open(self.path, encoding="utf-8") as fh:
            for line in fh:
                if not line.endswith("\n"):  # cut off by a kill mid-write
                    break
                try:
                    row = json.loads(line)
                except json.JSONDecodeError:
                    continue
                if isinstance(row, dict) and self.key in row:
                    rows[row[self.key]] = row
        return rows

    def append(self, row: dict) -> None:
        """Write one row and make sure it is on disk before returning."""
        # strict JSON lines: a number that is not finite (a metric not measured) is null
        clean = {
            k: None if isinstance(v, float) and not math.isfinite(v) else v for k, v in row.items()
        }
        text = json.dumps(clean, separators=(",", ":"), allow_nan=False) + "\n"
        with open(self.path, "a", encoding="utf-8") as fh:
            if not self._checked and fh.tell() > 0:
                self._terminate(fh)
            self._checked = True
            fh.write(text)
            fh.flush()
            os.fsync(fh.fileno())

    def _terminate(self, fh) -> None:
        """Start on a fresh line if a kill left a partial one."""
        with open(self.path, "rb") as rb:
            rb.seek(-1, os.SEEK_END)
            if rb.read(1) != b"\n":
                fh.write("\n")


def column_types(rows: list, columns: list, declared: dict) -> dict:
    """Arrow type name per column: ``declared`` (metrics) or inferred from the values."""
    types = {}
    for name in columns:
        if name in declared:
            types[name] = declared[name]
            continue
        values = [r.get(name) for r in rows if r.get(name) is not None]
        if values and all(isinstance(v, bool) for v in values):
            types[name] = "bool"
        elif values and all(isinstance(v, int) and not isinstance(v, bool) for v in values):
            types[name] = "int"
        elif values and all(
            isinstance(v, (int, float)) and not isinstance(v, bool) for v in values
        ):
            types[name] = "float"
        else:
            types[name] = "str"
    return types


def write_table(rows: list, columns: list, path, *, declared: dict | None = None, metadata=None):
    """Write ``rows`` (dicts) as a Parquet table with the given column order.

    Parameters
    ----------
    rows : list of dict
    columns : list of str
    path : path-like
    declared : dict, optional
        Column -> "float" | "int" | "bool" | "str" for columns whose type is known in advance
        (the metrics), so that a column that is empty in every row keeps its type.
    metadata : dict, optional
        JSON-able key/values stored in the file's schema metadata (``ccu.sweep``).

    The file is written next to ``path`` and renamed over it, so a reader never sees half a
    table.
    """
    import pyarrow as pa
    import pyarrow.parquet as pq

    arrow = {"float": pa.float64(), "int": pa.int64(), "bool": pa.bool_(), "str": pa.string()}
    types = column_types(rows, columns, declared or {})
    arrays, fields = [], []
    for name in columns:
        kind = types[name]
        values = [r.get(name) for r in rows]
        if kind == "str":
            values = [v if v is None or isinstance(v, str) else json.dumps(v) for v in values]
        elif kind == "float":
            values = [None if v is None else float(v) for v in values]
        arrays.append(pa.array(values, type=arrow[kind]))
        fields.append(pa.field(name, arrow[kind]))
    schema = pa.schema(fields)
    if metadata:
        schema = schema.with_metadata({"ccu.sweep": json.dumps(metadata)})
    table = pa.Table.from_arrays(arrays, schema=schema)
    path = Path(path)
    tmp = path.with_name(path.name + ".tmp")
    pq.write_table(table, tmp)
    os.replace(tmp, path)
    return path


def read_table(path) -> list:
    """Rows (dicts) of a results table; ``pandas.read_parquet`` reads it as a DataFrame."""
    import pyarrow.parquet as pq

    return pq.read_table(path).to_pylist()
