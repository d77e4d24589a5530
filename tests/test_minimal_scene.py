"""A minimal scene built from the package's public interfaces only, the worked example of
docs/adding_a_scene.md: a mass point pressed onto the plane z = 0 by a normal load and pushed along
+x by a constant force, with isotropic adhesion and friction, on both engines (the reference
integrator through a BodyModel of its own, Exudyn through mbs.CreateAnisotropicContact on a
MassPoint).

Oracles (closed forms of a point on a flat plane; its normal and tangential motions do not couple
there, so each holds exactly in the model):

* sliding (push > mu load): the point sticks on the adhesion spring, x = push / eps_t (1 - cos w t)
  with w = sqrt(eps_t / m), until the spring's force reaches mu load, then slides; from then on
  friction is mu N against the motion and vx grows at a = (push - mu load) / m. The trapezoidal rule
  integrates a constant acceleration exactly, so a straight-line fit of vx meets it to Newton's
  tolerance. The point stays on the line y = 0, its normal force stays the load, and friction
  dissipates mu N per metre slid.
* at rest (push < mu load, both dashpots on): the point never slides; it comes to rest at the
  penetration load / eps_n and the tangential displacement push / eps_t, from a start at half the
  static penetration, and the dashpots dissipate what the springs did not store.
* energy: the ledger (work of the constant force = kinetic + stored + dissipated) closes.
* the engines: both take the same steps with the same trapezoidal rule, so their states agree.

Every python code block of docs/adding_a_scene.md is this file's code or a verbatim excerpt of the
package (``test_the_page_shows_real_code``), so the page cannot drift.
"""
from __future__ import annotations

import dataclasses
import importlib.util
import math
import re
from pathlib import Path

import numpy as np
import pytest

from exu_aniso import HISTORY_FIELDS, RETURN_MAPS, SLIP, STICK, Adhesion, ContactLaw, Friction, Plane
from exu_aniso.engines import energy
from exu_aniso.engines.reference import BodyModel, jacobian_check, run
from exu_aniso.engines.result import Result
from exu_aniso.scenes.base import LEDGER_COLUMNS, SOLVERS, SceneParams, energy_ledger, scene_parameters
from exu_aniso.scenes.scene import Scene

ROOT = Path(__file__).resolve().parent.parent
PAGE = ROOT / "docs" / "adding_a_scene.md"
HAVE_EXUDYN = importlib.util.find_spec("exudyn") is not None
STATUS = HISTORY_FIELDS.index("status")
NORMAL = HISTORY_FIELDS.index("normal")


# ----------------------------------------------------------------------------------------------
# the scene: parameters, contact law, initial state, columns

PUSH_PARAMS = {
    "mass": (1.0, "kg", "mass of the point", "> 0"),
    "load": (10.0, "N", "normal load pressing the point onto the plane z = 0", "> 0"),
    "push": (6.0, "N", "constant force along +x", ">= 0"),
    "press0": (1.0, "-", "penetration at t = 0, as a share of the static one load / eps_n", "> 0"),
    "eps_n": (1e5, "N/m", "normal penalty stiffness", "> 0"),
    "eps_t": (1e4, "N/m", "isotropic adhesion (sticking) stiffness", "> 0"),
    "mu": (0.3, "-", "isotropic friction coefficient", "> 0"),
    "return_map": ("exact", "-", "sliding return map", RETURN_MAPS),
    "normal_damping": (0.0, "N s/m", "normal contact dashpot", ">= 0"),
    "tangential_damping": (0.0, "N s/m", "tangential dashpot parallel to friction while loaded", ">= 0"),
    "t_end": (0.5, "s", "simulated time", "> 0"),
    "dt": (1e-3, "s", "time step", "> 0"),
    "solver": ("trapezoidal", "-", "time integrator", SOLVERS),
}


