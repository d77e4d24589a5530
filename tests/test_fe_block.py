"""The fe_block scene (exu_aniso.scenes.fe_block, exu_aniso.models.fe_block): an elastic block on the
polar-orthotropic plane, its top face held by a press plate (the floating frame) that is pressed down
and then pulled by the block scene's drive, free across the plane and about the vertical.

Oracles: the stiff limit (as E grows the bottom face's path approaches the rigid block scene's
under the same drive, on the reference engine, like 1/E); the net's family of motions (a circle,
a straight line, an outward drift); the energy ledger (closes to the Newton tolerance with a
constant isotropic B); the reduced body with the bottom nodes' static modes against the full mesh;
the share of the contact's compliance a basis keeps; the parameters' rules."""
import math
import warnings

import numpy as np
import pytest

pytest.importorskip("exudyn")
pytest.importorskip("skfem")

from exu_aniso.fe.compliance import BasisWarning  # noqa: E402
from exu_aniso.models.fe_block import RunFeBlock  # noqa: E402
from exu_aniso.scenes.fe_block import FeBlockParams, path_from_rigid, rigid_limit  # noqa: E402
from _suite import HANG_S

SHORT = dict(cells=2, t_end=0.6, t_press=0.1, travel=0.02)


def test_the_stiff_limit_is_the_rigid_block_scene():
    """A contact softer than the default (eps_n 1e5 N/m in all) against E = 1e6, 1e7, 1e8 Pa: the
    bottom face's largest distance from the rigid block scene's path under the same drive (rigid_limit,
    the reference engine) falls like 1/E, and the drive's force at the end approaches the rigid
    block's (measured: 8.5e-5, 1.08e-5, 1.14e-6 m; force 2.0221, 2.0183, 2.0192 N against 2.0193)."""
    path, force = [], []
    for E in (1e6, 1e7, 1e8):
        p = FeBlockParams(E=E, eps_n=1e5, eps_r=1e4, eps_phi=1e2, **SHORT)
        res = RunFeBlock(p)
        limit = rigid_limit(p)
        assert res.summary["energy_ok"]
        path.append(path_from_rigid(p, res.trajectory, limit))
        force.append(abs(res.trajectory["drive_force"][-1] / limit["drive_force"][-1] - 1.0))
    assert 7.0 < path[0] / path[1] < 12.0 and 7.0 < path[1] / path[2] < 12.0, path
    assert path[2] < 2e-6 and force[2] < 1e-3, (path, force)


@pytest.mark.parametrize("ratio,shape", [(100.0, "circle"), (1.0, "straight"), (0.01, "outward")])
def test_the_net_steers_the_block(ratio, shape):
    """The paper's family of motions under the same drive along +y from (0.5, 0), sqrt(eps_r eps_phi)
    = 1e5 N/m: a stiff radial net keeps the bottom on the circle about the origin (radius within 0.1 %
    of its start, the block turning with it), an isotropic one lets it go straight (no offset across),
    a soft radial one lets it drift outward (measured at 2 cells: r_end 0.50010, 0.50964, 0.67323 m;
    steer_end 9.7 mm, 0, -166 mm)."""
    p = FeBlockParams(cells=2, eps_r=1e5 * math.sqrt(ratio), eps_phi=1e5 / math.sqrt(ratio))
    s = RunFeBlock(p).summary
    assert s["energy_ok"]
    if shape == "circle":
        assert abs(s["r_bottom_end"] / p.x0 - 1.0) < 1e-3 and s["steer_end"] > 0.005 and s["yaw_end"] > 0.1, s
    elif shape == "straight":
        assert abs(s["steer_end"]) < 1e-9 and abs(s["yaw_end"]) < 1e-9, s
    else:
        assert s["r_bottom_end"] > 0.6 and s["steer_end"] < -0.1, s


