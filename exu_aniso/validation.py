"""Parameter checks with messages that name the parameter, the rule and what came in."""
from __future__ import annotations

import math
import numbers

import numpy as np


def _describe(value):
    return f"{value!r} ({type(value).__name__})"


def check_real(name, value):
    """A finite real scalar."""
    if isinstance(value, bool) or not isinstance(value, (numbers.Real, np.floating, np.integer)):
        raise TypeError(f"{name} must be a real number; got {_describe(value)}")
    value = float(value)
    if not math.isfinite(value):
        raise ValueError(f"{name} must be finite; got {value!r}")
    return value


def check_positive(name, value):
    """A finite real scalar > 0."""
    value = check_real(name, value)
    if not value > 0.0:
        raise ValueError(f"{name} must be > 0; got {value!r}")
    return value


def check_nonnegative(name, value):
    """A finite real scalar >= 0."""
    value = check_real(name, value)
    if not value >= 0.0:
        raise ValueError(f"{name} must be >= 0; got {value!r}")
    return value


def check_vector(name, value, size):
    """A finite real vector of the given length."""
    try:
        arr = np.asarray(value, dtype=float)
    except (TypeError, ValueError):
        raise TypeError(f"{name} must be a sequence of {size} real numbers; got {_describe(value)}") from None
    if arr.shape != (size,):
        raise ValueError(f"{name} must have shape ({size},); got shape {arr.shape} from {value!r}")
    if not np.all(np.isfinite(arr)):
        raise ValueError(f"{name} must be finite; got {list(arr)}")
    return arr


def check_points(name, value):
    """A finite (K, 3) array of points, K >= 1."""
    try:
        arr = np.asarray(value, dtype=float)
    except (TypeError, ValueError):
        raise TypeError(f"{name} must be a (K, 3) array of real numbers; got {_describe(value)}") from None
    if arr.ndim == 1 and arr.shape == (3,):
        arr = arr[None, :]
    if arr.ndim != 2 or arr.shape[1] != 3 or arr.shape[0] < 1:
        raise ValueError(f"{name} must have shape (K, 3) with K >= 1; got shape {arr.shape}")
    if not np.all(np.isfinite(arr)):
        raise ValueError(f"{name} must be finite; got non-finite entries")
    return arr


def check_spd(name, matrix, sign=1.0):
    """A finite symmetric 2x2 matrix with sign*matrix positive definite; returns (s11, s12, s22).

    sign = -1 checks negative definiteness (the papers' adhesion tensor B).
    """
    try:
        M = np.asarray(matrix, dtype=float)
    except (TypeError, ValueError):
        raise TypeError(f"{name} must be a 2x2 matrix of real numbers; got {_describe(matrix)}") from None
    if M.shape != (2, 2):
        raise ValueError(f"{name} must be a 2x2 matrix; got shape {M.shape}")
    if not np.all(np.isfinite(M)):
        raise ValueError(f"{name} must be finite; got {M.tolist()}")
    if abs(M[0, 1] - M[1, 0]) > 1e-12 * max(1.0, np.abs(M).max()):
        raise ValueError(f"{name} must be symmetric; got {M.tolist()} (off-diagonal {M[0, 1]!r} != {M[1, 0]!r})")
    ev = np.linalg.eigvalsh(sign * M)
    if not ev[0] > 0.0:
        rule = "negative definite (papers' sign, B = -C)" if sign < 0 else "positive definite"
        raise ValueError(f"{name} must be {rule}; got {M.tolist()} with eigenvalues {[float(v) for v in sorted(sign * ev)]}")
    return (float(M[0, 0]), float(0.5 * (M[0, 1] + M[1, 0])), float(M[1, 1]))
