"""The loosening scene's preloaded joint (exu_aniso.scenes.bolted_joint, case="joint"): a nut clamping a
plate onto a bolt, shaken across the bolt's axis.

Oracles:
* the closed forms (exu_aniso.scenes.threads): the torque balance of two uniform sliding rings, its
  limits (a bearing ring alone is the bearing case's spin ratio; no lead, no turning; the lead's
  torque at the rings' whole friction, no steady state) and the sliding force's;
* model rings (the closed form's uniform rings): the nut's rotation per metre of slip path within
  1e-3 of the torque balance and the hysteresis loop's plateau within 1e-4 of the rings' sliding
  force, on a square and a 60 degree thread; with the bearing all but frictionless, the thread's own
  slip onset under the lead's torque (1e-3), and below it no slip and no turning, for 1000 cycles;
* model full (the nut on the bolt's helicoid, the plate on the joint's spring): the preload lost per
  radian turned loose within 1 % of the joint's stiffness times P / (2 pi) (with the contacts'
  compliances in series), to the cycle where the joint comes loose and the run ends; the energy
  ledger closes; with a flexible shank (the plate shaken; lumped at its end, or of Timoshenko beam
  elements), the plate's shift at which the bearing ring slides against the guided beam's closed form
  (1 %).
"""
import math

import pytest

from exu_aniso.scenes import threads
from exu_aniso.scenes.loosening import LooseningParams, simulate_loosening

M10 = dict(d2=9.026e-3, pitch=1.5e-3, mu_thread=0.12, mu_bearing=0.12, bearing_radius=6.6e-3)


def _rotation_per_path(flank_deg, **over):
    args = {**M10, **over}
    return threads.joint_rotation_per_path(args["d2"], args["pitch"], math.radians(flank_deg), args["mu_thread"],
                                           args["mu_bearing"], args["bearing_radius"])


def test_the_torque_balance_of_two_sliding_rings():
    """The root meets the balance it solves; with the thread's friction vanishing it is the bearing
    ring's own spin ratio (the bearing case's closed form) over r_K; with no lead, no turning."""
    h, r2, rK = M10["pitch"] / (2 * math.pi), M10["d2"] / 2, M10["bearing_radius"]
    for flank in (0.0, 60.0):
        c = _rotation_per_path(flank)
        mu_t = M10["mu_thread"] * threads.flank_load_per_axial_force(M10["d2"], M10["pitch"], math.radians(flank))
        torque = (mu_t * r2 * threads.ring_torque_factor(c * r2)
                  + M10["mu_bearing"] * rK * threads.ring_torque_factor(c * rK))
        assert torque == pytest.approx(h, rel=1e-10)
    alone = _rotation_per_path(0.0, mu_thread=1e-12)
    assert alone * rK == pytest.approx(threads.ring_spin_ratio(h / (M10["mu_bearing"] * rK)), rel=1e-8)
    assert _rotation_per_path(0.0, pitch=1e-12) == pytest.approx(0.0, abs=1e-6)
    with pytest.raises(ValueError, match="mu_thread, mu_bearing.*not self-locking"):
        _rotation_per_path(0.0, mu_thread=0.01, mu_bearing=0.01)
    assert threads.flank_load_per_axial_force(M10["d2"], M10["pitch"], math.radians(60.0)) == pytest.approx(
        1.0 / math.cos(math.radians(30.0)), rel=2e-3)                     # W / r: 1 / cos(beta / 2) at a small lead
    slide = threads.joint_slide_force_per_preload(M10["d2"], M10["pitch"], 0.0, M10["mu_thread"], M10["mu_bearing"], rK)
    assert 0.0 < slide < M10["mu_thread"] * 1.0014 + M10["mu_bearing"]      # the turning takes part of the grip


@pytest.fixture(scope="module")
def run():
    from exu_aniso.models.loosening import RunLoosening
    cache = {}

    def get(**values):
        key = tuple(sorted(values.items()))
        if key not in cache:
            cache[key] = RunLoosening(LooseningParams(case="joint", **values), show=False)
        return cache[key]
    return get


