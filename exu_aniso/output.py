"""Result files written all-or-nothing: every file goes to a temporary name in its directory and
is moved into place (``os.replace``), so an interrupted or failed run never leaves a half-written
file under the final name."""
from __future__ import annotations

import csv
import io
import json
import os
import tempfile


def atomic_write(path, write):
    """Call ``write(f)`` on a binary temporary file beside ``path``, then move it into place."""
    d = os.path.dirname(os.path.abspath(path))
    os.makedirs(d, exist_ok=True)
    fd, tmp = tempfile.mkstemp(dir=d, prefix=".tmp-", suffix=os.path.splitext(path)[1])
    try:
        with os.fdopen(fd, "wb") as f:
            write(f)
        os.replace(tmp, path)
    except BaseException:
        if os.path.exists(tmp):
            os.remove(tmp)
        raise


def write_text(path, text):
    atomic_write(path, lambda f: f.write(text.encode()))


def write_json(path, obj):
    write_text(path, json.dumps(obj, indent=1, allow_nan=True) + "\n")


def write_table(path, columns, rows):
    """CSV with a header row ``columns`` and one row per sequence in ``rows``; floats are written
    with ``repr`` (round-trip exact), everything else with ``str``."""
    buf = io.StringIO()
    w = csv.writer(buf, lineterminator="\n")
    w.writerow(columns)
    for row in rows:
        if len(row) != len(columns):
            raise ValueError(f"write_table({path!r}): row has {len(row)} values for {len(columns)} columns")
        w.writerow([repr(float(v)) if isinstance(v, float) else str(v) for v in row])
    write_text(path, buf.getvalue())


def read_table(path):
    """CSV written by ``write_table`` -> dict column -> list of values (floats where they parse)."""
    with open(path, newline="") as f:
        rows = list(csv.reader(f))
    cols = {name: [] for name in rows[0]}
    for row in rows[1:]:
        for name, v in zip(rows[0], row):
            try:
                cols[name].append(float(v))
            except ValueError:
                cols[name].append(v)
    return cols
