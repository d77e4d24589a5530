"""Every scene's parameter set is its table: one field per row, in the table's order, with the row's
default, frozen; the table is what `exu-aniso params` prints and what parsing and validation read."""
import dataclasses

import pytest

from exu_aniso.catalog import SCENES


@pytest.mark.parametrize("name", sorted(SCENES))
def test_parameter_set_is_its_table(name):
    P = SCENES[name].Params
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
        default, _, text = scene.Params.TABLE["return_map"][:3]
        if name in ("block", "screw", "fe_block", "fe_screw"):
            assert default == "radial" and "default is exact" in text and "steer" in text, name
        else:
            assert default == DEFAULT_RETURN_MAP, name


def test_one_vocabulary_for_fields_and_their_angle_old_names_still_accepted():
    """An orthotropic field of constant direction is "orthotropic" in every scene (the block said
    "cartesian"), its direction <what carries it>_angle (the particle's one net said "angle", the
    fastening's head net "head_lay_angle"). The old names still work, each with a FutureWarning
    naming the new one, and give the same parameters; old and new together are an error."""
    import warnings

    from exu_aniso.scenes.block import BlockParams
    from exu_aniso.scenes.fastening import FasteningParams
    from exu_aniso.scenes.particle import ParticleParams
    cases = [(BlockParams, dict(adhesion="cartesian", adhesion_angle=30.0), dict(adhesion="orthotropic",
                                                                                 adhesion_angle=30.0), "adhesion"),
             (ParticleParams, dict(angle=30.0), dict(net_angle=30.0), "net_angle"),
             (FasteningParams, dict(head_lay_angle=20.0), dict(head_net_angle=20.0), "head_net_angle")]
    for cls, old, new, word in cases:
        with pytest.warns(FutureWarning, match=f"now called {word}"):
            a = cls(**old)
        with pytest.warns(FutureWarning, match=f"now called {word}"):
            b = cls.from_strings({k: str(v) for k, v in old.items()})
        with warnings.catch_warnings():
            warnings.simplefilter("error")
            assert a == b == cls(**new) == cls().with_overrides(**new)
        with pytest.warns(FutureWarning):
            assert cls().with_overrides(**old) == a
        assert "Old names still accepted" in cls.describe()
    with pytest.raises(ValueError, match="angle is the old name of net_angle; give net_angle only"):
        ParticleParams(angle=30.0, net_angle=10.0)
    with pytest.raises(ValueError, match="adhesion must be one of"):
        BlockParams(adhesion="cartesain")
