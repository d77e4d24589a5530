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


def test_the_float_text_extension_is_built():
    from exu_aniso.util import output
    assert output._float_text is not None, ("exu_aniso.util._float_text is missing: `pip install .` builds it "
                                            "with a C++17 compiler (setup.py)")


def _cases():
    """Numbers of every kind: 400,000 random bit patterns (every exponent, subnormals, NaN payloads),
    normal values over 16 decades, round decimals, and the edges of repr's layout (1e-4 fixed, 1e-5
    scientific, 1e15 fixed, 1e16 scientific, signed zero, the largest and smallest doubles)."""
    import numpy as np

    rng = np.random.default_rng(20261127)
    bits = rng.integers(0, 2**64, size=(80000, 5), dtype=np.uint64).view(np.float64)
    spread = rng.normal(size=(20000, 5)) * 10.0 ** rng.integers(-8, 8, size=(20000, 5))
    rounded = np.round(rng.normal(size=(20000, 5)) * 1000, 3)
    edges = np.array([[0.0, -0.0, np.nan, -np.nan, np.inf, -np.inf, 1e-4, 1e-5, 9.99e-5, 1e15, 1e16,
                       9999999999999998.0, 12345678901234567.0, 0.1, 1 / 3, 5e-324, 2.2250738585072014e-308,
                       1.7976931348623157e308, -2.5e-7, 1e22, 1e-100, 100.0, 0.00012, 123456.789]]).reshape(-1, 4)
    return [bits, spread, rounded, edges]


def test_csv_numbers_are_what_repr_writes_byte_for_byte():
    """The compiled writer gives the bytes of repr() in Python, so a file does not depend on whether
    the extension was built, and every number reads back to the same double."""
    import numpy as np

    from exu_aniso.util import output
    if output._float_text is None:
        pytest.skip("exu_aniso.util._float_text not built")
    for values in _cases():
        text = output.csv_rows(values)
        assert text == output.python_csv_rows(values)
        back = np.array([[float(x) for x in line.split(",")] for line in text.decode().splitlines()])
        same = (back == values) | (np.isnan(back) & np.isnan(values))
        assert same.all() and (np.signbit(back) == np.signbit(values))[~np.isnan(values)].all()


def test_csv_rows_takes_a_table_only():
    from exu_aniso.util.output import csv_rows
    with pytest.raises(ValueError, match="2-D array"):
        csv_rows([1.0, 2.0])
    assert csv_rows([[1.0, -0.5], [1e-7, 3e16]]) == b"1.0,-0.5\n1e-07,3e+16\n"
