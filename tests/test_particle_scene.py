"""The particle scene (exu_aniso.scenes.particle, exu_aniso/models/particle.py, studies/particle.py): its
parameters and their errors, the textbook oracles measured through the scene on both engines, the
summary, the columns and the plot.

Oracles (exu_aniso.scenes.point_on_surface), with the error budget the tests hold them to:

* ``incline``: a point sliding along the top line of an inclined cylinder accelerates at
  g (sin a - mu cos a): the trapezoidal rule integrates a constant acceleration exactly, so the fit
  meets it to round-off (measured 1e-14 relative; tolerance 1e-9);
* ``cavity``: v = v0 exp(-mu psi); ``departure``: the angle of the textbook ODE. Both engines start
  the point sliding from the initial history of CreateAnisotropicContact (sticking, T = 0), so the
  first step misses half a step of friction impulse, mu |N0| dt / 2: a first-order error that
  ``point_on_surface.startup_impulse_error`` predicts from the oracle itself. The tests subtract it and
  hold the rest to a bound that falls with dt (cavity: second order; measured below). The
  convergence runs take seconds (both engines, four levels), so they are not slow-marked.
"""
from __future__ import annotations

import math
import warnings

import pytest

from exu_aniso.scenes import point_on_surface
from exu_aniso.scenes.particle import simulate_particle
from exu_aniso.scenes.particle import (COLUMNS, ORACLE_KEYS, TITLE_KEYS, ParticleParams, PlotParticle,
                                      particle_contact_law)
from _suite import HANG_S

CAVITY = dict(case="cavity", side="inside", gravity=0.0, speed=2.0, mu_1=0.3, t_end=0.5)
INCLINE = dict(case="incline", surface="cylinder", tilt=30.0, mu_1=0.3, speed=0.2, t_end=0.3)
DEPARTURE = dict(case="departure", t_end=0.8)


def engines():
    pytest.importorskip("exudyn")
    from exu_aniso.models.particle import RunParticle
    return [("reference", simulate_particle), ("exudyn", RunParticle)]


# ----------------------------------------------------------------------------------------------
# parameters

def test_defaults_and_table():
    p = ParticleParams()
    assert p.case == "departure" and p.surface == "sphere"
    assert "half_angle" in ParticleParams.describe() and "deg" in ParticleParams.describe()
    assert ParticleParams.from_strings({"net_angle": "pi", "case": "free"}).net_angle == pytest.approx(math.pi)


@pytest.mark.parametrize("values,match", [
    (dict(surface="ellipsoid"), "surface must be one of"),
    (dict(mu_1=0.0), "mu_1 must be > 0"),
    (dict(case="free", surface="torus", radius=0.2, minor_radius=0.3), "minor_radius must be < radius"),
    (dict(case="departure", x0=1.0), "x0 applies to case=free only"),
    (dict(case="free", speed=1.0), "speed applies to the oracle cases only"),
    (dict(case="departure", surface="torus"), "surface must be one of .* for case=departure"),
    (dict(case="cavity"), "side must be 'inside' for case=cavity"),
    (dict(case="cavity", side="inside"), "gravity must be 0 for case=cavity"),
    (dict(case="incline", surface="cylinder", side="inside"), "side must be 'outside' for case=incline"),
    (dict(case="departure", tilt=10.0), "tilt must be 0 for case=departure"),
    (dict(case="departure", speed=3.0), r"speed must satisfy speed\^2 < gravity \* radius"),
    (dict(tilt=90.0), r"tilt must lie in \(-90, 90\)"),
    (dict(dt=2.0), "dt must be <= t_end"),
    (dict(mass="heavy"), "mass: expected a decimal number"),
])
def test_bad_values_name_the_parameter_and_the_rule(values, match):
    with pytest.raises(ValueError, match=match):
        ParticleParams(**values)


def test_unknown_name():
    with pytest.raises(ValueError, match="unknown parameter"):
        ParticleParams.from_strings({"velocity": "1"})


# ----------------------------------------------------------------------------------------------
# oracles through the scene, both engines

def _err(s):
    return s["oracle"] - s["oracle_theory"]


