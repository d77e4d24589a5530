"""The tapered thread: the screw scene on a Cone (--set surface=cone --set half_angle=DEG).
Oracles: a half angle of 0 is the cylinder exactly; Exudyn equals the reference; the energy
ledger closes; and the back-out limit of a pressed cone: held by friction when tan(half_angle) <
mu, pushed out of the narrowing hole when tan(half_angle) > mu (a point pressed by N on the cone's
generator feels N sin(beta) along the axis against at most mu N cos(beta) of friction)."""
from __future__ import annotations

import numpy as np
import pytest

pytest.importorskip("exudyn")

from exu_aniso.models.screw import RunScrew  # noqa: E402
from exu_aniso.scenes.screw import simulate_screw  # noqa: E402
from exu_aniso.scenes.screw import ScrewParams  # noqa: E402


def test_zero_half_angle_is_the_cylinder():
    """The cone's chart at slope 0 is the cylinder's term by term; the cylinder declares a constant
    metric and skips the parallel transport that the cone carries out with Christoffel symbols that
    vanish to round-off, which moves where each step's Newton (tolerance 1e-10) stops: equal to 1e-8
    of each quantity's range (measured on the particle: 4e-10 relative in the normal force)."""
    for model in ("reduced", "full"):
        a = RunScrew(ScrewParams(model=model, t_end=0.2), contactOutputs=False)
        b = RunScrew(ScrewParams(model=model, t_end=0.2, surface="cone", half_angle=0.0), contactOutputs=False)
        assert a.summary["steps"] == b.summary["steps"]
        for k in ("angle", "z", "torque"):
            scale = np.max(np.abs(a.trajectory[k])) + 1e-300
            np.testing.assert_allclose(b.trajectory[k], a.trajectory[k], rtol=0, atol=1e-8 * scale,
                                       err_msg=f"{model} {k}")


@pytest.mark.parametrize("return_map", ["exact", "radial"])
def test_tapered_thread_exudyn_equals_reference(return_map):
    # dt resolves the axial contact mode of the taper (eps_n sin^2(beta) against the screw's mass)
    p = ScrewParams(surface="cone", half_angle=1.79, return_map=return_map, t_end=0.05, dt=1e-4, axial_load=-0.5)
    a = RunScrew(p, contactOutputs=False, symmetry=False)
    b = simulate_screw(p)
    assert a.summary["steps"] == b.summary["steps"]
    for k in ("angle", "z"):
        scale = np.max(np.abs(b.trajectory[k])) + 1e-12
        assert np.max(np.abs(np.asarray(a.trajectory[k]) - b.trajectory[k])) <= 1e-6 * scale, k
    assert a.summary["energy_ok"] and b.summary["energy_ok"], (a.summary["energy"], b.summary["energy"])


def test_symmetry_per_ring_equals_all_points():
    p = ScrewParams(surface="cone", half_angle=3.0, t_end=0.05, dt=1e-4, axial_load=-0.5)
    a = RunScrew(p, contactOutputs=False, symmetry=True)
    b = RunScrew(p, contactOutputs=False, symmetry=False)
    np.testing.assert_allclose(a.trajectory["z"], b.trajectory["z"], rtol=0, atol=1e-9 * np.max(np.abs(b.trajectory["z"])))
    np.testing.assert_allclose(a.trajectory["angle"], b.trajectory["angle"], rtol=1e-9, atol=1e-12)


@pytest.mark.parametrize("half_angle,held", [(5.0, True), (20.0, False)])
def test_back_out_limit(half_angle, held):
    """No drive (torque 0), isotropic friction mu = 0.2: tan(5 deg) = 0.087 < mu holds the pressed
    screw, tan(20 deg) = 0.36 > mu pushes it out towards the wide end (+z). The sticking stiffness
    equals the normal one (with the scene's soft default the screw leaves the contact before friction
    builds up), and dt resolves the contact (an unresolved release creates energy: the ledger says so)."""
    p = ScrewParams(surface="cone", half_angle=half_angle, drive="torque", torque=0.0, adhesion="isotropic",
                    friction="isotropic", mu_1=0.2, eps_1=1e7, dt=1e-5, t_end=0.01)
    r = RunScrew(p, contactOutputs=False)
    z = np.asarray(r.trajectory["z"])
    assert r.summary["energy_ok"], r.summary["energy"]
    if held:
        assert np.max(np.abs(z)) < 1e-5, np.max(np.abs(z))        # elastic sticking only (1.7 um)
    else:
        assert z[-1] > 1e-3 and np.all(np.diff(z) >= -1e-12)       # 1.9 mm in 10 ms


def test_unresolved_release_opens_the_ledger():
    """The same cone at the scene's dt = 1 ms: the normal contact (3 kHz against 10 g) releases within
    one step, the trapezoidal rule gives the screw more kinetic energy than the penalty held, and the
    ledger reports it instead of passing the result off as right."""
    p = ScrewParams(surface="cone", half_angle=5.0, drive="torque", torque=0.0, adhesion="isotropic",
                    friction="isotropic", mu_1=0.2, t_end=0.05)
    with pytest.warns(UserWarning, match="energy ledger"):
        r = RunScrew(p, contactOutputs=False)
    assert r.summary["energy_ok"] is False and r.summary["energy"]["residual"] > 0.1


def test_bad_half_angle_is_named():
    with pytest.raises(ValueError, match="half_angle"):
        ScrewParams(surface="cone", half_angle=60.0)
    with pytest.raises(ValueError, match="surface"):
        ScrewParams(surface="sphere")


def test_tapered_thread_study_quick(tmp_path, quick_study):
    """studies/tapered_thread.py --quick: the cylinder row equals the screw scene's closed form
    (advance/pitch 0.99, torque 0.1014 N m), the 1:16 taper jams (torque up), and the back-out rows
    agree with tan(half_angle) < mu."""
    from exu_aniso.util.output import read_table
    quick_study("tapered_thread", tmp_path)
    D = read_table(tmp_path / "drive.csv")
    i0 = D["half_angle [deg]"].index(0.0)
    assert abs(D["torque_mean [N m]"][i0] - 0.1014) < 1e-3 and abs(D["advance/pitch [-]"][i0] - 0.99) < 0.01
    it = [i for i, a in enumerate(D["half_angle [deg]"]) if a < 0.0][0]
    assert D["torque_mean [N m]"][it] > 2.0 * D["torque_mean [N m]"][i0]
    B = read_table(tmp_path / "backout.csv")
    assert B["held [-]"] == B["held_theory [-]"] and set(B["held [-]"]) == {"yes", "no"}
