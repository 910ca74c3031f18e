"""Describing functions of a Jenkins element: its equivalent stiffness and damping against the
motion amplitude, from the exact steady cycle (issue 39, item 3).

For the motion ``x = a cos ωt`` the steady force is ``T ≈ T0 + A cos ωt + B sin ωt + ...``
(first harmonic by exact integration over the cycle's segments, :mod:`lcpfric.exact.
driven_result`), and

    k_eq      = A / a                      in-phase first harmonic over a
    ω c_eq    = -B / a                     quadrature first harmonic over a (> 0 when the
                                           element dissipates: T ≈ k_eq x + c_eq dx/dt)
    W         = ∮ T dx = π a² ω c_eq       dissipation per cycle
    η         = W / (π k_eq a²) = ω c_eq / k_eq

The loss factor η is the dissipation per cycle over 2π times the peak energy ``k_eq a²/2``
stored by the equivalent linear spring (Nashif, Jones and Henderson, *Vibration Damping*,
Wiley 1985, Sec. 1.3; Lazan, *Damping of Materials and Members in Structural Mechanics*, 1968);
it is NaN (undefined) where k_eq <= 0. The largest |T| over the steady cycle is
``force_amplitude``.

With constant N the notes' closed forms hold (:func:`jenkins_closed_form`); with a varying normal
load ``N0 + N1 cos(ωt + φ)`` there is none, and the cycle is the exact single node's
(:mod:`lcpfric.exact.jenkins_node`), W for all amplitudes at once by :func:`lcpfric.exact.
exact_W_hat`.
"""

from __future__ import annotations

import math
import time
from dataclasses import dataclass

import numpy as np

from .. import _checks
from ..errors import InputError
from ..exact import exact_W_hat
from ..exact.driven import driven_cycle
from ..exact.jenkins_node import jenkins_cycle
from ..exact.trig import TrigPoly, periodic_sign_changes
from ..model.jenkins import JenkinsElement, amplitudes_checked, jenkins_closed_form
from ..model.single_node import W_from_W_hat

__all__ = ["DescribingFunctions", "describing_functions", "jenkins_closed_form", "METHODS"]

#: the ways a describing function is computed: the exact single node, or the event solver
METHODS = ("single-node", "driven")


@dataclass(frozen=True)
class DescribingFunctions:
    """A Jenkins element's describing functions over motion amplitudes.

    Parameters
    ----------
    amplitude, k_eq, c_eq_omega, loss_factor, W, force_amplitude, force_cos, force_sin
        Per amplitude (see Attributes).
    omega, method, seconds
        How they were computed (see Attributes).

    Attributes
    ----------
    amplitude : ndarray
        The motion amplitudes a (``x = a cos ωt``).
    k_eq : ndarray
        Equivalent stiffness: T's in-phase first harmonic over a.
    c_eq_omega : ndarray
        ω c_eq: T's quadrature first harmonic over a, positive for dissipation.
    loss_factor : ndarray
        ``W / (π k_eq a²)`` (NaN where k_eq <= 0).
    W : ndarray
        Dissipation per cycle.
    force_amplitude : ndarray
        ``max |T|`` over the steady cycle.
    force_cos, force_sin : ndarray
        Shape ``(n, harmonics + 1)``: T's Fourier coefficients (``force_cos[:, 0]`` the mean).
    omega : float
        ω (the results do not depend on it: the element is rate independent).
    method : str
        ``"single-node"`` or ``"driven"``.
    seconds : float
        Wall time.
    """

    amplitude: np.ndarray
    k_eq: np.ndarray
    c_eq_omega: np.ndarray
    loss_factor: np.ndarray
    W: np.ndarray
    force_amplitude: np.ndarray
    force_cos: np.ndarray
    force_sin: np.ndarray
    omega: float
    method: str
    seconds: float

    def as_dict(self, harmonics: bool = False) -> dict:
        """The results as JSON-ready lists (NaN as None).

        Parameters
        ----------
        harmonics : bool, optional
            Add ``force_cos`` and ``force_sin`` (per amplitude, k = 0..harmonics).

        Returns
        -------
        dict
            ``amplitude``, ``W``, ``k_eq``, ``c_eq_omega``, ``loss_factor``,
            ``force_amplitude`` (and the harmonics), each a list over the amplitudes.
        """

        def clean(values):
            return [None if not math.isfinite(v) else float(v) for v in np.ravel(values)]

        out = {
            name: clean(getattr(self, name))
            for name in ("amplitude", "W", "k_eq", "c_eq_omega", "loss_factor", "force_amplitude")
        }
        if harmonics:
            out["force_cos"] = [clean(row) for row in self.force_cos]
            out["force_sin"] = [clean(row) for row in self.force_sin]
        return out


