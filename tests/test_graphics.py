"""Renderer graphics of a contact set (exu_aniso.engines.exudyn_adapter.graphics.AddContactGraphics), checked without a display.

Two views of what is drawn: the user function's own output (float64 GraphicsData, compared to
1e-12) and ``SC.renderer.GetGraphicsData()`` (what the renderer draws; Exudyn stores its
coordinates as float32, so those are compared to float32 resolution). The graphics read the
Visualization configuration. The solver copies its state there only while a renderer runs
(CSolverBase: "update postprocess data only if visualization is running"), so after a solve the
tests copy it the same way (``_show_current``); without a renderer, GetGraphicsData and the
raytracer copy the Current state there themselves before drawing (Exudyn 1.13.6, measured).
Never call renderer.Start() here: there is no display.
"""
import math

import numpy as np
import pytest

exu = pytest.importorskip("exudyn")
from exudyn.utilities import InertiaCuboid, LoadSolutionFile, RigidBodyInertia, SetSolutionState  # noqa: E402

from exu_aniso import Adhesion, Friction  # noqa: E402
from exu_aniso.geometry import Cylinder, Plane
from exu_aniso.law.history import HISTORY_FIELDS, N_HISTORY, OPEN, SLIP, STICK  # noqa: E402
from exu_aniso.engines.exudyn_adapter.create_contact import CreateAnisotropicContact  # noqa: E402
from exu_aniso.engines.exudyn_adapter.graphics import NET_COLORS, STATUS_COLORS, AddContactGraphics  # noqa: E402

V = exu.ConfigurationType.Visualization
OBJECT = int(exu.ItemType.Object)
STATUS = HISTORY_FIELDS.index("status")
F32 = 2e-7          # float32 resolution (relative) of GetGraphicsData coordinates

A_BLOCK = 0.05      # half edge of the block [m]
EPS_N = 2.5e5       # normal stiffness per point [N/m]
LOCAL = np.array([[sx * A_BLOCK, sy * A_BLOCK, -A_BLOCK] for sx in (-1, 1) for sy in (-1, 1)])


def _settings(t_end, dt=1e-3):
    ss = exu.SimulationSettings()
    ss.timeIntegration.numberOfSteps = int(round(t_end / dt))
    ss.timeIntegration.endTime = t_end
    ss.timeIntegration.verboseMode = 0
    ss.solution.file.write = False
    return ss


def _block(load=(0.0, 0.0, 0.0), normal=9.81, x0=0.5, adhesion=None, friction=None, surface=None):
    """1 kg cube (EP node) on the plane z = 0 at the static penetration of `normal` [N]; extra
    constant force `load` at the centre. Polar adhesion and friction by default (README example);
    the exact map (its laws are compiled by other tests of the default run; the default friction
    is isotropic in value, where the maps agree)."""
    SC = exu.SystemContainer()
    mbs = SC.AddSystem()
    z0 = A_BLOCK - normal / (4 * EPS_N)
    inertia = InertiaCuboid(1000.0, [2 * A_BLOCK] * 3)
    oBlock = mbs.CreateRigidBody(inertia=inertia, referencePosition=[x0, 0.0, z0],
                                 nodeType=exu.NodeType.RotationEulerParameters)
    mbs.CreateForce(itemNumber=oBlock, loadVector=[load[0], load[1], load[2] - normal])
    contact = CreateAnisotropicContact(
        mbs, bodyNumber=oBlock, localPoints=LOCAL, surface=surface or Plane(coordinates="polar"),
        adhesion=adhesion or Adhesion.polar(eps_r=2.5e4, eps_phi=2.5e2, core_radius=1e-3),
        friction=friction or Friction.polar(mu_r=0.3, mu_phi=0.3, core_radius=1e-3),
        normalStiffness=EPS_N, returnMap="exact", implementation="numpy", storeHistory=True)
    return SC, mbs, oBlock, contact


ALPHA = math.radians(10.0)      # helix angle of the screw-like scene
R_HOLE = 0.005


