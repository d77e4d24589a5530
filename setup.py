"""Build of the two compiled extensions: exu_aniso.engines.exudyn_adapter._native (the native force
callbacks, see its source) and exu_aniso.util._float_text (result files' numbers as text).
Everything else is in pyproject.toml. Both optional: without a C++ compiler the install goes on,
every contact set keeps its Python callback and result files are written by repr() in Python."""
from pybind11.setup_helpers import Pybind11Extension
from setuptools import setup

setup(ext_modules=[Pybind11Extension("exu_aniso.engines.exudyn_adapter._native",
                                     ["exu_aniso/engines/exudyn_adapter/_native.cpp"], cxx_std=17,
                                     optional=True),
                   Pybind11Extension("exu_aniso.util._float_text", ["exu_aniso/util/_float_text.cpp"],
                                     cxx_std=17, optional=True)])