@scene_parameters(PUSH_PARAMS)
class PushParams(SceneParams):
    """Mass point pushed along a plane; see PUSH_PARAMS for units and meaning."""


def push_contact_law(p):
    """The scene's ContactLaw: the plane z = 0 (slave above it), isotropic adhesion and friction."""
    return ContactLaw(Plane(), Adhesion.isotropic(p.eps_t), Friction.isotropic(p.mu),
                      normal_stiffness=p.eps_n, normal_damping=p.normal_damping,
                      tangential_damping=p.tangential_damping, return_map=p.return_map)


def initial_state(p):
    """Position and velocity (3,), (3,) at t = 0: at rest, press0 of the static penetration deep."""
    return np.array([0.0, 0.0, -p.press0 * p.load / p.eps_n]), np.zeros(3)


def applied_force(p):
    """The constant force on the point [N]: the push along +x and the load along -z."""
    return np.array([p.push, 0.0, -p.load])


# trajectory columns (trajectory.csv) -> SI unit, the same keys from every engine
COLUMNS = {"t": "s", "x": "m", "y": "m", "z": "m", "vx": "m/s", "vy": "m/s", "vz": "m/s",
           "normal_force": "N", "status": "-", "slip_distance": "m", "dissipated_energy": "J",
           **LEDGER_COLUMNS}
TITLE_KEYS = ("acceleration", "acceleration_theory")


def finish_trajectory(traj, H):
    """Add the contact's columns from its history H (n, 1, 9): the normal force's magnitude and the
    status (STICK, SLIP, ...)."""
    traj["normal_force"] = -H[:, 0, NORMAL]
    traj["status"] = H[:, 0, STATUS]
    return traj


def push_energy(p, traj, H):
    """The energy ledger of a run (any engine): work of the constant force = kinetic + stored +
    dissipated (changes from t = 0, J); adds the ledger's columns to traj, returns the summary's
    entries."""
    X = np.column_stack([traj["x"], traj["y"], traj["z"]])
    V = np.column_stack([traj["vx"], traj["vy"], traj["vz"]])
    stored, dissipated = energy.contact_energy(push_contact_law(p), X[:, None, :], V[:, None, :], H)
    terms = dict(work_in=(X - X[0]) @ applied_force(p), kinetic=0.5 * p.mass * np.sum(V ** 2, axis=1),
                 potential=np.zeros(len(X)), stored=stored, dissipated=dissipated)
    return energy_ledger(terms, traj, "push run")


def push_closed_forms(p):
    """Sliding (push > mu load): the acceleration (push - mu load) / m [m/s^2] and the time the
    adhesion spring takes to carry mu load [s]; at rest: the tangential displacement push / eps_t [m];
    both: the penetration that carries the load [m]."""
    z_rest = -p.load / p.eps_n
    if p.push > p.mu * p.load:
        return dict(acceleration_theory=(p.push - p.mu * p.load) / p.mass,
                    slip_time_theory=math.acos(1 - p.mu * p.load / p.push) / math.sqrt(p.eps_t / p.mass),
                    x_rest_theory=None, z_rest_theory=z_rest,
                    undefined=dict(x_rest_theory="the point slides"))
    why = f"push = {p.push:g} N <= mu load = {p.mu * p.load:g} N: the point sticks"
    return dict(acceleration_theory=None, slip_time_theory=None, x_rest_theory=p.push / p.eps_t,
                z_rest_theory=z_rest, undefined=dict(acceleration_theory=why, slip_time_theory=why))


