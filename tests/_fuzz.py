"""What the property-based fuzz tests share (tests/test_fuzz_surfaces.py: the surfaces and the
tensor fields on them; tests/test_fuzz_law.py: the return maps and the contact set): the hypothesis
profile, the strategies that generate their cases, the property registry and its runs.

Every property is an oracle (geometry, invariants, finite differences, thermodynamics), checked on
generated cases inside physically meaningful ranges that include the hard corners: anisotropy ratios
up to 1e4 in B and 100 in mu, |N| down to 1e-12 (and 0), trial tractions up to 1e6 times the
friction limit, points close to the polar origin and the cylinder axis, cylinder axes in any
direction.

Default run: ``FUZZ_EXAMPLES`` cases per property (derandomized, no example database: reproducible
in CI). ``pytest -m slow tests/test_fuzz_surfaces.py tests/test_fuzz_law.py -s`` runs
``SLOW_EXAMPLES`` per property (>= 10^4 in total) and prints one line per property with its number
of checked cases.
"""
import math

import numpy as np
from hypothesis import HealthCheck, assume, given, settings
from hypothesis import strategies as st

from exu_aniso import Adhesion, Friction
from exu_aniso.geometry import Cylinder, Plane

FUZZ_EXAMPLES = 200
SLOW_EXAMPLES = 1000
# the slow run's >= 10^4 checked cases over the 12 properties of the two files, as a mean per
# property that each file's slow test asserts (so the two together check >= 10^4)
SLOW_MEAN_CHECKED = 10_000 / 12
settings.register_profile("exu_aniso-fuzz", deadline=None, derandomize=True, database=None, print_blob=False,
                          suppress_health_check=[HealthCheck.too_slow, HealthCheck.filter_too_much,
                                                 HealthCheck.data_too_large])

EPS = np.finfo(float).eps


# ----------------------------------------------------------------------------------------------
# strategies

def log_uniform(lo, hi):
    """10**U(lo, hi)."""
    return st.floats(lo, hi, allow_nan=False, allow_infinity=False).map(lambda e: 10.0 ** e)


def unit(lo=-1.0, hi=1.0):
    return st.floats(lo, hi, allow_nan=False, allow_infinity=False)


angles = unit(-math.pi, math.pi)


@st.composite
def directions(draw):
    """Unit 3-vectors: the coordinate axes (both signs) or a random direction."""
    if draw(st.booleans()):
        return np.eye(3)[draw(st.integers(0, 2))] * draw(st.sampled_from([1.0, -1.0]))
    v = np.array([draw(unit()) for _ in range(3)])
    assume(np.linalg.norm(v) > 0.1)
    return v / np.linalg.norm(v)


def orthonormal_pair(a):
    """Two unit vectors completing a to an orthonormal basis (independent of Cylinder's own choice)."""
    t = np.array([1.0, 0.0, 0.0]) if abs(a[0]) < 0.9 else np.array([0.0, 1.0, 0.0])
    u = np.cross(a, t)
    u /= np.linalg.norm(u)
    return u, np.cross(a, u)


@st.composite
def surfaces(draw, kinds=("cartesian", "polar", "inside", "outside")):
    kind = draw(st.sampled_from(kinds))
    if kind in ("cartesian", "polar"):
        return Plane(kind)
    R = draw(log_uniform(-3, 1))
    point = R * np.array([draw(unit()) for _ in range(3)])
    return Cylinder(R, axis_point=point, axis_direction=draw(directions()), side=kind)


@st.composite
def points_near(draw, surface, rel_min=1e-6, gap=None, origin=True):
    """A point (3,) near the surface: on a plane at r >= rel_min from the polar origin (or exactly at
    it for a Cartesian chart if origin), on a cylinder at rho >= rel_min R from the axis;
    gap=(lo, hi): normal gap xi3 / (1 m or R) in [lo, hi]."""
    if isinstance(surface, Plane):
        at_origin = origin and surface.coordinates == "cartesian"
        r = draw(st.one_of(log_uniform(math.log10(rel_min), 1), st.just(0.0) if at_origin else st.nothing()))
        phi = draw(angles)
        z = draw(unit(-1.0, 1.0)) if gap is None else draw(unit(*gap))
        return np.array([r * math.cos(phi), r * math.sin(phi), z])
    R = surface.radius
    a = surface.axes[2]
    u, w = orthonormal_pair(a)
    if gap is None:
        rho = R * draw(st.one_of(log_uniform(math.log10(rel_min), 0), unit(0.5, 3.0)))
    else:
        rho = R * (1.0 + surface.sign * draw(unit(*gap)))
    phi = draw(angles)
    z = R * draw(unit(-10.0, 10.0))
    return surface.axis_point + z * a + rho * (math.cos(phi) * u + math.sin(phi) * w)


def sym_components(l1, l2, theta):
    c, s = math.cos(theta), math.sin(theta)
    return (l1 * c * c + l2 * s * s, (l1 - l2) * c * s, l1 * s * s + l2 * c * c)


