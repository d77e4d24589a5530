"""Screw steady sliding in closed form and the calibration of B and F (exu_aniso.calibration).

Oracles: the closed form (derived in exu_aniso.calibration) against simulations of both engines,
its analytic limits, the sticking threshold of the torque drive, and calibrated parameters checked by a
simulation on the OTHER engine, which the optimizer never ran."""
from __future__ import annotations

import math

import numpy as np
import pytest

import exu_aniso.calibration as cal
from exu_aniso.calibration import DEFAULT_BASE, calibrate_screw, steady_sliding
from exu_aniso.scenes.screw import simulate_screw
from exu_aniso.scenes.screw import ScrewParams, pitch

SMALL = dict(rings=2, points_per_ring=4, t_end=0.3)       # K = 8: N and the closed form do not depend on K


def small(**kw):
    return DEFAULT_BASE.with_overrides(**dict(SMALL, **kw))


@pytest.mark.parametrize("return_map,axial_load", [("radial", 0.0), ("radial", -3.0), ("exact", 2.0)])
def test_steady_sliding_matches_reference_simulation(return_map, axial_load):
    p = small(return_map=return_map, eps_2=1e5, axial_load=axial_load)
    cf = steady_sliding(p)
    s = simulate_screw(p).summary
    # generalized-alpha damps the drive oscillation; the fitted slope/mean then match to ~1e-4
    assert s["advance_per_rev"] == pytest.approx(cf.advance_per_rev, rel=1e-3)
    assert s["torque_mean"] == pytest.approx(cf.torque, rel=1e-4)


def test_closed_form_limits():
    p = ScrewParams()
    a = math.radians(p.helix_angle)
    N = p.eps_n * p.interference
    rho = p.radius        # the traction acts where the slip is measured, on the hole (surfaces.Frame)
    # no axial load: advance/pitch = (1 - r)/(1 + r tan^2 a); torque on the friction ellipse along e_phi
    for rm, r in (("radial", p.eps_1 / p.eps_2), ("exact", (p.mu_1 / p.mu_2) ** 2)):
        cf = steady_sliding(p.with_overrides(return_map=rm))
        assert cf.advance_ratio == pytest.approx((1 - r) / (1 + r * math.tan(a) ** 2), rel=1e-12)
        assert cf.torque == pytest.approx(rho * N / math.sqrt(math.cos(a) ** 2 / p.mu_1 ** 2
                                                              + math.sin(a) ** 2 / p.mu_2 ** 2), rel=1e-12)
    # thread limit and isotropy
    assert steady_sliding(p.with_overrides(eps_2=p.eps_1 * 1e9)).advance_ratio > 1 - 1e-8
    assert steady_sliding(p.with_overrides(adhesion="isotropic")).advance_ratio == pytest.approx(0.0, abs=1e-12)
    iso = steady_sliding(p.with_overrides(return_map="exact", friction="isotropic"))
    assert iso.advance_ratio == pytest.approx(0.0, abs=1e-12)
    assert iso.torque == pytest.approx(rho * N * p.mu_1, rel=1e-12)
    # an axial load pushing against the advance raises the torque; the friction limit caps the load
    assert steady_sliding(p.with_overrides(axial_load=-5.0)).torque > steady_sliding(p).torque
    with pytest.raises(ValueError, match="axial_load"):
        steady_sliding(p.with_overrides(axial_load=-1.01 * N * p.mu_2))
    with pytest.raises(ValueError, match="return_map"):
        steady_sliding(p.with_overrides(return_map="seed"))


@pytest.mark.parametrize("factor,slides", [(0.9, False), (1.1, True)])
def test_torque_drive_sticks_below_the_closed_form_sliding_torque(factor, slides):
    p = small(drive="torque", dt=1e-4, t_end=0.03)
    p = p.with_overrides(torque=factor * steady_sliding(p).torque)
    tr = simulate_screw(p).trajectory
    t, ang = np.asarray(tr["t"]), np.asarray(tr["angle"])
    late_rotation = ang[-1] - ang[t >= 0.6 * t[-1]][0]
    # 0.9: the step torque slips during its overshoot, then the screw stops; 1.1: it keeps accelerating
    assert (late_rotation > 1.0) if slides else (abs(late_rotation) < 0.1)