def test_the_ledger_closes_with_strain_energy():
    """The short run: polar B (eps_r 100 eps_phi) leaves its hypo-elastic part (below 1e-2, as the
    rigid block's); with eps_r = eps_phi the adhesion is a constant isotropic B and the books close to
    the Newton tolerance: the drive's and the press's work = kinetic + strain + the drive spring's +
    the contact's stored energy + friction's and the damping's dissipation."""
    res = RunFeBlock(FeBlockParams(**SHORT))
    assert res.summary["energy_ok"] and res.summary["energy"]["residual"] < 1e-2
    assert res.summary["strain_energy_end"] > 0.0 and res.summary["energy"]["work_in"] > 0.0
    iso = RunFeBlock(FeBlockParams(eps_r=1e5, eps_phi=1e5, **SHORT))
    assert iso.summary["energy"]["residual"] < 1e-6, iso.summary["energy"]
    assert np.all(np.diff(iso.trajectory["dissipated_energy"]) >= -1e-12)


def test_the_press_and_the_drive():
    """The plate goes down by w and stays level; after the pressing the drive's force is the spring's
    and the dashpot's along +y; the press carries the contact's normal force (F_z < 0 on the frame)."""
    p = FeBlockParams(**SHORT)
    tr = RunFeBlock(p).trajectory
    t = np.asarray(tr["t"])
    assert np.all(np.abs(np.asarray(tr["drive_force"])[t <= p.t_press]) < 1e-9)
    assert tr["force_z"][-1] < 0.0 and abs(tr["force_x"][-1]) < 1e-9 * abs(tr["force_y"][-1])
    assert np.all(np.asarray(tr["stick_fraction"]) + tr["slip_fraction"] <= 1.0 + 1e-12)


def test_the_bottom_nodes_static_modes_hold_the_full_mesh():
    """Craig-Bampton's static modes of the bottom nodes (the default) against every coordinate off the
    top face (model=full) on the short run: the path within 1e-4 of the travel, the forces within 1 %
    (the fixed-interface modes left out carry only the block's inertia; measured 1.5e-6 m, 7.6e-5 of
    the travel)."""
    a = RunFeBlock(FeBlockParams(model="full", **SHORT)).trajectory
    b = RunFeBlock(FeBlockParams(model="reduced", **SHORT)).trajectory
    path = np.hypot(np.asarray(a["x_bottom"]) - b["x_bottom"], np.asarray(a["y_bottom"]) - b["y_bottom"]).max()
    assert path < 1e-4 * SHORT["travel"], path
    for key in ("drive_force", "force_z"):
        assert np.abs(np.asarray(a[key]) - b[key]).max() < 0.01 * np.abs(a[key]).max(), key


def test_a_basis_says_how_much_of_the_contact_it_feels():
    """Six eigenmodes of the block clamped at its top keep a small share of the bottom nodes' static
    compliance: the run warns, names the basis and the fix, and says so in its summary; the default
    (the bottom nodes' static modes) keeps all of it and does not warn."""
    with pytest.warns(BasisWarning, match="6 eigenmodes of the block clamped at its top.*basis=craig_bampton"):
        s = RunFeBlock(FeBlockParams(model="reduced", basis="eigenmodes", modes=6, **SHORT)).summary
    assert s["contact_compliance_share"] < 0.9 and "keeps" in s["basis_warning"]
    with warnings.catch_warnings():
        warnings.simplefilter("error", BasisWarning)
        s = RunFeBlock(FeBlockParams(**SHORT)).summary
    assert s["contact_compliance_share"] == pytest.approx(1.0, abs=1e-9) and s["basis_warning"] is None