def test_incline_meets_the_textbook_acceleration():
    for name, run in engines():
        s = run(ParticleParams(dt=5e-4, **INCLINE)).summary
        assert s["incline_acceleration_theory"] == pytest.approx(9.81 * (0.5 - 0.3 * math.cos(math.radians(30))))
        assert abs(_err(s)) <= 1e-9 * abs(s["oracle_theory"]), (name, s["oracle"], s["oracle_theory"])
        assert s["energy_ok"]


def test_incline_that_stops():
    """tan(10 deg) < mu: launched downhill at 0.2 m/s the point slows down at g (sin - mu cos) =
    -1.195 m/s^2 and sticks after 0.167 s. Over 0.5 s the fit (t >= 0.1 s, still sliding) measures the
    deceleration; over 1 s nothing slides after 0.2 s and the acceleration is undefined."""
    s = simulate_particle(ParticleParams(dt=5e-4, **dict(INCLINE, tilt=10.0, t_end=0.5))).summary
    assert s["incline_acceleration_theory"] == pytest.approx(-1.195, abs=1e-3)
    assert abs(_err(s)) <= 1e-9 and s["speed_end"] < 5e-3      # stuck: the elastic vibration of the stick
    s = simulate_particle(ParticleParams(dt=5e-4, **dict(INCLINE, tilt=10.0, t_end=1.0))).summary
    assert s["incline_acceleration"] is None and "stopped" in s["undefined"]["incline_acceleration"]


def test_cavity_speed_follows_the_exponential():
    """Measured (dt 5e-4, eps_n 1e6): cavity_speed_error 3.0321e-4 on both engines, against the
    start-up term mu v0 dt / (2 R) = 3.0000e-4; the rest, 3.2e-6, is second order (slow test)."""
    dt = 5e-4
    startup = point_on_surface.startup_impulse_error("cavity", 0.3, 0.5, 0.0, 2.0, dt)
    for name, run in engines():
        s = run(ParticleParams(dt=dt, **CAVITY)).summary
        assert s["cavity_psi_end_deg"] > 80.0                    # nearly a quarter turn (89.8 deg)
        assert abs(s["cavity_speed_error"] - startup) <= 1e-5, (name, s["cavity_speed_error"], startup)
        assert abs(_err(s) - startup * s["oracle_theory"]) <= 1e-5, (name, _err(s))
        assert s["energy_ok"]


def test_departure_angle():
    """Measured (dt 5e-4): the simulated angle is 2.59e-3 deg below the textbook 51.4547 deg, the
    start-up term is 2.28e-3 deg; the rest, 3.1e-4 deg, is the penalty's normal vibration in the fit
    (bounded by 5e-4 deg)."""
    dt = 5e-4
    startup = math.degrees(point_on_surface.startup_impulse_error("departure", 0.15, 0.5, 9.81, 0.5, dt))
    for name, run in engines():
        s = run(ParticleParams(dt=dt, **DEPARTURE)).summary
        assert s["departure_angle_deg_theory"] == pytest.approx(51.4547, abs=1e-4)
        assert abs(_err(s) - startup) <= 5e-4, (name, _err(s), startup)
        assert s["energy_ok"]


def test_the_oracle_is_sensitive_to_friction():
    """The measurement can fail: mu 0.15 against 0.10 moves the departure by degrees."""
    a = simulate_particle(ParticleParams(dt=5e-4, **DEPARTURE)).summary
    b = simulate_particle(ParticleParams(dt=5e-4, mu_1=0.10, mu_2=0.10, **DEPARTURE)).summary
    assert abs(a["oracle"] - b["oracle"]) > 1.0
    assert abs(b["oracle"] - b["oracle_theory"]) < 5e-3


def _slow_engines():
    """Both engines; Exudyn with Newton tolerance 1e-8 (at eps_n 1.6e7 the contact force's round-off
    lies above the models' 1e-10: see studies/particle.py)."""
    out = [("reference", simulate_particle)]
    for name, run in engines():
        if name == "exudyn":
            out.append((name, lambda p, run=run: run(p, newtonTolerance=1e-8)))
    return out