@pytest.mark.parametrize("flank_angle", [0.0, 60.0])
def test_uniform_rings_turn_loose_by_the_torque_balance(run, flank_angle):
    """Model rings, two cycles at dt 4e-4: the rotation per metre of slip path within 1e-3 of
    threads.joint_rotation_per_path and the loop's plateau within 1e-4 of the rings' sliding force."""
    r = run(model="rings", flank_angle=flank_angle, dt=4e-4, t_end=0.005 + 2 / 12.5)
    s = r.summary
    assert s["energy_ok"], s["energy"]
    assert s["rotation_per_path"] == pytest.approx(s["rotation_per_path_theory"], rel=1e-3)
    assert s["slide_force_per_preload"] == pytest.approx(s["slide_force_per_preload_theory"], rel=1e-4)
    assert s["rotation"] > 0.0 and s["thread_open_share"] == 0.0


@pytest.mark.parametrize("flank_angle, flank_limit", [(0.0, 0.1202), (60.0, 0.1387)])
def test_the_thread_alone_slides_at_its_flanks_limit_under_the_leads_torque(run, flank_angle, flank_limit):
    """Model rings with the bearing all but frictionless (mu 1e-6), four cycles at dt 4e-4: the thread's
    ring alone holds the lead's torque and resists the slide. The loop's plateau, the force at which the
    nut slides as a whole, lies within 1e-3 of the thread ring's limit under that torque,
    mu_t (W / r) D(c r2) with mu_t (W / r) r2 G(c r2) = h (threads.joint_slide_force_per_preload at
    mu_K 1e-6), below the flank's Coulomb limit mu_t W / r (1 / cos(beta / 2) at a small lead); the
    nut turns by the balance within 1e-2. Shaken by 3 um, below that onset, no thread point slips and
    the nut turns by round-off only."""
    s = run(model="rings", mu_bearing=1e-6, flank_angle=flank_angle, dt=4e-4, t_end=0.005 + 4 / 12.5).summary
    assert s["energy_ok"], s["energy"]
    limit = M10["mu_thread"] * threads.flank_load_per_axial_force(M10["d2"], M10["pitch"], math.radians(flank_angle))
    assert limit == pytest.approx(flank_limit, abs=5e-5)
    assert s["slide_force_per_preload"] == pytest.approx(s["slide_force_per_preload_theory"], rel=1e-3)
    assert s["slide_force_per_preload_theory"] < 0.9 * limit                # the lead's torque lowers the onset
    assert s["rotation_per_path"] == pytest.approx(s["rotation_per_path_theory"], rel=1e-2)
    below = run(model="rings", mu_bearing=1e-6, flank_angle=flank_angle, shake_displacement=3e-6, dt=4e-4,
                t_end=0.005 + 8 / 12.5).summary
    assert below["energy_ok"] and below["thread_slip_share"] == 0.0
    assert abs(below["rotation_per_cycle"]) < 1e-15


def test_below_the_onset_a_thousand_cycles_turn_the_joint_nothing(run):
    """Model rings shaken by 3 um for 1000 cycles at dt 1e-3 (the rings meet their balance at that
    step, docs/guide/scenes.md): the sideways force stays far below the rings' sliding force (the
    shaker's spring pulls the nut by a fifth of its travel against the two rings' sticking
    stiffness), no point of either ring ever slides, and over the 1000 cycles the nut turns only by
    its elastic twist under the lead's torque, at round-off per cycle; the ledger closes."""
    s = run(model="rings", shake_displacement=3e-6, dt=1e-3, t_end=0.005 + 1000 / 12.5).summary
    assert s["energy_ok"], s["energy"]
    assert s["cycles"] == 1000 and s["thread_slip_share"] == 0.0 and s["bearing_slip_share"] == 0.0
    assert abs(s["rotation_per_cycle"]) < 1e-15 and abs(s["rotation"]) < 1e-6


FULL = dict(model="full", dt=1e-4)


