"""Limits the tests share.

HANG_S [s]: the timeout of every subprocess a test starts (a study's quick run, a command line, a
script of the docs). It guards against a hang and is never a check of speed: it is ten times the
longest such subprocess measured with a cold kernel cache on this 2-core machine with the other core
busy (the quick fastening study, 170 s: ``pytest --durations=60`` of the suite from an empty
``NUMBA_CACHE_DIR``), so how fast the machine is cannot decide a test's outcome.
"""
HANG_S = 1800
