"""One run's result folder, whole or not at all (``result_folder``), and a run's identity
(``run_identity``). Apart from ``util.output`` (which the compiled kernels' sources include), so
that an edit here recompiles no kernel."""
from __future__ import annotations

import contextlib
import json
import os
import tempfile

from exu_aniso.util.output import json_safe


RESULT_FILES = ("trajectory.csv", "trajectory.png", "summary.json", "snapshot.png")
"""The files a run writes into its result folder; a folder holding anything else is not replaced."""


class ResultFolderError(ValueError):
    """A folder that cannot take a run's results (--out): named with the reason."""


class FolderInUse(ResultFolderError):
    """Another run is writing into the result folder (its lock is held)."""


def run_identity(params_dict):
    """dict(run_id, params_hash) of a run: a new id per run (UTC time and 8 random hex digits) and the
    first 16 hex digits of the sha256 of its parameters as sorted JSON (the same parameters, the same
    hash, whatever the run)."""
    import hashlib
    import time
    import uuid
    run_id = time.strftime("%Y%m%dT%H%M%SZ", time.gmtime()) + "-" + uuid.uuid4().hex[:8]
    text = json.dumps(json_safe(params_dict), sort_keys=True, separators=(",", ":"), allow_nan=False)
    return dict(run_id=run_id, params_hash=hashlib.sha256(text.encode()).hexdigest()[:16])


def _check_result_folder(out):
    """Why ``out`` [an absolute path] cannot become a run's result folder, or None."""
    cwd = os.path.abspath(os.getcwd())
    if out == cwd or cwd.startswith(out.rstrip(os.sep) + os.sep) or out == os.sep:
        return f"it is the current folder or holds it ({out}); name a folder of its own"
    if os.path.lexists(out) and not os.path.isdir(out):
        return f"{out} exists and is not a folder"
    if os.path.isdir(out):
        other = sorted(n for n in os.listdir(out) if n not in RESULT_FILES and not n.startswith(".tmp-"))
        if other:
            shown = ", ".join(other[:5]) + (", ..." if len(other) > 5 else "")
            return (f"{out} holds files that are not a run's results ({shown}); a run replaces its folder "
                    f"whole, so name an empty folder or a result folder")
    return None


@contextlib.contextmanager
def result_folder(out):
    """One run's result folder, whole or not at all. Yields a staging folder beside ``out``
    (.NAME.staging-XXXX, hidden) for the run to write into; when the block ends normally, or with an
    Exception after the run wrote its own files (a failed run's partial results and summary), the
    staging folder replaces ``out`` whole: the old folder is moved aside, the new one moved into
    place, the old one removed. So ``out`` never holds files of two runs: a run killed before that
    leaves the earlier results untouched, a failed run leaves only its own files. A lock beside it
    (.NAME.lock, held with flock from start to end) refuses a second run into the same folder
    (FolderInUse, naming the process). ``out`` must not be the current folder or above it, and an
    existing folder must hold only result files (ResultFolderError naming it)."""
    import fcntl
    import shutil
    out = os.path.abspath(out)
    why = _check_result_folder(out)
    if why is not None:
        raise ResultFolderError(f"--out cannot be used: {why}")
    parent, name = os.path.split(out)
    os.makedirs(parent, exist_ok=True)
    lock = os.open(os.path.join(parent, f".{name}.lock"), os.O_RDWR | os.O_CREAT, 0o666)
    try:
        try:
            fcntl.flock(lock, fcntl.LOCK_EX | fcntl.LOCK_NB)
        except BlockingIOError:
            holder = os.pread(lock, 64, 0).decode(errors="replace").strip() or "another process"
            raise FolderInUse(f"another run (process {holder}) is writing into {out}; wait for it or name "
                              f"another --out") from None
        os.ftruncate(lock, 0)
        os.pwrite(lock, str(os.getpid()).encode(), 0)
        for stale in os.listdir(parent):       # a killed run's staging folders (this lock is ours now)
            if stale.startswith(f".{name}.staging-"):
                shutil.rmtree(os.path.join(parent, stale), ignore_errors=True)
        staging = tempfile.mkdtemp(dir=parent, prefix=f".{name}.staging-")
        os.chmod(staging, 0o777 & ~_umask_mask())
        try:
            yield staging
        except Exception:
            if os.listdir(staging):
                _publish(staging, out)
            else:
                shutil.rmtree(staging, ignore_errors=True)
            raise
        except BaseException:                  # interrupted: its files may be half there; keep the old ones
            shutil.rmtree(staging, ignore_errors=True)
            raise
        _publish(staging, out)
    finally:
        os.close(lock)


def _umask_mask():
    mask = os.umask(0o022)
    os.umask(mask)
    return mask


def _publish(staging, out):
    """Move the staging folder into place as ``out``, the old ``out`` aside and then away."""
    import shutil
    old = None
    if os.path.isdir(out):
        old = staging + ".old"
        os.rename(out, old)
    os.rename(staging, out)
    if old is not None:
        shutil.rmtree(old, ignore_errors=True)
