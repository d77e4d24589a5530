"""The fastening scene's phases after the tightening, from its trajectory: the untightening's
break-loose torque (``break_loose``, when the driver turns back) and a nutrunner's shut-off and torque
overshoot (``shutoff``), each against its closed form. ``exu_aniso.scenes.fastening``'s summary adds
their entries; read its module docstring for the scene.
"""
from __future__ import annotations

import math

import numpy as np

from exu_aniso.scenes import threads

BREAK_LOOSE_TURN = 1.0      # deg: the bolt has broken loose once it turned back this far after the torque's peak


def break_loose(p, t, angle, clamp_force, torque, undefined):
    """The untightening's entries of the summary when the driver turns back (reverse_time > 0; else
    none): ``break_loose_torque`` [N m], the largest torque against the turning back (the drive
    torque's most negative value after reverse_time, as a magnitude), ``break_loose_clamp_force`` [N] at
    that sample, and its closed forms with that clamp force: ``break_loose_torque_theory``, the thread
    carrying the clamp force and axial_load, (F + F_a) thread_loosening_torque_per_force + F mu_head
    r_K, and ``break_loose_torque_vdi2230``, VDI 2230's linearized loosening torque with the same
    forces. None, with the reason added to ``undefined``, where the bolt did not turn back
    BREAK_LOOSE_TURN after the peak by the end of the run, or a closed form does not apply (the net; an
    orthotropic head or, under another map than the exact one, flank)."""
    if p.reverse_time == 0.0:
        return {}
    keys = ("break_loose_torque", "break_loose_clamp_force", "break_loose_torque_theory", "break_loose_torque_vdi2230")
    after = np.flatnonzero(t > p.reverse_time)
    j = after[np.argmin(torque[after])] if len(after) else None
    turned = None if j is None else math.degrees(angle[j] - angle[-1])
    if j is None or torque[j] >= 0.0 or turned < BREAK_LOOSE_TURN:
        why = ("the bolt did not break loose by the end of the run: "
               + ("no torque against it after reverse_time" if j is None or torque[j] >= 0.0 else
                  f"it turned back {turned:.3g} deg after the torque's peak, less than {BREAK_LOOSE_TURN:g} deg")
               + "; run longer after reverse_time (t_end)")
        undefined.update({k: why for k in keys})
        return {k: None for k in keys}
    Tb, Fb = float(-torque[j]), float(clamp_force[j])
    out = dict(break_loose_torque=Tb, break_loose_clamp_force=Fb)
    beta = math.radians(p.flank_angle)
    why = None
    if p.thread == "net":
        why = "thread=net: the loosening formula is a flank's (normal force from the load)"
    elif p.head_net != "isotropic":
        why = "the loosening formula is for an isotropic head bearing"
    elif p.thread_net == "orthotropic" and p.return_map != "exact":
        why = f"orthotropic flank under the {p.return_map!r} map: the formula is checked for the exact map"
    if why is not None:
        undefined.update(break_loose_torque_theory=why, break_loose_torque_vdi2230=why)
        return dict(out, break_loose_torque_theory=None, break_loose_torque_vdi2230=None)
    thread = threads.thread_loosening_torque_per_force(p.d2, p.pitch, beta, p.mu_thread)
    vdi_thread = threads.loosening_torque_per_clamp_force_vdi2230(p.d2, p.pitch, p.mu_thread, 0.0, 0.0)
    head = p.mu_head * p.head_radius * Fb
    return dict(out, break_loose_torque_theory=(Fb + p.axial_load) * thread + head,
                break_loose_torque_vdi2230=(Fb + p.axial_load) * vdi_thread + head)


STOPPED_SPEED = 1e-3        # the bolt has stopped after a shut-off below this share of its shut-off speed
ISO5393_HARD_DEG = 30.0     # ISO 5393: a hard joint reaches the target torque within 30 deg from half of it,
ISO5393_SOFT_DEG = 720.0    # a soft joint within 720 deg


def shutoff(p, t, omega, torque, joint_torque, drive_on, closed, undefined, J):
    """A nutrunner's entries of the summary (tool='nutrunner'; else none): when it shut off
    (``shutoff_time`` [s]), the torque it holds (``shutoff_torque_held`` [N m]) and the bolt's speed then
    (``shutoff_speed`` [rad/s]), the joint's peak torque after it (``peak_torque`` [N m]: thread and
    head) and the overshoot (``torque_overshoot`` [N m]) against the closed form ``torque_overshoot_theory``
    = omega sqrt(J k_T): the rotating inertia's kinetic energy J omega^2 / 2 wound into a joint whose
    torque rises by k_T per radian (k_T = T/F dF/dangle, the closed forms ``closed``; J [kg m^2] the bolt's
    and the tool's inertia about the axis) while the tool holds its torque; and the joint's ISO 5393 class from
    the angle in which it climbs from half the held torque to all of it, T / (2 k_T): ``joint_class``
    hard (<= 30 deg), soft (>= 720 deg) or between, with ``joint_angle_half_to_full`` [deg]."""
    if p.tool != "nutrunner":
        return {}
    keys = ("shutoff_time", "shutoff_torque_held", "shutoff_speed", "peak_torque", "torque_overshoot",
            "torque_overshoot_theory", "joint_angle_half_to_full", "joint_class")
    off = np.flatnonzero(np.asarray(drive_on) < 0.5)
    if len(off) == 0:
        why = "the nutrunner did not shut off within the run: run longer (t_end) or shut off sooner"
        undefined.update({k: why for k in keys})
        return {k: None for k in keys}
    i = off[0] - 1                     # the last sample with the drive running: the shut-off state
    Ts, ws = float(torque[off[0]]), float(omega[i])
    if not np.min(omega[off[0]:]) <= STOPPED_SPEED * abs(ws):
        why = ("the run ended before the bolt stopped after the shut-off (its torque's peak not reached yet): run "
               "longer (t_end)")
        undefined.update({k: why for k in keys[3:]})
        return dict(shutoff_time=float(t[i]), shutoff_torque_held=Ts, shutoff_speed=ws,
                    **{k: None for k in keys[3:]})
    peak = float(np.max(joint_torque[off[0]:]))
    out = dict(shutoff_time=float(t[i]), shutoff_torque_held=Ts, shutoff_speed=ws, peak_torque=peak,
               torque_overshoot=peak - Ts)
    T_per_F, S = closed.get("torque_per_clamp_force_theory"), closed.get("clamp_force_per_angle_theory")
    if T_per_F is None or S is None:
        why = "the joint's torque rate T/F dF/dangle has no closed form here (see their entries)"
        undefined.update(torque_overshoot_theory=why, joint_angle_half_to_full=why, joint_class=why)
        return dict(out, torque_overshoot_theory=None, joint_angle_half_to_full=None, joint_class=None)
    k_T = T_per_F * S
    half = math.degrees(0.5 * Ts / k_T)
    return dict(out, torque_overshoot_theory=ws * math.sqrt(J * k_T), joint_angle_half_to_full=half,
                joint_class="hard" if half <= ISO5393_HARD_DEG else "soft" if half >= ISO5393_SOFT_DEG else "between")