@pytest.mark.parametrize("flank_angle", [0.0, 60.0])
def test_the_preload_falls_by_the_joint_stiffness_per_radian(run, flank_angle):
    """Model full, four cycles: the preload at the cycles' ends against the angle turned loose falls by
    threads.clamp_force_per_angle (the lead over the joint's and the contacts' compliances) within 1 %;
    the run starts at the preload asked (the plate's spring load makes up the contacts' compression)
    and its ledger closes."""
    r = run(flank_angle=flank_angle, t_end=0.005 + 4 / 12.5, **FULL)
    s = r.summary
    assert s["energy_ok"], s["energy"]
    assert s["rotation"] > 0.01
    assert s["preload_loss_per_radian"] == pytest.approx(s["preload_loss_per_radian_theory"], rel=1e-2)
    assert s["preload_start"] == pytest.approx(1e4, rel=1e-3)


def test_the_full_joint_ends_its_run_when_it_comes_loose(run):
    """Model full on the 60 degree thread, shaken until its preload falls under a tenth
    (bolted_joint.LOOSE_SHARE): the run ends at the end of that cycle, and the preload there is the
    start's less the closed form's loss per radian times the angle turned, within 1 % of the preload."""
    from exu_aniso.scenes.bolted_joint import LOOSE_SHARE
    s = run(t_end=3.0, **FULL).summary
    assert s["energy_ok"], s["energy"]
    assert s["cycles_to_loose"] is not None and s["cycles"] == math.ceil(s["cycles_to_loose"]) < 3.0 * 12.5
    assert s["preload_end"] < LOOSE_SHARE * 1e4
    predicted = s["preload_start"] - s["preload_loss_per_radian_theory"] * s["rotation"]
    assert s["preload_end"] == pytest.approx(predicted, abs=1e-2 * 1e4)


@pytest.mark.slow          # the Junker study's quick form (tests/test_junker.py) brackets both at mu 0.12 by default
@pytest.mark.parametrize("shank", ["guided_beam", "fe_beam"])
def test_a_flexible_shank_slides_the_bearing_at_its_critical_amplitude(shank):
    """A flexible shank on the 60 degree thread, the plate shaken for two cycles: bisecting the shaker's
    amplitude between a run whose bearing ring never slides as a whole and one whose ring does, the
    plate's largest shift there brackets the guided beam's closed form mu_K F (1 / k_shank + 1 /
    sticking_stiffness) (bolted_joint.joint_closed_forms) within 1 %: while the bearing sticks, the nut
    and the bolt's end follow the plate and the bent shank's force grows to the bearing's friction.
    k_shank is 12 E I / L^3 for the lumped shank and, for the finite elements, the Timoshenko beam's
    (threads.guided_shear_beam_stiffness), 15 % softer: the two onsets lie apart by more than the 1 %."""
    from exu_aniso.models.loosening import RunLoosening

    def run(amplitude):
        p = LooseningParams(case="joint", shank=shank, shake_displacement=amplitude, t_end=0.005 + 2 / 12.5,
                            **FULL)
        s = RunLoosening(p, show=False).summary
        assert s["energy_ok"], s["energy"]
        return s["bearing_slid"], s["plate_amplitude"], s["critical_amplitude_theory"]
    lo, hi = (5e-5, None), (8e-5, None)
    for _ in range(7):
        mid = 0.5 * (lo[0] + hi[0])
        slid, amplitude, theory = run(mid)
        if slid:
            hi = (mid, amplitude)
        else:
            lo = (mid, amplitude)
    assert lo[1] is not None and hi[1] is not None, (lo, hi)
    assert lo[1] < hi[1]
    assert lo[1] > 0.99 * theory and hi[1] < 1.01 * theory, (lo, hi, theory)


def test_the_joint_runs_on_exudyn_only():
    with pytest.raises(ValueError, match="case: the reference engine runs the loosening's case bearing"):
        simulate_loosening(LooseningParams(case="joint"))


@pytest.mark.parametrize("name, value, rule", [("points_per_turn", 2, "points_per_turn must be >= 3"),
                                                ("flank_angle", 180.0, r"flank_angle must lie in \[0, 180\)"),
                                                ("poissons_ratio", 0.5, r"poissons_ratio must lie in \[0, 0.5\)"),
                                                ("shank_elements", 0, "shank_elements"),
                                                ("shank", "fe_beam", "a flexible shank .* is the full joint's")])
def test_bad_thread_is_refused(name, value, rule):
    with pytest.raises(ValueError, match=rule):
        LooseningParams(case="joint", **{name: value})