@pytest.mark.parametrize("return_map,engine,ratio,torque", [("radial", "reference", 0.97, 0.12),
                                                             ("exact", "exudyn", 0.7, 0.06)])
def test_calibration_hits_targets_verified_on_the_other_engine(return_map, engine, ratio, torque):
    b = small(return_map=return_map)
    res = calibrate_screw(ratio * pitch(b), torque, base=b, engine=engine, tol=1e-4)
    assert res.residual <= 1e-4
    v = res.verification
    assert v["engine"] != engine
    # tolerance: optimizer tol 1e-4 plus engine parity (1e-7)
    assert abs(v["advance_error"]) < 2e-4 and abs(v["torque_error"]) < 2e-4
    assert v["advance_per_rev"] / pitch(b) == pytest.approx(ratio, rel=2e-4)
    names = cal.UNKNOWNS[return_map]
    assert tuple(res.unknowns) == names
    if return_map == "radial":      # only the unknowns moved
        assert res.params.eps_1 == b.eps_1 and res.params.mu_1 / res.params.mu_2 == pytest.approx(b.mu_1 / b.mu_2)
    else:
        assert (res.params.eps_1, res.params.eps_2) == (b.eps_1, b.eps_2)


def test_optimizer_solves_a_perturbed_model(monkeypatch):
    """least_squares must reach the targets when the 'simulation' differs from the closed form that gives
    its start and Jacobian (here by known factors; solution: the closed form hits the target / factor)."""
    calls = []

    def fake(p, engine):
        calls.append(p)
        cf = steady_sliding(p)
        return 1.03 * cf.advance_per_rev + 1e-5 * p.mu_1, 0.95 * cf.torque

    monkeypatch.setattr(cal, "run_for_targets", fake)
    b = DEFAULT_BASE
    target_adv, target_tq = 0.9 * pitch(b), 0.2
    res = calibrate_screw(target_adv, target_tq, base=b, tol=1e-8, verify=False)
    assert res.residual <= 1e-8 and 2 <= res.iterations <= 10
    cf = steady_sliding(res.params)
    assert cf.torque == pytest.approx(target_tq / 0.95, rel=1e-7)
    assert res.unknowns["eps_ratio"] != pytest.approx(res.guess["eps_ratio"], rel=1e-3)


@pytest.mark.parametrize("kwargs,match", [
    (dict(target_advance_per_rev="pitch*1.0"), "target_advance_per_rev"),
    (dict(target_advance_per_rev="pitch*1.2"), "target_advance_per_rev"),
    (dict(target_advance_per_rev=0.0), "target_advance_per_rev"),
    (dict(target_advance_per_rev="pitch*-0.5"), "target_advance_per_rev"),
    (dict(target_advance_per_rev=float("nan")), "target_advance_per_rev"),
    (dict(target_torque=0.0), "target_torque"),
    (dict(target_torque=-0.1), "target_torque"),
    (dict(target_torque=float("inf")), "target_torque"),
    (dict(base=DEFAULT_BASE.with_overrides(return_map="seed")), "base.return_map"),
    (dict(base=DEFAULT_BASE.with_overrides(adhesion="isotropic")), "base.adhesion"),
    (dict(base=DEFAULT_BASE.with_overrides(return_map="exact", friction="isotropic")), "base.friction"),
    (dict(base=DEFAULT_BASE.with_overrides(helix_angle=0.0)), "base.helix_angle"),
    (dict(engine="mujoco"), "engine"),
    (dict(tol=0.0), "tol"),
])
def test_infeasible_targets_and_bad_settings_raise(kwargs, match, monkeypatch):
    monkeypatch.setattr(cal, "run_for_targets", lambda p, e: pytest.fail("no simulation for bad input"))
    args = dict(target_advance_per_rev="pitch*0.9", target_torque=0.1, base=DEFAULT_BASE)
    args.update(kwargs)
    pt = pitch(args["base"])
    if isinstance(args["target_advance_per_rev"], str):
        args["target_advance_per_rev"] = pt * float(args["target_advance_per_rev"][6:])
    with pytest.raises(ValueError, match=match):
        calibrate_screw(args.pop("target_advance_per_rev"), args.pop("target_torque"), **args)
