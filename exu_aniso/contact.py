"""A contact set: K slave points against one analytical master surface, evaluated at once.

``ContactLaw.evaluate`` is the kernel every engine calls (reference integrator and Exudyn glue):
given the slave points and their velocities relative to the master (master frame) and the last
*converged* history, it returns forces, the consistent tangent and the history candidate that
``commit`` makes the new converged history once a step is accepted. Nothing is stored inside.

History layout, one row per point (``HISTORY_FIELDS``): traction T in the transport frame (2),
anchor coordinates u of the contact point at the last accepted step (2; cylinder phi unwrapped,
so it counts revolutions), active flag (1 = was in contact), accumulated dissipated energy [J],
accumulated slip distance [m], status of the step (OPEN 0 / STICK 1 / SLIP 2) and the normal
traction N [N] (the last two are outputs for sensors; the law does not read them back).

Decisions (documented in README):
* rate form, papers' eq. (5): ``T_tr = T_n + B(C_new) du`` with B evaluated at the new contact
  point (backward Euler); with a position-dependent B (polar orthotropy) the stick response is
  hypo-elastic (path dependent), as in the papers;
* first contact (active = 0): the anchor is the current contact point, T_n = 0, so the first
  contact step carries no tangential traction; losing contact resets T and the anchor (the
  accumulated dissipation and slip distance are kept);
* normal damping ``d_N`` (off by default) adds ``d_N dxi3/dt`` to N; N is clipped to <= 0.
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from . import geometry as _geometry
from .law import N_PARAMS, _return_map_batch, check_return_map, elastic_energy_batch, return_map_point
from .nets import net_of
from .validation import check_array, check_choice, check_nonnegative, check_points, check_positive

HISTORY_FIELDS = ("traction_1", "traction_2", "anchor_1", "anchor_2", "active",
                  "dissipated_energy", "slip_distance", "status", "normal")
N_HISTORY = len(HISTORY_FIELDS)
OPEN, STICK, SLIP, UNRESOLVED = 0, 1, 2, 3
STATUS_NAMES = ("open", "stick", "slip", "unresolved")


@dataclass
class ContactState:
    """Result of one evaluation of K points (all arrays have leading axis K).

    force: on the slave points, master frame (K, 3) [N]; stiffness: d force / d x (K, 3, 3);
    damping: d force / d v (K, 3, 3); traction: T in the transport frame (K, 2); normal: N (K,)
    (<= 0); gap: xi3 (K,); status: OPEN / STICK / SLIP; slip: slip increment (K, 2) [m];
    dissipation: energy dissipated by friction in the step (K,) [J]; history: candidate (K, 9).
    """

    force: np.ndarray
    stiffness: np.ndarray | None
    damping: np.ndarray | None
    traction: np.ndarray
    normal: np.ndarray
    gap: np.ndarray
    status: np.ndarray
    slip: np.ndarray
    dissipation: np.ndarray
    history: np.ndarray
    contact_point: np.ndarray


class ContactLaw:
    """Point-to-analytical-surface contact with anisotropic adhesion B and friction F.

    surface: Plane or Cylinder; adhesion, friction: TensorField (see exu_aniso.fields);
    normal_stiffness eps_N [N/m per point]; normal_damping d_N [N s/m per point];
    return_map: "seed" | "exact" | "radial";
    formulation: "transport" (default, vectorised, analytic tangent; history in physical
    components of the transport frame) or "chart" (the papers' covariant route point by point:
    projection in the surface chart, B covariant and F contravariant chart components, history as
    covariant components T_i at the anchor xi_n, transport through 3D vectors; tangent by central
    differences). The two give the same forces; "chart" exists to prove it (covariance tests).
    """

    def __init__(self, surface, adhesion, friction, normal_stiffness, normal_damping=0.0, return_map="exact",
                 formulation="transport", tangential_damping=0.0):
        if getattr(adhesion, "kind", None) != "adhesion":
            raise TypeError(f"adhesion must be an Adhesion field (exu_aniso.Adhesion.*); got {adhesion!r}")
        if getattr(friction, "kind", None) != "friction":
            raise TypeError(f"friction must be a Friction field (exu_aniso.Friction.*); got {friction!r}")
        self.covariant = isinstance(surface, _geometry.Surface)
        if not self.covariant and getattr(surface, "kind", None) not in ("plane", "cylinder"):
            raise TypeError("surface must be a surface of exu_aniso (Plane, Cylinder, Cone, Sphere, Torus, "
                            f"SurfaceOfRevolution, ParametricSurface); got {surface!r}")
        if self.covariant:
            # the covariant kernel (exu_aniso.kernel) on the surface protocol; nets of B and F
            check_choice("formulation", formulation, ("transport",))
            self._nets = (net_of(adhesion, surface), net_of(friction, surface))
        else:
            adhesion.check_surface(surface)
            friction.check_surface(surface)
        self.surface = surface
        self.adhesion = adhesion
        self.friction = friction
        self.eps_N = check_positive("normal_stiffness", normal_stiffness)
        self.d_N = check_nonnegative("normal_damping", normal_damping)
        self.d_T = check_nonnegative("tangential_damping", tangential_damping)
        self.return_map = check_return_map(return_map)
        check_choice("formulation", formulation, ("transport", "chart"))
        self.formulation = formulation

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
        anchors = np.asarray(anchors, dtype=float)
        if not self.covariant:
            return self.adhesion.physical(anchors, derivatives=False)[0]
        from . import kernel
        adhesion_at = kernel.adhesion_at if self.surface.compiled else kernel.plain_python().adhesion_at
        out = np.empty((anchors.shape[0], 3))
        for k, (a1, a2) in enumerate(anchors):
            out[k] = adhesion_at(self.surface.params, self._nets[0], float(a1), float(a2))
        return out

    def gap_and_normal(self, x):
        """Normal gap xi3 (K,) and unit normal n (K, 3) (towards the slave side) of slave points x
        (K, 3); the normal is NaN where the point is not in contact (xi3 >= 0)."""
        x = np.asarray(x, dtype=float)
        if not self.covariant:
            gap = x[:, 2].copy() if self.surface.kind == "plane" else self.surface.gap(x)
            n = np.full(x.shape, np.nan)
            inside = gap < 0.0
            if np.any(inside):
                n[inside] = self.surface.frame(x[inside], derivatives=False).n
            return gap, n
        gap, n = np.empty(x.shape[0]), np.full(x.shape, np.nan)
        for k in range(x.shape[0]):
            gap[k], nk = self.surface.gap_and_normal(x[k])
            if gap[k] < 0.0:
                n[k] = nk
        return gap, n

    def traction_frames(self, x):
        """The frame E (K, 3, 2) in which the history stores the traction of points in contact at
        x (K, 3), and the normal n (K, 3) (graphics: the force E T - N n)."""
        x = np.asarray(x, dtype=float)
        if not self.covariant:
            fr = self.surface.frame(x, derivatives=False)
            return fr.E, fr.n
        from .nets import tangent_frame
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
        H = np.asarray(H, dtype=float)
        E = np.zeros(H.shape[0])
        act = H[:, 4] > 0.5
        if np.any(act):
            E[act] = elastic_energy_batch(H[act, 0:2], self.adhesion_components(H[act, 2:4]))
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
        if self.formulation == "chart":
            return self._evaluate_chart(x, v, H, tangent)
        if self.covariant:
            return self._evaluate_covariant(x, v, H, tangent, dt)
        force = np.zeros((K, 3))
        stiff = np.zeros((K, 3, 3)) if tangent else None
        damp = np.zeros((K, 3, 3)) if tangent else None
        traction = np.zeros((K, 2))
        normal = np.zeros(K)
        status = np.zeros(K, dtype=int)
        slip = np.zeros((K, 2))
        diss = np.zeros(K)
        cpoint = np.full((K, 2), np.nan)
        newH = H.copy()
        newH[:, :5] = 0.0
        newH[:, 7:] = 0.0
        surf = self.surface
        gap = x[:, 2].copy() if surf.kind == "plane" else surf.gap(x)
        inside = gap < 0.0
        released = ~inside & (H[:, 4] > 0.5)        # contact lost: the adhesion spring lets go
        if np.any(released):
            diss[released] = self.released_energy(H[released])
            newH[released, 5] += diss[released]
        idx = np.nonzero(inside)[0]
        if idx.size == 0:
            return ContactState(force, stiff, damp, traction, normal, gap, status, slip, diss, newH, cpoint)

        fr = surf.frame(x[idx], derivatives=tangent)
        vi = v[idx]
        n = fr.n
        vn = np.einsum("ki,ki->k", n, vi)
        N = self.eps_N * fr.gap
        if self.d_N > 0.0:
            N = N + self.d_N * vn
        loaded = N < 0.0
        N = np.where(loaded, N, 0.0)
        Hi = H[idx]
        active = Hi[:, 4] > 0.5
        t_n = np.where(active[:, None], Hi[:, 0:2], 0.0)
        predicted = None if dt is None else np.einsum("kaj,kj->ka", fr.du_dx, vi) * dt
        du, anchor, unresolved = surf.resolve(fr.u, Hi[:, 2:4], predicted)
        du = np.where(active[:, None], du, 0.0)
        Bp, dB = self.adhesion.physical(fr.u, tangent)
        Fp, dF = self.friction.physical(fr.u, tangent)
        T_tr = np.stack([t_n[:, 0] + Bp[:, 0] * du[:, 0] + Bp[:, 1] * du[:, 1],
                         t_n[:, 1] + Bp[:, 1] * du[:, 0] + Bp[:, 2] * du[:, 1]], axis=-1)
        law = _return_map_batch(T_tr, -N, Bp, Fp, self.return_map, tangent)
        T = law.T
        # the force conjugate to the slip of C: du_dx^T T (see surfaces.Frame), normal -N n
        f = np.einsum("kaj,ka->kj", fr.du_dx, T) - N[:, None] * n
        # tangential dashpot parallel to the friction element: -d_T (v - n (n.v)) while loaded
        d_T = np.where(loaded, self.d_T, 0.0)
        f -= d_T[:, None] * (vi - n * vn[:, None])

        if tangent:
            # d N / d x and d N / d v (zero where N is clipped)
            vdn = np.einsum("ki,kij->kj", vi, fr.dn_dx)                  # v . dn/dx
            dN_dx = self.eps_N * n
            if self.d_N > 0.0:
                dN_dx = dN_dx + self.d_N * vdn
            dN_dx = np.where(loaded[:, None], dN_dx, 0.0)
            dN_dv = np.where(loaded[:, None], self.d_N * n, 0.0)
            # derivatives of the nine law inputs p with respect to x
            dpos = fr.du_dx                                              # (k, 2, 3)
            dinc = np.where(active[:, None, None], dpos, 0.0)
            dB_dx = np.einsum("kca,kaj->kcj", dB, dpos)                  # (k, 3, 3)
            dF_dx = np.einsum("kca,kaj->kcj", dF, dpos)
            Bm = np.stack([np.stack([Bp[:, 0], Bp[:, 1]], -1), np.stack([Bp[:, 1], Bp[:, 2]], -1)], -2)
            dTtr = np.einsum("kab,kbj->kaj", Bm, dinc)
            dTtr[:, 0, :] += dB_dx[:, 0, :] * du[:, 0, None] + dB_dx[:, 1, :] * du[:, 1, None]
            dTtr[:, 1, :] += dB_dx[:, 1, :] * du[:, 0, None] + dB_dx[:, 2, :] * du[:, 1, None]
            dp = np.concatenate([dTtr, -dN_dx[:, None, :], dB_dx, dF_dx], axis=1)  # (k, 9, 3)
            assert dp.shape[1] == N_PARAMS
            dT_dx = np.einsum("kap,kpj->kaj", law.dT, dp)
            K_i = np.einsum("kai,kaj->kij", fr.du_dx, dT_dx) - n[:, :, None] * dN_dx[:, None, :]
            K_i += np.einsum("kaij,ka->kij", fr.d2u_dx2, T) - N[:, None, None] * fr.dn_dx
            # dashpot: d/dx [-d_T (v - n (n.v))] = d_T (dn (n.v) + n (v . dn))
            K_i += d_T[:, None, None] * (fr.dn_dx * vn[:, None, None] + n[:, :, None] * vdn[:, None, :])
            stiff[idx] = K_i
            dT_dv = -law.dT[:, :, 2, None] * dN_dv[:, None, :]
            D_i = np.einsum("kai,kaj->kij", fr.du_dx, dT_dv) - n[:, :, None] * dN_dv[:, None, :]
            D_i -= d_T[:, None, None] * (np.eye(3) - n[:, :, None] * n[:, None, :])
            damp[idx] = D_i

        # energy the return map removes in the step, with the integrator's (trapezoidal) quadrature:
        # the work (T_n + T)/2 . du of the traction minus the change of T.C^-1 T / 2 (constant C);
        # equal to -(T_n + T)/2 . dxi_sl
        D = -0.5 * np.einsum("ka,ka->k", t_n + T, law.slip)
        force[idx] = f
        traction[idx] = T
        normal[idx] = N
        status[idx] = np.where(unresolved & active, UNRESOLVED, np.where(law.state > 0, SLIP, STICK))
        slip[idx] = law.slip
        diss[idx] = D
        cpoint[idx] = fr.u
        newH[idx, 0:2] = T
        newH[idx, 2:4] = np.where(active[:, None], anchor, fr.u)
        newH[idx, 4] = 1.0
        newH[idx, 5] = Hi[:, 5] + D
        newH[idx, 6] = Hi[:, 6] + np.hypot(law.slip[:, 0], law.slip[:, 1])
        newH[idx, 7] = status[idx]
        newH[idx, 8] = N
        return ContactState(force, stiff, damp, traction, normal, gap, status, slip, diss, newH, cpoint)

    def _evaluate_covariant(self, x, v, H, tangent, dt):
        """Every point through the compiled covariant kernel (exu_aniso.kernel.contact_point), the
        definition the Exudyn compiled route uses too."""
        from . import kernel
        from .kernel import LawParams, MAP_CODES
        contact_point = kernel.contact_point if self.surface.compiled else kernel.plain_python().contact_point
        K = x.shape[0]
        law = LawParams(self.eps_N, self.d_N, self.d_T, MAP_CODES[self.return_map])
        sp, nB, nF = self.surface.params, self._nets[0], self._nets[1]
        force = np.zeros((K, 3))
        stiff = np.zeros((K, 3, 3))
        damp = np.zeros((K, 3, 3))
        newH = np.zeros((K, N_HISTORY))
        status = np.zeros(K, dtype=int)
        gap = np.zeros(K)
        W = np.zeros((3, 9, 9))
        for k in range(K):
            status[k], gap[k] = contact_point(sp, nB, nF, law, x[k], v[k], H[k], 0.0 if dt is None else float(dt),
                                              tangent, force[k], stiff[k], damp[k], newH[k], W)
        closed = status != OPEN
        return ContactState(force, stiff if tangent else None, damp if tangent else None,
                            np.where(closed[:, None], newH[:, 0:2], 0.0), newH[:, 8].copy(), gap, status,
                            np.full((K, 2), np.nan), newH[:, 5] - H[:, 5], newH,
                            np.where(closed[:, None], newH[:, 2:4], np.nan))

    # ------------------------------------------------------------------------------------------
    # the papers' covariant route, one point at a time (reference formulation)
    def _chart_point(self, x, v, h):
        """Force, traction (covariant), N, status, slip (contravariant), D, history row, xi.
        (No branch prediction: the chart route takes the shortest branch of periodic coordinates.)"""
        surf = self.surface
        row = np.zeros(N_HISTORY)
        row[5:7] = h[5:7]
        xi3 = x[2] if surf.kind == "plane" else float(surf.gap(x[None, :])[0])
        if not xi3 < 0.0:
            D = 0.0
            if h[4] > 0.5:                        # contact lost: T.C^-1 T / 2 at the anchor is released
                C_inv = np.linalg.inv(-self.adhesion.components(surf, h[2:4]))
                D = 0.5 * float(h[0:2] @ C_inv @ h[0:2])
            row[5] += D
            return np.zeros(3), np.zeros(2), 0.0, OPEN, np.zeros(2), D, row, np.full(2, np.nan)
        p = surf.project(x)
        N = self.eps_N * p.xi3 + self.d_N * float(p.n @ v)
        loaded = N < 0.0
        N = min(N, 0.0)
        rho_c = p.rho_contra
        if h[4] > 0.5:
            old = surf.at(h[2:4])
            t_vec = surf.transport_vector(h[0:2] @ old.rho_contra, h[2:4], p.xi)
            T_bar = p.rho @ t_vec                                # covariant T_i at xi
            dxi = rho_c @ surf.increment_vector(h[2:4], p.xi)    # contravariant increment
        else:
            T_bar = np.zeros(2)
            dxi = np.zeros(2)
        b = self.adhesion.components(surf, p.xi)
        f = self.friction.components(surf, p.xi)
        T_tr = T_bar + b @ dxi
        r = return_map_point(T_tr, -N, (b[0, 0], b[0, 1], b[1, 1]), (f[0, 0], f[0, 1], f[1, 1]),
                             self.return_map, tangent=False)
        # force conjugate to the slip of C: T_i (A^-1)^ij rho_j, A_ij = m_ij - xi3 h_ij (SPEC section 7)
        force = r.T @ np.linalg.inv(p.m - p.xi3 * p.h) @ p.rho - N * p.n
        if loaded and self.d_T > 0.0:
            force -= self.d_T * (v - p.n * float(p.n @ v))
        D = -0.5 * float((T_bar + r.T) @ r.slip)          # trapezoidal quadrature, as in evaluate
        row[0:2] = r.T
        row[2:4] = p.xi
        row[4] = 1.0
        row[5] += D
        slip_len = float(np.sqrt(r.slip @ p.m @ r.slip))
        row[6] += slip_len
        row[7] = SLIP if r.state else STICK
        row[8] = N
        return force, r.T, N, int(row[7]), r.slip, D, row, p.xi

    def _evaluate_chart(self, x, v, H, tangent):
        K = x.shape[0]
        out = [self._chart_point(x[k], v[k], H[k]) for k in range(K)]
        force = np.array([o[0] for o in out])
        stiff = damp = None
        if tangent:
            stiff = np.zeros((K, 3, 3))
            damp = np.zeros((K, 3, 3))
            h = 1e-7 * max(1.0, float(np.abs(x).max()))
            for k in range(K):
                for j in range(3):
                    e = np.zeros(3)
                    e[j] = h
                    stiff[k, :, j] = (self._chart_point(x[k] + e, v[k], H[k])[0]
                                      - self._chart_point(x[k] - e, v[k], H[k])[0]) / (2 * h)
                    damp[k, :, j] = (self._chart_point(x[k], v[k] + e, H[k])[0]
                                     - self._chart_point(x[k], v[k] - e, H[k])[0]) / (2 * h)
        return ContactState(force, stiff, damp, np.array([o[1] for o in out]), np.array([o[2] for o in out]),
                            x[:, 2].copy() if self.surface.kind == "plane" else self.surface.gap(x),
                            np.array([o[3] for o in out]), np.array([o[4] for o in out]),
                            np.array([o[5] for o in out]), np.array([o[6] for o in out]),
                            np.array([o[7] for o in out]))
