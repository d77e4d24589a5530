"""Build of the one compiled extension, exu_aniso.engines.exudyn_adapter._native (the native force
callbacks, see its source). Everything else is in pyproject.toml. Optional: without a C++ compiler
the install goes on and every contact set keeps its Python callback."""
from pybind11.setup_helpers import Pybind11Extension
from setuptools import setup

setup(ext_modules=[Pybind11Extension("exu_aniso.engines.exudyn_adapter._native",
                                     ["exu_aniso/engines/exudyn_adapter/_native.cpp"], cxx_std=17,
                                     optional=True)])
