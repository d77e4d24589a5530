"""Renderer graphics of a contact set: the master surface with its net, the contact points coloured
by state and (optionally) traction arrows, in Exudyn's live renderer and in the SolutionViewer.

``AddContactGraphics(mbs, contact)`` attaches a ``graphicsDataUserFunction`` to the contact's
``ObjectGenericODE2``. Exudyn calls it only when the scene is drawn (a renderer redraw, the
SolutionViewer, ``SC.renderer.GetGraphicsData()`` or ``RedrawAndGetImage``), never from the solver,
so graphics cost nothing during a solve. It reads the state it draws from
``exu.ConfigurationType.Visualization``: during a live simulation the solver copies its whole state
(ODE2 coordinates and the data coordinates that hold the contact history) there at each graphics
update; the SolutionViewer loads each stored row there (``exudyn.utilities.SetSolutionState``).

For the SolutionViewer the solution file must hold the data coordinates (the history, 9 numbers per
point): ``simulationSettings.solution.file.write = True`` and
``simulationSettings.solution.file.export.dataCoordinates = True``, both Exudyn 1.13.6 defaults (the
scenes' ``SimulationSettingsFor`` switches the file off). Without them the points are drawn at the
stored positions, but with whatever state the Visualization configuration held before. Without a
running renderer, ``SC.renderer.GetGraphicsData()`` and ``RedrawAndGetImage(useRaytracer=True)``
first copy the Current state into the Visualization configuration (Exudyn 1.13.6, measured), so
they show the Current state.

What is drawn (global coordinates; a moving master's surface in the master body's current pose):

* the master surface: a translucent face and the net of the field that sets the anisotropy (the
  adhesion field unless it is isotropic, then the friction field; a polar field on either wins).
  Lines along e1 of the field are drawn in ``NET_COLORS[0]``, lines along e2 in ``NET_COLORS[1]``:

  - Plane, polar field (or an isotropic field on ``Plane("polar")``): a disk about the polar origin
    with rays (e1 = e_r, every 15 deg) through the origin and circles (e2 = e_phi) centred at it;
  - Plane, other fields: a square aligned with e1 (orthotropic: at the field's angle; a field from
    a matrix: its principal axis of the larger eigenvalue; isotropic: e_x) with the coordinate grid
    lines of that frame;
  - Cylinder (hole or shaft, any axis): a tube with two families of helices on it, e1 at the field's
    angle from e_phi towards e_axis (spiral field: the helix angle ``TensorField.angle``;
    orthotropic: its angle) and e2 at 90 deg to it; an isotropic field gives the phi lines (circles)
    and z lines (generatrices). A family that would wind more than ``MAX_TURNS`` times over the
    drawn length is drawn as circles (it is indistinguishable from them at that density).

  The net lines lie exactly on the surface; the face lies ``FACE_OFFSET`` * L behind it (on the
  master side) so that the lines are not hidden in it (depth fighting).
* the contact points (slave points S) as spheres coloured by the history column ``status`` of the
  drawn configuration: ``STATUS_COLORS`` (open grey, stick green, slip red);
* with ``showTraction``: at each loaded point an arrow of the force the master exerts on the slave
  point, ``E T - N n`` (T: history ``traction_1``, ``traction_2`` in the orthonormal tangent frame
  E = [a_1, a_2] of the contact point, ``ContactLaw.traction_frames``; N <= 0: history ``normal``;
  n: surface normal), times tractionScale.

Drawing rules by surface class (``_DRAWINGS``): the Plane (a polar disk or a grid) and the Cylinder
(a tube with helices); every other surface of the protocol is drawn from its chart
(``_chart_patch``: a face and the coordinate lines, inside the surface's ``limits``).

Scene size (computed once, from the slave points in the master frame at the nodes' initial
coordinates, and cached with all static geometry): the body length a = the largest of the points'
diameter (largest distance between two points), twice their largest distance from the slave body's
origin and 0.1 times the distance of their centroid from the surface's origin (1 m if all three are
zero). Then the scene length L is

* polar plane: the disk radius, max_k |x_k| (in-plane distance from the polar origin) + a;
* other planes: the square's half-width, ``GRID_HALF_WIDTH`` * a, centred at the points' centroid;
* cylinder: the tube's half-length, half the points' extent along the axis + ``CYLINDER_MARGIN`` * R,
  centred at the middle of that extent;

``size`` replaces L. Sphere radius = min(``POINT_RADIUS`` * L, 0.25 * the smallest distance
between two points). Default tractionScale [m/N] = ``ARROW_LENGTH`` * L / max_k |N_k| with N_k the
normal traction of the initial history (points in contact at the start, ``initializeHistory``); if
no point carries load there, it is fixed at the first drawn configuration that has a loaded point.
"""
from __future__ import annotations