def test_cavity_converges():
    """After the start-up term the cavity's largest relative speed error falls faster than dt, tending
    to dt^2 (eps_n * 4 per halving keeps the normal mode's omega dt). Measured rest (reference):
    1.3e-5, 3.2e-6, 8.0e-7, 2.0e-7 at dt 1e-3 ... 1.25e-4."""
    for name, run in _slow_engines():
        rest = []
        for k, dt in enumerate((1e-3, 5e-4, 2.5e-4, 1.25e-4)):
            eps = 2.5e5 * 4 ** k
            s = run(ParticleParams(dt=dt, eps_n=eps, eps_1=eps / 10, **CAVITY)).summary
            startup = point_on_surface.startup_impulse_error("cavity", 0.3, 0.5, 0.0, 2.0, dt)
            rest.append(abs(s["cavity_speed_error"] - startup))
        assert all(b < 0.35 * a for a, b in zip(rest, rest[1:])), (name, rest)


def test_departure_error_is_the_startup_term():
    """The departure error halves with dt as the start-up term does; the rest stays below 5e-4 deg
    (measured 1.1e-4 to 3.5e-4 deg: the penalty's normal vibration in the fit, omega dt = 1.6 here)."""
    for name, run in _slow_engines():
        errs = []
        for k, dt in enumerate((1e-3, 5e-4, 2.5e-4, 1.25e-4)):
            eps = 2.5e5 * 4 ** k
            s = run(ParticleParams(dt=dt, eps_n=eps, eps_1=eps / 10, **DEPARTURE)).summary
            startup = math.degrees(point_on_surface.startup_impulse_error("departure", 0.15, 0.5, 9.81, 0.5, dt))
            errs.append(_err(s))
            assert abs(_err(s) - startup) <= 5e-4, (name, dt, _err(s), startup)
        assert all(abs(b) < 0.8 * abs(a) for a, b in zip(errs, errs[1:])), (name, errs)


# ----------------------------------------------------------------------------------------------
# every oracle knows its domain: just inside it the theory is reported and met, just outside it
# is None with the reason (scenes.particle.theory_domain, point_on_surface.OutsideDomain)

MU_EDGE = 0.2312331401      # departure at speed 0.5 m/s, R 0.5 m: the ODE's point stops above this mu
#                             (bisection of point_on_surface.departure_angle; checked below, not trusted)


def _stop_angle(mu, speed):
    with pytest.raises(point_on_surface.OutsideDomain) as e:
        point_on_surface.departure_angle(mu, 0.5, 9.81, speed)
    return e.value.stop_angle


def test_departure_oracle_refuses_a_point_that_friction_stops():
    """The ODE's -mu N term used to push a stopped point backwards (mu 0.5 gave -37.2 deg). A point
    that friction stops is held by it (moving downhill, v falls to 0 only where g (sin - mu cos) <= 0,
    the sticking rule), so there is no departure angle: OutsideDomain naming mu and the rule."""
    assert point_on_surface.departure_angle(MU_EDGE - 1e-6, 0.5, 9.81, 0.5) > 0.9          # leaves (54.5 deg)
    for mu in (MU_EDGE + 1e-6, 0.5, 0.8, 1.0, 1.1):
        with pytest.raises(point_on_surface.OutsideDomain, match=r"mu = .*sticking rule .*never leaves"):
            point_on_surface.departure_angle(mu, 0.5, 9.81, 0.5)
        th = _stop_angle(mu, 0.5)
        assert 0.0 < th and math.tan(th) <= mu                                    # where friction can hold it
    with pytest.raises(point_on_surface.OutsideDomain, match="speed = 0: the point rests on the top"):
        point_on_surface.departure_angle(0.15, 0.5, 9.81, 0.0)
    assert issubclass(point_on_surface.OutsideDomain, ValueError)
    with pytest.raises(ValueError, match="speed"):                                # bad input: plain ValueError
        point_on_surface.departure_angle(0.15, 0.5, 9.81, -1.0)


