"""The scenes the command line knows, one record each: ``exu-aniso run NAME`` and ``exu-aniso params NAME``.

A scene is a parameter class (a frozen dataclass with ``scenes.SceneParams``), the columns of its
trajectory.csv with their SI units, the two summary values in the plot title, a function that
draws trajectory.png on a matplotlib Figure, its Exudyn model script's ``Run<Model>(p, progress=,
snapshot=, solutionFile=)`` and ``Build<Model>(p)`` (``exu_aniso.models.<model>``) and, where one
exists, its reference-engine function ``params -> Result``: every piece named by an import the
layers' test sees.

Adding a scene means one module (parameters, summary, plot), one model script and one entry in
``_ENTRIES`` below; the command line does not change.
"""
from __future__ import annotations

from dataclasses import dataclass
from typing import Callable

from exu_aniso.scenes.base import ENERGY_COLUMNS

# the main job of ``exu-aniso run all``: the papers' two scenes (the README's quick start)
MAIN_JOB = ("block", "screw")

_LEDGER = {k: "J" for k in ENERGY_COLUMNS}


@dataclass(frozen=True)
class Scene:
    """One scene of the command line (see the module docstring)."""

    name: str
    params: type
    columns: dict
    title_keys: tuple
    plot: Callable            # (traj, params, fig) -> None: the content of trajectory.png
    run: Callable             # Run<Model>(params, progress=, snapshot=, solutionFile=) -> Result
    build: Callable           # Build<Model>(params) -> the assembled Exudyn model (for the SolutionViewer)
    reference: Callable | None = None  # params -> Result of the reference engine, None if it has no model
    figsize: tuple = (6.0, 5.0)         # of trajectory.png [in]


def _block():
    from exu_aniso.models.block import BuildBlock, RunBlock
    from exu_aniso.scenes.block import BlockParams, PlotBlock, simulate_block
    return Scene("block", BlockParams,
                 {"t": "s", "x": "m", "y": "m", "theta": "rad", "vx": "m/s", "vy": "m/s", "omega": "rad/s",
                  "slip_distance": "m", "dissipated_energy": "J", "drive_force": "N",
                  # the full model's other motions (the planar model holds z and has no vz, tilt, omega_x, omega_y)
                  "z": "m", "vz": "m/s", "tilt": "rad", "omega_x": "rad/s", "omega_y": "rad/s", **_LEDGER},
                 ("heading_deg", "r_mean"), PlotBlock, RunBlock, BuildBlock, simulate_block, (5.5, 5.0))


def _screw():
    from exu_aniso.models.screw import BuildScrew, RunScrew
    from exu_aniso.scenes.screw import PlotScrew, ScrewParams, simulate_screw
    return Scene("screw", ScrewParams,
                 {"t": "s", "angle": "rad", "z": "m", "omega": "rad/s", "vz": "m/s", "torque": "N m",
                  "axial_force": "N", "dissipated_energy": "J",
                  # the full model's other motions (axis_*: the screw's axis in the world)
                  "x": "m", "y": "m", "vx": "m/s", "vy": "m/s", "tilt": "rad", "omega_x": "rad/s", "omega_y": "rad/s",
                  "axis_x": "-", "axis_y": "-", "axis_z": "-", **_LEDGER},
                 ("advance_per_rev", "torque_mean"), PlotScrew, RunScrew, BuildScrew, simulate_screw, (6.0, 6.5))


def _particle():
    from exu_aniso.models.particle import BuildParticle, RunParticle
    from exu_aniso.scenes.particle import COLUMNS, TITLE_KEYS, ParticleParams, PlotParticle, simulate_particle
    return Scene("particle", ParticleParams, COLUMNS, TITLE_KEYS, PlotParticle, RunParticle, BuildParticle,
                 simulate_particle, (6.0, 6.5))


def _capstan():     # no reference-engine model of the ANCF rope: the oracle is Euler-Eytelwein
    from exu_aniso.models.capstan import BuildCapstan, RunCapstan
    from exu_aniso.scenes.capstan import COLUMNS, TITLE_KEYS, CapstanParams, PlotCapstan
    return Scene("capstan", CapstanParams, COLUMNS, TITLE_KEYS, PlotCapstan, RunCapstan, BuildCapstan, None,
                 (6.0, 6.5))


def _feeder():
    from exu_aniso.models.feeder import BuildFeeder, RunFeeder
    from exu_aniso.scenes.feeder import COLUMNS, TITLE_KEYS, FeederParams, PlotFeeder, simulate_feeder
    return Scene("feeder", FeederParams, COLUMNS, TITLE_KEYS, PlotFeeder, RunFeeder, BuildFeeder, simulate_feeder,
                 (7.5, 6.5))


def _fastening():     # no reference-engine model: the oracles are ISO 16047 / VDI 2230's closed forms
    from exu_aniso.models.fastening import BuildFastening, RunFastening
    from exu_aniso.scenes.fastening import COLUMNS, TITLE_KEYS, FasteningParams, PlotFastening
    return Scene("fastening", FasteningParams, COLUMNS, TITLE_KEYS, PlotFastening, RunFastening, BuildFastening,
                 None, (7.0, 7.0))


def _fe_block():   # no reference-engine model of the FE body: its limit is scenes.fe_block.rigid_limit
    from exu_aniso.models.fe_block import BuildFeBlock, RunFeBlock
    from exu_aniso.scenes.fe_block import COLUMNS, TITLE_KEYS, FeBlockParams, PlotFeBlock
    return Scene("fe_block", FeBlockParams, COLUMNS, TITLE_KEYS, PlotFeBlock, RunFeBlock, BuildFeBlock, None,
                 (11.0, 4.8))


def _fe_screw():   # its limit is the screw scene's rigid screw with the same points (scenes.fe_screw.rigid_screw)
    from exu_aniso.models.fe_screw import BuildFeScrew, RunFeScrew
    from exu_aniso.scenes.fe_screw import COLUMNS, TITLE_KEYS, FeScrewParams, PlotFeScrew
    return Scene("fe_screw", FeScrewParams, COLUMNS, TITLE_KEYS, PlotFeScrew, RunFeScrew, BuildFeScrew, None,
                 (13.0, 4.8))


_ENTRIES = (_block, _screw, _particle, _capstan, _feeder, _fastening, _fe_block, _fe_screw)

SCENES = {s.name: s for s in (entry() for entry in _ENTRIES)}
