"""Every scene is one object (exu_aniso.scenes.scene.Scene) that the catalog lists and every engine
asks: its pieces are there and consistent, its closed forms say why where they are None, and the
closed forms moved to the scenes hold what they promise (the block's heading is objective: turning
the drive and the friction's axes together turns it by the same angle)."""
import math

import numpy as np
import pytest

from exu_aniso.catalog import MODELS, SCENES
from exu_aniso.kernel.contact_law import ContactLaw
from exu_aniso.scenes.base import SceneParams
from exu_aniso.scenes.block import BlockParams, orthotropic_heading
from exu_aniso.scenes.scene import Scene


def _choices(scene):
    """The scene's defaults and, one parameter at a time, every other value of its choice parameters
    (a tuple in the table's range column) that makes a valid parameter set."""
    out = [scene.Params()]
    for name, row in scene.Params.TABLE.items():
        if isinstance(row[-1], tuple):
            for value in row[-1]:
                if value != row[0]:
                    try:
                        out.append(scene.Params(**{name: value}))
                    except ValueError:          # a value that needs another parameter set with it
                        pass
    return out


@pytest.mark.parametrize("name", sorted(SCENES))
def test_scene_implements_the_interface(name):
    """For the defaults and every choice of a choice parameter (the loosening's case joint, a model's
    variant, ...): the scene's laws and points by contact, of one set of names, finite (K, 3) points."""
    scene = SCENES[name]
    assert isinstance(scene, Scene) and scene.name == name and MODELS[name].scene is scene
    assert issubclass(scene.Params, SceneParams)
    assert all(isinstance(u, str) and u for u in scene.columns.values()) and "t" in scene.columns
    assert len(scene.title_keys) == 2 and len(scene.figsize) == 2
    for p in _choices(scene):
        assert len(scene.title_keys_for(p)) == 2
        laws, points = scene.law(p), scene.points(p)
        laws, points = (laws, points) if isinstance(laws, dict) else ({"": laws}, {"": points})
        assert set(laws) == set(points), p
        for k in laws:
            assert isinstance(laws[k], ContactLaw)
            P = np.asarray(points[k])
            assert P.ndim == 2 and P.shape[1] == 3 and len(P) >= 1 and np.all(np.isfinite(P)), (p, k, P.shape)
    assert scene.reference is None or callable(scene.reference)


@pytest.mark.parametrize("name", sorted(SCENES))
def test_closed_forms_give_a_reason_for_every_none_and_only_then(name):
    scene = SCENES[name]
    cases = [scene.Params()]
    if name == "block":        # the default's displacement drive has none; a force drive on a constant net has one
        cases.append(BlockParams(drive="force", friction="orthotropic", mu_2=0.6))
    for p in cases:
        out = scene.closed_forms(p)
        undefined = out.pop("undefined")
        assert {k for k, v in out.items() if v is None} == set(undefined), (name, out, undefined)
        assert all(isinstance(why, str) and why for why in undefined.values())
        assert all(v is None or np.all(np.isfinite(v)) for v in out.values())


def test_block_heading_closed_form_is_objective_and_its_limits_hold():
    """The block's heading under a force on an orthotropic net: turning the drive and the net's axes by
    the same angle turns the heading by it (to 1e-9 deg); an isotropic net slides along the pull; a
    pull inside the friction ellipse sticks and says so, naming the force."""
    base = BlockParams(drive="force", friction="orthotropic", mu_1=0.2, mu_2=0.6, force=10.0, drive_angle=45.0)
    h0 = SCENES["block"].closed_forms(base)["heading_deg_theory"]
    assert h0 == pytest.approx(math.degrees(orthotropic_heading(math.radians(45.0), 10.0, base.normal_load, 0.2, 0.6)))
    for turn in (30.0, -75.0, 200.0):
        h = SCENES["block"].closed_forms(base.with_overrides(drive_angle=45.0 + turn,
                                                             friction_angle=turn))["heading_deg_theory"]
        assert (h - h0 - turn + 180.0) % 360.0 - 180.0 == pytest.approx(0.0, abs=1e-9)
    iso = SCENES["block"].closed_forms(base.with_overrides(friction="isotropic", drive_angle=33.0))
    assert iso["heading_deg_theory"] == pytest.approx(33.0, abs=1e-9)
    stuck = SCENES["block"].closed_forms(base.with_overrides(force=1.0))
    assert stuck["heading_deg_theory"] is None and "sticks" in stuck["undefined"]["heading_deg_theory"]
    assert stuck["undefined"]["heading_deg_theory"].startswith("force")