import math
import numbers

import exudyn as exu
import numpy as np
from exudyn import graphics

from exu_aniso.law.history import HISTORY_FIELDS, OPEN, SLIP, STICK
from exu_aniso.geometry import Cylinder, Plane
from exu_aniso.util.validation import check_bool, check_instance

_WHERE = "AddContactGraphics"
_VIS = exu.ConfigurationType.Visualization
_STATUS = HISTORY_FIELDS.index("status")
_TRACTION = [HISTORY_FIELDS.index("traction_1"), HISTORY_FIELDS.index("traction_2")]
_NORMAL = HISTORY_FIELDS.index("normal")
_CONTACT_KEYS = ("oContact", "law", "points", "masterBodyNumber", "pointsAndMasterPose", "historyAt",
                 "bodyPosition")

# colours (RGBA)
STATUS_COLORS = {OPEN: (0.6, 0.6, 0.6, 1.0), STICK: (0.0, 0.75, 0.0, 1.0), SLIP: (0.9, 0.0, 0.0, 1.0)}
UNKNOWN_STATUS_COLOR = (1.0, 0.0, 1.0, 1.0)    # not in a committed history (unresolved steps are rejected)
SURFACE_COLOR = (0.55, 0.65, 0.8, 0.35)        # translucent face
NET_COLORS = ((0.1, 0.2, 0.65, 1.0), (0.45, 0.55, 0.7, 1.0))   # lines along e1, lines along e2
TRACTION_COLOR = (1.0, 0.55, 0.0, 1.0)

# scene-size rule (module docstring)
GRID_HALF_WIDTH = 2.0        # square half-width / a
CYLINDER_MARGIN = 2.0        # tube half-length beyond the points' axial extent / R
POINT_RADIUS = 0.03          # sphere radius / L (at most a quarter of the closest point spacing)
FACE_OFFSET = 2e-3           # face behind the surface / L
ARROW_LENGTH = 0.2           # arrow of the expected largest force / L
MAX_TURNS = 100              # windings over the drawn length above which a helix family is drawn as circles

_RAYS = 24                   # polar rays (every 15 deg)
_CIRCLE_SEGMENTS = 96        # segments of a full circle (net lines and the polar disk)
_TUBE_SEGMENTS = 48          # segments of the tube face around the axis
_TUBE_LINES = 24             # generatrices of an isotropic cylinder net (sets the line spacing)


# ----------------------------------------------------------------------------------------------
# argument checks

def _positive_or_none(name, value):
    if value is None:
        return None
    if isinstance(value, bool) or not isinstance(value, (numbers.Real, np.floating, np.integer)):
        raise TypeError(f"{_WHERE}: {name} must be a number > 0 or None; "
                        f"got {value!r} ({type(value).__name__})")
    if not math.isfinite(float(value)):
        raise ValueError(f"{_WHERE}: {name} must be a finite number > 0; got {value!r}")
    if not float(value) > 0.0:
        raise ValueError(f"{_WHERE}: {name} must be > 0; got {value!r}")
    return float(value)


def _rgba(name, value, default):
    """An RGB or RGBA colour (3 or 4 numbers in [0, 1]); RGB gets the default's alpha."""
    try:
        c = np.asarray(value, dtype=float)
    except (TypeError, ValueError):
        c = None
    if c is None or c.ndim != 1 or c.shape[0] not in (3, 4) or not np.all(np.isfinite(c)) \
            or np.any(c < 0.0) or np.any(c > 1.0):
        shape = "" if c is None or c.shape in ((3,), (4,)) else f" (shape {c.shape})"
        raise ValueError(f"{_WHERE}: {name} must be an RGB or RGBA list of 3 or 4 numbers in [0, 1]; "
                         f"got {value!r}{shape}")
    if c.shape[0] == 3:
        c = np.append(c, default[3])
    return tuple(float(v) for v in c)


# ----------------------------------------------------------------------------------------------
# geometry helpers (all in the master frame)

