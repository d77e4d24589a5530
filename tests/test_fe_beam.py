"""The shank's Timoshenko beam elements (exu_aniso.fe.beam).

Oracles, all closed forms of beam theory:
* a cantilever under a tip force deflects by P L^3 / (3 E I) + P L / (kappa G A), whatever the number
  of elements (the element is exact for a beam loaded at its nodes);
* the clamped-guided shank's end stiffness equals ``threads.guided_shear_beam_stiffness``, and with no
  shear compliance the Euler-Bernoulli ``threads.guided_beam_stiffness``;
* the first eigenfrequency of the clamped-guided Euler-Bernoulli beam, (beta L)^2 sqrt(E I / (rho A
  L^4)) with beta L the root of tan x + tanh x = 0, is approached at the consistent cubic mass's
  fourth order;
* the matrices are symmetric, M positive definite, D = damping_time K.
"""
import math

import numpy as np
import pytest
from scipy.optimize import brentq

from exu_aniso.fe.beam import RoundSection, assemble, guided_shank, round_section, tip_stiffness
from exu_aniso.scenes import threads

E, NU, D, RHO, L = 2.1e11, 0.3, 8.6e-3, 7850.0, 0.03     # the M10 shank of the loosening scene's joint


@pytest.mark.parametrize("elements", [1, 3, 8])
def test_a_cantilever_deflects_by_bending_and_shear(elements):
    s = round_section(E, NU, D, RHO)
    _, K = assemble(s, L, elements)
    free = np.arange(2, K.shape[0])                  # the head clamped
    f = np.zeros(free.size)
    f[-2] = 1e3                                      # P at the free end's w
    w = np.linalg.solve(K[np.ix_(free, free)], f)[-2]
    assert w == pytest.approx(1e3 * L ** 3 / (3.0 * s.bending_stiffness) + 1e3 * L / s.shear_stiffness, rel=1e-12)


@pytest.mark.parametrize("elements", [1, 2, 5])
def test_the_guided_shank_has_the_guided_beams_stiffness(elements):
    s = round_section(E, NU, D, RHO)
    assert tip_stiffness(guided_shank(s, L, elements)) == pytest.approx(
        threads.guided_shear_beam_stiffness(s, L), rel=1e-12)
    rigid_in_shear = s._replace(shear_stiffness=math.inf)
    assert tip_stiffness(guided_shank(rigid_in_shear, L, elements)) == pytest.approx(
        threads.guided_beam_stiffness(E, D, L), rel=1e-12)
    assert threads.guided_shear_beam_stiffness(s, L) < threads.guided_beam_stiffness(E, D, L)


def test_the_first_eigenfrequency_converges_at_fourth_order():
    s = RoundSection(E * math.pi * D ** 4 / 64.0, math.inf, RHO * math.pi * D ** 2 / 4.0, 0.0)   # Euler-Bernoulli
    beta_L = brentq(lambda x: math.tan(x) + math.tanh(x), 2.0, 3.0)
    exact = beta_L ** 2 * math.sqrt(s.bending_stiffness / (s.mass_per_length * L ** 4))
    errors = []
    for n in (2, 4, 8):
        shank = guided_shank(s, L, n)
        m = shank.mass.shape[0] // 2                 # one plane
        lam = np.linalg.eigvals(np.linalg.solve(shank.mass[:m, :m], shank.stiffness[:m, :m])).real
        errors.append(math.sqrt(lam.min()) / exact - 1.0)
    assert all(e > 0 for e in errors)                # consistent mass: from above
    orders = [math.log2(a / b) for a, b in zip(errors, errors[1:])]
    assert min(orders) > 3.5, (errors, orders)
    assert errors[-1] < 1e-5


def test_the_matrices_are_symmetric_and_the_mass_positive():
    shank = guided_shank(round_section(E, NU, D, RHO), L, 4, damping_time=4e-5)
    for A in shank:
        if isinstance(A, np.ndarray):
            assert np.array_equal(A, A.T)
    assert np.linalg.eigvalsh(shank.mass).min() > 0.0 and np.linalg.eigvalsh(shank.stiffness).min() > 0.0
    assert np.array_equal(shank.damping, 4e-5 * shank.stiffness)
    assert shank.tip == (6, 13)                      # 3 inner nodes' (w, psi), the end's w; x then y


@pytest.mark.parametrize("call, rule", [
    (lambda: round_section(E, 0.5, D, RHO), r"poissons_ratio must lie in \[0, 0.5\)"),
    (lambda: round_section(-E, NU, D, RHO), "youngs_modulus"),
    (lambda: guided_shank(round_section(E, NU, D, RHO), L, 0), "elements must be an integer >= 1"),
    (lambda: guided_shank(round_section(E, NU, D, RHO), L, 2, damping_time=-1.0), "damping_time must be"),
    (lambda: guided_shank(round_section(E, NU, D, RHO), float("nan"), 2), "length"),
])
def test_bad_beam_input_is_refused(call, rule):
    with pytest.raises(ValueError, match=rule):
        call()