def _screw(axis=(1.0, 1.0, 0.0), axis_point=(0.01, 0.0, 0.0), side="inside", rings=3, per_ring=8):
    """A rigid body with rings of points pressed 1e-5 m into a hole (side='inside') or onto a shaft
    with a spiral field, about an oblique axis."""
    SC = exu.SystemContainer()
    mbs = SC.AddSystem()
    cyl = Cylinder(R_HOLE, axis_point=axis_point, axis_direction=axis, side=side)
    e1, e2, ea = cyl.axes
    rho = R_HOLE + (1e-5 if side == "inside" else -1e-5)
    phi = 2 * np.pi * np.arange(per_ring) / per_ring
    pts = np.array([rho * (math.cos(f) * e1 + math.sin(f) * e2) + z * ea
                    for z in np.linspace(-0.01, 0.01, rings) for f in phi])
    inertia = RigidBodyInertia(mass=0.01, inertiaTensor=np.diag([1e-6, 1e-6, 1.25e-7]))
    oScrew = mbs.CreateRigidBody(inertia=inertia, referencePosition=list(axis_point),
                                 nodeType=exu.NodeType.RotationEulerParameters)
    K = len(pts)
    contact = CreateAnisotropicContact(
        mbs, bodyNumber=oScrew, localPoints=pts, surface=cyl,
        adhesion=Adhesion.spiral(1e4 / K, 1e6 / K, ALPHA), friction=Friction.spiral(0.2, 0.6, ALPHA),
        normalStiffness=1e7 / K, implementation="numpy")
    return SC, mbs, oScrew, contact, cyl


def _solve(mbs, t_end):
    mbs.SolveDynamic(_settings(t_end), solverType=exu.DynamicSolverType.TrapezoidalIndex2)


def _show_current(mbs):
    """What the solver does at a graphics update while a renderer runs: Current -> Visualization."""
    C = exu.ConfigurationType.Current
    mbs.systemData.SetSystemState(mbs.systemData.GetSystemState(C), V)
    mbs.systemData.SetTime(mbs.systemData.GetTime(C), V)


def _drawn(SC, contact, kind):
    """Rows of GetGraphicsData()[kind] drawn by the contact object: (points, colors, all of the kind)."""
    d = SC.renderer.GetGraphicsData()[kind]
    mine = np.all(d["items"] == [0, OBJECT, int(contact["oContact"])], axis=1)
    return d["points"][mine], d["colors"][mine], d


def _of_color(points, colors, color):
    """Line segments (n, 2, 3) whose vertices all have `color` (float32 colours)."""
    sel = np.all(np.abs(colors - np.asarray(color, dtype=np.float32)) < 1e-6, axis=(1, 2))
    return np.asarray(points[sel], dtype=float)


def _slave_points_global(mbs, oBody, local, configuration=V):
    return np.array([mbs.GetObjectOutputBody(oBody, exu.OutputVariableType.Position, localPosition=list(b),
                                             configuration=configuration) for b in local])


def _slopes(segments, cyl):
    """dz / (R dphi) of line segments (n, 2, 3) on a cylinder, and the distance of their ends from
    the axis (n, 2)."""
    loc = (segments - cyl.axis_point) @ cyl.axes.T
    phi = np.arctan2(loc[:, :, 1], loc[:, :, 0])
    dphi = np.angle(np.exp(1j * (phi[:, 1] - phi[:, 0])))
    return (loc[:, 1, 2] - loc[:, 0, 2]) / (cyl.radius * dphi), np.hypot(loc[:, :, 0], loc[:, :, 1])


def _status_colors(status):
    return np.array([STATUS_COLORS[int(s)] for s in status], dtype=np.float32)


# ----------------------------------------------------------------------------------------------
# contact points: number, position, colour by state

def test_points_count_and_centres_equal_the_slave_points():
    SC, mbs, oBlock, contact = _block()
    uf = AddContactGraphics(mbs, contact)
    mbs.Assemble()
    K = len(LOCAL)
    centres, colors, _ = _drawn(SC, contact, "spheres")
    assert centres.shape == (K, 3)
    exact = _slave_points_global(mbs, oBlock, LOCAL)
    spheres = [g for g in uf(mbs, int(contact["oContact"])) if g["type"] == "Spheres"]
    assert len(spheres) == 1
    own = np.asarray(spheres[0]["points"], dtype=float).reshape(-1, 3)
    assert np.abs(own - exact).max() < 1e-12                       # the user function, float64
    assert np.abs(centres - exact).max() < F32 * np.abs(exact).max()   # what the renderer gets, float32
    np.testing.assert_array_equal(colors, _status_colors([STICK] * K))  # initialised sticking under load


@pytest.mark.parametrize("load, t_end, state", [((0.0, 0.0, 0.0), 0.05, STICK),    # at rest under load
                                                ((0.0, 10.0, 0.0), 0.1, SLIP),     # pulled along y: slides
                                                ((0.0, 0.0, 20.0), 0.05, OPEN)],   # pulled up: lifted off
                         ids=["rest-stick", "pulled-slip", "lifted-open"])