def _nice_step(x):
    """The largest of 1, 2, 5 times a power of ten that is <= x (x > 0)."""
    e = 10.0 ** math.floor(math.log10(x))
    for m in (5.0, 2.0, 1.0):
        if m * e <= x * (1.0 + 1e-12):
            return m * e
    return e


def _segments(polyline):
    """Consecutive point pairs (2 (m-1), 3) of a polyline (m, 3): the rows of a 'Lines' item."""
    p = np.asarray(polyline, dtype=float)
    return np.stack([p[:-1], p[1:]], axis=1).reshape(-1, 3)


def _lines(pairs, color):
    """One 'Lines' item from a list of point-pair arrays (segments), all in one colour."""
    pts = np.concatenate(pairs) if pairs else np.zeros((0, 3))
    colors = np.tile(np.asarray(color, dtype=float), (len(pts), 1))
    return {"type": "Lines", "shape": "linear", "points": pts, "colors": colors}


def _face(points, triangles, normal, color):
    """TriangleList with per-point normals; triangles turned so that their corners run counter-clockwise
    about the normal."""
    points = np.asarray(points, dtype=float)
    tri = np.array(triangles, dtype=int)
    normal = np.broadcast_to(np.asarray(normal, dtype=float), points.shape)
    a, b, c = points[tri[:, 0]], points[tri[:, 1]], points[tri[:, 2]]
    flip = np.einsum("ij,ij->i", np.cross(b - a, c - a), normal[tri[:, 0]]) < 0.0
    tri[flip] = tri[flip][:, [0, 2, 1]]
    return graphics.FromPointsAndTrigs(points, tri, color=list(color), normals=np.array(normal))


def _net_field(law):
    """(kind, angle) of the net to draw: kind 'polar' or 'angle' (lines along e1 at angle [rad] from the
    xi1 coordinate line: plane e_x, cylinder e_phi), from the nets the kernel evaluates."""
    from exu_aniso.fields.nets import OrthotropicNet, PolarNet, SpiralNet
    surf = law.surface
    nets = law.nets
    if any(isinstance(n, PolarNet) for n in nets):
        return "polar", 0.0
    for n in nets:
        if isinstance(n, SpiralNet):   # e1 along rho_1 + lead / (2 pi) rho_2: on a cylinder atan(lead / 2 pi R)
            return "angle", math.atan2(n.lead, 2.0 * math.pi * getattr(surf, "radius", 1.0))
        if isinstance(n, OrthotropicNet) and n.l1 != n.l2:
            return "angle", float(n.angle)
    if getattr(surf, "coordinates", None) == "polar":
        return "polar", 0.0
    return "angle", 0.0


def _body_length(X, origin, centroid_distance):
    """Characteristic length a of the slave body (module docstring)."""
    diameter = float(np.max(np.linalg.norm(X[:, None, :] - X[None, :, :], axis=-1)))
    arm = float(np.max(np.linalg.norm(X - origin, axis=-1)))
    a = max(diameter, 2.0 * arm, 0.1 * centroid_distance)
    return a if a > 0.0 else 1.0


def _closest_spacing(X):
    d = np.linalg.norm(X[:, None, :] - X[None, :, :], axis=-1)
    d = d[np.triu_indices(len(X), 1)]
    d = d[d > 0.0]
    return float(d.min()) if d.size else math.inf


def _plane_polar(X, a, size, colors, face_color):
    """Disk about the polar origin with rays and circles; returns (items, L)."""
    rho = size if size is not None else float(np.max(np.hypot(X[:, 0], X[:, 1]))) + a
    phi = np.linspace(0.0, 2.0 * np.pi, _CIRCLE_SEGMENTS + 1)
    ring = np.stack([np.cos(phi), np.sin(phi), np.zeros_like(phi)], axis=-1)
    ang = 2.0 * np.pi * np.arange(_RAYS) / _RAYS
    rays = [np.array([[0.0, 0.0, 0.0], [rho * math.cos(t), rho * math.sin(t), 0.0]]) for t in ang]
    step = _nice_step(rho / 8.0)
    radii = step * np.arange(1, int(math.floor(rho / step * (1.0 + 1e-12))) + 1)
    circles = [_segments(r * ring) for r in radii]
    dz = -FACE_OFFSET * rho
    pts = np.vstack([[0.0, 0.0, dz], rho * ring[:-1] + [0.0, 0.0, dz]])
    n = _CIRCLE_SEGMENTS
    tri = [[0, 1 + i, 1 + (i + 1) % n] for i in range(n)]
    face = _face(pts, tri, [0.0, 0.0, 1.0], face_color)
    return [face, _lines(rays, colors[0]), _lines(circles, colors[1])], rho


