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


def test_one_default_return_map():
    """Wherever a return map can be left out, the default is DEFAULT_RETURN_MAP ("exact"): the
    contact law, both forms of CreateAnisotropicContact, the Python maps and every scene but the
    two that choose "radial" and say why in their table (the papers' adhesion-steered sliding)."""
    import inspect

    from exu_aniso.engines.exudyn_adapter import create_contact, mainsystem
    from exu_aniso.kernel.contact_law import ContactLaw
    from exu_aniso.law import return_maps
    from exu_aniso.law.return_maps import DEFAULT_RETURN_MAP
    assert DEFAULT_RETURN_MAP == "exact"
    for f, name in ((ContactLaw.__init__, "return_map"), (create_contact.CreateAnisotropicContact, "returnMap"),
                    (mainsystem.MainSystemCreateAnisotropicContact, "returnMap"),
                    (return_maps.return_map_point, "method"), (return_maps.return_map_batch, "method")):
        assert inspect.signature(f).parameters[name].default == DEFAULT_RETURN_MAP, f
    for name, scene in SCENES.items():
        default, _, text = scene.params.TABLE["return_map"][:3]
        if name in ("block", "screw", "fe_block", "fe_screw"):
            assert default == "radial" and "default is exact" in text and "steer" in text, name
        else:
            assert default == DEFAULT_RETURN_MAP, name
