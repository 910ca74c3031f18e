r"""Describing functions of a continuum contact: the MDR sphere under a prescribed tangential
displacement (issue 39, items 1 and 3 for the sphere).

Under a prescribed rigid-body displacement ``x(t) = a cos ωt`` the springs of the MDR sphere
(:class:`~lcpfric.model.continuum.mdr.MDRSphere`: spring i of tangential stiffness ``k_i =
2 G* Δx`` and normal force ``N_i(t)`` from the normal problem) no longer share an unknown bar
displacement: each is a Jenkins element of its own, ``T_i = k_i (x - s_i)``, ``|T_i| <= μ N_i``,
and the contact's force is ``T = Σ T_i``. So

* **constant normal load**: every spring is the notes' Jenkins element with constant ``N_i``,
  and the contact's k_eq, ω c_eq and W are the sums of the springs' closed forms
  (:func:`~lcpfric.analysis.describing.jenkins_closed_form`): exact for the discretized
  contact (``method="closed-form"``); the force amplitude ``Σ min(k_i a, μ N_i)`` (from the
  unloaded state: a spring that never slips keeps its slider at 0);
* **varying normal load** ``P(t)`` (the model's, of period 2π/ω): the springs' ``N_i(t)`` are
  sampled over the period and every spring is marched to its steady cycle
  (:func:`~lcpfric.harmonic.jenkins_march`, exact for the piecewise-linear input through the
  samples; ``method="march"``); the force's Fourier coefficients by the discrete transform,
  W as the springs' sum. Against the smooth input the first harmonics and W converge at order 2
  in the samples (measured in ``tests/test_describing_contact.py``).

The springs that never touch (``N_i = 0`` over the cycle) carry nothing. Against the continuum,
the Mindlin-Deresiewicz dissipation at the force amplitude reached
(:func:`~lcpfric.model.continuum.closed_forms.mindlin_deresiewicz_W`) is the check:
the discretization's error (``benchmarks/validation/describing.py``).
"""

from __future__ import annotations

import math
import time

import numpy as np

from ..errors import InputError
from ..harmonic import fourier_basis, jenkins_march
from ..model.continuum.mdr import MDRSphere
from .describing import DescribingFunctions, jenkins_closed_form

__all__ = ["contact_describing_functions"]

#: the largest springs x samples x amplitudes marched at once (memory: 8 bytes each, several
#: arrays)
_MAX_BLOCK = 4_000_000


def contact_describing_functions(
    model: MDRSphere, amplitudes, *, samples: int = 1024, harmonics: int = 1
) -> DescribingFunctions:
    """The MDR sphere's describing functions under ``x = a cos ωt`` (module docstring).

    Parameters
    ----------
    model : MDRSphere
        The contact (its tangential load is not used: the motion is prescribed). A constant
        normal load gives the exact sums of the springs' closed forms; a varying one (period
        2π/ω, phase as given in the model's P) the springs' marched cycles.
    amplitudes : float or array_like
        Motion amplitudes a > 0.
    samples : int, optional
        Samples per period of the march (varying normal load only), >= 8.
    harmonics : int, optional
        Harmonics of the force kept in ``force_cos`` / ``force_sin`` (1 for the closed forms).

    Returns
    -------
    DescribingFunctions
        k_eq, ω c_eq, the loss factor, W and the force amplitude per amplitude; ``method``
        ``"closed-form"`` or ``"march"``.

    Raises
    ------
    InputError
        A model that is not an MDR sphere, an amplitude <= 0 or not finite, ``samples`` too
        small for the harmonics, or a closed-form request for more than one harmonic.
    """
    start = time.perf_counter()
    if not isinstance(model, MDRSphere):
        raise InputError(
            "model", f"must be an MDRSphere (the springs of the MDR), got {type(model).__name__}"
        )
    a = np.atleast_1d(np.asarray(amplitudes, dtype=float))
    if a.ndim != 1 or a.size == 0 or not np.all(np.isfinite(a)) or np.any(a <= 0):
        raise InputError("amplitudes", "must be finite numbers > 0")
    omega = 2.0 * math.pi / model.period
    if model.P.is_constant:
        if harmonics != 1:
            raise InputError(
                "harmonics", "a constant normal load gives the first harmonic in closed form: 1"
            )
        out = _closed_forms(model, a)
        method = "closed-form"
    else:
        out = _march(model, a, int(samples), int(harmonics))
        method = "march"
    k_eq = out["k_eq"]
    with np.errstate(divide="ignore", invalid="ignore"):
        loss = np.where(k_eq > 0, out["c_eq_omega"] / k_eq, np.nan)
    return DescribingFunctions(
        amplitude=a,
        k_eq=k_eq,
        c_eq_omega=out["c_eq_omega"],
        loss_factor=loss,
        W=out["W"],
        force_amplitude=out["force_amplitude"],
        force_cos=out["force_cos"],
        force_sin=out["force_sin"],
        omega=omega,
        method=method,
        seconds=time.perf_counter() - start,
    )


def _closed_forms(model, a):
    """The sums of the springs' closed forms (constant normal load)."""
    N = model.normal_forces(0.0)[0]
    keys = ("k_eq", "c_eq_omega", "W", "force_amplitude")
    total = {key: np.zeros(a.size) for key in keys}
    for k, n in zip(model.k, N):
        if n > 0.0:
            one = jenkins_closed_form(float(k), model.mu, float(n), a)
            for key in keys:
                total[key] += one[key]
    mean = np.zeros(a.size)
    total["force_cos"] = np.stack([mean, total["k_eq"] * a], axis=1)
    total["force_sin"] = np.stack([mean, -total["c_eq_omega"] * a], axis=1)
    return total


def _march(model, a, samples, harmonics):
    """Every spring marched to its steady cycle, for each amplitude (varying normal load)."""
    if samples < 8:
        raise InputError("samples", f"must be >= 8, got {samples}")
    basis = fourier_basis(harmonics, samples)
    t = basis.angles / (2.0 * math.pi) * model.period
    N = model.normal_forces(t).T  # (springs, samples)
    touch = np.flatnonzero(N.max(axis=1) > 0.0)
    N, k = N[touch], model.k[touch]
    c = np.cos(basis.angles)
    per = max(1, _MAX_BLOCK // max(1, N.size))
    K = 2 * harmonics + 1
    out = {key: np.zeros(a.size) for key in ("k_eq", "c_eq_omega", "W", "force_amplitude")}
    coef = np.zeros((a.size, K))
    for lo in range(0, a.size, per):
        block = a[lo : lo + per]
        x = (block[:, None, None] * c[None, None, :]) * np.ones((1, k.size, 1))
        cyc = jenkins_march(
            x.reshape(-1, samples),
            np.broadcast_to(N, (block.size, *N.shape)).reshape(-1, samples),
            np.tile(k, block.size),
            model.mu,
        )
        T = cyc.force[:, 0, :].reshape(block.size, k.size, samples).sum(axis=1)  # the contact
        coef[lo : lo + block.size] = basis.to_coefficients(T)
        out["W"][lo : lo + block.size] = cyc.dissipation.reshape(block.size, -1).sum(axis=1)
        out["force_amplitude"][lo : lo + block.size] = np.abs(T).max(axis=1)
    out["k_eq"] = coef[:, 1] / a
    out["c_eq_omega"] = -coef[:, 2] / a
    out["force_cos"] = np.concatenate([coef[:, :1], coef[:, 1::2]], axis=1)
    out["force_sin"] = np.concatenate([np.zeros((a.size, 1)), coef[:, 2::2]], axis=1)
    return out