def push_summary(traj, p, wall_s, steps, newton_iterations):
    """The end state, the acceleration fitted to vx over the samples that slide after t = 0.1 s
    beside its closed form, and the cost; None with the reason under "undefined"."""
    t, vx = np.asarray(traj["t"]), np.asarray(traj["vx"])
    late = (t >= 0.1) & (np.asarray(traj["status"]) == SLIP)
    theory = push_closed_forms(p)
    undefined = {k: v for k, v in theory["undefined"].items() if k == "acceleration_theory"}
    if late.sum() >= 3:
        acceleration = float(np.polyfit(t[late], vx[late], 1)[0])
    else:
        acceleration = None
        undefined["acceleration"] = f"{late.sum()} samples slide after t = 0.1 s: fewer than 3 to fit"
    return dict(x_end=float(traj["x"][-1]), z_end=float(traj["z"][-1]), vx_end=float(vx[-1]),
                acceleration=acceleration, acceleration_theory=theory["acceleration_theory"],
                slip_distance=float(traj["slip_distance"][-1]),
                dissipated_energy=float(traj["dissipated_energy"][-1]),
                wall_s=float(wall_s), steps=int(steps), newton_iterations=int(newton_iterations),
                undefined=undefined)


def PlotPush(traj, params, fig):
    """trajectory.png: the velocity along the push over time."""
    ax = fig.add_subplot(1, 1, 1)
    ax.plot(traj["t"], traj["vx"])
    ax.set(xlabel="t [s]", ylabel="vx [m/s]")


# ----------------------------------------------------------------------------------------------
# the reference engine: a body model and the run

class PushedPoint(BodyModel):
    """Mass point: q = x (3,) in the plane's frame, v = dx/dt; one contact point at x."""

    n = 3          # coordinates
    K = 1          # contact points

    def __init__(self, p, law):
        self.p, self.law = p, law
        self.mass = np.full(3, p.mass)                   # diagonal of the mass matrix
        self.row_scale = np.ones(3)                      # residual rows are forces: no scaling
        self.dof_scale = np.full(3, p.load / p.eps_n)    # a length of the motion (numerical Jacobian)
        self.q0, self.v0 = initial_state(p)
        self.force = applied_force(p)

    def points0(self, q, v):
        return q[None, :], v[None, :]

    def evaluate(self, q, v, t, H, tangent=True, dt=None):
        st = self.law.evaluate(q[None, :], v[None, :], H, tangent, dt)
        g = st.force[0] + self.force
        if not tangent:
            return g, None, None, st
        return g, st.stiffness[0].copy(), st.damping[0].copy(), st

    def motion(self, q, v):
        return q.copy(), np.eye(3), v.copy(), np.zeros(3)

    def record(self, q, v, t, st):
        return dict(x=q[0], y=q[1], z=q[2], vx=v[0], vy=v[1], vz=v[2])


def simulate_push(p, **options):
    """The scene on the reference engine: a Result with the trajectory (COLUMNS), the summary and
    the ledger. options: of the engine's run (RUN_OPTIONS)."""
    model = PushedPoint(p, push_contact_law(p))
    traj, wall, iters, steps, info, motion, H = run(model, p, floor=1e-6 * p.load, **options)
    finish_trajectory(traj, H)
    summary = push_summary(traj, p, wall, steps, iters)
    summary.update(push_energy(p, traj, H))
    return Result(traj, summary, p, info)


# ----------------------------------------------------------------------------------------------
# the scene, as every engine and the command line see it

class PushScene(Scene):
    """A mass point pushed along a plane (the module docstring)."""

    name = "push"
    Params = PushParams
    columns = COLUMNS
    title_keys = TITLE_KEYS
    law = staticmethod(push_contact_law)
    closed_forms = staticmethod(push_closed_forms)
    summary = staticmethod(push_summary)
    ledger = staticmethod(push_energy)
    plot = staticmethod(PlotPush)
    reference = staticmethod(simulate_push)

    def points(self, p):
        """The one contact point: the mass point itself."""
        return np.zeros((1, 3))


SCENE = PushScene()


# ----------------------------------------------------------------------------------------------
# the Exudyn model script: build, read back, run

