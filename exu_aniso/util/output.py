"""Result files written all-or-nothing: every file goes to a temporary name in its directory and
is moved into place (``os.replace``), so an interrupted or failed run never leaves a half-written
file under the final name."""
from __future__ import annotations

import csv
import io
import json
import os
import tempfile

try:
    from exu_aniso.util import _float_text
except ImportError:          # built by setup.py when a C++ compiler is there; csv_rows falls back
    _float_text = None


def _umask_mode():
    """Mode of a new regular file under the process umask (0o666 & ~umask), what open() gives.
    The umask can only be read by setting it, so it is set and restored at once."""
    mask = os.umask(0o022)
    os.umask(mask)
    return 0o666 & ~mask


def atomic_write(path, write):
    """Call ``write(f)`` on a binary temporary file beside ``path``, then move it into place.
    The file gets the permissions of any file the user writes (0o666 minus the umask), not the
    0600 that ``mkstemp`` gives its temporary file."""
    d = os.path.dirname(os.path.abspath(path))
    os.makedirs(d, exist_ok=True)
    fd, tmp = tempfile.mkstemp(dir=d, prefix=".tmp-", suffix=os.path.splitext(path)[1])
    try:
        with os.fdopen(fd, "wb") as f:
            write(f)
            os.fchmod(f.fileno(), _umask_mode())
        os.replace(tmp, path)
    except BaseException:
        if os.path.exists(tmp):
            os.remove(tmp)
        raise


def write_text(path, text):
    atomic_write(path, lambda f: f.write(text.encode()))


def json_safe(obj, undefined=None, _key=None):
    """A copy of ``obj`` (dicts, lists, tuples, numpy scalars and arrays) valid as strict JSON:
    every non-finite float (NaN, +-inf; invalid in JSON) becomes None (null). With ``undefined`` (a
    dict) each top-level key whose value was replaced is recorded there with the reason "not
    finite (nan)" unless it already has a reason."""
    import math

    import numpy as np

    if isinstance(obj, dict):
        return {k: json_safe(v, undefined, k if _key is None else _key) for k, v in obj.items()}
    if isinstance(obj, (list, tuple, np.ndarray)):
        return [json_safe(v, undefined, _key) for v in (obj.tolist() if isinstance(obj, np.ndarray) else obj)]
    if isinstance(obj, np.generic):
        obj = obj.item()
    if isinstance(obj, float) and not math.isfinite(obj):
        if undefined is not None and _key is not None:
            undefined.setdefault(_key, f"not finite ({obj!r})")
        return None
    return obj


def dumps_json(obj):
    """Strict JSON text (no NaN/Infinity tokens) of ``obj``; see ``json_safe``."""
    return json.dumps(json_safe(obj), indent=1, allow_nan=False)


def write_json(path, obj):
    write_text(path, dumps_json(obj) + "\n")


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


def csv_rows(values):
    """Text (bytes) of the rows of a 2-D float array as CSV lines, each number as ``repr`` writes
    it: the shortest text that reads back to the same double. Compiled (``_float_text``, about
    1.3 us per row of 21 numbers against 10.6 for repr in Python) when the extension was built;
    the same bytes from Python otherwise."""
    import numpy as np

    values = np.asarray(values, dtype=float)
    if values.ndim != 2:
        raise ValueError(f"csv_rows: values must be a 2-D array (rows x columns); got shape {values.shape}")
    if _float_text is not None:
        return _float_text.csv_rows(values)
    return python_csv_rows(values)


def python_csv_rows(values):
    """``csv_rows`` by ``repr`` in Python: what is written without the compiled extension."""
    return "".join(",".join(map(repr, row)) + "\n" for row in values.tolist()).encode()


def read_table(path):
    """CSV written by ``write_table`` (or a run's trajectory.csv, whose first line is a comment
    "# exu-aniso ..." with the run's identity) -> dict column -> list of values (floats where they
    parse). Lines starting with # are skipped."""
    with open(path, newline="") as f:
        rows = list(csv.reader(line for line in f if not line.startswith("#")))
    cols = {name: [] for name in rows[0]}
    for row in rows[1:]:
        for name, v in zip(rows[0], row):
            try:
                cols[name].append(float(v))
            except ValueError:
                cols[name].append(v)
    return cols