def test_point_colours_follow_the_state_after_a_solve(load, t_end, state):
    SC, mbs, oBlock, contact = _block(load=load)
    AddContactGraphics(mbs, contact)
    mbs.Assemble()
    _solve(mbs, t_end)
    _show_current(mbs)
    status = contact["historyAt"](mbs, V)[:, STATUS]
    assert np.all(status == state)
    centres, colors, _ = _drawn(SC, contact, "spheres")
    np.testing.assert_array_equal(colors, _status_colors(status))
    exact = _slave_points_global(mbs, oBlock, LOCAL)
    assert np.abs(centres - exact).max() < F32 * np.abs(exact).max()


def test_graphics_cost_nothing_during_the_solve():
    """The user function runs on redraws only; the cached static items are returned as they are."""
    SC, mbs, oBlock, contact = _block(load=(0.0, 10.0, 0.0))
    uf = AddContactGraphics(mbs, contact)
    calls = []

    def counting(mbs, itemNumber):
        calls.append(itemNumber)
        return uf(mbs, itemNumber)

    mbs.SetObjectParameter(contact["oContact"], "VgraphicsDataUserFunction", counting)
    mbs.Assemble()
    _solve(mbs, 0.05)
    assert calls == []
    SC.renderer.GetGraphicsData()
    assert len(calls) == 1
    first, second = uf(mbs, 0), uf(mbs, 0)
    assert all(a is b for a, b in zip(first[:len(uf.static)], second[:len(uf.static)]))
    assert first[:len(uf.static)] == uf.static and len(uf.static) == 3     # face, e1 lines, e2 lines


def test_solution_viewer_state_is_drawn(tmp_path):
    """SolutionViewer loads every stored row into the Visualization configuration (SetSolutionState:
    ODE2 and data coordinates) and redraws; the graphics show that row: the positions and the
    states of the stored history.

    The redraw is the user function itself, called as the renderer calls it. (GetGraphicsData cannot
    be used for this step: without a running renderer, Exudyn 1.13.6 copies the Current state into
    the Visualization configuration before it draws -- measured, it replaces whatever was loaded --
    so the row is also loaded into Current to check what the renderer receives.)"""
    SC, mbs, oBlock, contact = _block(load=(0.0, 10.0, 0.0))
    uf = AddContactGraphics(mbs, contact)
    mbs.Assemble()
    ss = _settings(0.1)
    ss.solution.file.write = True
    ss.solution.file.name = str(tmp_path / "solution.txt")
    ss.solution.file.writePeriod = 0.01
    ss.solution.file.export.dataCoordinates = True           # the default; the history lives there
    ss.solution.precision = 17                                # the file holds the state to round-off
    mbs.SolveDynamic(ss, solverType=exu.DynamicSolverType.TrapezoidalIndex2)
    H = mbs.GetSensorStoredData(contact["sHistory"])         # every step, stored apart from the file
    sol = LoadSolutionFile(str(tmp_path / "solution.txt"), verbose=False)
    assert sol["columnsExported"][6] == len(LOCAL) * N_HISTORY + 1       # history and the set's total dissipation
    seen = set()
    start = None
    for row in range(sol["nRows"]):
        t = sol["data"][row][0]
        h = H[np.argmin(np.abs(H[:, 0] - t)), 1:].reshape(-1, N_HISTORY)     # the stored history at t
        SetSolutionState(mbs, sol, row, V)                    # what SolutionViewer does
        spheres = [g for g in uf(mbs, int(contact["oContact"])) if g["type"] == "Spheres"][0]
        centres = np.asarray(spheres["points"], float).reshape(-1, 3)
        x, p, A = contact["pointsAndMasterPose"](mbs, V)      # the positions the contact law evaluates
        np.testing.assert_allclose(centres, p + x @ A.T, rtol=0, atol=1e-12)
        # Exudyn's own body output builds the rotation matrix with another formula, equal to the law's
        # only for |e| = 1; TrapezoidalIndex2 keeps |e|^2 = 1 to ~1e-7 here (velocity-level constraint)
        exact = _slave_points_global(mbs, oBlock, LOCAL, V)
        np.testing.assert_allclose(centres, exact, rtol=0, atol=1e-7)
        np.testing.assert_array_equal(np.asarray(spheres["colors"]).reshape(-1, 4),
                                      [STATUS_COLORS[int(s)] for s in h[:, STATUS]])
        start = exact if start is None else start
        SetSolutionState(mbs, sol, row, exu.ConfigurationType.Current)      # the windowless renderer path
        centres, colors, _ = _drawn(SC, contact, "spheres")
        np.testing.assert_array_equal(colors, _status_colors(h[:, STATUS]))
        assert np.abs(centres - exact).max() < F32 * np.abs(exact).max()
        seen.update(int(s) for s in h[:, STATUS])
    assert seen == {STICK, SLIP}                              # the rows differ: sticking, then sliding
    assert np.linalg.norm(exact - start, axis=1).min() > 0.01  # and the block moved