def BuildPush(p):
    """The scene as an Exudyn model: a MassPoint under the constant force, one contact set."""
    import exudyn as exu
    from exudyn.itemInterface import SensorNode

    from exu_aniso import RecommendedSimulationSettings

    SC = exu.SystemContainer()
    mbs = SC.AddSystem()
    x0, v0 = initial_state(p)
    oPoint = mbs.CreateMassPoint(referencePosition=x0.tolist(), initialVelocity=v0.tolist(), mass=p.mass)
    mbs.CreateForce(itemNumber=oPoint, loadVector=applied_force(p).tolist())
    contact = mbs.CreateAnisotropicContact(name="pushContact", bodyNumber=oPoint,
                                           localPoints=[[0.0, 0.0, 0.0]], contactLaw=push_contact_law(p),
                                           storeHistory=True, show=False)
    nPoint = mbs.GetObject(oPoint)["nodeNumber"]
    sensors = {name: mbs.AddSensor(SensorNode(nodeNumber=nPoint, storeInternal=True, outputVariableType=ovt))
               for name, ovt in (("sPosition", exu.OutputVariableType.Position),
                                 ("sVelocity", exu.OutputVariableType.Velocity))}
    mbs.Assemble()
    ss, solverType = RecommendedSimulationSettings(p.t_end, p.dt, solver=p.solver)
    return dict(SC=SC, mbs=mbs, simulationSettings=ss, solverType=solverType, contact=contact,
                sensors=sensors)


def ReadPush(model, complete):
    """The trajectory with the reference's keys, the summary's inputs (none) and the ledger's (the
    contact history)."""
    from exu_aniso.engines.exudyn_adapter.runner import HistoryOutputs

    mbs, contact = model["mbs"], model["contact"]
    P = mbs.GetSensorStoredData(model["sensors"]["sPosition"])
    V = mbs.GetSensorStoredData(model["sensors"]["sVelocity"])
    dissipated, slipped, H = HistoryOutputs(mbs, contact)
    traj = dict(t=P[:, 0], x=P[:, 1], y=P[:, 2], z=P[:, 3], vx=V[:, 1], vy=V[:, 2], vz=V[:, 3],
                dissipated_energy=dissipated, slip_distance=slipped)
    return finish_trajectory(traj, H), {}, dict(H=H)


def push_model():
    """The model script's MODEL (a function here, so that the module imports without Exudyn)."""
    from exu_aniso.engines.exudyn_adapter.runner import ModelScript

    return ModelScript(SCENE, BuildPush, ReadPush)


# ----------------------------------------------------------------------------------------------
# the cases and the runs (each run once per module)

SLIDING = PushParams()                                   # push 6 N > mu load = 3 N
AT_REST = PushParams(push=1.0, press0=0.5,               # push 1 N < 3 N; dashpots about half critical
                     normal_damping=300.0, tangential_damping=100.0)
CASES = {"sliding": SLIDING, "at_rest": AT_REST}
NEEDS_EXUDYN = pytest.mark.skipif(not HAVE_EXUDYN, reason="needs exudyn")
ENGINES = ["reference", pytest.param("exudyn", marks=NEEDS_EXUDYN)]


@pytest.fixture(scope="module")
def runs():
    """runs(engine, case) -> the Result, each simulated once."""
    cache = {}

    def get(engine, case):
        if (engine, case) not in cache:
            run_case = SCENE.reference if engine == "reference" else push_model().run
            cache[engine, case] = run_case(CASES[case])
        return cache[engine, case]
    return get


# ----------------------------------------------------------------------------------------------
# the tests

def test_parameter_set_is_its_table():
    """scene_parameters makes the table a frozen dataclass: one field per row, in order, with its default."""
    fields = dataclasses.fields(PushParams)
    assert [f.name for f in fields] == list(PUSH_PARAMS) and PushParams.TABLE is PUSH_PARAMS
    assert all(f.default == PUSH_PARAMS[f.name][0] for f in fields)
    assert AT_REST.push == 1.0 and AT_REST.mu == PUSH_PARAMS["mu"][0]
    with pytest.raises(dataclasses.FrozenInstanceError):
        SLIDING.push = 1.0


