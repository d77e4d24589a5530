"""Plots of a scene's trajectory, after matplotlib's conventions: every function takes ``ax=None``
(None: a new figure with one Axes), draws into that Axes and returns it.

* ``PlotBlockPath(traj, params, ax=None)``: the block's centre path in the plane, over the net of
  its adhesion and friction fields (polar: rays and circles about the origin; cartesian: lines
  along direction 1), with the start, the end and the polar origin marked;
* ``PlotScrewAdvance(traj, params, ax=None)``: axial position z [mm] against rotation [rev] with the
  closed-form steady-sliding advance per revolution (``exu_aniso.scenes.screw.steady_sliding``) as a
  straight line through the last point, and the thread pitch for comparison;
* ``PlotScrewTorque(traj, params, ax=None)``: drive torque [N m] against time [s] with the
  closed-form sliding torque as a horizontal line.

``traj`` is a trajectory dict of either engine (``Result.trajectory``) or the columns of
trajectory.csv; ``params`` the BlockParams / ScrewParams of the run. Where the closed form does
not exist (the seed map, the axial drive, an axial load beyond the friction capacity) the legend
says why instead of drawing a line. The closed-form lines carry ``gid="closed_form"``.
"""
from __future__ import annotations

import math

import numpy as np

CLOSED_FORM_GID = "closed_form"
NET_STYLES = ({"color": "0.82", "lw": 0.7, "ls": "-"}, {"color": "0.6", "lw": 0.7, "ls": "--"})


def _axes(ax, figsize=(5.5, 5.0)):
    if ax is not None:
        return ax
    import matplotlib.pyplot as plt
    return plt.subplots(figsize=figsize)[1]


def _nice_step(span, count):
    """A 1-2-5 step giving about ``count`` intervals over ``span`` (> 0)."""
    raw = span / max(count, 1)
    exp = math.floor(math.log10(raw))
    for m in (1.0, 2.0, 5.0, 10.0):
        if m * 10.0 ** exp >= raw:
            return m * 10.0 ** exp
    return 10.0 ** (exp + 1)


def _finite(*arrays):
    """The arrays as float arrays, restricted to the rows where all are finite."""
    a = [np.asarray(x, dtype=float) for x in arrays]
    keep = np.all([np.isfinite(x) for x in a], axis=0)
    return [x[keep] for x in a]


# the most vertices a drawn line gets: matplotlib's legend placement (loc="best") tests every vertex,
# which made the plot the largest per-step cost of a command-line run (block, 6000 samples: 120 us
# per sample, against 30 us for the solve); 2000 vertices are far below a figure's resolution
PLOT_VERTICES = 2000