# ----------------------------------------------------------------------------------------------
# the net: polar plane, orthotropic plane, spiral cylinder

def test_polar_plane_rays_through_origin_and_circles_about_it():
    SC, mbs, oBlock, contact = _block()
    uf = AddContactGraphics(mbs, contact)
    mbs.Assemble()
    points, colors, _ = _drawn(SC, contact, "lines")
    rays = _of_color(points, colors, NET_COLORS[0])
    circles = _of_color(points, colors, NET_COLORS[1])
    assert len(rays) >= 12 and len(circles) >= 100
    tol = F32 * uf.sceneSize
    # rays: every segment on a line through the origin (the two ends are parallel), in the plane z = 0
    assert np.abs(np.cross(rays[:, 0], rays[:, 1])).max() < 10 * tol * uf.sceneSize
    assert np.abs(rays[:, :, 2]).max() < tol
    assert np.abs(np.linalg.norm(rays[:, 0], axis=1)).min() < tol          # they start at the origin
    # circles: both ends of a segment at the same distance from the origin; each circle centred there
    r = np.linalg.norm(circles, axis=2)
    assert np.abs(r[:, 0] - r[:, 1]).max() < 10 * tol
    for radius in np.unique(np.round(r[:, 0] / (100 * tol))):
        ring = circles[np.round(r[:, 0] / (100 * tol)) == radius].reshape(-1, 3)
        assert np.abs(ring.mean(axis=0)).max() < 10 * tol
    # the disk is large enough to hold the block's points, with margin
    assert uf.sceneSize > np.max(np.hypot(LOCAL[:, 0] + 0.5, LOCAL[:, 1]))


def _rotated_B(eps_1, eps_2, angle):
    c, s = math.cos(angle), math.sin(angle)
    R = np.array([[c, -s], [s, c]])
    return -(R @ np.diag([eps_1, eps_2]) @ R.T)


@pytest.mark.parametrize("angle, adhesion, friction", [
    (math.radians(30.0), Adhesion.orthotropic(2.5e4, 2.5e2, math.radians(30.0)), Friction.isotropic(0.3)),
    (math.radians(-20.0), Adhesion.isotropic(2.5e4), Friction.orthotropic(0.2, 0.4, math.radians(-20.0))),
    (math.radians(20.0), Adhesion.from_matrix(_rotated_B(2.5e4, 2.5e2, math.radians(20.0))),
     Friction.isotropic(0.3)),
    (0.0, Adhesion.isotropic(2.5e4), Friction.isotropic(0.3)),
], ids=["orthotropic-adhesion", "orthotropic-friction", "matrix", "isotropic"])
def test_plane_grid_at_the_field_angle(angle, adhesion, friction):
    SC, mbs, oBlock, contact = _block(surface=Plane(), adhesion=adhesion, friction=friction)
    uf = AddContactGraphics(mbs, contact)
    mbs.Assemble()
    points, colors, _ = _drawn(SC, contact, "lines")
    e1 = np.array([math.cos(angle), math.sin(angle), 0.0])
    e2 = np.array([-math.sin(angle), math.cos(angle), 0.0])
    for color, direction in zip(NET_COLORS, (e1, e2)):
        seg = _of_color(points, colors, color)
        assert len(seg) >= 5
        d = seg[:, 1] - seg[:, 0]
        d /= np.linalg.norm(d, axis=1)[:, None]
        assert np.abs(np.abs(d @ direction) - 1.0).max() < 1e-5
    face, _, _ = _drawn(SC, contact, "triangles")
    assert len(face) == 2 and np.all(face[:, :, 2] < 0.0)      # the face lies just behind the plane
    assert np.abs(face[:, :, 2]).max() < 1e-2 * uf.sceneSize