def _plane_grid(X, a, angle, size, colors, face_color):
    """Square aligned with e1 = (cos angle, sin angle) with the coordinate lines of that frame."""
    e1 = np.array([math.cos(angle), math.sin(angle), 0.0])
    e2 = np.array([-math.sin(angle), math.cos(angle), 0.0])
    h = size if size is not None else GRID_HALF_WIDTH * a
    c = np.array([X[:, 0].mean(), X[:, 1].mean(), 0.0])
    u0, v0 = float(c @ e1), float(c @ e2)          # centre in the (e1, e2) coordinates
    step = _nice_step(h / 6.0)

    def levels(centre):
        k = np.arange(math.ceil((centre - h) / step - 1e-9), math.floor((centre + h) / step + 1e-9) + 1)
        return k * step

    # lines of constant v run along e1, lines of constant u along e2
    along1 = [np.array([(u0 - h) * e1 + v * e2, (u0 + h) * e1 + v * e2]) for v in levels(v0)]
    along2 = [np.array([u * e1 + (v0 - h) * e2, u * e1 + (v0 + h) * e2]) for u in levels(u0)]
    dz = np.array([0.0, 0.0, -FACE_OFFSET * h])
    signs = ((-1, -1), (1, -1), (1, 1), (-1, 1))
    corners = [(u0 + su * h) * e1 + (v0 + sv * h) * e2 + dz for su, sv in signs]
    face = _face(corners, [[0, 1, 2], [0, 2, 3]], [0.0, 0.0, 1.0], face_color)
    return [face, _lines(along1, colors[0]), _lines(along2, colors[1])], h


def _helix_family(R, zlo, zhi, beta, spacing):
    """Polylines (phi, z) of a family of parallel lines at angle beta from e_phi towards e_axis on the
    unrolled tube (arc length R phi, z), z in [zlo, zhi], neighbours about `spacing` apart."""
    cb, sb = math.cos(beta), math.sin(beta)
    if sb < 0.0:                                    # the same family, run upwards
        cb, sb = -cb, -sb
    length = zhi - zlo
    nseg_circle = _CIRCLE_SEGMENTS
    turns = math.inf if sb < 1e-12 else length * abs(cb) / sb / (2.0 * math.pi * R)
    out = []
    if turns > MAX_TURNS:                           # (nearly) circles: phi lines at equal z spacing
        n = max(1, int(round(length / spacing)))
        phi = np.linspace(0.0, 2.0 * np.pi, nseg_circle + 1)
        for z in zlo + (np.arange(n) + 0.5) * length / n:
            out.append((phi, np.full_like(phi, z)))
        return out
    n = max(1, int(round(2.0 * math.pi * R * sb / spacing)))   # starts around the circumference
    T = length / sb                                             # length of each line
    dphi = T * cb / R
    nseg = max(1, int(math.ceil(abs(dphi) / (2.0 * np.pi / nseg_circle))))
    t = np.linspace(0.0, T, nseg + 1)
    for j in range(n):
        out.append((2.0 * np.pi * j / n + t * cb / R, zlo + t * sb))
    return out


def _cylinder(cyl, X, a, angle, size, colors, face_color):
    """Tube about the cylinder axis with two line families (e1 at `angle`, e2 at angle + 90 deg)."""
    R = cyl.radius
    e_ref, e_ref2, e_axis = cyl.axes
    z = (X - cyl.axis_point) @ e_axis
    zc = 0.5 * (z.max() + z.min())
    h = size if size is not None else 0.5 * (z.max() - z.min()) + CYLINDER_MARGIN * R
    zlo, zhi = zc - h, zc + h
    spacing = max(2.0 * np.pi * R / _TUBE_LINES, 2.0 * h / 60.0)

    def on_tube(phi, zz, radius=R):
        return (cyl.axis_point + radius * (np.cos(phi)[:, None] * e_ref + np.sin(phi)[:, None] * e_ref2)
                + zz[:, None] * e_axis)

    items = []
    for beta, color in ((angle, colors[0]), (angle + 0.5 * np.pi, colors[1])):
        family = _helix_family(R, zlo, zhi, beta, spacing)
        items.append(_lines([_segments(on_tube(phi, zz)) for phi, zz in family], color))
    # face behind the surface: outside the hole's wall, inside the shaft's
    L = max(h, R)
    Rf = R - cyl.sign * min(FACE_OFFSET * L, 0.01 * R)
    phi = 2.0 * np.pi * np.arange(_TUBE_SEGMENTS) / _TUBE_SEGMENTS
    pts = np.vstack([on_tube(phi, np.full_like(phi, zlo), Rf), on_tube(phi, np.full_like(phi, zhi), Rf)])
    normals = cyl.sign * np.vstack([np.cos(phi)[:, None] * e_ref + np.sin(phi)[:, None] * e_ref2] * 2)
    m = _TUBE_SEGMENTS
    tri = []
    for i in range(m):
        j = (i + 1) % m
        tri += [[i, j, m + j], [i, m + j, m + i]]
    return [_face(pts, tri, normals, face_color)] + items, L