def test_departure_domain_edge_through_the_scene():
    """mu 0.21, just inside: the theory is reported and met as in test_departure_angle (the start-up
    term plus 5e-4 deg; measured rest 4.9e-5 deg). mu 0.25, just outside: no theory, the reason names
    mu and the sticking rule, and the simulated point does stop where the oracle says: at the stop
    angle moved by the start-up term (its derivative by the launch speed times dv = mu |N0| dt / 2m),
    within 5e-4 deg (measured 1e-4 deg; the stick's elastic offset m g sin / (eps_1 R) is 1.7e-4 deg)."""
    dt, R, g, v0 = 5e-4, 0.5, 9.81, 0.5
    startup = math.degrees(point_on_surface.startup_impulse_error("departure", 0.21, R, g, v0, dt))
    dv, h = 0.25 * (g - v0 * v0 / R) * dt / 2.0, 1e-4 * v0
    stop = math.degrees(_stop_angle(0.25, v0) + (_stop_angle(0.25, v0 + h) - _stop_angle(0.25, v0 - h)) / (2 * h) * dv)
    for name, run in engines():
        s = run(ParticleParams(dt=dt, **dict(DEPARTURE, mu_1=0.21, mu_2=0.21, t_end=1.0))).summary
        assert s["oracle_theory"] is not None and abs(_err(s) - startup) <= 5e-4, (name, s["oracle_theory"])
        r = run(ParticleParams(dt=dt, **dict(DEPARTURE, mu_1=0.25, mu_2=0.25, t_end=0.4)))
        s = r.summary
        assert s["departure_angle_deg_theory"] is None and s["oracle_theory"] is None
        assert "mu = 0.25" in s["undefined"]["oracle_theory"] and "sticking rule" in s["undefined"]["oracle_theory"]
        assert s["departure_angle_deg"] is None and "still on the sphere" in s["undefined"]["departure_angle_deg"]
        end = math.degrees(math.atan2(r.trajectory["y"][-1], r.trajectory["z"][-1]))
        assert s["speed_end"] < 1e-3 and abs(end - stop) <= 5e-4, (name, end, stop, s["speed_end"])


def test_cavity_dashpots():
    """A normal dashpot leaves the oracle in its domain (n.v = 0 but for the penalty's own
    penetration rate): at 1e4 N s/m (16 times critical) the error is the start-up term within the
    1e-5 of test_cavity_speed_follows_the_exponential (measured 3.0228e-4 against 3.0321e-4 without).
    Any tangential dashpot acts with friction while the point slides: no theory; at 1e-3 N s/m the
    speed ratio lies 2.93e-3 below exp(-mu psi_end) (reference: 0.62258 against 0.62552), ten times
    the start-up term 3.0e-4 (the test asks for five)."""
    dt = 5e-4
    startup = point_on_surface.startup_impulse_error("cavity", 0.3, 0.5, 0.0, 2.0, dt)
    for name, run in engines():
        s = run(ParticleParams(dt=dt, normal_damping=1e4, **CAVITY)).summary
        assert abs(s["cavity_speed_error"] - startup) <= 1e-5, (name, s["cavity_speed_error"])
        s = run(ParticleParams(dt=dt, tangential_damping=1e-3, **CAVITY)).summary
        for k in ("cavity_speed_ratio_theory", "cavity_speed_error", "oracle_theory"):
            assert s[k] is None and "tangential_damping=0.001" in s["undefined"][k], (name, k)
        textbook = math.exp(-0.3 * math.radians(s["cavity_psi_end_deg"]))
        assert textbook - s["cavity_speed_ratio"] > 5 * startup, (name, s["cavity_speed_ratio"], textbook)


def test_incline_domain_edges():
    """The incline's acceleration is constant while the point slides, so inside the domain the fit
    meets it to round-off (1e-9 relative, as test_incline_meets_the_textbook_acceleration): with a
    normal dashpot of 1e4 N s/m (N is constant: it does nothing) and from rest at tilt 18 deg
    (tan 0.325 > mu 0.3: it slides). Outside: any tangential dashpot (the user's 3.63 -> 0.278 m/s^2),
    and from rest at tilt 16 deg (tan 0.287 <= mu: friction holds it; it stays at rest)."""
    for name, run in engines():
        for kw in (dict(normal_damping=1e4), dict(speed=0.0, tilt=18.0)):
            s = run(ParticleParams(dt=5e-4, **dict(INCLINE, **kw))).summary
            assert abs(_err(s)) <= 1e-9 * abs(s["oracle_theory"]), (name, kw, s["oracle"])
        s = run(ParticleParams(dt=5e-4, **dict(INCLINE, tangential_damping=1e-3))).summary
        assert s["incline_acceleration_theory"] is None and "tangential_damping" in s["undefined"]["oracle_theory"]
        s = run(ParticleParams(dt=5e-4, **dict(INCLINE, speed=0.0, tilt=16.0, t_end=0.1))).summary
        assert s["oracle_theory"] is None and "sticking rule" in s["undefined"]["oracle_theory"]
        assert s["speed_end"] < 1e-3, (name, s["speed_end"])