def test_body_model_tangent_equals_finite_differences():
    """The analytic Newton Jacobian of PushedPoint against central differences of the residual,
    after 50 steps: sliding (measured 6.1e-9) and sticking with both dashpots (2.6e-10; a model
    that returned a zero damping tangent there would give 0.86)."""
    for p in (SLIDING, AT_REST):
        _, _, err = jacobian_check(PushedPoint(p, push_contact_law(p)), 1e-6 * p.load, p, steps=50)
        assert err < 1e-6, err


@pytest.mark.parametrize("engine", ENGINES)
def test_sliding_point_accelerates_at_push_minus_mu_N_over_m(engine, runs):
    p = SLIDING
    result = runs(engine, "sliding")
    traj, theory = result.trajectory, SCENE.closed_forms(p)
    t, status = traj["t"], traj["status"]
    # it sticks until the adhesion spring carries mu N: push (1 - cos w t_s) = mu load
    t_s = math.acos(1.0 - p.mu * p.load / p.push) / math.sqrt(p.eps_t / p.mass)     # 0.01047 s
    assert theory["slip_time_theory"] == pytest.approx(t_s, rel=1e-15)
    first = np.argmax(status == SLIP)
    assert t_s < t[first] <= t_s + p.dt
    assert np.all(status[1:first] == STICK) and np.all(status[first:] == SLIP)
    # then it slides at a = (push - mu N) / m: measured 1.6e-13 (reference) and 3.9e-11 (Exudyn)
    # relative, Newton's tolerance 1e-10 of the force level
    a = (p.push - p.mu * p.load) / p.mass                                            # 3 m/s^2
    assert result.summary["acceleration_theory"] == theory["acceleration_theory"]
    assert theory["acceleration_theory"] == pytest.approx(a, rel=1e-15)
    assert result.summary["acceleration"] == pytest.approx(a, rel=1e-8)
    # along +x only, and the normal force stays the load (the start is the static penetration)
    assert np.max(np.abs(traj["y"])) < 1e-12 and np.max(np.abs(traj["vy"])) < 1e-12
    assert np.allclose(traj["normal_force"], p.load, rtol=1e-9, atol=0)
    assert np.allclose(traj["z"], -p.load / p.eps_n, rtol=1e-9, atol=0)
    # Coulomb: friction dissipates mu N per metre slid (measured 3e-16 relative)
    i, j = np.searchsorted(t, 0.2), len(t) - 1
    rate = (traj["dissipated_energy"][j] - traj["dissipated_energy"][i]) / (
        traj["slip_distance"][j] - traj["slip_distance"][i])
    assert rate == pytest.approx(p.mu * p.load, rel=1e-9)


@pytest.mark.parametrize("engine", ENGINES)
def test_point_below_the_friction_limit_comes_to_rest_at_the_static_displacements(engine, runs):
    p = AT_REST
    result = runs(engine, "at_rest")
    traj, theory = result.trajectory, SCENE.closed_forms(p)
    assert np.all(traj["status"][1:] == STICK) and traj["slip_distance"][-1] == 0.0
    assert result.summary["acceleration"] is None and result.summary["acceleration_theory"] is None
    assert "sticks" in result.summary["undefined"]["acceleration_theory"]
    # from press0 = 0.5 and x = 0 to the static solution (dashpots' decay e^-25 by t_end; measured
    # x 1.0e-10 relative on the reference, 6e-12 on Exudyn; z 2e-16)
    assert abs(traj["z"][0] - theory["z_rest_theory"]) > 0.4 * p.load / p.eps_n     # not the answer
    assert traj["z"][-1] == pytest.approx(-p.load / p.eps_n, rel=1e-9)              # 1e-4 m
    assert traj["x"][-1] == pytest.approx(p.push / p.eps_t, rel=1e-8)               # 1e-4 m
    assert theory["x_rest_theory"] == pytest.approx(p.push / p.eps_t, rel=1e-15)
    assert abs(traj["vx"][-1]) < 1e-9 and abs(traj["vz"][-1]) < 1e-9
    # the dashpots dissipate what the springs do not store: push^2 / (2 eps_t) tangentially and
    # (1 - press0)^2 load^2 / (2 eps_n) normally, 1.75e-4 J (measured 1e-15 relative)
    diss = (p.push ** 2 / p.eps_t + (1.0 - p.press0) ** 2 * p.load ** 2 / p.eps_n) / 2.0
    assert result.summary["energy"]["dissipated"] == pytest.approx(diss, rel=1e-9)


