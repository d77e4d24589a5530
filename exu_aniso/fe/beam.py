"""Linear shear-deformable (Timoshenko) beam finite elements for a straight round shank bending across
its axis: the matrices only (no Exudyn here; the loosening scene's model script adds them as one
``ObjectGenericODE2``).

One element of length h bends in one plane with the coordinates (w1, psi1, w2, psi2): the deflections
w [m] across the axis and the cross-sections' rotations psi [rad] (psi = w' without shear). Its
stiffness is the exact one of the Timoshenko beam with no load between the nodes (the element of
Przemieniecki's "Theory of Matrix Structural Analysis", 1968, section 5.6, with
Phi = 12 E I / (kappa G A h^2)): a beam loaded at its nodes only, as a shank is by its head and its
nut, is solved exactly by any number of elements. Its mass is the consistent one of the cubic (Euler-
Bernoulli) interpolation of w, with the rotary inertia of the cross-sections; it converges to the
beam's eigenfrequencies as the elements shrink (tests/test_fe_beam.py).

``guided_shank`` assembles a shank clamped at its head and guided at its other end (that end shifts
across the axis but does not turn, as a nut clamped onto a plate holds it), bending in both planes
through the axis: its coordinates are, plane by plane (x, then y), the inner nodes' (w, psi) from the
head on and the guided end's w.
"""
from __future__ import annotations

import math
from typing import NamedTuple

import numpy as np

from exu_aniso.util.validation import check_integer, check_positive


class RoundSection(NamedTuple):
    """A solid round section's constants (``round_section``)."""
    bending_stiffness: float   # E I [N m^2]
    shear_stiffness: float     # kappa G A [N], kappa Cowper's shear coefficient of a solid circle
    mass_per_length: float     # rho A [kg/m]
    rotary_inertia: float      # rho I [kg m], the cross-sections' rotary inertia per length


def round_section(youngs_modulus, poissons_ratio, diameter, density):
    """The RoundSection of a solid round bar: youngs_modulus E [Pa], poissons_ratio nu in [0, 0.5),
    diameter d [m], density rho [kg/m^3]; I = pi d^4 / 64, A = pi d^2 / 4, G = E / (2 (1 + nu)) and
    Cowper's kappa = 6 (1 + nu) / (7 + 6 nu) (0.886 at nu = 0.3)."""
    for name, v in (("youngs_modulus", youngs_modulus), ("diameter", diameter), ("density", density)):
        check_positive(name, v)
    if not (math.isfinite(poissons_ratio) and 0.0 <= poissons_ratio < 0.5):
        raise ValueError(f"poissons_ratio must lie in [0, 0.5); got {poissons_ratio!r}")
    area, inertia = math.pi * diameter ** 2 / 4.0, math.pi * diameter ** 4 / 64.0
    kappa = 6.0 * (1.0 + poissons_ratio) / (7.0 + 6.0 * poissons_ratio)
    shear_modulus = youngs_modulus / (2.0 * (1.0 + poissons_ratio))
    return RoundSection(youngs_modulus * inertia, kappa * shear_modulus * area, density * area, density * inertia)


def element_matrices(section, h):
    """The element's mass and stiffness matrices (4, 4) on (w1, psi1, w2, psi2) (module docstring), of
    length h [m]; section a RoundSection (shear_stiffness inf: the Euler-Bernoulli element)."""
    EI, kGA, rhoA, rhoI = section
    Phi = 12.0 * EI / (kGA * h * h)
    K = EI / ((1.0 + Phi) * h ** 3) * np.array([
        [12.0, 6.0 * h, -12.0, 6.0 * h],
        [6.0 * h, (4.0 + Phi) * h * h, -6.0 * h, (2.0 - Phi) * h * h],
        [-12.0, -6.0 * h, 12.0, -6.0 * h],
        [6.0 * h, (2.0 - Phi) * h * h, -6.0 * h, (4.0 + Phi) * h * h]])
    translation = rhoA * h / 420.0 * np.array([
        [156.0, 22.0 * h, 54.0, -13.0 * h],
        [22.0 * h, 4.0 * h * h, 13.0 * h, -3.0 * h * h],
        [54.0, 13.0 * h, 156.0, -22.0 * h],
        [-13.0 * h, -3.0 * h * h, -22.0 * h, 4.0 * h * h]])
    rotation = rhoI / (30.0 * h) * np.array([
        [36.0, 3.0 * h, -36.0, 3.0 * h],
        [3.0 * h, 4.0 * h * h, -3.0 * h, -h * h],
        [-36.0, -3.0 * h, 36.0, -3.0 * h],
        [3.0 * h, -h * h, -3.0 * h, 4.0 * h * h]])
    return translation + rotation, K


def assemble(section, length, elements):
    """The mass and stiffness matrices (2 (elements + 1),) * 2 of a beam of ``length`` [m] cut into
    ``elements`` equal elements, bending in one plane: coordinates (w, psi) node by node from x = 0."""
    check_positive("length", length)
    elements = check_integer("elements", elements, minimum=1)
    n = 2 * (elements + 1)
    M, K = np.zeros((n, n)), np.zeros((n, n))
    Me, Ke = element_matrices(section, length / elements)
    for e in range(elements):
        M[2 * e:2 * e + 4, 2 * e:2 * e + 4] += Me
        K[2 * e:2 * e + 4, 2 * e:2 * e + 4] += Ke
    return M, K


class ShankMatrices(NamedTuple):
    """A shank's coordinates q across the axis: M q'' + D q' + K q = f, its guided end's x and y the
    coordinates ``tip`` (two indices)."""
    mass: np.ndarray        # (m, m) [kg, kg m, kg m^2 by coordinate]
    damping: np.ndarray     # (m, m)
    stiffness: np.ndarray   # (m, m)
    tip: tuple              # (index of the guided end's x, of its y)


def guided_shank(section, length, elements, damping_time=0.0):
    """The ShankMatrices of a shank clamped at x = 0 and guided at x = length [m] (module docstring),
    bending in the two planes through its axis, with stiffness-proportional damping D = damping_time K
    (damping_time [s] >= 0)."""
    if not (math.isfinite(damping_time) and damping_time >= 0.0):
        raise ValueError(f"damping_time must be a finite number >= 0 s; got {damping_time!r}")
    M, K = assemble(section, length, elements)
    free = np.arange(2, M.shape[0] - 1)               # not the head's (w, psi), not the guided end's psi
    m = free.size
    M2, K2 = np.zeros((2 * m, 2 * m)), np.zeros((2 * m, 2 * m))
    for plane in (0, 1):
        s = slice(plane * m, (plane + 1) * m)
        M2[s, s], K2[s, s] = M[np.ix_(free, free)], K[np.ix_(free, free)]
    return ShankMatrices(M2, damping_time * K2, K2, (m - 1, 2 * m - 1))


def tip_stiffness(shank):
    """The lateral stiffness [N/m] of a ShankMatrices' guided end along x: its stiffness matrix
    condensed onto that coordinate."""
    K, i = shank.stiffness, shank.tip[0]
    rest = np.delete(np.arange(K.shape[0]), i)
    return K[i, i] - K[i, rest] @ np.linalg.solve(K[np.ix_(rest, rest)], K[rest, i])