@pytest.mark.parametrize("side", ["inside", "outside"])
def test_spiral_cylinder_helices_have_the_helix_angle_and_lie_on_the_surface(side):
    SC, mbs, oScrew, contact, cyl = _screw(side=side)
    uf = AddContactGraphics(mbs, contact)
    mbs.Assemble()
    # float64 output of the user function: every net line vertex on the cylinder, to 1e-12
    lines = [g for g in uf(mbs, 0) if g["type"] == "Lines"]
    assert len(lines) == 2
    for g in lines:
        rel = np.asarray(g["points"], dtype=float).reshape(-1, 3) - cyl.axis_point
        dist = np.linalg.norm(rel - np.outer(rel @ cyl.axes[2], cyl.axes[2]), axis=1)
        assert np.abs(dist - R_HOLE).max() < 1e-12
    # what the renderer draws: the e1 family are helices of angle ALPHA, dz / (R dphi) = tan(ALPHA)
    points, colors, _ = _drawn(SC, contact, "lines")
    helix = _of_color(points, colors, NET_COLORS[0])
    assert len(helix) > 100
    slope, radius = _slopes(helix, cyl)
    assert np.abs(slope / math.tan(ALPHA) - 1.0).max() < 1e-3
    assert np.abs(radius - R_HOLE).max() < 10 * F32 * np.abs(helix).max()
    # e2 family: across the helix, dz / (R dphi) = -1 / tan(ALPHA)
    slope, _ = _slopes(_of_color(points, colors, NET_COLORS[1]), cyl)
    assert np.abs(slope * math.tan(ALPHA) + 1.0).max() < 1e-3
    # the tube covers the points along the axis; the face sits behind the wall (master side)
    z = (contact["pointsAndMasterPose"](mbs, V)[0] - cyl.axis_point) @ cyl.axes[2]
    face = np.asarray(uf.static[0]["points"], float).reshape(-1, 3)
    zf = (face - cyl.axis_point) @ cyl.axes[2]
    assert zf.min() < z.min() and zf.max() > z.max()
    rf = np.linalg.norm((face - cyl.axis_point) - np.outer(zf, cyl.axes[2]), axis=1)
    assert np.all((rf > R_HOLE) if side == "inside" else (rf < R_HOLE))
    # contact points: K spheres, in contact initially (interference): stick
    centres, colors, _ = _drawn(SC, contact, "spheres")
    K = len(contact["points"])
    assert len(centres) == K
    np.testing.assert_array_equal(colors, _status_colors([STICK] * K))


def test_small_helix_angle_is_drawn_as_circles():
    SC = exu.SystemContainer()
    mbs = SC.AddSystem()
    o = mbs.CreateRigidBody(inertia=RigidBodyInertia(mass=0.01, inertiaTensor=np.eye(3) * 1e-6),
                            referencePosition=[0, 0, 0], nodeType=exu.NodeType.RotationEulerParameters)
    contact = CreateAnisotropicContact(mbs, bodyNumber=o, localPoints=[[0.004, 0, 0], [-0.004, 0, 0.005]],
                                       surface=Cylinder(R_HOLE), adhesion=Adhesion.spiral(1e3, 1e5, 1e-6),
                                       friction=Friction.isotropic(0.2), normalStiffness=1e6)
    uf = AddContactGraphics(mbs, contact)
    helix = np.asarray(uf.static[1]["points"], dtype=float).reshape(-1, 2, 3)
    assert np.abs(helix[:, 0, 2] - helix[:, 1, 2]).max() < 1e-15          # phi lines: constant z
    assert len(helix) < 10000


# ----------------------------------------------------------------------------------------------
# moving master, traction arrows

def test_moving_master_surface_follows_the_master_pose():
    SC = exu.SystemContainer()
    mbs = SC.AddSystem()
    c, s = math.cos(0.4), math.sin(0.4)
    A = np.array([[1.0, 0.0, 0.0], [0.0, c, -s], [0.0, s, c]])       # master tilted about x
    p = np.array([0.2, -0.1, 1.0])
    plate = mbs.CreateRigidBody(inertia=InertiaCuboid(1000.0, [1.0, 1.0, 0.02]), referencePosition=list(p),
                                referenceRotationMatrix=A, nodeType=exu.NodeType.RotationEulerParameters,
                                returnDict=True)
    block = mbs.CreateRigidBody(inertia=InertiaCuboid(1000.0, [0.1] * 3),
                                referencePosition=list(p + A @ [0.3, 0.1, 0.05]), referenceRotationMatrix=A,
                                nodeType=exu.NodeType.RotationEulerParameters, returnDict=True)
    contact = CreateAnisotropicContact(mbs, bodyNumber=block["bodyNumber"], localPoints=LOCAL,
                                       surface=Plane(), adhesion=Adhesion.orthotropic(2e4, 5e3, 0.3),
                                       friction=Friction.isotropic(0.3), normalStiffness=1e5,
                                       masterBodyNumber=plate["bodyNumber"])
    uf = AddContactGraphics(mbs, contact)
    static_points = [np.array(g["points"], dtype=float) for g in uf.static]
    mbs.Assemble()

    def check(p, A):
        out = uf(mbs, 0)
        for g, local in zip(out, static_points):
            np.testing.assert_allclose(np.asarray(g["points"], float).reshape(-1, 3),
                                       p + local.reshape(-1, 3) @ A.T, rtol=0, atol=1e-12)
        centres = np.asarray(out[-1]["points"], float).reshape(-1, 3)
        exact = _slave_points_global(mbs, block["bodyNumber"], LOCAL)
        assert np.abs(centres - exact).max() < 1e-12
        lines = np.asarray(out[1]["points"], float).reshape(-1, 3)
        assert np.abs((lines - p) @ (A @ [0.0, 0.0, 1.0])).max() < 1e-12     # in the master's plane

    check(p, A)
    # move the master in the Visualization configuration (as a stored solution row would)
    q = np.array(mbs.systemData.GetODE2Coordinates(configuration=V))
    idx = list(mbs.systemData.GetNodeLTGODE2(plate["nodeNumber"]))
    shift = np.array([0.1, 0.2, -0.3])
    q[idx[0:3]] += shift
    mbs.systemData.SetODE2Coordinates(q.tolist(), configuration=V)
    check(p + shift, A)
    for g, local in zip(uf.static, static_points):        # the cached geometry itself never moves
        np.testing.assert_array_equal(np.asarray(g["points"], float), local)


