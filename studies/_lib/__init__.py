"""Private helpers of the study scripts in ``studies/`` (not part of the installed package).

``studylib`` (command line, parallel sweeps, tables, reports), ``baseline`` (the C++ spring-damper
baseline of the benchmarks), ``targets`` (the speed targets: each scene against a cube on as many
C++ springs; their yardstick in ``yardstick``, their other models in ``target_models``, their timing
in ``target_timing``, their tables in ``target_tables``), ``implementations`` (the implementations
the timing studies compare) and ``mujoco_models`` (MuJoCo peers; needs the optional ``bench``
extra). The scripts put their folder ``studies/`` first on ``sys.path`` and import ``from _lib
import studylib``; only runnable study scripts live at the top of ``studies/``.
"""
