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


_NOT_NUMBERS = (str, bytes, bool, np.bool_)


def _not_a_number(value) -> bool:
    """Strings and booleans are not numbers for the API (the CLI parses its strings first)."""
    if isinstance(value, _NOT_NUMBERS):
        return True
    return isinstance(value, (np.ndarray, np.generic)) and value.dtype.kind not in "fiu"


def _short(value) -> str:
    text = repr(value)
    return text if len(text) <= 40 else text[:18] + "..." + text[-18:]


def parse_angle(text, name: str = "phi") -> float:
    """Parse an angle in radians: a plain number, or a multiple of pi such as ``0.6pi``,
    ``pi/2``, ``3*pi/10`` or ``-pi`` (the CLI's parser: it accepts strings)."""
    if not isinstance(text, str):
        return finite(name, text)
    s = text.strip().lower().replace("π", "pi")
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
            name,
            f"cannot parse {text!r}; give radians (e.g. 1.885) or a multiple of pi "
            "(e.g. 0.6pi, pi/2)",
        ) from None
    return finite(name, value)


def parse_number(text, name: str) -> float:
    """Parse a real number given as text (CLI) or as a number."""
    if isinstance(text, str):
        try:
            value = float(text)
        except ValueError:
            raise InputError(name, f"cannot parse {text!r} as a number") from None
        return finite(name, value)
    return finite(name, text)


def finite(name: str, value) -> float:
    """Return ``value`` as a float, raising :class:`InputError` if it is not a finite real.

    Strings and booleans are refused (``"1.5"``, ``True``): the API takes numbers; text goes
    through :func:`parse_number` or :func:`parse_angle`.
    """
    if _not_a_number(value) or isinstance(value, (complex, np.complexfloating)):
        raise InputError(
            name,
            f"expected a finite real number (int or float), got {value!r} "
            f"of type {type(value).__name__}",
        )
    try:
        x = float(value)
    except OverflowError:
        raise InputError(
            name,
            f"must be a finite number within the double range "
            f"(|x| <= {np.finfo(float).max:.4g}), got {_short(value)}",
        ) from None
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


def byte_budget(name: str, value, minimum: float = 1.0) -> float:
    """A number of bytes: a real >= ``minimum``, or ``math.inf`` for no bound; strings and
    booleans are refused."""
    x = math.nan
    if not (_not_a_number(value) or isinstance(value, (complex, np.complexfloating))):
        try:
            x = float(value)
        except OverflowError:
            x = math.inf
        except (TypeError, ValueError):
            pass
    if not x >= minimum:  # NaN fails too
        raise InputError(
            name,
            f"must be a number of bytes in [{minimum:g}, inf] (inf: no bound), got {_short(value)}",
        )
    return x


def boolean(name: str, value) -> bool:
    """Return ``value`` as a bool; only ``True``/``False`` (or numpy booleans) are accepted, not
    ``"yes"``, 1 or None."""
    if isinstance(value, (bool, np.bool_)):
        return bool(value)
    raise InputError(name, f"must be True or False, got {value!r} of type {type(value).__name__}")


def positive_int(name: str, value, minimum: int = 1) -> int:
    """An integer >= ``minimum``. The CLI passes its text: integer strings and integral numbers
    written as floats (``"4000"``, ``"4e3"``, ``"4000.0"``) are accepted; floats only when
    integral; booleans are refused. One message for every count: "must be a whole number >=
    minimum"."""
    bad = f"must be a whole number >= {minimum}, got {value!r}"
    if isinstance(value, (bool, np.bool_)):
        raise InputError(name, bad)
    if isinstance(value, str):
        text = value.strip()
        try:
            ivalue = int(text)
        except ValueError:
            try:
                x = float(text)
            except ValueError:
                raise InputError(name, bad) from None
            if not (math.isfinite(x) and x == int(x)):
                raise InputError(name, bad) from None
            ivalue = int(x)
    else:
        try:
            ivalue = int(value)
        except (TypeError, ValueError, OverflowError):
            raise InputError(name, bad) from None
        try:
            if float(value) != ivalue:
                raise InputError(name, bad)
        except (TypeError, ValueError, OverflowError):
            raise InputError(name, bad) from None
    if ivalue < minimum:
        raise InputError(name, f"must be a whole number >= {minimum}, got {ivalue}")
    return ivalue


