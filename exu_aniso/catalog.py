"""The scenes the command line knows: ``exu-aniso run NAME`` and ``exu-aniso params NAME``.

Each scene is its module's ``SCENE`` (``exu_aniso.scenes.scene.Scene``: parameters, columns, summary,
ledger, closed forms, plot, reference engine) and its Exudyn model script's ``MODEL``
(``engines.exudyn_adapter.runner.ModelScript``: build, read back, run). Adding a scene adds one
model script to ``MODELS`` below; the command line does not change.
"""
from __future__ import annotations

from exu_aniso.models import block, capstan, fastening, fe_block, fe_screw, feeder, loosening, nut, particle, screw

# the main job of ``exu-aniso run all``: the papers' two scenes (the README's quick start)
MAIN_JOB = ("block", "screw")

MODELS = {m.scene.name: m for m in (block.MODEL, screw.MODEL, particle.MODEL, capstan.MODEL, feeder.MODEL,
                                    fastening.MODEL, nut.MODEL, loosening.MODEL, fe_block.MODEL,
                                    fe_screw.MODEL)}
"""name -> the scene's Exudyn model script (``ModelScript``: ``run``, ``build``)."""

SCENES = {name: m.scene for name, m in MODELS.items()}
"""name -> the scene (``Scene``), in the command line's order."""
