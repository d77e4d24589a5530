"""Parameter checks with messages that name the parameter, the rule and what came in."""
from __future__ import annotations

import math
import numbers

import numpy as np


class ParameterError(ValueError):
    """A parameter set that is valid value by value but cannot run as asked (a combination found
    out of reach only while preparing the run, e.g. a calibration target no setting attains). The
    command line treats it as bad input (exit code 2), like every other ValueError of validation."""


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
        raise ValueError(f"{name} must be finite; got {arr.tolist()}")
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


def check_integer(name, value, minimum=None):
    """An integer (a float with an integral value is accepted: 3.0 -> 3), optionally >= minimum."""
    if isinstance(value, bool) or not isinstance(value, (numbers.Real, np.floating, np.integer)):
        raise TypeError(f"{name} must be an integer; got {_describe(value)}")
    v = float(value)
    if not math.isfinite(v) or v != int(v):
        raise ValueError(f"{name} must be an integer; got {value!r}")
    v = int(v)
    if minimum is not None and v < minimum:
        raise ValueError(f"{name} must be an integer >= {minimum}; got {value!r}")
    return v


def check_in_range(name, value, lo, hi, why=None):
    """A finite real scalar with lo <= value <= hi (why: what the range is, for the message)."""
    value = check_real(name, value)
    if not lo <= value <= hi:
        reason = f" ({why})" if why else ""
        raise ValueError(f"{name} must lie in [{lo}, {hi}]{reason}; got {value!r}")
    return value


def check_bool(name, value):
    """True or False (numpy booleans too); no truthy strings or numbers."""
    if not isinstance(value, (bool, np.bool_)):
        raise TypeError(f"{name} must be True or False; got {_describe(value)}")
    return bool(value)


def check_instance(name, value, cls, what=None):
    """An instance of cls (a class or a tuple of classes); what: how to name the expected type."""
    if not isinstance(value, cls):
        if what is None:
            what = " or ".join(c.__name__ for c in (cls if isinstance(cls, tuple) else (cls,)))
        article = "an" if what[:1].lower() in "aeiou" else "a"
        raise TypeError(f"{name} must be {article} {what}; got {_describe(value)}")
    return value


def check_keywords(where, given, allowed):
    """Refuse keyword names that are not in allowed."""
    bad = sorted(set(given) - set(allowed))
    if bad:
        raise TypeError(f"{where}: unknown option(s) {bad}; valid options: {sorted(allowed)}")


def check_array(name, value, shape, finite=True):
    """A real array of the given shape (None in shape: any length; finite unless finite=False)."""
    shape = tuple(shape)
    text = "(" + ", ".join("K" if d is None else str(d) for d in shape) + ("," if len(shape) == 1 else "") + ")"
    try:
        arr = np.asarray(value, dtype=float)
    except (TypeError, ValueError):
        raise TypeError(f"{name} must be an array of real numbers with shape {text}; got {_describe(value)}") from None
    if arr.ndim != len(shape) or any(d is not None and d != n for d, n in zip(shape, arr.shape)):
        raise ValueError(f"{name} must have shape {text}; got shape {arr.shape}")
    if finite and not np.all(np.isfinite(arr)):
        raise ValueError(f"{name} must be finite; got non-finite entries at {np.argwhere(~np.isfinite(arr)).tolist()[:5]}")
    return arr


def check_definite_components(name, value, sign=1.0, shape=None):
    """Symmetric 2x2 tensors stored as components (s11, s12, s22), shape (3,) or (K, 3): finite and
    sign * tensor positive definite (sign = -1: the papers' negative definite adhesion B)."""
    arr = check_array(name, value, shape if shape is not None else (3,))
    s11, s12, s22 = sign * arr[..., 0], sign * arr[..., 1], sign * arr[..., 2]
    ok = (s11 > 0.0) & (s11 * s22 - s12 * s12 > 0.0)
    if not np.all(ok):
        rule = "negative definite (papers' sign, B = -C: b11 < 0, b11 b22 - b12^2 > 0)" if sign < 0 else \
            "positive definite (f11 > 0, f11 f22 - f12^2 > 0)"
        bad = arr if arr.ndim == 1 else arr[~ok][0]
        raise ValueError(f"{name} (components s11, s12, s22) must be {rule}; got {bad.tolist()}")
    return arr


def check_index(name, value, count, what="item"):
    """An item number in [0, count): an int, or an Exudyn index (ObjectIndex, NodeIndex, ...)."""
    if isinstance(value, (numbers.Integral, np.integer)) and not isinstance(value, bool):
        v = int(value)
    elif type(value).__name__.endswith("Index") and hasattr(value, "__int__"):
        v = int(value)
    else:
        raise TypeError(f"{name} must be an {what} number (int); got {_describe(value)}")
    if not 0 <= v < count:
        raise ValueError(f"{name} must be an existing {what} number in [0, {count - 1}]; got {v}")
    return v
