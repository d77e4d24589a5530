"""Every scene's parameter set is its table: one field per row, in the table's order, with the row's
default, frozen; the table is what `exu-aniso params` prints and what parsing and validation read."""
import dataclasses

import pytest

from exu_aniso.catalog import SCENES


@pytest.mark.parametrize("name", sorted(SCENES))
def test_parameter_set_is_its_table(name):
    P = SCENES[name].params
    fields = dataclasses.fields(P)
    assert [f.name for f in fields] == list(P.TABLE)
    assert all(f.default == P.TABLE[f.name][0] for f in fields)
    p = P()
    with pytest.raises(dataclasses.FrozenInstanceError):
        setattr(p, fields[0].name, P.TABLE[fields[0].name][0])
    assert P.from_strings({}) == p
