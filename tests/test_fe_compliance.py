"""exu_aniso.fe.compliance_share: the share of the contact nodes' static compliance a mode basis keeps,
against its oracles: a basis spanning every coordinate keeps all of it, so do the static modes of the
contact nodes (they span K^-1 P); a few eigenmodes keep less, more with every mode added
(Rayleigh-Ritz); the share does not depend on how the span is written (Psi -> Psi A); on a clamped
shank and on a free block (rigid motion to the frame)."""
import numpy as np
import pytest
import scipy.linalg

pytest.importorskip("skfem")

from exu_aniso.fe import block_mesh, compliance_share, shank_mesh   # noqa: E402


@pytest.fixture(scope="module")
def shank():
    m = shank_mesh(0.005, 0.0025, 0.02, (1, 8, 3), E=3e9, nu=0.3, rho=1150.0)
    return m, m.node_sets["thread"], m.node_sets["head"]


@pytest.fixture(scope="module")
def block():
    return block_mesh((0.1, 0.1, 0.1), (2, 2, 2), E=1e6, nu=0.3, rho=1000.0)


def _free_free_modes(mesh, count):
    """The count lowest elastic free-free eigenmodes (the six rigid ones skipped)."""
    _, V = scipy.linalg.eigh(mesh.stiffness.toarray(), mesh.mass.toarray(), subset_by_index=[6, 5 + count])
    return V


def test_a_complete_basis_and_the_static_modes_keep_all_of_the_clamped_compliance(shank):
    m, thread, head = shank
    assert compliance_share(m, m.clamped_modes(head, None), thread, head) == pytest.approx(1.0, abs=1e-10)
    assert compliance_share(m, m.craig_bampton_modes(head, thread, 0), thread, head) == pytest.approx(1.0, abs=1e-10)
    assert compliance_share(m, m.craig_bampton_modes(head, thread, 5), thread, head) == pytest.approx(1.0, abs=1e-10)


def test_eigenmodes_keep_a_share_below_one_growing_with_every_mode(shank):
    m, thread, head = shank
    shares = [compliance_share(m, m.clamped_modes(head, k), thread, head) for k in (1, 3, 6, 12, 24, 48)]
    assert all(0.0 < s < 1.0 - 1e-3 for s in shares), shares
    assert all(b > a for a, b in zip(shares, shares[1:])), shares


def test_the_share_is_the_spans_not_the_columns(shank):
    """Psi -> Psi A (A invertible) and a column repeated leave the share as it was."""
    m, thread, head = shank
    Psi = m.clamped_modes(head, 10)
    A = np.random.default_rng(3).normal(size=(10, 10)) + 3.0 * np.eye(10)
    s = compliance_share(m, Psi, thread, head)
    assert compliance_share(m, Psi @ A, thread, head) == pytest.approx(s, rel=1e-9)
    assert compliance_share(m, np.hstack([Psi, Psi[:, :2]]), thread, head) == pytest.approx(s, rel=1e-9)


def test_a_free_body_with_its_rigid_motion_removed(block):
    """The free block (no fixed nodes): every coordinate, or the bottom nodes' static modes with
    their rigid motion removed (ElasticMesh.without_rigid_motion, the fe_block scene's reduced basis),
    keep all of the bottom's compliance; free-free eigenmodes keep less, more with every mode; a
    rigid-body mode adds nothing."""
    m, bottom = block, block.node_sets["bottom"]
    assert compliance_share(m, np.eye(m.number_of_coordinates), bottom) == pytest.approx(1.0, abs=1e-9)
    static = np.zeros((m.number_of_coordinates, 3 * len(bottom)))
    static[(3 * bottom[:, None] + np.arange(3)).ravel(), np.arange(static.shape[1])] = 1.0
    interior = np.setdiff1d(np.arange(m.number_of_nodes), bottom)
    i = (3 * interior[:, None] + np.arange(3)).ravel()
    b = (3 * bottom[:, None] + np.arange(3)).ravel()
    K = m.stiffness.toarray()
    static[i] = -np.linalg.solve(K[np.ix_(i, i)], K[np.ix_(i, b)])
    assert compliance_share(m, m.without_rigid_motion(static), bottom) == pytest.approx(1.0, abs=1e-9)
    shares = [compliance_share(m, _free_free_modes(m, k), bottom) for k in (3, 6, 12, 24)]
    assert all(0.0 < s < 1.0 for s in shares) and all(b > a for a, b in zip(shares, shares[1:])), shares
    with_rigid = np.hstack([_free_free_modes(m, 6), m.rigid_body_modes()])
    assert compliance_share(m, with_rigid, bottom) == pytest.approx(shares[1], rel=1e-9)


@pytest.mark.parametrize("bad, rule", [("shape", "basis must be"), ("fixed", "vanish at fixed_nodes"),
                                       ("nodes", "contact_nodes")])
def test_bad_input_names_the_rule(shank, bad, rule):
    m, thread, head = shank
    Psi = m.clamped_modes(head, 4)
    args = {"shape": (m, Psi[:-3], thread, head), "fixed": (m, Psi + 1.0, thread, head),
            "nodes": (m, Psi, [m.number_of_nodes], head)}[bad]
    with pytest.raises(ValueError, match=rule):
        compliance_share(*args)
