"""The command line's grids of values: ``START:STOP:NUM`` or ``a,b,c`` (angles as multiples of
pi)."""

from __future__ import annotations

import numpy as np

from .. import _checks
from ..errors import InputError

__all__ = ["parse_grid", "parse_phi_list"]


def parse_grid(text: str, name: str, angle: bool = False) -> np.ndarray:
    """Parse ``START:STOP:NUM`` (NUM points, both ends included) or ``a,b,c`` (or one value).

    With ``angle=True`` every number may be written as a multiple of pi (``0.6pi``, ``pi/2``).
    """
    parse = (
        (lambda s: _checks.parse_angle(s, name))
        if angle
        else (lambda s: _checks.parse_number(s, name))
    )
    text = str(text).strip()
    if ":" in text:
        parts = text.split(":")
        if len(parts) != 3:
            raise InputError(name, f"expected START:STOP:NUM, got {text!r}")
        start, stop = parse(parts[0]), parse(parts[1])
        num = _checks.positive_int(f"{name} (NUM)", parts[2].strip())
        if num > 1 and start == stop:
            raise InputError(name, f"START = STOP gives {num} equal values; give NUM = 1")
        return np.linspace(start, stop, num)
    items = [s for s in text.split(",") if s.strip()]
    if not items:
        raise InputError(name, "expected START:STOP:NUM or a comma-separated list of values")
    return np.array([parse(s) for s in items])  # a value given twice: refused by the sweep


def parse_amplitudes(text: str, name: str = "--amplitude") -> np.ndarray:
    """Amplitudes ``a > 0``: one value, ``a,b,c``, or ``A:B:N``, N values from A to B spaced
    *logarithmically* (amplitudes span decades: the describing functions, the modal damping)."""
    a = parse_grid(text, name)
    if np.any(a <= 0):
        raise InputError(name, f"every amplitude must be > 0, got {a.min():g}")
    if ":" in str(text) and a.size > 1:
        a = np.geomspace(a[0], a[-1], a.size)
    return a


def parse_phi_list(text: str) -> np.ndarray:
    """Parse a φ list such as ``0,0.6pi,pi/2,1.2`` (radians) or ``0:pi:11``."""
    return parse_grid(text, "phi", angle=True)