def _chart_patch(surf, X, a, size, colors, face_color, n1=48, n2=24, lines1=24, lines2=12):
    """Any surface of the protocol (exu_aniso.geometry) drawn from its chart: a patch of the
    coordinate box around the slave points' closest points (a periodic coordinate over its whole
    period; otherwise the points' range widened by L on each side, L = size or 2 a, measured along
    rho_i, at most the largest |rho_i| at the points) with the coordinate lines xi1 = const and
    xi2 = const. Returns (items, L)."""
    L = size if size is not None else 2.0 * a
    xi = []
    for x in X:
        try:
            xi.append(surf.project(x).xi)
        except ValueError:                       # a point with no closest point: leave it out
            continue
    if not xi:
        return [], L
    xi = np.array(xi)
    if size is None:        # at most the surface's own size there (a cone's radius: not past its apex)
        L = min(L, max(float(np.max(np.linalg.norm(surf.at(q).rho, axis=1))) for q in xi))
    ranges = []
    for i, period in enumerate(surf.periods):
        lo, hi = float(xi[:, i].min()), float(xi[:, i].max())
        if period > 0.0:
            c = 0.5 * (lo + hi)
            ranges.append((c - 0.5 * period, c + 0.5 * period))
            continue
        g = surf.at(xi[np.argmin(xi[:, i])])
        w = L / max(float(np.linalg.norm(g.rho[i])), 1e-300)
        ranges.append((lo - w, hi + w))
    for i, (lo, hi) in enumerate(surf.limits):      # stay off the chart's poles, axis or apex
        margin = 1e-3 * (hi - lo if math.isfinite(hi - lo) else max(ranges[i][1] - ranges[i][0], 1e-300))
        ranges[i] = (max(ranges[i][0], lo + margin), min(ranges[i][1], hi - margin))

    def point(u, v, offset=0.0):
        try:
            g = surf.at((u, v))
        except ValueError:
            return None
        return g.point - offset * g.n, g.n

    off = min(FACE_OFFSET * L, 0.01 * L)
    U = np.linspace(*ranges[0], n1 + 1)
    V = np.linspace(*ranges[1], n2 + 1)
    grid = [[point(u, v, off) for v in V] for u in U]
    pts, nrm, index = [], [], {}
    for i in range(n1 + 1):
        for j in range(n2 + 1):
            if grid[i][j] is not None:
                index[i, j] = len(pts)
                pts.append(grid[i][j][0])
                nrm.append(grid[i][j][1])
    tri = []
    for i in range(n1):
        for j in range(n2):
            q = [(i, j), (i + 1, j), (i + 1, j + 1), (i, j + 1)]
            if all(k in index for k in q):
                a0, a1, a2, a3 = (index[k] for k in q)
                tri += [[a0, a1, a2], [a0, a2, a3]]
    items = [_face(np.array(pts), tri, np.array(nrm), face_color)] if tri else []
    for family, (fixed, free), color, count in ((0, (U, V), colors[0], lines1), (1, (V, U), colors[1], lines2)):
        polylines = []
        for c in np.linspace(fixed[0], fixed[-1], count + 1)[:-1 if surf.periods[family] > 0.0 else None]:
            line = [point(c, t) if family == 0 else point(t, c) for t in np.linspace(free[0], free[-1], 4 * len(free))]
            line = [q[0] for q in line if q is not None]
            if len(line) > 1:
                polylines.append(_segments(np.array(line)))
        items.append(_lines(polylines, color))
    return items, L


# ----------------------------------------------------------------------------------------------