def describing_functions(
    element: JenkinsElement,
    amplitudes,
    *,
    harmonics: int = 1,
    start: float | None = None,
    method: str = "single-node",
    omega: float = 1.0,
) -> DescribingFunctions:
    """k_eq, ω c_eq, the loss factor, W and the force amplitude of a Jenkins element over
    motion amplitudes, from its exact steady cycle under ``x = a cos ωt``.

    Parameters
    ----------
    element : JenkinsElement
        The element and its normal side (constant N0, or ``N0 + N1 cos(ωt + φ)`` clipped at
        zero, or a normal spring with a harmonic normal displacement).
    amplitudes : array_like
        Motion amplitudes a > 0.
    harmonics : int, optional
        The highest harmonic of T kept in ``force_cos``/``force_sin``, >= 1.
    start : float, optional
        The slider at t = 0 (default 0, the motion's mean): it matters only where the element
        shakes down (then the mean force and ``force_amplitude`` depend on it, k_eq = kt and
        c_eq = 0 do not).
    method : {"single-node", "driven"}, optional
        The exact single node (default; W for all amplitudes in one vectorized call), or the
        event solver of :mod:`lcpfric.exact.driven` (the independent check). With μ = 0 the
        element carries no force and ``driven`` is used.
    omega : float, optional
        ω > 0 (no result depends on it).

    Returns
    -------
    DescribingFunctions
        One entry per amplitude, in the order given.

    Raises
    ------
    InputError
        Naming the parameter: an amplitude <= 0 or not finite, ``harmonics`` < 1, an unknown
        ``method``, ``element`` not a JenkinsElement.

    Examples
    --------
    >>> from lcpfric.model.jenkins import JenkinsElement
    >>> el = JenkinsElement(kt=1.0, mu=1.0, N0=1.0)
    >>> df = describing_functions(el, [0.5, 2.0])
    >>> df.k_eq.round(12).tolist(), df.W.round(12).tolist()
    ([1.0, 0.5], [0.0, 4.0])
    """
    started = time.perf_counter()
    if not isinstance(element, JenkinsElement):
        raise InputError("element", f"must be a JenkinsElement, got {type(element).__name__}")
    a = amplitudes_checked(amplitudes)
    harmonics = _checks.positive_int("harmonics", harmonics)
    omega = _checks.positive("omega", omega)
    start = None if start is None else _checks.finite("start", start)
    if method not in METHODS:
        raise InputError("method", f"must be one of {', '.join(METHODS)}, got {method!r}")
    if element.mu == 0.0:
        method = "driven"
    if method == "driven":
        cycles = [
            driven_cycle(element, element.motion(ai, omega), start=start, harmonics=harmonics,
                         samples=4)
            for ai in a
        ]  # fmt: skip
        W = np.array([c.W for c in cycles])
    else:
        # the extrema of x = a cos ωt and of N do not depend on a: found once
        x1 = TrigPoly([0.0, 1.0])
        N1 = TrigPoly.from_load(element.normal_load(omega), omega)
        extrema = (periodic_sign_changes(x1.derivative())[0],
                   periodic_sign_changes(N1.derivative())[0])  # fmt: skip
        cycles = [
            jenkins_cycle(element, ai, omega=omega, start=start, harmonics=harmonics, samples=4,
                          extrema=extrema)
            for ai in a
        ]  # fmt: skip
        # W of every amplitude in one call of the exact node's vectorized path (Eq. 6 units)
        node = element.single_node(float(a[0]), omega)
        P1, _, phi = node.normalized_parameters()
        Q1 = element.kt * a  # the node's Q1 = kt a, and Q̂1 = Q1 / (f P0) as SingleNode has it
        W = W_from_W_hat(exact_W_hat(P1, Q1 / (element.mu * node.P0), phi), element.kt,
                         element.mu, node.P0, Q1)  # fmt: skip
    force_cos = np.array([c.force_cos for c in cycles])
    force_sin = np.array([c.force_sin for c in cycles])
    k_eq = force_cos[:, 1] / a
    c_eq = W / (math.pi * a * a)  # = -force_sin[:, 1] / a: W = ∮ T dx = -π a B
    with np.errstate(divide="ignore", invalid="ignore"):
        loss = np.where(k_eq > 0.0, c_eq / k_eq, np.nan)
    return DescribingFunctions(
        amplitude=a,
        k_eq=k_eq,
        c_eq_omega=c_eq,
        loss_factor=loss,
        W=np.asarray(W, dtype=float),
        force_amplitude=np.array([c.force_amplitude for c in cycles]),
        force_cos=force_cos,
        force_sin=force_sin,
        omega=omega,
        method=method,
        seconds=time.perf_counter() - started,
    )