@st.composite
def law_inputs(draw, factor=None, N=None):
    """(T_tr, |N|, B, F): B = -(eps_1 e1 e1 + eps_2 e2 e2), eps_1/eps_2 in [1e-4, 1e4]; F from mu_1, mu_2
    with mu_1/mu_2 in [1e-2, 1e2]; T_tr = factor x (friction limit in its direction)."""
    eps1 = draw(log_uniform(0, 6))
    eps2 = eps1 * draw(log_uniform(-4, 4))
    B = tuple(-b for b in sym_components(eps1, eps2, draw(angles)))
    mu1 = draw(log_uniform(-2, 0.3))
    mu2 = mu1 * draw(log_uniform(-2, 2))
    F = sym_components(1.0 / mu1 ** 2, 1.0 / mu2 ** 2, draw(angles))
    if N is None:
        N = draw(st.one_of(st.sampled_from([0.0, 1e-12, 1e-9, 1.0]), log_uniform(-12, 6)))
    if factor is None:
        factor = draw(st.one_of(log_uniform(-3, 6), unit(0.5, 2.0), st.sampled_from([1e6, 1.0 + 1e-9, 0.0])))
    psi = draw(angles)
    d = np.array([math.cos(psi), math.sin(psi)])
    limit = max(N, 1e-300) / math.sqrt(quad(F, d))
    return np.array(d * factor * limit), float(N), B, F


def quad(S, x):
    return S[0] * x[0] * x[0] + 2.0 * S[1] * x[0] * x[1] + S[2] * x[1] * x[1]


def sym_matrix(S):
    return np.array([[S[0], S[1]], [S[1], S[2]]])


def surface_kind_of(surface):
    return "plane" if isinstance(surface, Plane) else "cylinder"


@st.composite
def fields(draw, kind, surface_kind, patterns=None):
    """(field, (lambda_1, lambda_2) of the positive tensor, pattern, angle, core_radius)."""
    if kind == "adhesion":
        v1 = draw(log_uniform(0, 6))
        v2 = v1 * draw(log_uniform(-4, 4))
        lam = (v1, v2)
        make = Adhesion
    else:
        v1 = draw(log_uniform(-2, 0.3))
        v2 = v1 * draw(log_uniform(-2, 2))
        lam = (1.0 / v1 ** 2, 1.0 / v2 ** 2)
        make = Friction
    if patterns is None:
        patterns = ["isotropic", "orthotropic"] + (["polar"] if surface_kind == "plane" else ["spiral"])
    pattern = draw(st.sampled_from(patterns))
    if pattern == "isotropic":
        return make.isotropic(v1), (lam[0], lam[0]), pattern, 0.0, 0.0
    if pattern == "orthotropic":
        angle = draw(angles)
        return make.orthotropic(v1, v2, angle), lam, pattern, angle, 0.0
    if pattern == "spiral":
        alpha = draw(unit(-1.5, 1.5))
        return make.spiral(v1, v2, alpha), lam, pattern, alpha, 0.0
    rc = draw(st.one_of(st.just(0.0), log_uniform(-4, -1)))
    return make.polar(v1, v2, core_radius=rc), lam, pattern, 0.0, rc


# ----------------------------------------------------------------------------------------------
# property registry and runs

def property_registry():
    """(properties, prop): a test module's registry {name: (strategy, check, first line of its
    docstring)} and the decorator ``@prop(name, strategy)`` that registers a check in it."""
    properties = {}

    def prop(name, strategy):
        def deco(f):
            properties[name] = (strategy, f, f.__doc__.strip().splitlines()[0])
            return f
        return deco
    return properties, prop


def run_property(properties, name, max_examples):
    """Run one property of a registry (property_registry) with hypothesis; returns (cases checked,
    cases generated): a generated case is skipped (hypothesis.assume) where the oracle does not
    apply, e.g. within the margin of Phi = 0."""
    strategy, check, _ = properties[name]
    count = [0, 0]

    @settings(settings.get_profile("exu_aniso-fuzz"), max_examples=max_examples)
    @given(strategy)
    def run(case):
        count[1] += 1
        check(*case)
        count[0] += 1

    run()
    return tuple(count)


def check_property(properties, name):
    """The default run of one property: FUZZ_EXAMPLES generated cases, a quarter of them usable."""
    n, generated = run_property(properties, name, FUZZ_EXAMPLES)
    assert n >= FUZZ_EXAMPLES // 4, f"{name}: only {n} of {generated} generated cases were usable"


def check_many_cases(properties):
    """The slow run of a registry: SLOW_EXAMPLES generated cases per property, printed one line a
    property (run pytest with -s to see them); at least SLOW_MEAN_CHECKED checked cases per property
    on average."""
    total = 0
    for name, (_, _, what) in properties.items():
        n, generated = run_property(properties, name, SLOW_EXAMPLES)
        total += n
        print(f"fuzz {name:36s} {n:5d} checked of {generated:5d} generated: {what}")
        assert n >= SLOW_EXAMPLES // 4
    print(f"fuzz total {total} checked cases over {len(properties)} properties")
    assert total >= SLOW_MEAN_CHECKED * len(properties)