def _draw_plane(surf, X, origin, kind, angle, size, colors, face_color):
    a = _body_length(X, origin, float(np.hypot(X[:, 0].mean(), X[:, 1].mean())))
    if kind == "polar":
        return _plane_polar(X, a, size, colors, face_color)
    return _plane_grid(X, a, angle, size, colors, face_color)


def _draw_cylinder(surf, X, origin, kind, angle, size, colors, face_color):
    rel = X - surf.axis_point
    radial = rel - np.outer(rel @ surf.axes[2], surf.axes[2])
    a = _body_length(X, origin, float(np.linalg.norm(radial.mean(axis=0))))
    return _cylinder(surf, X, a, angle, size, colors, face_color)


def _draw_chart(surf, X, origin, kind, angle, size, colors, face_color):
    return _chart_patch(surf, X, _body_length(X, origin, 0.0), size, colors, face_color)


_DRAWINGS = {Plane: _draw_plane, Cylinder: _draw_cylinder}


class _ContactGraphics:
    """The graphicsDataUserFunction of one contact set: static geometry built once at construction
    (master frame), per call only the master's pose, the point colours and the arrows."""

    def __init__(self, mbs, contact, color, showNet, showPoints, showTraction, tractionScale, size):
        self.contact = contact
        self.law = contact["law"]
        self.moving = contact["masterBodyNumber"] is not None
        self.showPoints = showPoints
        self.showTraction = showTraction
        surf = self.law.surface
        X, p0, A0 = contact["pointsAndMasterPose"](mbs, None)     # initial coordinates (before Assemble too)
        origin = (contact["bodyPosition"](mbs, None) - p0) @ A0   # slave body origin in the master frame
        kind, angle = _net_field(self.law)
        face_color = SURFACE_COLOR if color is None else color
        self.netColors = NET_COLORS if color is None else (
            tuple(0.5 * np.array(color[:3])) + (1.0,), tuple(0.8 * np.array(color[:3])) + (1.0,))
        static, L = _DRAWINGS.get(type(surf), _draw_chart)(surf, X, origin, kind, angle, size, self.netColors,
                                                           face_color)
        self.sceneSize = L
        self.static = static if showNet else []
        self.pointRadius = min(POINT_RADIUS * L, 0.25 * _closest_spacing(X))
        self.tractionScale = tractionScale
        if tractionScale is None:
            N = np.abs(contact["historyAt"](mbs, None)[:, _NORMAL])
            if N.max() > 0.0:
                self.tractionScale = ARROW_LENGTH * L / float(N.max())
        self._colorTable = np.array([STATUS_COLORS[OPEN], STATUS_COLORS[STICK], STATUS_COLORS[SLIP],
                                     UNKNOWN_STATUS_COLOR])

    def pointColors(self, status):
        """RGBA (K, 4) of history status values."""
        s = np.asarray(status, dtype=float)
        idx = np.full(s.shape, 3, dtype=int)
        for code in (OPEN, STICK, SLIP):
            idx[s == code] = code
        return self._colorTable[idx]

    def __call__(self, mbs, itemNumber):
        """Graphics of the Visualization configuration (what the renderer / SolutionViewer shows)."""
        x, p, A = self.contact["pointsAndMasterPose"](mbs, _VIS)
        if self.moving:
            out = [graphics.Move(g, p, A) for g in self.static]
            X = p + x @ A.T
        else:
            out = list(self.static)                  # the cached items themselves: nothing rebuilt
            X = x
        if not (self.showPoints or self.showTraction):
            return out
        H = self.contact["historyAt"](mbs, _VIS)
        if self.showPoints:
            colors = self.pointColors(H[:, _STATUS])
            out.append(graphics.Spheres(points=X, radii=self.pointRadius, colors=colors))
        if self.showTraction:
            out += self._arrows(x, X, A, H)
        return out

    def _arrows(self, x, X, A, H):
        """Arrows of the force on the slave points, E T - N n (global), from the points."""
        loaded = (H[:, _STATUS] != OPEN) & ((H[:, _NORMAL] != 0.0) | np.any(H[:, _TRACTION] != 0.0, axis=1))
        if not np.any(loaded):
            return []
        E, n = self.law.traction_frames(x[loaded])
        f = np.einsum("kij,kj->ki", E, H[loaded][:, _TRACTION]) - H[loaded][:, _NORMAL, None] * n
        f = f @ A.T
        if self.tractionScale is None:               # nothing was loaded initially: fix the scale now
            largest = float(np.max(np.abs(H[loaded][:, _NORMAL])))
            if not largest > 0.0:                    # tangential traction only (N = 0 at the gap's edge)
                largest = float(np.max(np.linalg.norm(f, axis=1)))
            self.tractionScale = ARROW_LENGTH * self.sceneSize / largest
        out = []
        headFactor, headStretch = 2.0, 4.0
        for start, v in zip(X[loaded], self.tractionScale * f):
            length = float(np.linalg.norm(v))
            if not length > 0.0:
                continue
            radius = min(0.3 * self.pointRadius, length / (headFactor * headStretch))   # the head fits in
            out.append(graphics.Arrow(pAxis=start, vAxis=v, radius=radius, color=list(TRACTION_COLOR),
                                      headFactor=headFactor, headStretch=headStretch, nTiles=8))
        return out


