"""Result files (exu_aniso.util.output): written atomically, with the permissions of any other file the
user writes (the umask decides, as for open()), never the 0600 of the temporary file."""
from __future__ import annotations

import os
import stat

import pytest

from exu_aniso.util.output import atomic_write, write_json, write_text


@pytest.mark.parametrize("umask", [0o022, 0o077, 0o002])
def test_result_files_get_the_umask_permissions(tmp_path, umask):
    old = os.umask(umask)
    try:
        write_text(tmp_path / "a.txt", "x")
        write_json(tmp_path / "b.json", {"a": 1.0})
        with open(tmp_path / "plain.txt", "w") as f:   # what any other file of the user gets
            f.write("x")
    finally:
        os.umask(old)
    plain = stat.S_IMODE((tmp_path / "plain.txt").stat().st_mode)
    assert plain == 0o666 & ~umask
    for name in ("a.txt", "b.json"):
        assert stat.S_IMODE((tmp_path / name).stat().st_mode) == plain, name


def test_failed_write_leaves_nothing(tmp_path):
    def broken(f):
        f.write(b"half")
        raise RuntimeError("disk full")

    with pytest.raises(RuntimeError, match="disk full"):
        atomic_write(tmp_path / "r.csv", broken)
    assert list(tmp_path.iterdir()) == []