@pytest.mark.parametrize("kw,message", [
    (dict(nu=0.5), r"nu must lie in \(-1, 0.5\)"),
    (dict(press=0.06), "press must be < size / 2"),
    (dict(t_press=1.2), "t_press must be < t_end"),
    (dict(drive_ramp=1.0), "drive_ramp must be < t_end - t_press"),
    (dict(return_map="seed"), "return_map=seed is refused here"),
    (dict(model="reduced", basis="eigenmodes", modes=0), "modes must be >= 1"),
    (dict(model="reduced", cells=3, modes=100), "modes must be <= 96"),
    (dict(model="full", cells=8), r"would have 1944 modes \(cells=8, model=full\)"),
    (dict(cells=12), "about 95 s per step that refreshes its Jacobian"),     # did not finish 3 steps in 400 s
    (dict(model="full", cells=5), "about 32.5 s per step"),                  # measured: 30.6 s, studies/fe_cost.py
    (dict(cells=13), "cells must be <= 12"),
    (dict(E=-1.0), "E must be > 0"),
    (dict(modes=-1), "modes must be an integer >= 0"),
])
def test_bad_parameters_name_the_rule(kw, message):
    with pytest.raises(ValueError, match=message):
        FeBlockParams(**kw)


def test_fe_block_study_quick(tmp_path, quick_study):
    """studies/fe_block.py --quick: the paths of two ratios beside the rigid block's (the stiff radial
    net, 100, keeps the bottom on its circle, the soft one, 0.01, lets it out), the speed-against-error
    table with the full mesh as its zero, the report and the figure."""
    from exu_aniso.util.output import read_table
    quick_study("fe_block", tmp_path, timeout=HANG_S)
    P = read_table(tmp_path / "paths.csv")
    steer = dict(zip(P["eps_r/eps_phi [-]"], P["steer_end [m]"]))
    assert steer[100.0] > 0.0 > steer[0.01]
    C = read_table(tmp_path / "convergence.csv")
    assert 0.0 in C["path_error [m]"] and all(w > 0.0 for w in C["solve_wall [s]"])
    assert (tmp_path / "fe_block.png").stat().st_size > 10000 and "Regenerate" in (tmp_path / "report.md").read_text()


def test_the_rigid_block_under_the_same_drive_on_both_engines():
    """The stiff limit's model (rigid_block: the block scene with the drive's dashpot and ramp, which
    only this scene uses) is the same on Exudyn and the reference engine: the path to 1e-9 m, the
    drive's force to 1e-6 of its largest value; the ledger closes (eps_r = eps_phi: no hypo-elastic
    part) and its work is the drive's."""
    from exu_aniso.models.block import RunBlock
    from exu_aniso.scenes.block import simulate_block
    from exu_aniso.scenes.fe_block import rigid_block
    b = rigid_block(FeBlockParams(eps_n=1e5, eps_r=1e4, eps_phi=1e4, **SHORT))
    assert b.drive_damping > 0.0 and b.drive_ramp > 0.0
    a, r = RunBlock(b), simulate_block(b)
    ta, tr = a.trajectory, r.trajectory
    assert np.hypot(np.asarray(ta["x"]) - tr["x"], np.asarray(ta["y"]) - tr["y"]).max() < 1e-9
    F = np.asarray(tr["drive_force"])
    assert np.abs(np.asarray(ta["drive_force"]) - F).max() < 1e-6 * np.abs(F).max()
    assert a.summary["energy"]["residual"] < 1e-6 and r.summary["energy"]["residual"] < 1e-6


def test_fe_cost_study_quick(tmp_path, quick_study):
    """studies/fe_cost.py --quick: the cost of a step after an abrupt press on 3 and 4 cells beside
    the estimate the scene checks (exu_aniso.fe.cost); the nodes and modes are the mesh's and the
    basis's. (A timing study: the figures are printed, not checked.)"""
    from exu_aniso.util.output import read_table
    quick_study("fe_cost", tmp_path)
    T = read_table(tmp_path / "fe_cost.csv")
    assert list(T["case [-]"]) == ["cells=3", "cells=4"]
    assert T["nodes [-]"] == [64, 125] and T["modes [-]"] == [48, 75]
    assert min(T["per_step [s]"]) > 0.0 and min(T["estimate [s]"]) > 0.0
