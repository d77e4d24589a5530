"""A contact set: K slave points against one analytical master surface, evaluated at once.

``ContactLaw.evaluate`` is the kernel every engine calls (reference integrator and Exudyn adapter):
given the slave points and their velocities relative to the master (master frame) and the last
*converged* history, it returns forces, the consistent tangent and the history candidate that
``commit`` makes the new converged history once a step is accepted. Nothing is stored inside.

The points go through the covariant kernel, compiled when the surface is (every built-in surface,
a user surface numba can compile: ``exu_aniso.kernel.law_call.law_entry``, the code the compiled Exudyn
route calls), its plain-Python source otherwise (``contact_point`` point by point).

History layout, one row per point, and the status codes: ``exu_aniso.law.history``.

Decisions (documented in docs/guide/decisions.md):
* rate form, papers' eq. (5): ``T_tr = T_n (transported to the new contact point) + B(C_new) du``
  with B evaluated at the new contact point (backward Euler); with a position-dependent B (polar
  orthotropy) or a curved surface (holonomy) the stick response is hypo-elastic (path dependent),
  as in the papers;
* first contact (active = 0): the anchor is the current contact point, T_n = 0, so the first
  contact step carries no tangential traction; losing contact resets T and the anchor (the
  accumulated dissipation and slip distance are kept);
* normal damping ``d_N`` (off by default) adds ``d_N dxi3/dt`` to N; N is clipped to <= 0.
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from exu_aniso import geometry as _geometry
from exu_aniso.law.history import H_DISSIPATED, H_NORMAL, H_T1, H_T2, H_XI1, H_XI2, N_HISTORY, OPEN
from exu_aniso.law.return_maps import DEFAULT_RETURN_MAP, check_return_map
from exu_aniso.fields.nets import net_of
from exu_aniso.util.validation import check_array, check_nonnegative, check_points, check_positive



@dataclass
class ContactState:
    """Result of one evaluation of K points (all arrays have leading axis K).

    force: on the slave points, master frame (K, 3) [N]; stiffness: d force / d x (K, 3, 3);
    damping: d force / d v (K, 3, 3); traction: T in the transport frame (K, 2); normal: N (K,)
    (<= 0); gap: xi3 (K,); status: OPEN / STICK / SLIP / UNRESOLVED;
    dissipation: energy dissipated by friction in the step (K,) [J]; history: candidate (K, 9).
    """

    force: np.ndarray
    stiffness: np.ndarray | None
    damping: np.ndarray | None
    traction: np.ndarray
    normal: np.ndarray
    gap: np.ndarray
    status: np.ndarray
    dissipation: np.ndarray
    history: np.ndarray
    contact_point: np.ndarray


class ContactLaw:
    """Point-to-analytical-surface contact with anisotropic adhesion B and friction F.

    surface: a surface of exu_aniso.geometry (Plane, Cylinder, Cone, Sphere, Torus, Helicoid,
    SurfaceOfRevolution, ParametricSurface); adhesion, friction: TensorField (see
    exu_aniso.fields.tensor_fields); normal_stiffness eps_N [N/m per point]; normal_damping d_N [N s/m per
    point]; tangential_damping d_T [N s/m per point]; return_map: "seed" | "exact" | "radial".
    """

    def __init__(self, surface, adhesion, friction, normal_stiffness, normal_damping=0.0, return_map=DEFAULT_RETURN_MAP,
                 tangential_damping=0.0):
        if getattr(adhesion, "kind", None) != "adhesion":
            raise TypeError(f"adhesion must be an Adhesion field (exu_aniso.Adhesion.*); got {adhesion!r}")
        if getattr(friction, "kind", None) != "friction":
            raise TypeError(f"friction must be a Friction field (exu_aniso.Friction.*); got {friction!r}")
        if not isinstance(surface, _geometry.Surface):
            raise TypeError("surface must be a surface of exu_aniso (Plane, Cylinder, Cone, Sphere, Torus, Helicoid, "
                            f"SurfaceOfRevolution, ParametricSurface); got {surface!r}")
        self._nets = (net_of(adhesion, surface), net_of(friction, surface))
        # the compiled kernel, or its plain-Python source for a user surface or field numba cannot compile
        self.compiled = surface.compiled and all(f.pattern != "user" or f.cfunc is not None for f in (adhesion, friction))
        self.surface = surface
        self.adhesion = adhesion
        self.friction = friction
        self.eps_N = check_positive("normal_stiffness", normal_stiffness)
        self.d_N = check_nonnegative("normal_damping", normal_damping)
        self.d_T = check_nonnegative("tangential_damping", tangential_damping)
        self.return_map = check_return_map(return_map)
        self._call = None       # (parameters, what they name, the compiled law's call and its stored bundle)

    def __getstate__(self):
        state = dict(self.__dict__)
        state["_call"] = None   # addresses of this process
        return state

    @property
    def nets(self):
        """(adhesion net, friction net): the fields as the kernel evaluates them (exu_aniso.fields.nets)."""
        return self._nets

    def __repr__(self):
        return (f"ContactLaw({self.surface!r}, {self.adhesion!r}, {self.friction!r}, "
                f"normal_stiffness={self.eps_N}, normal_damping={self.d_N}, tangential_damping={self.d_T}, "
                f"return_map={self.return_map!r})")

    @staticmethod
    def initial_history(n_points):
        return np.zeros((int(n_points), N_HISTORY))

    def adhesion_components(self, anchors):
        """B (negative definite) by its components (b11, b12, b22) in the frame of the stored
        traction at the anchors (K, 2) of history rows."""
        return -self._net_components(self._nets[0], anchors)

    def friction_components(self, anchors):
        """F by its components (f11, f12, f22) in the frame of the stored traction at the anchors
        (K, 2) of history rows."""
        return self._net_components(self._nets[1], anchors)

    def _net_components(self, net, anchors):
        anchors = np.asarray(anchors, dtype=float)
        from exu_aniso.kernel import point as kernel
        batch = kernel.net_at_batch if self.compiled else kernel.plain_python().net_at_batch
        out = np.empty((anchors.shape[0], 3))
        batch(self.surface.params, net, np.ascontiguousarray(anchors.reshape(-1, 2)), out)
        return out

    def gap_and_normal(self, x):
        """Normal gap xi3 (K,) and unit normal n (K, 3) (towards the slave side) of slave points x
        (K, 3); the normal is NaN where the point is not in contact (xi3 >= 0)."""
        x = np.ascontiguousarray(x, dtype=float).reshape(-1, 3)
        gap, n = np.empty(x.shape[0]), np.empty(x.shape)
        self.surface.protocol.gap_and_normal_batch(self.surface.params, x, gap, n)
        return gap, n

    def traction_frames(self, x):
        """The frame E (K, 3, 2) in which the history stores the traction of points in contact at
        x (K, 3), and the normal n (K, 3) (graphics: the force E T - N n)."""
        x = np.asarray(x, dtype=float)
        from exu_aniso.fields.nets import tangent_frame
        E, n = np.zeros((x.shape[0], 3, 2)), np.zeros((x.shape[0], 3))
        for k in range(x.shape[0]):
            p = self.surface.project(x[k])
            a1, a2, _ = tangent_frame(tuple(p.rho[0]), tuple(p.rho[1]))
            E[k, :, 0], E[k, :, 1], n[k] = a1, a2, p.n
        return E, n

    def released_energy(self, H):
        """Tangential elastic energy T . C^-1 T / 2 [J] (K,) of history rows H (K, 9), C = -B at the
        stored anchor; zero for inactive rows. Losing contact resets T, so this energy leaves the
        adhesion spring: the law books it as dissipated."""
        H = np.ascontiguousarray(H, dtype=float).reshape(-1, N_HISTORY)
        from exu_aniso.kernel import point as kernel
        batch = kernel.stored_energy_batch if self.compiled else kernel.plain_python().stored_energy_batch
        E = np.empty(H.shape[0])
        batch(self.surface.params, self._nets[0], H, E)
        return E

    def evaluate(self, x, v=None, history=None, tangent=True, dt=None):
        """Contact forces of K slave points. x, v: (K, 3) position and velocity relative to the
        master, master frame; history: (K, 9) last converged history (zeros if None); dt: time
        since the converged history [s] (engines pass it): it predicts the increment of periodic
        surface coordinates (cylinder phi) as du_dx v dt, so a point may turn more than half a
        revolution per step; a step whose motion the prediction cannot resolve gets the status
        UNRESOLVED and must be rejected by the engine."""
        x = check_points("x", x)
        K = x.shape[0]
        v = np.zeros((K, 3)) if v is None else check_array("v", np.reshape(v, (K, 3)) if np.size(v) == 3 * K else v,
                                                            (K, 3))
        H = self.initial_history(K) if history is None else check_array(
            "history", np.reshape(history, (K, N_HISTORY)) if np.size(history) == K * N_HISTORY else history,
            (K, N_HISTORY))
        dt = 0.0 if dt is None else float(dt)
        if self.compiled:
            force, stiff, damp, newH, status, gap = self._compiled_points(x, v, H, tangent, dt)
        else:
            force, stiff, damp, newH, status, gap = self._python_points(x, v, H, tangent, dt)
        closed = status != OPEN
        return ContactState(force, stiff if tangent else None, damp if tangent else None,
                            np.where(closed[:, None], newH[:, H_T1:H_T2 + 1], 0.0), newH[:, H_NORMAL].copy(), gap,
                            status, newH[:, H_DISSIPATED] - H[:, H_DISSIPATED], newH,
                            np.where(closed[:, None], newH[:, H_XI1:H_XI2 + 1], np.nan))

    def _compiled_points(self, x, v, H, tangent, dt):
        """The law at the K points in one compiled call (the code the set kernels call: kernel.law_call.law_entry),
        a second one for the tangent: (force, df/dx, df/dv, history candidate, status, gap)."""
        from exu_aniso.kernel import law_call
        from exu_aniso.kernel.sets import SCRATCH_SLOTS, Y_DV, Y_F, Y_GAP, Y_INFO, Y_KX, Y_ROWS, Y_V, Y_X
        # made again if the law's parameters were changed since (the old code's address is not used again);
        # the surface and nets are held with it, so that their ids in the key name them
        key = (self.eps_N, self.d_N, self.d_T, self.return_map, id(self.surface), id(self._nets))
        if self._call is None or self._call[0] != key:
            self._call = (key, (self.surface, self._nets)) + law_call.law_call(law_call.law_bundle(self))
        law = self._call[2]
        K = x.shape[0]
        Y = np.zeros((K, Y_ROWS, 3))
        Y[:, Y_X], Y[:, Y_V] = x, v
        H = np.ascontiguousarray(H, dtype=float)
        newH, S = np.zeros((K, N_HISTORY)), np.zeros((SCRATCH_SLOTS, 9, 9))
        law_call.call_law(law, Y, H, newH, 0, K, dt, False, S)
        force, status, gap = Y[:, Y_F].copy(), Y[:, Y_INFO, 2].astype(int), Y[:, Y_GAP, 0].copy()
        stiff = damp = None
        if tangent:
            law_call.call_law(law, Y, H, newH, 0, K, dt, True, S)
            stiff, damp = Y[:, Y_KX:Y_KX + 3].copy(), Y[:, Y_DV:Y_DV + 3].copy()
        return force, stiff, damp, newH, status, gap

    def _python_points(self, x, v, H, tangent, dt):
        """The law point by point in plain Python (a user surface or field numba cannot compile):
        what _compiled_points gives."""
        from exu_aniso.kernel import law_call
        from exu_aniso.kernel import point as kernel
        contact_point = kernel.plain_python().contact_point
        K = x.shape[0]
        law = law_call.law_params(self)
        sp, nB, nF = self.surface.params, self._nets[0], self._nets[1]
        force = np.zeros((K, 3))
        stiff = np.zeros((K, 3, 3))
        damp = np.zeros((K, 3, 3))
        newH = np.zeros((K, N_HISTORY))
        status = np.zeros(K, dtype=int)
        gap = np.zeros(K)
        W = np.zeros((3, 9, 9))
        for k in range(K):
            status[k], gap[k] = contact_point(sp, nB, nF, law, x[k], v[k], H[k], dt, tangent, force[k], stiff[k],
                                              damp[k], newH[k], W)
        return force, stiff, damp, newH, status, gap