@pytest.mark.parametrize("engine", ENGINES)
@pytest.mark.parametrize("case", sorted(CASES))
def test_energy_ledger_closes(engine, case, runs):
    """work in = kinetic + stored + dissipated; measured residual 8.3e-14 (reference, sliding) and
    1.9e-11 (Exudyn, sliding: its modified Newton stops at the tolerance 1e-10), 1e-15 at rest."""
    summary = runs(engine, case).summary
    assert summary["energy_ok"] and summary["energy"]["residual"] < 1e-9, summary
    assert summary["energy"]["work_in"] > 1e-4                                      # something happened


@NEEDS_EXUDYN
@pytest.mark.parametrize("case", sorted(CASES))
def test_engines_agree(case, runs):
    """Both engines take the same time grid and the same trapezoidal rule; each solves every step to
    Newton's tolerance 1e-10 of its force level, so the states differ by what that tolerance lets
    through. Measured at every sample, relative to the largest value of the column: sliding 3.7e-11
    (x, vx), at rest 5.6e-10 (x) and 1.2e-9 (vx, whose peak is only 5e-3 m/s). Tolerance 1e-8. Both
    give every column and the same summary keys."""
    ra, rb = runs("reference", case), runs("exudyn", case)
    a, b = ra.trajectory, rb.trajectory
    assert set(COLUMNS) <= set(a) and set(COLUMNS) <= set(b)
    assert set(ra.summary) == set(rb.summary)
    assert np.allclose(a["t"], b["t"], rtol=0, atol=1e-12)
    for k in ("x", "y", "z", "vx", "vy", "vz", "slip_distance", "dissipated_energy"):
        scale = max(float(np.max(np.abs(a[k]))), 1e-300)
        assert np.max(np.abs(a[k] - b[k])) <= 1e-8 * scale, (case, k)


# ----------------------------------------------------------------------------------------------
# the page

def _code_blocks(text):
    """(source file named before the block, block) for every python block of the page: the source is
    the last `....py` path in backticks between the previous block and this one."""
    out, last = [], 0
    for m in re.finditer(r"^```python\n(.*?)^```$", text, re.M | re.S):
        named = re.findall(r"`([\w./]+\.py)`", text[last:m.start()])
        out.append((named[-1] if named else None, m.group(1)))
        last = m.end()
    return out


def test_the_page_shows_real_code():
    """Every python block of docs/adding_a_scene.md is verbatim in the file named just before it
    (this test file or a file of the package); lines <= 110 characters; every repository path the
    page names exists, but the new scene's own files (push)."""
    text = PAGE.read_text()
    blocks = _code_blocks(text)
    assert len(blocks) >= 8
    for source, block in blocks:
        assert source is not None, f"no source file named before the block:\n{block}"
        assert block in (ROOT / source).read_text(), f"not verbatim in {source}:\n{block}"
    assert max(len(line) for line in text.splitlines()) <= 110
    for path in set(re.findall(r"`((?:exu_aniso|tests|studies|docs)/[\w./]*\w)`", text)):
        assert "push" in path or (ROOT / path).exists(), path
