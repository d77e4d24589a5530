"""The fe_block scene (exu_aniso.scenes.fe_block, exu_aniso.models.fe_block): an elastic block on the
polar-orthotropic plane, its top face pressed and moved, its bottom nodes in contact.

Oracles: the stiff limit (as E grows the block's normal force and its bottom's path approach the
rigid block's, computed by scenes.fe_block.rigid_limit without any multibody engine, like 1/E); the
energy ledger with the strain energy, the drive's springs and the damping (closes like the rigid
block's: polar B's hypo-elastic part only; to 1e-6 with B isotropic); the reduced body (Craig-Bampton
modes of the faces) against the full one; the parameters' rules."""
import numpy as np
import pytest

pytest.importorskip("exudyn")
pytest.importorskip("skfem")

from exu_aniso.models.fe_block import RunFeBlock  # noqa: E402
from exu_aniso.scenes.fe_block import FeBlockParams, drive, rigid_limit  # noqa: E402
from _suite import HANG_S

SHORT = dict(cells=2, t_end=0.6, t_press=0.1, travel=0.02)


def _end_force(res):
    tr = res.trajectory
    return np.array([tr["force_x"][-1], tr["force_y"][-1], tr["force_z"][-1]])


def test_the_stiff_limit_is_the_rigid_block():
    """A contact ten times softer than the default (eps_n 1e5 N/m in all) against E = 1e6, 1e7, 1e8 Pa
    (E size / eps_n = 1, 10, 100): the drive's force at the end approaches the rigid limit's (the
    law stepped along the prescribed motion) and the bottom centre's largest distance from the top's
    path falls, both like 1/E once E size >> eps_n (measured: force 0.51, 0.094, 0.0105 of |F|; path
    1.4e-4, 2.7e-5, 3.0e-6 m)."""
    force, path = [], []
    for E in (1e6, 1e7, 1e8):
        p = FeBlockParams(E=E, eps_n=1e5, eps_r=1e4, eps_phi=1e2, stiffness_damping=0.0, **SHORT)
        res = RunFeBlock(p)
        limit = rigid_limit(p)
        F = _end_force(res)
        assert res.summary["energy_ok"]
        force.append(np.abs(F + limit["force"][-1]).max() / np.abs(limit["force"][-1]).max())
        tr = res.trajectory
        path.append(np.hypot(tr["x_bottom"] - tr["x_top"], tr["y_bottom"] - tr["y_top"]).max())
    assert force[0] > force[1] > force[2] and force[2] < 0.02, force
    assert 7.0 < force[1] / force[2] < 11.0, force
    assert 7.0 < path[1] / path[2] < 11.0 and path[0] > path[1], path


def test_the_ledger_closes_with_strain_energy():
    """The default material on the short run: polar B (eps_r 100 eps_phi) leaves its hypo-elastic part
    (below 1e-2, as the rigid block's); with eps_r = eps_phi the adhesion is a constant isotropic B and
    the books close to the Newton tolerance: the drive's work = kinetic + strain + the springs' + the
    contact's stored energy + friction's and the damping's dissipation."""
    res = RunFeBlock(FeBlockParams(**SHORT))
    assert res.summary["energy_ok"] and res.summary["energy"]["residual"] < 1e-2
    assert res.summary["strain_energy_end"] > 0.0 and res.summary["energy"]["work_in"] > 0.0
    iso = RunFeBlock(FeBlockParams(eps_r=1e5, eps_phi=1e5, **SHORT))
    assert iso.summary["energy"]["residual"] < 1e-6, iso.summary["energy"]
    tr = iso.trajectory
    assert np.all(np.diff(tr["dissipated_energy"]) >= -1e-12)