@pytest.mark.parametrize("values,mu,reason", [
    (dict(INCLINE, gravity=0.0), None, "gravity=0"),
    (dict(INCLINE, speed=0.0, tilt=-30.0), None, "toward -x"),
    (dict(INCLINE, friction="orthotropic", mu_2=0.15, net_angle=0.0), 0.15, None),       # the axis is xi2
    (dict(INCLINE, friction="orthotropic", mu_2=0.15, net_angle=90.0), 0.3, None),       # direction 1 on the axis
    (dict(DEPARTURE, friction="orthotropic", mu_1=0.3, mu_2=0.15, net_angle=90.0), 0.15, None),
    (dict(DEPARTURE, friction="orthotropic", mu_1=0.3, mu_2=0.15, net_angle=45.0), None, "net_angle=45"),
    (dict(CAVITY, tangential_damping=1e-6), None, "tangential_damping=1e-06"),
    (dict(CAVITY, normal_damping=1e6), 0.3, None),
    (dict(CAVITY, adhesion="orthotropic", eps_2=1e4, net_angle=30.0, return_map="radial"), None, "return_map=radial"),
    (dict(CAVITY, adhesion="orthotropic", eps_2=1e4, net_angle=30.0, return_map="exact"), 0.3, None),
    (dict(CAVITY, adhesion="orthotropic", eps_2=1e4, net_angle=90.0, return_map="seed"), 0.3, None),
])
def test_theory_domain_rules(values, mu, reason):
    """The rules of scenes.particle.theory_domain (the measurements behind them: its docstring and the
    tests above; an orthotropic F at angle 90 deg gave the isotropic mu_2 angle to 1e-12 deg)."""
    from exu_aniso.scenes.particle import path_mu, theory_domain
    p = ParticleParams(**values)
    why = theory_domain(p)
    if reason is None:
        assert why is None and path_mu(p)[0] == mu
    else:
        assert why is not None and reason in why, why


def test_bent_friction_of_a_non_associated_map_has_no_theory():
    """Just outside: radial map, B orthotropic at 30 deg (eps_2 = eps_1 / 10): the friction force turns
    toward B v and the cavity's speed leaves exp(-mu psi) by 7 % (measured 7.3e-2); no theory. Just
    inside: the exact map on the same B meets the oracle as with isotropic B (start-up term + 1e-5)."""
    kw = dict(CAVITY, adhesion="orthotropic", eps_1=1e5, eps_2=1e4, net_angle=30.0)
    startup = point_on_surface.startup_impulse_error("cavity", 0.3, 0.5, 0.0, 2.0, 5e-4)
    s = simulate_particle(ParticleParams(dt=5e-4, return_map="exact", **kw)).summary
    assert abs(s["cavity_speed_error"] - startup) <= 1e-5, s["cavity_speed_error"]
    s = simulate_particle(ParticleParams(dt=5e-4, return_map="radial", **kw)).summary
    assert s["oracle_theory"] is None and "return_map=radial" in s["undefined"]["cavity_speed_error"]
    textbook = math.exp(-0.3 * math.radians(s["cavity_psi_end_deg"]))
    assert abs(s["cavity_speed_ratio"] / textbook - 1.0) > 100 * startup