def test_traction_arrows_show_the_contact_force():
    SC, mbs, oBlock, contact = _block(load=(0.0, 10.0, 0.0))
    uf = AddContactGraphics(mbs, contact, showTraction=True)
    # default scale: the initial normal load per point draws 0.2 scene lengths
    assert uf.tractionScale == pytest.approx(0.2 * uf.sceneSize / (9.81 / 4), rel=1e-9)
    mbs.Assemble()
    _solve(mbs, 0.1)
    _show_current(mbs)
    out = uf(mbs, 0)
    arrows = [g for g in out if g["type"] == "TriangleList" and g is not uf.static[0]]
    assert len(arrows) == len(LOCAL)
    H = contact["historyAt"](mbs, V)
    x = contact["pointsAndMasterPose"](mbs, V)[0]
    T = H[:, [HISTORY_FIELDS.index("traction_1"), HISTORY_FIELDS.index("traction_2")]]
    N = H[:, HISTORY_FIELDS.index("normal")]
    # polar plane: T is stored in the frame (e_r, e_phi) of the contact point, n = e_z
    e_r = x[:, :2] / np.linalg.norm(x[:, :2], axis=1)[:, None]
    e_phi = np.column_stack([-e_r[:, 1], e_r[:, 0]])
    force = np.column_stack([T[:, :1] * e_r + T[:, 1:] * e_phi, -N])
    for g, start, f in zip(arrows, x, force):
        pts = np.asarray(g["points"], float).reshape(-1, 3)
        tip = pts[np.argmax((pts - start) @ f)]
        np.testing.assert_allclose(tip - start, uf.tractionScale * f, rtol=0, atol=1e-9)
    # the friction part points against the sliding (+y) on every point
    assert np.all(T[:, 1] < 0.0)
    scaled = AddContactGraphics(mbs, contact, showTraction=True, tractionScale=1e-3)
    assert scaled.tractionScale == 1e-3


