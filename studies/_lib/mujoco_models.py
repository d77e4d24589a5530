"""MJCF builders for the peer benchmark (``studies/peers.py``): MuJoCo's side of the two cases.

Needs the optional ``bench`` extra (``pip install ".[bench]"``, i.e. ``mujoco>=3.2``); importing this
module without mujoco raises ImportError, so ``peers.py`` imports it only in its MuJoCo cases, which
it runs only when mujoco imports (without it, their rows say how to install it).

1. ``BoxOnPlane``: a box (free joint) on a plane, anisotropic Coulomb friction through an explicit
   ``<contact><pair condim="3" friction="...">`` and ``<option cone="elliptic"|"pyramidal">``, a
   constant horizontal pull at the centre of mass (``xfrc_applied``), gravity along -z.

   How MuJoCo orients the tangent frame of a plane-box contact (measured, see ``TangentFrame``):
   the collider sets only the contact normal (the plane's z axis) and the two tangents come from
   ``mju_makeFrame(normal)``; for the normal +z they are t1 = +e_y, t2 = -e_x, whatever the plane's
   rotation about its normal (a plane with euler="0 0 90" gives the same frame). The pair's
   friction="f1 f2 ..." acts along (t1, t2). ``BoxOnPlane`` therefore reads the frame of a compiled
   model and writes the two coefficients in the order that puts ``mu_x`` along e_x and ``mu_y``
   along e_y; ``peers.py`` checks it with pulls along x and along y.

2. ``NutOnBolt``: the nut and bolt of MuJoCo's example ``model/plugin/sdf/nutbolt.xml`` (SDF
   plugins ``mujoco.sdf.nut`` / ``mujoco.sdf.bolt`` shipped in the wheel; ``import mujoco`` loads
   every library in ``mujoco/plugin/`` (``mujoco.PLUGINS_DIR``) with ctypes at import time, so
   ``MjModel.from_xml_string`` finds them, no explicit plugin loading). The example's contact
   parameters (solref 0.01 1, solimp .95 .99 .0001, friction 0.01, free-joint damping 30) and SDF
   settings (sdf_iterations 15, sdf_initpoints 60) are the defaults here. Differences from the
   example: the nut body is axis-aligned with the world (the 180 deg flip of the example sits on
   the geoms), it starts centred on the axis, and a ``<velocity>`` actuator (gear on the free
   joint's rotation about the body z axis = world z) drives its spin.

   Thread geometry (from the plugin source): ``triangle = |fract(12 z - azimuth / 2 pi) - 1/2|`` in
   the SDF frame, a right-handed single-start thread of pitch 1/12 (model units, m). Rotations keep
   the handedness, so in the world a rotation of the nut by +dpsi about +z advances it by
   +dpsi / (2 pi) * pitch along +z. The bolt (flipped by 180 deg about x) has its head at
   z in [0, 0.5] and its thread up to z = 1; the nut starts at z = 0.83 on the last turns, so a
   negative spin (clockwise seen from above) screws it down towards the head.
"""
from __future__ import annotations

import math
import time

import mujoco
import numpy as np

BOLT_PITCH = 1.0 / 12.0          # m per revolution (``screw = 12`` in the SDF plugins)
BOLT_RADIUS = 0.26               # m, the example's ``radius`` attribute of nut and bolt
NUT_Z0 = 0.83                    # m, start height of the nut (as in the example)


# ----------------------------------------------------------------------------------------------
# 1. box on an orthotropic plane

def _box_xml(f1, f2, cone, dt, mass, size, impratio):
    h = 0.5 * size
    imp = "" if impratio is None else f' impratio="{impratio!r}"'
    return f"""<mujoco model="orthotropic box">
  <option timestep="{dt!r}" gravity="0 0 -9.81" cone="{cone}"{imp}/>
  <worldbody>
    <geom name="floor" type="plane" size="100 100 0.1"/>
    <body name="box" pos="0 0 {h!r}">
      <freejoint name="box"/>
      <geom name="box" type="box" size="{h!r} {h!r} {h!r}" mass="{mass!r}"/>
    </body>
  </worldbody>
  <contact>
    <exclude body1="world" body2="box"/>
    <pair geom1="floor" geom2="box" condim="3" friction="{f1!r} {f2!r} 0.005 0.0001 0.0001"/>
  </contact>
</mujoco>"""


