"""Cases of studies/feeder.py (not part of the installed package): one feeder run per case dict,
reduced to the numbers the study tabulates."""
from __future__ import annotations

import math
import warnings

THROW_NUMBER = 0.7          # A w^2 sin(beta) / g of the frequency sweep (the part stays on the track)


def amplitude_for(frequency, throw_angle_deg, throw_number=THROW_NUMBER, gravity=9.81):
    """Track amplitude [m] that gives the throw number at this frequency and throw angle."""
    w = 2.0 * math.pi * frequency
    return throw_number * gravity / (w * w * math.sin(math.radians(throw_angle_deg)))


def run_case(case):
    """case: dict(params=dict of FeederParams fields). Returns the summary numbers of the run."""
    from exu_aniso.models.feeder import RunFeeder
    from exu_aniso.scenes.feeder import FeederParams
    p = FeederParams(**case["params"])
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        r = RunFeeder(p)
    s = r.summary
    return dict(vx=s["transport_velocity_x"], vy=s["transport_velocity_y"], speed=s["transport_velocity"],
                direction_deg=s["transport_direction_deg"], theory=s["transport_velocity_theory"],
                spread=s["velocity_spread"], yaw_end_deg=max(abs(y) for y in s["part_yaw_end_deg"]),
                throw_number=s["throw_number"], energy_residual=s["energy"]["residual"], energy_ok=s["energy_ok"],
                steps=s["steps"], wall_s=s["wall_s"], newton_per_step=s["newton_iterations"] / s["steps"])