def test_planar_and_screw_joint_nodes():
    """NodeRigidBody2D (the local z of a point is its height over the plane) and the 2-coordinate
    screw-joint node (rotation psi about z, translation z)."""
    from exudyn.itemInterface import NodeGenericODE2, NodeRigidBody2D, ObjectGenericODE2, ObjectRigidBody2D
    SC = exu.SystemContainer()
    mbs = SC.AddSystem()
    n2 = mbs.AddNode(NodeRigidBody2D(referenceCoordinates=[0.3, 0.2, 0.5]))
    o2 = mbs.AddObject(ObjectRigidBody2D(nodeNumber=n2, mass=1.0, inertia=1e-3))
    local = LOCAL.copy()
    local[:, 2] = -1e-5
    planar = CreateAnisotropicContact(mbs, bodyNumber=o2, localPoints=local, surface=Plane(),
                                      adhesion=Adhesion.isotropic(1e4), friction=Friction.isotropic(0.3),
                                      normalStiffness=EPS_N)
    nS = mbs.AddNode(NodeGenericODE2(referenceCoordinates=[0.0, 0.0], initialCoordinates=[0.7, 0.002],
                                     initialCoordinates_t=[0.0, 0.0], numberOfODE2Coordinates=2))
    oS = mbs.AddObject(ObjectGenericODE2(nodeNumbers=[nS], massMatrix=np.diag([1e-6, 0.01])))
    screw = CreateAnisotropicContact(mbs, bodyNumber=oS, localPoints=[[R_HOLE + 1e-5, 0.0, 0.0]],
                                     surface=Cylinder(R_HOLE), adhesion=Adhesion.spiral(1e4, 1e6, ALPHA),
                                     friction=Friction.spiral(0.2, 0.6, ALPHA), normalStiffness=1e7)
    ufs = [AddContactGraphics(mbs, c) for c in (planar, screw)]
    mbs.Assemble()
    c, s = math.cos(0.5), math.sin(0.5)
    expected = np.column_stack([0.3 + c * local[:, 0] - s * local[:, 1],
                                0.2 + s * local[:, 0] + c * local[:, 1], local[:, 2]])
    got = np.asarray(ufs[0](mbs, 0)[-1]["points"], float).reshape(-1, 3)
    np.testing.assert_allclose(got, expected, rtol=0, atol=1e-15)
    got = np.asarray(ufs[1](mbs, 0)[-1]["points"], float).reshape(-1, 3)
    rho = R_HOLE + 1e-5
    np.testing.assert_allclose(got, [[rho * math.cos(0.7), rho * math.sin(0.7), 0.002]], rtol=0, atol=1e-15)
    # one point in the hole: tube half-length CYLINDER_MARGIN * R about it; sphere radius from the scene
    assert ufs[1].sceneSize == pytest.approx(2.0 * R_HOLE)
    assert ufs[1].pointRadius == pytest.approx(0.03 * 2.0 * R_HOLE)
    for c in (planar, screw):
        assert len(_drawn(SC, c, "spheres")[0]) == len(c["points"])


def test_show_flags_and_colour():
    SC, mbs, oBlock, contact = _block()
    uf = AddContactGraphics(mbs, contact, show=False, showNet=False, color=[0.2, 0.4, 0.6])
    assert mbs.GetObject(contact["oContact"])["Vshow"] is False
    assert uf.static == [] and uf.netColors[0] == (0.1, 0.2, 0.3, 1.0)
    mbs.Assemble()
    assert len(_drawn(SC, contact, "spheres")[0]) == 0      # hidden
    mbs.SetObjectParameter(contact["oContact"], "Vshow", True)
    assert len(_drawn(SC, contact, "spheres")[0]) == len(LOCAL)
    assert len(_drawn(SC, contact, "lines")[0]) == 0        # no net
    uf = AddContactGraphics(mbs, contact, showPoints=False)
    assert [g["type"] for g in uf(mbs, 0)] == ["TriangleList", "Lines", "Lines"]
    uf = AddContactGraphics(mbs, contact, size=0.3)            # size: the polar disk's radius
    assert uf.sceneSize == 0.3
    face = np.asarray(uf.static[0]["points"], float).reshape(-1, 3)
    assert np.hypot(face[:, 0], face[:, 1]).max() == pytest.approx(0.3, rel=1e-12)


@pytest.mark.parametrize("kwargs, message", [
    (dict(tractionScale=-1), "AddContactGraphics: tractionScale must be > 0; got -1"),
    (dict(tractionScale=0.0), "AddContactGraphics: tractionScale must be > 0; got 0.0"),
    (dict(size=float("nan")), "AddContactGraphics: size must be a finite number > 0; got nan"),
    (dict(size=-2.0), "AddContactGraphics: size must be > 0; got -2.0"),
    (dict(color=[1.0, 0.0]), "AddContactGraphics: color must be an RGB or RGBA list"),
    (dict(color=[[1.0, 0.0, 0.0, 1.0]]), "AddContactGraphics: color must be an RGB or RGBA list"),
    (dict(color=[1.0, 0.0, 2.0]), "AddContactGraphics: color must be an RGB or RGBA list"),
    (dict(color="red"), "AddContactGraphics: color must be an RGB or RGBA list"),
])
def test_bad_arguments_name_the_argument(kwargs, message):
    SC, mbs, oBlock, contact = _block()
    with pytest.raises(ValueError) as e:
        AddContactGraphics(mbs, contact, **kwargs)
    assert str(e.value).startswith(message)


def test_bad_contact_and_flags():
    SC, mbs, oBlock, contact = _block()
    with pytest.raises(ValueError, match="AddContactGraphics: contact must be the dict returned by "
                                         "CreateAnisotropicContact; missing keys"):
        AddContactGraphics(mbs, {"oContact": contact["oContact"]})
    with pytest.raises(TypeError, match="AddContactGraphics: showTraction must be True or False"):
        AddContactGraphics(mbs, contact, showTraction="yes")
    with pytest.raises(TypeError, match="AddContactGraphics: tractionScale must be a number"):
        AddContactGraphics(mbs, contact, tractionScale="1")
    with pytest.raises(TypeError, match="AddContactGraphics: mbs must be a MainSystem"):
        AddContactGraphics(SC, contact)