def TangentFrame(model, data):
    """Rows (normal, t1, t2) of the first active contact's frame after mj_forward, shape (3, 3)."""
    mujoco.mj_forward(model, data)
    if data.ncon == 0:
        raise RuntimeError("TangentFrame: the model has no active contact at its initial state")
    return np.array(data.contact.frame[0]).reshape(3, 3)


def BoxOnPlane(mu_x, mu_y, cone="elliptic", dt=0.002, mass=1.0, size=0.1, impratio=None):
    """Compiled (model, data, frame) of the box on the plane with friction mu_x along e_x and mu_y
    along e_y. The pair's friction order is chosen from the contact frame MuJoCo builds (see the
    module doc); ``frame`` is that frame (rows normal, t1, t2). Raises if the frame is not aligned
    with the axes (then a constant-axes orthotropic pair cannot be written)."""
    for name, v in (("mu_x", mu_x), ("mu_y", mu_y), ("dt", dt), ("mass", mass), ("size", size)):
        if not (isinstance(v, (int, float)) and math.isfinite(v) and v > 0):
            raise ValueError(f"BoxOnPlane: {name} must be a finite number > 0; got {v!r}")
    if cone not in ("elliptic", "pyramidal"):
        raise ValueError(f"BoxOnPlane: cone must be 'elliptic' or 'pyramidal'; got {cone!r}")
    model = mujoco.MjModel.from_xml_string(_box_xml(1.0, 1.0, cone, dt, mass, size, impratio))
    frame = TangentFrame(model, mujoco.MjData(model))
    t1 = frame[1]
    if abs(abs(t1[0]) - 1.0) < 1e-9:
        f1, f2 = mu_x, mu_y
    elif abs(abs(t1[1]) - 1.0) < 1e-9:
        f1, f2 = mu_y, mu_x
    else:
        raise RuntimeError(f"BoxOnPlane: contact tangent t1 = {t1} is not along e_x or e_y")
    model = mujoco.MjModel.from_xml_string(_box_xml(f1, f2, cone, dt, mass, size, impratio))
    return model, mujoco.MjData(model), frame


def SlideBox(model, data, force, angle, t_end, count_airborne=False):
    """Pull the box from rest with a constant horizontal force [N] at ``angle`` [rad] from e_x for
    t_end [s]. Returns dict: wall_s, cpu_s (wall and CPU time of the stepping only:
    ``mj_step(..., nstep)`` in two chunks, no Python per step unless count_airborne), steps, vx, vy (end velocity), x, y (end
    position), x_mid, y_mid (position at t_end / 2), airborne_fraction (share of steps without an
    active contact; counted step by step only with count_airborne, else NaN), max_lift (largest
    height of the box's centre above its resting height size/2 [m], with count_airborne)."""
    b = model.body("box").id
    data.xfrc_applied[b, :3] = [force * math.cos(angle), force * math.sin(angle), 0.0]
    n = int(round(t_end / model.opt.timestep))
    n_mid = n // 2
    free = 0
    lift = 0.0
    h = float(model.geom_size[model.geom("box").id][2])
    t0, c0 = time.perf_counter(), time.process_time()
    if count_airborne:
        for i in range(n):
            mujoco.mj_step(model, data)
            free += data.ncon == 0
            lift = max(lift, float(data.qpos[2]) - h)
            if i + 1 == n_mid:
                mid = (float(data.qpos[0]), float(data.qpos[1]))
    else:
        mujoco.mj_step(model, data, nstep=n_mid)
        mid = (float(data.qpos[0]), float(data.qpos[1]))
        mujoco.mj_step(model, data, nstep=n - n_mid)
    wall, cpu = time.perf_counter() - t0, time.process_time() - c0
    return dict(wall_s=wall, cpu_s=cpu, steps=n, vx=float(data.qvel[0]), vy=float(data.qvel[1]), x=float(data.qpos[0]),
                y=float(data.qpos[1]), x_mid=mid[0], y_mid=mid[1],
                airborne_fraction=free / n if count_airborne else float("nan"),
                max_lift=lift if count_airborne else float("nan"))


# ----------------------------------------------------------------------------------------------
# 2. nut on a bolt (SDF plugins)

