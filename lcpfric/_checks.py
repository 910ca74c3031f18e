"""Input validation shared by the model, the API and the CLI.

Each check names the parameter and the allowed range in its message, so the CLI can print the
message as it is.
"""

from __future__ import annotations

import math
import re

import numpy as np

from .errors import InputError

_NUMBER = r"(?:\d+(?:\.\d*)?|\.\d+)(?:[eE][+-]?\d+)?"
_PI_FORM = re.compile(rf"^\s*([+-])?\s*({_NUMBER})?\s*\*?\s*pi\s*(?:/\s*({_NUMBER}))?\s*$")


def parse_angle(text, name: str = "phi") -> float:
    """Parse an angle in radians: a plain number, or a multiple of pi such as ``0.6pi``,
    ``pi/2``, ``3*pi/10`` or ``-pi``."""
    if isinstance(text, (int, float, np.floating, np.integer)):
        return finite(name, float(text))
    s = str(text).strip().lower().replace("π", "pi")
    m = _PI_FORM.match(s)
    if m:
        factor = (-1.0 if m.group(1) == "-" else 1.0) * (float(m.group(2)) if m.group(2) else 1.0)
        denom = float(m.group(3)) if m.group(3) else 1.0
        if denom == 0:
            raise InputError(name, f"cannot parse {text!r}: division by zero")
        return finite(name, factor * math.pi / denom)
    try:
        value = float(s)
    except ValueError:
        raise InputError(
            name, f"cannot parse {text!r}; give radians (e.g. 1.885) or a multiple of pi "
                  "(e.g. 0.6pi, pi/2)") from None
    return finite(name, value)


def parse_number(text, name: str) -> float:
    """Parse a real number given as text (CLI) or as a number."""
    if isinstance(text, str):
        try:
            value = float(text)
        except ValueError:
            raise InputError(name, f"cannot parse {text!r} as a number") from None
    else:
        try:
            value = float(text)
        except (TypeError, ValueError):
            raise InputError(name, f"expected a real number, got {text!r}") from None
    return finite(name, value)


def finite(name: str, value) -> float:
    """Return ``value`` as a float, raising :class:`InputError` if it is not a finite real."""
    try:
        x = float(value)
    except (TypeError, ValueError):
        raise InputError(name, f"expected a finite real number, got {value!r}") from None
    if not math.isfinite(x):
        raise InputError(name, f"must be a finite number, got {x}")
    return x


def nonnegative(name: str, value) -> float:
    x = finite(name, value)
    if x < 0:
        raise InputError(name, f"must be >= 0 (allowed range [0, inf)), got {x}")
    return x


def positive(name: str, value) -> float:
    x = finite(name, value)
    if x <= 0:
        raise InputError(name, f"must be > 0 (allowed range (0, inf)), got {x}")
    return x


def positive_int(name: str, value, minimum: int = 1) -> int:
    try:
        ivalue = int(value)
    except (TypeError, ValueError):
        raise InputError(name, f"expected an integer >= {minimum}, got {value!r}") from None
    if ivalue != value and not (isinstance(value, str) and str(ivalue) == value.strip()):
        try:
            if float(value) != ivalue:
                raise InputError(name, f"expected an integer >= {minimum}, got {value!r}")
        except (TypeError, ValueError):
            raise InputError(name, f"expected an integer >= {minimum}, got {value!r}") from None
    if ivalue < minimum:
        raise InputError(name, f"must be an integer >= {minimum}, got {ivalue}")
    return ivalue


def finite_array(name: str, values, *, nonneg: bool = False) -> np.ndarray:
    """Return ``values`` as a float array, checking every entry is finite (and >= 0)."""
    try:
        arr = np.asarray(values, dtype=float)
    except (TypeError, ValueError):
        raise InputError(name, f"expected real numbers, got {values!r}") from None
    if not np.all(np.isfinite(arr)):
        raise InputError(name, "every value must be a finite number; found NaN or inf")
    if nonneg and np.any(arr < 0):
        raise InputError(name, f"every value must be >= 0 (allowed range [0, inf)); "
                               f"smallest given is {arr.min()}")
    return arr


NONCONVERGENCE = ("raise", "warn", "ignore")


def driver_options(tol, max_cycles, on_nonconvergence) -> tuple[float, int, str]:
    """Validate the periodic driver's options (shared by :mod:`lcpfric.periodic` and
    :mod:`lcpfric.batch`)."""
    tol = positive("tol", tol)
    max_cycles = positive_int("max_cycles", max_cycles, minimum=1)
    if on_nonconvergence not in NONCONVERGENCE:
        raise InputError("on_nonconvergence", f"must be one of {NONCONVERGENCE}, "
                                              f"got {on_nonconvergence!r}")
    return tol, max_cycles, on_nonconvergence
