"""Cases of studies/capstan.py (not part of the installed package): one capstan run per case dict,
reduced to the numbers the study tabulates.

CapstanParams has no angle for the orthotropic friction net (scenes.capstan.capstan_contact_law
builds ``Friction.orthotropic(mu_1, mu_2, angle=0.0)``: mu_1 along the circumference, mu_2 along
the axis). A "turned" case (``turn_deg``) builds the same law with the net turned by that angle in
the drum's transport frame (``Friction.orthotropic(mu_1, mu_2, angle=radians(turn_deg))``) and runs
the unchanged model with it: ``models.capstan.capstan_contact_law`` is replaced for this one run
only. At 90 deg mu_2 then acts along the rope and the theory is exp(mu_2 phi).
"""
from __future__ import annotations

import math
import warnings
from unittest import mock

SUMMARY_KEYS = ("tension_ratio", "tension_ratio_displacement", "t_slip", "t_end_reached", "steps", "wall_s",
                "energy_ok", "energy_tolerance")
LEDGER_KEYS = ("work_in", "kinetic", "potential", "stored", "dissipated", "residual")


def turned_contact_law(turn_deg):
    """A replacement for scenes.capstan.capstan_contact_law whose friction net is turned by turn_deg."""
    from exu_aniso.kernel.contact_law import ContactLaw
    from exu_aniso.fields.tensor_fields import Adhesion, Friction
    from exu_aniso.geometry import Cylinder
    from exu_aniso.scenes.capstan import point_spacing

    def law(p):
        ds = point_spacing(p)
        B = (Adhesion.isotropic(p.eps_1_per_length * ds) if p.adhesion == "isotropic"
             else Adhesion.orthotropic(p.eps_1_per_length * ds, p.eps_2_per_length * ds, angle=0.0))
        F = Friction.orthotropic(p.mu_1, p.mu_2, angle=math.radians(turn_deg))
        return ContactLaw(Cylinder(p.radius, side="outside"), B, F, normal_stiffness=p.eps_n_per_length * ds,
                          normal_damping=p.normal_damping_per_length * ds, return_map=p.return_map)
    return law


def mu_along_rope(case):
    """Friction coefficient along the rope (the circumference) of a case."""
    p = case["params"]
    if case.get("turn_deg", 0.0):
        if abs(case["turn_deg"] - 90.0) > 1e-12:
            raise ValueError("only a 90 deg turn has a closed-form theory here")
        return p.get("mu_2", 0.3)
    return p.get("mu_1", 0.3)


def run_case(case):
    """case: dict(params=dict of CapstanParams fields, turn_deg=0.0 optional). Returns the summary
    numbers, the theory exp(mu_along phi), its relative error and the ledger."""
    from exu_aniso.models import capstan as model
    from exu_aniso.scenes.capstan import CapstanParams
    p = CapstanParams(**case["params"])
    turn = case.get("turn_deg", 0.0)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        if turn:
            with mock.patch.object(model, "capstan_contact_law", turned_contact_law(turn)):
                r = model.RunCapstan(p)
        else:
            r = model.RunCapstan(p)
    s = r.summary
    theory = math.exp(mu_along_rope(case) * math.radians(p.wrap_angle))
    ratio = s["tension_ratio"]
    out = {k: s[k] for k in SUMMARY_KEYS}
    out.update(theory=theory, error=float("nan") if ratio is None else (ratio - theory) / theory,
               undefined="; ".join(f"{k}: {v}" for k, v in s["undefined"].items()),
               **{"ledger_" + k: float(s["energy"][k]) for k in LEDGER_KEYS})
    if ratio is None:
        out["tension_ratio"] = float("nan")
    if out["tension_ratio_displacement"] is None:
        out["tension_ratio_displacement"] = float("nan")
    return out
