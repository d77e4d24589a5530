"""Build of the two compiled extensions: exu_aniso.engines.exudyn_adapter._native (the native force
callbacks, see its source) and exu_aniso.util._float_text (result files' numbers as text), and the
compilation of the main job's contact kernels into numba's cache (``exu-aniso compile``, run on the
package just built: a first ``exu-aniso run`` then loads them instead of compiling for 15-25 s).
Everything else is in pyproject.toml. All optional: without a C++ compiler the install goes on,
every contact set keeps its Python callback and result files are written by repr() in Python; if
the kernels cannot be compiled here (or EXU_ANISO_COMPILE=0), the first run compiles them."""
import os
import subprocess
import sys
import tempfile

from pybind11.setup_helpers import Pybind11Extension
from setuptools import setup
from setuptools.command.build_ext import build_ext

ROOT = os.path.dirname(os.path.abspath(__file__))


class BuildWithKernels(build_ext):
    """build_ext, then ``python -m exu_aniso.cli compile`` on the built package (the kernel cache is
    keyed on the kernel sources' content, so the installed copy finds what the built one compiled)."""

    def run(self):
        super().run()
        if os.environ.get("EXU_ANISO_COMPILE", "1") == "0":
            return
        where = ROOT if self.inplace else os.path.abspath(self.build_lib)
        env = dict(os.environ, PYTHONPATH=os.pathsep.join(filter(None, [where, os.environ.get("PYTHONPATH")])))
        with tempfile.TemporaryDirectory() as tmp:
            try:
                done = subprocess.run([sys.executable, "-m", "exu_aniso.cli", "compile"], cwd=tmp, env=env,
                                      capture_output=True, text=True, timeout=1800)
                message = (done.stdout + done.stderr).strip()
                ok = done.returncode == 0
            except (OSError, subprocess.SubprocessError) as e:
                message, ok = f"{type(e).__name__}: {e}", False
        print(message if ok else f"exu_aniso: the kernels were not compiled at install (the first run compiles "
              f"them): {message[-2000:]}", file=sys.stderr)


setup(cmdclass={"build_ext": BuildWithKernels},
      ext_modules=[Pybind11Extension("exu_aniso.engines.exudyn_adapter._native",
                                     ["exu_aniso/engines/exudyn_adapter/_native.cpp"], cxx_std=17,
                                     optional=True),
                   Pybind11Extension("exu_aniso.util._float_text", ["exu_aniso/util/_float_text.cpp"],
                                     cxx_std=17, optional=True)])