def test_the_drive_and_its_force():
    """The top follows its prescribed path exactly (the trajectory's x_top, y_top are the drive's);
    the drive presses (F_z < 0 on the top face) with the contact's normal force, within the springs'
    stretch; the bottom nodes slide or stick (their shares add up to at most 1)."""
    p = FeBlockParams(**SHORT)
    res = RunFeBlock(p)
    tr = res.trajectory
    u, _ = drive(p, tr["t"])
    np.testing.assert_allclose(tr["x_top"], p.x0 + u[:, 0])
    np.testing.assert_allclose(tr["y_top"], p.y0 + u[:, 1])
    assert tr["force_z"][-1] < 0.0
    assert np.all(np.asarray(tr["stick_fraction"]) + tr["slip_fraction"] <= 1.0 + 1e-12)
    assert res.summary["y_bottom_end"] == pytest.approx(p.y0 + p.travel, abs=0.1 * p.travel)


def test_reduced_equals_full_with_the_faces_static_modes():
    """One cell: Craig-Bampton's static modes of the two faces span every deformation of the mesh, so
    the reduced body (floating frame + 18 modes) is the full one but for the frame's
    exact rotation and its damping on the modal coordinates: normal force within 0.2 %, the path within
    1e-3 of the travel, the tangential forces within 3 % of their largest value (measured 0.11 %,
    4.6e-4, 2.1 %). The 2.1 % is a shift in time: F_y drops fast at t = 0.416 s (16.7 to 12.7 N in
    10 ms) and the two bodies' drops are a millisecond or two apart, not of different size: at dt / 4
    the gap is 2.3 %, 0.8 % with the reduced body's trace shifted by 1.5 ms; with the load twice as
    slow 2.2 %, 0.33 % shifted by 2 ms; without Rayleigh damping the two vibrate apart (45 %)."""
    out = {}
    for model in ("full", "reduced"):
        out[model] = RunFeBlock(FeBlockParams(model=model, **dict(SHORT, cells=1))).trajectory
    a, b = out["full"], out["reduced"]
    assert len(a["t"]) == len(b["t"])
    rel = {k: np.abs(np.asarray(a[k]) - b[k]).max() / np.abs(a[k]).max() for k in ("force_x", "force_y", "force_z")}
    assert rel["force_z"] < 2e-3 and rel["force_x"] < 0.03 and rel["force_y"] < 0.03, rel
    path = np.hypot(np.asarray(a["x_bottom"]) - b["x_bottom"], np.asarray(a["y_bottom"]) - b["y_bottom"]).max()
    assert path < 1e-3 * 0.02, path


@pytest.mark.parametrize("kw,message", [
    (dict(nu=0.5), r"nu must lie in \(-1, 0.5\)"),
    (dict(press=0.06), "press must be < size / 2"),
    (dict(t_press=1.2), "t_press must be < t_end"),
    (dict(model="reduced", basis="eigenmodes", modes=0), "modes must be >= 1"),
    (dict(cells=13), "cells must be <= 12"),
    (dict(E=-1.0), "E must be > 0"),
    (dict(modes=-1), "modes must be an integer >= 0"),
])
def test_bad_parameters_name_the_rule(kw, message):
    with pytest.raises(ValueError, match=message):
        FeBlockParams(**kw)


def test_fe_block_study_quick(tmp_path, quick_study):
    """studies/fe_block.py --quick: the paths of two ratios (the stiff radial net, 100, pulls the bottom
    towards the origin, the soft one, 0.1, lets it out), the speed-against-error table with the finest
    full body as its zero, the report and the figure."""
    from exu_aniso.util.output import read_table
    quick_study("fe_block", tmp_path, timeout=HANG_S)
    P = read_table(tmp_path / "paths.csv")
    steer = dict(zip(P["eps_r/eps_phi [-]"], P["steer_end [m]"]))
    assert steer[100.0] > 0.0 > steer[0.1]
    C = read_table(tmp_path / "convergence.csv")
    finest = C["body [-]"].index("full, 2 cells")
    assert C["steer_error [m]"][finest] == 0.0 and all(w > 0.0 for w in C["solve_wall [s]"])
    assert (tmp_path / "fe_block.png").stat().st_size > 10000 and "Regenerate" in (tmp_path / "report.md").read_text()