def AddContactGraphics(mbs, contact, show=True, color=None, showNet=True, showPoints=True, showTraction=False,
                       tractionScale=None, size=None):
    """Draw a contact set in Exudyn's renderer and SolutionViewer: the master surface with its net, the
    contact points coloured by state (open grey, stick green, slip red) and optional traction arrows.

    Attaches a graphicsDataUserFunction (and Vshow = show) to the contact's ObjectGenericODE2. It runs
    only when the scene is drawn and draws the Visualization configuration, so the SolutionViewer shows
    each stored state; for that the solution file must contain the data coordinates (the contact
    history): ``simulationSettings.solution.file.write = True`` and
    ``simulationSettings.solution.file.export.dataCoordinates = True`` (both Exudyn 1.13.6 defaults).
    Static geometry (surface face and net) is built here, once, from the initial coordinates; each
    redraw only moves it with a moving master and colours the points. Rules for the sizes: module
    docstring of exu_aniso.engines.exudyn_adapter.graphics.

    Args:
        mbs: the MainSystem holding the contact
        contact: the dict returned by exu_aniso.engines.exudyn_adapter.create_contact.CreateAnisotropicContact
        show: draw the contact (Vshow of the object); False keeps the function but hides it
        color: RGBA or RGB colour of the surface face (4 or 3 numbers in [0, 1]; RGB gets the alpha
            0.35 of SURFACE_COLOR); None: SURFACE_COLOR; the net lines get darker shades of it
        showNet: draw the master surface (face and net lines)
        showPoints: draw the contact points as spheres coloured by state (STATUS_COLORS)
        showTraction: draw arrows of the force the master exerts on each loaded point, E T - N n
        tractionScale: arrow length per Newton [m/N], > 0; None: ARROW_LENGTH * L / the largest initial |N|
        size: scene length L [m], > 0 (polar disk radius, square half-width or tube half-length);
            None: from the slave points (module docstring)

    Returns:
        the user function object (callable (mbs, itemNumber) -> list of GraphicsData); its attributes
        sceneSize, pointRadius and tractionScale give the sizes it chose
    """
    try:
        check_instance("mbs", mbs, exu.MainSystem, "MainSystem of Exudyn (SC.AddSystem())")
    except TypeError as e:
        raise TypeError(f"{_WHERE}: {e}") from None
    if not isinstance(contact, dict) or any(k not in contact for k in _CONTACT_KEYS):
        missing = [k for k in _CONTACT_KEYS if k not in contact] if isinstance(contact, dict) else None
        raise ValueError(f"{_WHERE}: contact must be the dict returned by CreateAnisotropicContact"
                         + (f"; missing keys {missing}" if missing else f"; got {type(contact).__name__}"))
    flags = {}
    for name, value in (("show", show), ("showNet", showNet), ("showPoints", showPoints),
                        ("showTraction", showTraction)):
        try:
            flags[name] = check_bool(name, value)
        except TypeError as e:
            raise TypeError(f"{_WHERE}: {e}") from None
    tractionScale = _positive_or_none("tractionScale", tractionScale)
    size = _positive_or_none("size", size)
    color = None if color is None else _rgba("color", color, SURFACE_COLOR)
    uf = _ContactGraphics(mbs, contact, color, flags["showNet"], flags["showPoints"], flags["showTraction"],
                          tractionScale, size)
    mbs.SetObjectParameter(contact["oContact"], "VgraphicsDataUserFunction", uf)
    mbs.SetObjectParameter(contact["oContact"], "Vshow", flags["show"])
    return uf
