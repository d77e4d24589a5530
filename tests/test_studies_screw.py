"""Quick runs of studies/screw_driving.py and studies/calibration.py, checked for physics, not for files."""
from __future__ import annotations

import os

import numpy as np
import pytest

from exu_aniso.util.output import read_table
from _suite import HANG_S



@pytest.fixture(scope="module")
def screw_out(tmp_path_factory, quick_study):
    out = tmp_path_factory.mktemp("screw_driving")
    quick_study("screw_driving", out, timeout=HANG_S)
    return out


def test_screw_driving_thread_limit(screw_out):
    S = read_table(os.path.join(screw_out, "r_sweep.csv"))
    m = np.array(S["map [-]"])
    r = np.array(S["r [-]"])[m == "radial"]
    adv = np.array(S["advance/pitch [-]"])[m == "radial"]
    order = np.argsort(r)
    # radial map: advance/pitch grows monotonically as r = eps_1/eps_2 falls and reaches the pitch
    assert np.all(np.diff(adv[order]) < 0)
    assert adv[order][0] > 0.99
    assert abs(adv[order][-1]) < 1e-3 and r[order][-1] == 1.0          # isotropic adhesion: no advance
    # closed form (1 - r)/(1 + r tan^2 a) and sliding torque, both maps
    assert np.allclose(S["advance/pitch [-]"], S["advance/pitch_closed_form [-]"], atol=2e-3)
    assert np.allclose(S["torque_mean [N m]"], S["torque_closed_form [N m]"], rtol=1e-3)
    # exact map: B does not steer steady sliding, the advance is flat in r
    ex = np.array(S["advance/pitch [-]"])[m == "exact"]
    assert np.ptp(ex) < 2e-3


def test_screw_driving_helix_and_torque_drive(screw_out):
    A = read_table(os.path.join(screw_out, "helix_sweep.csv"))
    order = np.argsort(A["helix_angle [deg]"])
    # larger helix angle: more cross-helix friction in the circumferential direction -> more torque
    assert np.all(np.diff(np.array(A["torque_mean [N m]"])[order]) > 0)
    T = read_table(os.path.join(screw_out, "torque_drive.csv"))
    f = np.array(T["torque/T_slide [-]"])
    slides = np.array(T["sliding_at_end [-]"]) > 0
    assert np.all(slides == (f > 1.0))              # closed-form sliding torque separates stick and slide
    C = read_table(os.path.join(screw_out, "crosscheck.csv"))
    assert np.ptp(C["advance/pitch [-]"]) < 1e-7 and np.ptp(C["torque_mean [N m]"]) < 1e-8   # Exudyn = reference


def test_calibration_study_hits_targets(tmp_path, quick_study):
    quick_study("calibration", tmp_path, timeout=HANG_S)
    T = read_table(os.path.join(tmp_path, "calibration.csv"))
    assert len(T["map [-]"]) >= 2 and set(T["verify engine [-]"]) == {"exudyn"}
    # independent Exudyn runs reach the targets (optimizer tolerance 1e-4 on the reference engine)
    assert np.allclose(T["verified advance/pitch [-]"], T["target advance/pitch [-]"], rtol=3e-4)
    assert np.allclose(T["verified torque [N m]"], T["target torque [N m]"], rtol=3e-4)
    assert max(np.abs(T["advance rel. error [-]"])) < 3e-4