def test_ledger_recomputed_from_csv(tmp_path):
    """trajectory.csv and the parameters hold the whole ledger of a particle run: work in 0 (no
    drive), kinetic m |v|^2 / 2 and potential -m g . (x - x0), g = gravity (sin tilt, 0, -cos tilt),
    each as the change from the first row, recomputed from the file's columns equal the file's
    energy_* columns, and so does the residual with the file's stored and dissipated energy. The
    csv writes repr(float), so the only difference is the round-off of the sums (1e-12 of the
    largest term). An inclined cylinder with both dashpots exercises every term."""
    import csv
    import json

    import numpy as np

    from exu_aniso.cli import main
    sets = dict(case="incline", surface="cylinder", tilt=30.0, mu_1=0.3, speed=0.2, t_end=0.05, dt=1e-3,
                normal_damping=10.0, tangential_damping=0.01)
    for name, _ in engines():
        out = tmp_path / name
        assert main(["run", "particle", "--engine", name, "--out", str(out), "--quiet",
                     *[a for k, v in sets.items() for a in ("--set", f"{k}={v}")]]) == 0
        with open(out / "trajectory.csv") as f:
            rows = list(csv.DictReader(line for line in f if not line.startswith("#")))
        c = {k: np.array([float(r[k]) for r in rows]) for k in rows[0]}
        p = json.loads((out / "summary.json").read_text())["params"]
        m, a = p["mass"], math.radians(p["tilt"])
        g = p["gravity"] * np.array([math.sin(a), 0.0, -math.cos(a)])
        X = np.column_stack([c["x"], c["y"], c["z"]])
        kin = 0.5 * m * (c["vx"] ** 2 + c["vy"] ** 2 + c["vz"] ** 2)
        terms = dict(work_in=np.zeros(len(kin)), kinetic=kin - kin[0], potential=-m * (X - X[0]) @ g)
        scale = max(np.max(np.abs(c["energy_" + k])) for k in ("kinetic", "potential", "stored", "dissipated"))
        assert np.max(np.abs(c["energy_dissipated"])) > 1e-3 * scale            # the dashpots and friction work
        for k, v in terms.items():
            assert np.max(np.abs(v - c["energy_" + k])) <= 1e-12 * scale, (name, k)
        res = terms["work_in"] - terms["kinetic"] - terms["potential"] - c["energy_stored"] - c["energy_dissipated"]
        assert np.max(np.abs(res - c["energy_residual"])) <= 1e-12 * scale, name


# ----------------------------------------------------------------------------------------------
# summary, columns, plot

def test_summary_and_columns():
    r = simulate_particle(ParticleParams(dt=1e-3, t_end=0.05, case="free"))
    assert set(COLUMNS) <= set(r.trajectory), set(COLUMNS) - set(r.trajectory)
    s = r.summary
    assert set(TITLE_KEYS) <= set(s) and s["oracle"] is None and "free" in s["undefined"]["oracle"]
    assert {"energy", "energy_ok", "energy_tolerance"} <= set(s)
    for case, kw in (("departure", DEPARTURE), ("cavity", CAVITY), ("incline", INCLINE)):
        s = simulate_particle(ParticleParams(dt=1e-3, **dict(kw, t_end=0.05))).summary
        for k in ORACLE_KEYS[case]:                 # present; a value, or None with its reason
            assert k in s and (s[k] is not None or k in s["undefined"]), (case, k)


def test_orthotropic_friction_off_axis_has_no_theory():
    s = simulate_particle(ParticleParams(dt=1e-3, friction="orthotropic", mu_1=0.1, mu_2=0.2, net_angle=30.0,
                                         **DEPARTURE)).summary
    assert s["departure_angle_deg_theory"] is None and "principal direction" in s["undefined"]["oracle_theory"]


def test_contact_law_takes_another_surface():
    from exu_aniso.geometry import Sphere
    law = particle_contact_law(ParticleParams(), surface=Sphere(2.0))
    assert law.surface.radius == 2.0


@pytest.mark.parametrize("case", ["departure", "cavity", "incline", "free"])
def test_plot_draws_path_and_oracle(case):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    kw = dict({"departure": DEPARTURE, "cavity": CAVITY, "incline": INCLINE, "free": dict(case="free")}[case])
    kw["t_end"] = 0.05
    p = ParticleParams(dt=1e-3, **kw)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        r = simulate_particle(p)
    fig = plt.figure()
    a1, a2 = PlotParticle(r.trajectory, p, fig)
    assert len(a1.lines) >= 2 and len(a2.lines) >= 1 and a2.get_legend() is not None
    plt.close(fig)


def test_particle_study_quick(tmp_path, quick_study):
    """studies/particle.py --quick: the three oracles against theory on both engines at two steps."""
    from exu_aniso.util.output import read_table
    quick_study("particle", tmp_path, timeout=HANG_S)
    T = read_table(tmp_path / "refinement.csv")
    assert set(T["case [-]"]) == {"departure", "cavity", "incline"}
    assert set(T["engine [-]"]) == {"reference", "exudyn"}
    for c, rest, ok in zip(T["case [-]"], T["error_after_startup [-]"], T["energy_ok [-]"]):
        assert ok == "yes"
        assert abs(rest) < {"departure": 1e-5, "cavity": 2e-5, "incline": 1e-9}[c], (c, rest)
    assert (tmp_path / "particle.png").exists()
    assert "python studies/particle.py" in (tmp_path / "report.md").read_text()