def _drawn(*arrays):
    """Every k-th row of the arrays (and the last), at most PLOT_VERTICES rows: for drawing only."""
    n = len(arrays[0])
    if n <= PLOT_VERTICES:
        return arrays
    rows = np.unique(np.r_[np.arange(0, n, -(-n // PLOT_VERTICES)), n - 1])
    return [np.asarray(x)[rows] for x in arrays]


# ----------------------------------------------------------------------------------------------
# block

def _block_nets(params):
    """[(kind, angle [rad], label)] of the distinct non-isotropic nets of adhesion B and friction F."""
    nets = []
    for name, kind, angle in (("B", params.adhesion, params.adhesion_angle),
                              ("F", params.friction, params.friction_angle)):
        if kind == "isotropic":
            continue
        a = math.radians(angle) if kind == "cartesian" else 0.0
        for i, (k0, a0, names) in enumerate(nets):
            same_lines = math.isclose(math.remainder(a - a0, math.pi), 0.0, abs_tol=1e-12)
            if k0 == kind and (kind == "polar" or same_lines):
                nets[i] = (k0, a0, names + [name])
                break
        else:
            nets.append((kind, a, [name]))
    out = []
    for kind, a, names in nets:
        who = " and ".join(names)
        if kind == "polar":
            out.append((kind, a, f"{who} net: polar (rays e1, circles e2)"))
        else:
            out.append((kind, a, f"{who} net: lines along e1 ({math.degrees(a):.4g} deg)"))
    return out


def _add_net(ax, segments, style, label):
    """The net lines as one LineCollection under everything else (it does not change the limits)."""
    from matplotlib.collections import LineCollection
    ax.add_collection(LineCollection(segments, colors=style["color"], linewidths=style["lw"],
                                     linestyles=style["ls"], zorder=0, label=label), autolim=False)


def _polar_net(centre, half):
    """Segments of rays and circles about the origin that cover the square centre +- half."""
    cx, cy = centre
    dist = math.hypot(cx, cy)
    reach = 1.05 * half * math.sqrt(2.0)        # the square's circumcircle
    r_lo, r_hi = max(dist - reach, 0.0), dist + reach
    dr = _nice_step(2.0 * half, 12)
    radii = np.arange(math.ceil(r_lo / dr), math.floor(r_hi / dr) + 1) * dr
    radii = radii[radii > 0.0]
    if dist > reach:       # origin outside the view: rays and arcs only over the angles seen from it
        width = 2.0 * math.asin(min(reach / dist, 1.0))
        phi0 = math.atan2(cy, cx)
    else:
        width, phi0 = 2.0 * math.pi, 0.0
    dphi = math.radians(_nice_angle(math.degrees(width) / (24.0 if dist <= reach else 10.0)))
    k = np.arange(math.floor((phi0 - 0.5 * width) / dphi), math.ceil((phi0 + 0.5 * width) / dphi) + 1)
    segs = [np.array([[r_lo * math.cos(p), r_lo * math.sin(p)], [r_hi * math.cos(p), r_hi * math.sin(p)]])
            for p in k * dphi]
    t = np.linspace(phi0 - 0.5 * width, phi0 + 0.5 * width, 361)
    segs += [np.column_stack([r * np.cos(t), r * np.sin(t)]) for r in radii]
    return segs


def _nice_angle(deg):
    for step in (90, 45, 30, 15, 10, 5, 2, 1, 0.5, 0.2, 0.1, 0.05, 0.02, 0.01):
        if step <= deg:
            return float(step)
    return _nice_step(deg, 1)


def _line_net(centre, half, angle):
    """Segments of the lines along e1 = (cos a, sin a) that cover the square centre +- half."""
    e1 = np.array([math.cos(angle), math.sin(angle)])
    n = np.array([-e1[1], e1[0]])
    c = np.asarray(centre, dtype=float)
    reach = 1.05 * half * math.sqrt(2.0)
    ds = _nice_step(2.0 * half, 12)
    o = float(n @ c)
    segs = []
    for k in np.arange(math.floor((o - reach) / ds), math.ceil((o + reach) / ds) + 1):
        base = n * (k * ds) + e1 * float(e1 @ c)
        segs.append(np.array([base - reach * e1, base + reach * e1]))
    return segs


def PlotBlockPath(traj, params, ax=None):
    """The block's centre path (x, y) over the field net, start and end marked, and the polar
    origin when a field is polar; equal axes. Returns the Axes."""
    ax = _axes(ax)
    x, y = _finite(traj["x"], traj["y"])
    nets = _block_nets(params)
    polar = any(kind == "polar" for kind, _, _ in nets)
    origin_in_view = polar
    if x.size:
        xs, ys = list(x), list(y)
        origin_in_view = polar and math.hypot(x[0], y[0]) < 20.0 * max(np.ptp(x), np.ptp(y), params.size)
        if origin_in_view:            # keep the origin in view unless it is far away
            xs.append(0.0)
            ys.append(0.0)
        lo, hi = np.array([min(xs), min(ys)]), np.array([max(xs), max(ys)])
        centre = 0.5 * (lo + hi)
        half = 0.5 * max(hi[0] - lo[0], hi[1] - lo[1], params.size) * 1.12
        for (kind, angle, label), style in zip(nets, NET_STYLES):
            segments = _polar_net(centre, half) if kind == "polar" else _line_net(centre, half, angle)
            _add_net(ax, segments, style, label)
        ax.plot(*_drawn(x, y), "-", color="C0", lw=1.6, label="centre path", zorder=3)
        ax.plot(x[0], y[0], "o", color="C2", label="start", zorder=4)
        ax.plot(x[-1], y[-1], "s", color="C3", ms=5, label="end", zorder=4)
        # the view: the padded square box around the path (and the origin); the net reaches beyond it
        ax.set_xlim(centre[0] - half, centre[0] + half)
        ax.set_ylim(centre[1] - half, centre[1] + half)
    if origin_in_view:
        ax.plot(0.0, 0.0, "k+", ms=12, mew=2, label="polar origin", zorder=4, scalex=False, scaley=False)
    elif polar:
        _note(ax, "polar origin (0, 0) out of view")
    if not nets:
        ax.plot([], [], ls="none", label="isotropic B and F: no net")
    ax.set_xlabel("x [m]")
    ax.set_ylabel("y [m]")
    ax.set_aspect("equal", adjustable="box")
    ax.legend(loc="best", fontsize=7)
    return ax


# ----------------------------------------------------------------------------------------------
# screw

def screw_closed_form(params):
    """(SteadySliding or None, reason text when None) for the screw parameters ``params``."""
    from exu_aniso.scenes.screw import steady_sliding
    if params.return_map == "seed":
        return None, "seed map: no closed form (its steady state depends on dt)"
    if params.drive == "axial":
        return None, "axial drive: no closed form (steady sliding is for the rotation and torque drives)"
    try:
        return steady_sliding(params), ""
    except ValueError as e:
        return None, f"no closed form: {e}"


def _note(ax, text):
    """A legend entry without a line: a statement about the plot."""
    ax.plot([], [], ls="none", label=text)


def PlotScrewAdvance(traj, params, ax=None):
    """Axial position z [mm] against rotation [rev], with the closed form's advance per revolution
    (radial/exact map) as a straight line through the last point, and the thread pitch dotted.
    Returns the Axes."""
    ax = _axes(ax, figsize=(6.0, 4.0))
    rev, z = _finite(np.asarray(traj["angle"], dtype=float) / (2.0 * math.pi),
                     np.asarray(traj["z"], dtype=float) * 1e3)
    ax.plot(*_drawn(rev, z), "-", color="C0", lw=1.6, label=f"screw ({params.return_map} map)")
    st, why = screw_closed_form(params)
    if rev.size:
        xr = np.array([min(rev.min(), 0.0), max(rev.max(), 0.0)])
        if xr[1] - xr[0] <= 0.0:
            xr = np.array([rev[-1] - 0.5, rev[-1] + 0.5])
        from exu_aniso.scenes.screw import pitch
        p_mm = pitch(params) * 1e3
        ax.plot(xr, z[-1] + p_mm * (xr - rev[-1]), ls=":", color="0.5", lw=1.0, gid="pitch",
                label=f"thread pitch {p_mm:.4g} mm/rev")
        if st is not None and rev[-1] < 0.0 and params.axial_load != 0.0:
            st, why = None, "no closed form: it is for positive rotation (axial load breaks the symmetry)"
        if st is not None:
            k = st.advance_per_rev * 1e3
            ax.plot(xr, z[-1] + k * (xr - rev[-1]), "--", color="C3", lw=1.2, gid=CLOSED_FORM_GID,
                    label=f"closed form, steady sliding: {k:.4g} mm/rev")
    if st is None:
        _note(ax, why)
    ax.set_xlabel("rotation [rev]")
    ax.set_ylabel("axial position z [mm]")
    ax.legend(loc="best", fontsize=7)
    return ax


def PlotScrewTorque(traj, params, ax=None):
    """Drive torque [N m] against time [s] with the closed form's sliding torque (radial/exact map)
    as a horizontal line. Returns the Axes."""
    ax = _axes(ax, figsize=(6.0, 4.0))
    t, tau = _finite(traj["t"], traj["torque"])
    ax.plot(*_drawn(t, tau), "-", color="C0", lw=1.2, label=f"drive torque ({params.drive} drive)")
    st, why = screw_closed_form(params)
    sign = -1.0 if t.size and np.mean(tau) < 0.0 else 1.0     # a screw driven backwards
    if st is not None and sign < 0.0 and params.axial_load != 0.0:
        st, why = None, "no closed form: it is for positive rotation (axial load breaks the symmetry)"
    if st is not None and t.size:
        ax.plot([float(t[0]), float(t[-1])], [sign * st.torque] * 2, "--", color="C3", lw=1.2,
                gid=CLOSED_FORM_GID, label=f"closed-form sliding torque {sign * st.torque:.4g} N m")
    elif st is None:
        _note(ax, why)
    ax.set_xlabel("t [s]")
    ax.set_ylabel("torque [N m]")
    ax.legend(loc="best", fontsize=7)
    return ax