# ----------------------------------------------------------------------------------------------

@pytest.mark.slow
def test_raytraced_image_shows_the_states():
    """Software raytracer (no window, no OpenGL): the picture is not blank and shows the points in
    the stick colour at rest and in the slip colour while pulled."""
    def picture(load, t_end):
        SC, mbs, oBlock, contact = _block(load=load)
        AddContactGraphics(mbs, contact)
        mbs.Assemble()
        _solve(mbs, t_end)
        _show_current(mbs)
        vs = SC.visualizationSettings
        vs.view0.window.renderWindowSize = [320, 240]
        vs.view0.scene.drawWorldBasis = False
        vs.view0.scene.drawCoordinateSystem = False
        vs.view0.window.showComputationInfo = False
        SC.renderer.ZoomAll()           # sets up the render state; the model view below then holds
        SC.renderer.SetModelView(zoom=0.2, rotationVector=[-0.6, 0.0, 0.0], centerPoint=[0.5, 0.0, 0.0])
        return np.asarray(SC.renderer.RedrawAndGetImage(useRaytracer=True), dtype=float)

    def share(img, rgb):
        """Share of pixels whose hue is the given status colour's (dominant channel, others < 40 %)."""
        c = np.asarray(rgb[:3])
        k = int(np.argmax(c))
        others = [i for i in range(3) if i != k]
        mask = (img[:, :, k] > 60) & np.all(img[:, :, others] < 0.4 * img[:, :, k:k + 1], axis=2)
        return mask.mean()

    rest = picture((0.0, 0.0, 0.0), 0.05)
    pulled = picture((0.0, 10.0, 0.0), 0.1)
    for img in (rest, pulled):
        assert img.shape[2] == 3 and img.std() > 10.0          # not blank
    assert share(rest, STATUS_COLORS[STICK]) > 0.005 and share(rest, STATUS_COLORS[SLIP]) == 0.0
    assert share(pulled, STATUS_COLORS[SLIP]) > 0.005 and share(pulled, STATUS_COLORS[STICK]) == 0.0


@pytest.mark.parametrize("make", [lambda: __import__("exu_aniso").Sphere(0.5, axis_direction=(1, 0, 0)),
                                  lambda: __import__("exu_aniso").Torus(1.0, 0.3),
                                  lambda: __import__("exu_aniso").Cone(0.3, 0.5),
                                  lambda: __import__("exu_aniso.geometry").geometry.Helicoid(
                                      0.1, math.pi / 3, 0.4, axis_direction=(0, 1, 1))],
                         ids=["sphere", "torus", "cone", "helicoid"])
def test_any_protocol_surface_is_drawn_from_its_chart(make):
    """Surfaces without a drawing rule of their own (sphere, torus, cone, helicoid: phi unbounded and
    not periodic, r > 0) are drawn from their chart: a face and the coordinate lines, every line
    point on the surface (to the float32 of the graphics data), and the contact point."""
    import exu_aniso  # noqa: F401  (mbs.CreateAnisotropicContact)
    from exu_aniso import Adhesion, Friction
    surf = make()
    g = surf.at((0.3, 1.2 if type(surf).__name__ == "Sphere" else 0.2))
    SC = exu.SystemContainer()
    mbs = SC.AddSystem()
    o = mbs.CreateMassPoint(referencePosition=list(g.point - 1e-6 * g.n), mass=0.1)
    mbs.CreateAnisotropicContact(bodyNumber=o, localPoints=[[0.0, 0.0, 0.0]], surface=surf,
                                 adhesion=Adhesion.isotropic(1e4), friction=Friction.isotropic(0.2), normalStiffness=1e6)
    mbs.Assemble()
    d = SC.renderer.GetGraphicsData()
    drawnByObjects = np.asarray(d["spheres"]["items"])[:, 1] == int(exu.ItemType.Object)   # not the node's own dot
    assert len(d["triangles"]["items"]) > 100 and int(np.sum(drawnByObjects)) == 1
    P = np.asarray(d["lines"]["points"], dtype=float).reshape(-1, 3)
    assert len(P) > 100
    gaps = np.array([surf.project(p).xi3 for p in P[::7]])
    assert np.max(np.abs(gaps)) < 1e-6, np.max(np.abs(gaps))