def _range(nonneg: bool, upper) -> str:
    return f"[{0 if nonneg else '-inf'}, {'inf)' if upper is None else f'{upper:g}]'}"


def amplitude(name: str, value, upper: float) -> float:
    """A finite real in ``[0, upper]``."""
    if _not_a_number(value) or isinstance(value, (complex, np.complexfloating)):
        finite(name, value)  # raises, with the type in the message
    try:
        x = float(value)
    except OverflowError:
        x = math.inf
    except (TypeError, ValueError):
        return finite(name, value)  # raises
    if not 0.0 <= x <= upper:  # NaN fails too
        raise InputError(name, f"must be a finite number in [0, {upper:g}], got {_short(value)}")
    return x


def finite_array(
    name: str, values, *, nonneg: bool = False, upper: float | None = None
) -> np.ndarray:
    """Return ``values`` as a float array, checking every entry is a finite real (and >= 0,
    and <= ``upper`` if given).

    Strings and booleans are refused, as in :func:`finite`.
    """
    try:
        raw = np.asarray(values)
    except (TypeError, ValueError):
        raise InputError(name, f"expected real numbers, got {values!r}") from None
    kind = raw.dtype.kind
    # a large array is named by its shape, not printed
    shown = repr(values) if raw.size <= 16 else f"an array of shape {raw.shape}"
    if kind == "O":  # e.g. a list mixing Python numbers and other objects
        flat = raw.ravel().tolist()
        if any(_not_a_number(v) or isinstance(v, (complex, np.complexfloating)) for v in flat):
            raise InputError(name, f"expected real numbers (int or float), got {shown}")
    elif kind not in "fiu":
        raise InputError(
            name, f"expected real numbers (int or float), got {shown} (dtype {raw.dtype})"
        )
    try:
        arr = np.asarray(raw, dtype=float)
    except OverflowError:
        raise InputError(
            name, f"every value must be within the double range (|x| <= {np.finfo(float).max:.4g})"
        ) from None
    except (TypeError, ValueError):
        raise InputError(name, f"expected real numbers, got {values!r}") from None
    if not np.all(np.isfinite(arr)):
        where = np.argwhere(~np.isfinite(arr))
        at = f" at index {tuple(int(i) for i in where[0])}" if arr.ndim else ""
        bounds = f" in {_range(nonneg, upper)}" if nonneg or upper is not None else ""
        raise InputError(
            name,
            f"every value must be a finite number{bounds}; found "
            f"{arr[tuple(where[0])] if arr.ndim else arr}{at} ({len(where)} not finite)",
        )
    if nonneg and np.any(arr < 0):
        raise InputError(
            name,
            f"every value must be >= 0 (allowed range {_range(nonneg, upper)}"
            f"); smallest given is {arr.min()}",
        )
    if upper is not None and np.any(arr > upper):
        raise InputError(
            name,
            f"every value must be <= {upper:g} (allowed range "
            f"{_range(nonneg, upper)}); largest given is {arr.max()}",
        )
    return arr


NONCONVERGENCE = ("raise", "warn", "ignore")


def driver_options(tol, max_cycles, on_nonconvergence) -> tuple[float, int, str]:
    """Validate the periodic driver's options (shared by :mod:`lcpfric.periodic` and
    :mod:`lcpfric.batch`)."""
    tol = positive("tol", tol)
    max_cycles = positive_int("max_cycles", max_cycles, minimum=1)
    if on_nonconvergence not in NONCONVERGENCE:
        raise InputError(
            "on_nonconvergence", f"must be one of {NONCONVERGENCE}, got {on_nonconvergence!r}"
        )
    return tol, max_cycles, on_nonconvergence