def _nut_xml(dt, kv, sdf_iterations, sdf_initpoints, friction, damping):
    return f"""<mujoco model="nut on bolt">
  <extension>
    <plugin plugin="mujoco.sdf.nut"><instance name="nut"><config key="radius" value="{BOLT_RADIUS!r}"/></instance></plugin>
    <plugin plugin="mujoco.sdf.bolt"><instance name="bolt"><config key="radius" value="{BOLT_RADIUS!r}"/></instance></plugin>
  </extension>
  <compiler autolimits="true"/>
  <asset>
    <mesh name="nut"><plugin instance="nut"/></mesh>
    <mesh name="bolt"><plugin instance="bolt"/></mesh>
  </asset>
  <option timestep="{dt!r}" sdf_iterations="{int(sdf_iterations)}" sdf_initpoints="{int(sdf_initpoints)}"/>
  <default><geom solref="0.01 1" solimp=".95 .99 .0001" friction="{friction!r}"/></default>
  <worldbody>
    <body name="nut" pos="0 0 {NUT_Z0!r}">
      <freejoint name="nut"/>
      <geom type="sdf" name="nut" mesh="nut" euler="180 0 0"><plugin instance="nut"/></geom>
    </body>
    <body name="bolt" euler="180 0 0">
      <geom type="sdf" name="bolt" mesh="bolt"><plugin instance="bolt"/></geom>
    </body>
  </worldbody>
  <actuator><velocity name="spin" joint="nut" gear="0 0 0 0 0 1" kv="{kv!r}"/></actuator>
</mujoco>""".replace('<freejoint name="nut"/>', f'<joint name="nut" type="free" damping="{damping!r}"/>')


def NutOnBolt(dt=0.002, sdf_iterations=15, sdf_initpoints=60, friction=0.01, damping=30.0, spin_time=0.05):
    """Compiled (model, data) of the nut on the bolt; the velocity actuator's gain kv is set to
    J_z / spin_time (J_z: the nut's moment of inertia about the axis, from the SDF mesh), so the
    spin follows its command with the time constant spin_time [s]."""
    if not (dt > 0 and spin_time > 0):
        raise ValueError(f"NutOnBolt: dt and spin_time must be > 0; got dt={dt!r}, spin_time={spin_time!r}")
    probe = mujoco.MjModel.from_xml_string(_nut_xml(dt, 1.0, sdf_iterations, sdf_initpoints, friction, damping))
    b = probe.body("nut").id
    R = np.zeros(9)
    mujoco.mju_quat2Mat(R, probe.body_iquat[b])
    R = R.reshape(3, 3)
    J = R @ np.diag(probe.body_inertia[b]) @ R.T          # inertia in the body frame (= world axes)
    kv = float(J[2, 2]) / spin_time
    model = mujoco.MjModel.from_xml_string(_nut_xml(dt, kv, sdf_iterations, sdf_initpoints, friction, damping))
    return model, mujoco.MjData(model)


def SpinNut(model, data, omega, t_end, record=True):
    """Drive the nut's spin at omega [rad/s] (about +z) for t_end [s]. Returns dict: wall_s, cpu_s
    (wall and CPU time of the stepping only), steps, t, angle (unwrapped yaw [rad]), z (height of the nut's frame
    [m]) at every step (record=True) or at the start and the end only (record=False: one
    ``mj_step(..., nstep)`` call, for timing), xy_drift (largest distance of the nut from the axis
    [m], NaN without record)."""
    b = model.body("nut").id
    data.ctrl[0] = omega
    n = int(round(t_end / model.opt.timestep))
    rows = []
    drift = 0.0 if record else float("nan")

    def state():
        q = data.xquat[b]
        yaw = math.atan2(2.0 * (q[0] * q[3] + q[1] * q[2]), 1.0 - 2.0 * (q[2] ** 2 + q[3] ** 2))
        rows.append((data.time, yaw, data.xpos[b, 2]))

    mujoco.mj_forward(model, data)
    state()
    t0, c0 = time.perf_counter(), time.process_time()
    if record:
        for _ in range(n):
            mujoco.mj_step(model, data)
            state()
            drift = max(drift, math.hypot(data.xpos[b, 0], data.xpos[b, 1]))
    else:
        mujoco.mj_step(model, data, nstep=n)
        state()
    wall, cpu = time.perf_counter() - t0, time.process_time() - c0
    A = np.array(rows)
    return dict(wall_s=wall, cpu_s=cpu, steps=n, t=A[:, 0], angle=np.unwrap(A[:, 1]), z=A[:, 2], xy_drift=drift)
