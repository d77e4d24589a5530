"""What the scenes' trajectory plots share, after matplotlib's conventions (a plot function takes
``ax=None``: None makes a new figure with one Axes; it draws into the Axes and returns it): the
Axes, the rows drawn (at most PLOT_VERTICES), the nets' lines, a legend note, and the gid of a
closed form's line (CLOSED_FORM_GID). matplotlib is imported where a figure is made."""
from __future__ import annotations

import math

import numpy as np

CLOSED_FORM_GID = "closed_form"
NET_STYLES = ({"color": "0.82", "lw": 0.7, "ls": "-"}, {"color": "0.6", "lw": 0.7, "ls": "--"})


def axes_of(ax, figsize=(5.5, 5.0)):
    if ax is not None:
        return ax
    import matplotlib.pyplot as plt
    return plt.subplots(figsize=figsize)[1]


def nice_step(span, count):
    """A 1-2-5 step giving about ``count`` intervals over ``span`` (> 0)."""
    raw = span / max(count, 1)
    exp = math.floor(math.log10(raw))
    for m in (1.0, 2.0, 5.0, 10.0):
        if m * 10.0 ** exp >= raw:
            return m * 10.0 ** exp
    return 10.0 ** (exp + 1)


def finite_rows(*arrays):
    """The arrays as float arrays, restricted to the rows where all are finite."""
    a = [np.asarray(x, dtype=float) for x in arrays]
    keep = np.all([np.isfinite(x) for x in a], axis=0)
    return [x[keep] for x in a]


# the most vertices a drawn line gets: matplotlib's legend placement (loc="best") tests every vertex,
# which made the plot the largest per-step cost of a command-line run (block, 6000 samples: 120 us
# per sample, against 30 us for the solve); 2000 vertices are far below a figure's resolution
PLOT_VERTICES = 2000


def drawn(*arrays):
    """Every k-th row of the arrays (and the last), at most PLOT_VERTICES rows: for drawing only."""
    n = len(arrays[0])
    if n <= PLOT_VERTICES:
        return arrays
    rows = np.unique(np.r_[np.arange(0, n, -(-n // PLOT_VERTICES)), n - 1])
    return [np.asarray(x)[rows] for x in arrays]


def add_net(ax, segments, style, label):
    """The net lines as one LineCollection under everything else (it does not change the limits)."""
    from matplotlib.collections import LineCollection
    ax.add_collection(LineCollection(segments, colors=style["color"], linewidths=style["lw"],
                                     linestyles=style["ls"], zorder=0, label=label), autolim=False)


def polar_net(centre, half):
    """Segments of rays and circles about the origin that cover the square centre +- half."""
    cx, cy = centre
    dist = math.hypot(cx, cy)
    reach = 1.05 * half * math.sqrt(2.0)        # the square's circumcircle
    r_lo, r_hi = max(dist - reach, 0.0), dist + reach
    dr = nice_step(2.0 * half, 12)
    radii = np.arange(math.ceil(r_lo / dr), math.floor(r_hi / dr) + 1) * dr
    radii = radii[radii > 0.0]
    if dist > reach:       # origin outside the view: rays and arcs only over the angles seen from it
        width = 2.0 * math.asin(min(reach / dist, 1.0))
        phi0 = math.atan2(cy, cx)
    else:
        width, phi0 = 2.0 * math.pi, 0.0
    dphi = math.radians(nice_angle(math.degrees(width) / (24.0 if dist <= reach else 10.0)))
    k = np.arange(math.floor((phi0 - 0.5 * width) / dphi), math.ceil((phi0 + 0.5 * width) / dphi) + 1)
    segs = [np.array([[r_lo * math.cos(p), r_lo * math.sin(p)], [r_hi * math.cos(p), r_hi * math.sin(p)]])
            for p in k * dphi]
    t = np.linspace(phi0 - 0.5 * width, phi0 + 0.5 * width, 361)
    segs += [np.column_stack([r * np.cos(t), r * np.sin(t)]) for r in radii]
    return segs


def nice_angle(deg):
    for step in (90, 45, 30, 15, 10, 5, 2, 1, 0.5, 0.2, 0.1, 0.05, 0.02, 0.01):
        if step <= deg:
            return float(step)
    return nice_step(deg, 1)


def line_net(centre, half, angle):
    """Segments of the lines along e1 = (cos a, sin a) that cover the square centre +- half."""
    e1 = np.array([math.cos(angle), math.sin(angle)])
    n = np.array([-e1[1], e1[0]])
    c = np.asarray(centre, dtype=float)
    reach = 1.05 * half * math.sqrt(2.0)
    ds = nice_step(2.0 * half, 12)
    o = float(n @ c)
    segs = []
    for k in np.arange(math.floor((o - reach) / ds), math.ceil((o + reach) / ds) + 1):
        base = n * (k * ds) + e1 * float(e1 @ c)
        segs.append(np.array([base - reach * e1, base + reach * e1]))
    return segs


def note(ax, text):
    """A legend entry without a line: a statement about the plot."""
    ax.plot([], [], ls="none", label=text)


def labelled(ax, xlabel, ylabel):
    """The Axes ax with its axis labels and a legend (the small font the scenes' plots use); returns it."""
    ax.set_xlabel(xlabel)
    ax.set_ylabel(ylabel)
    ax.legend(loc="best", fontsize=7)
    return ax
