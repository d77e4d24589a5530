"""Analytical master surfaces, one module each, on one protocol (``core``): chart and its
derivatives, closest point projection, metric, curvature, Christoffel symbols, parallel transport
and the slip increment. See docs/adding_a_surface.md for how to add one (the torus as the example).
"""
from .base import Point, Surface
from .cone import Cone
from .cylinder import Cylinder
from .helicoid import Helicoid
from .parametric import ParametricSurface
from .plane import Plane
from .revolution import SurfaceOfRevolution
from .sphere import Sphere
from .torus import Torus

__all__ = ["Surface", "Point", "Plane", "Cylinder", "Cone", "Sphere", "Torus", "Helicoid",
           "SurfaceOfRevolution", "ParametricSurface"]
