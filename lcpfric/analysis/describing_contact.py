r"""Describing functions of a continuum contact under a prescribed tangential displacement (issue
39, items 1 and 3 for the continuum contacts): the MDR sphere, the half-plane cylinder and the
3-D half-space.

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

**The half-plane and the half-space** (d = 1): their nodes are coupled through the
compliance, so the contact under the motion is a matrix-free
:class:`~lcpfric.model.ContactSystem` (:func:`~lcpfric.model.continuum.bridge.
displacement_system`: the body held by the motion, ``K = C_s⁻¹``, loads ``-C_s⁻¹ 1 x(t)``)
solved to its steady state by the driver with ``active-set`` (``method="active-set"``; ``steps``
increments per cycle, exact for the loads interpolated linearly between them; events located);
its tangential force ``T = -Σ F``, whose Fourier coefficients come from the cycle's records
(the grid's instants and the events between them) by the trapezoidal rule
(:func:`~lcpfric.harmonic.trapezoid_coefficients`: the discrete transform on a uniform grid).
The same route on the MDR sphere gives the springs' closed forms to round-off
(``tests/test_describing_contact.py``).

**A prescribed normal approach** instead of a normal load: ``MDRSphere.under_approach``,
``HalfPlaneCylinder.under_approach`` and ``HalfSpace.under_approach`` build the model whose
load ``P(t)`` is the one of the approach ``d(t)`` (:mod:`lcpfric.model.continuum.approach`;
exact for the discretized contact, 0 where the bodies are apart), and the routes above apply
unchanged: with similar materials the normal problem does not see the shear.

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
from ..harmonic import fourier_basis, jenkins_march, trapezoid_coefficients
from ..model.continuum.bridge import displacement_system
from ..model.continuum.mdr import MDRSphere
from ..periodic.driver import steady_state
from .describing import DescribingFunctions, jenkins_closed_form

__all__ = ["contact_describing_functions"]

#: the largest springs x samples x amplitudes marched at once (memory: 8 bytes each, several
#: arrays)
_MAX_BLOCK = 4_000_000


def contact_describing_functions(
    model,
    amplitudes,
    *,
    samples: int = 1024,
    harmonics: int = 1,
    steps: int = 400,
    method: str | None = None,
) -> DescribingFunctions:
    """A continuum contact's describing functions under ``x = a cos ωt`` (module docstring).

    Parameters
    ----------
    model : MDRSphere, HalfPlaneCylinder or HalfSpace
        The contact (its tangential load and support are not used: the motion is prescribed).
        The MDR sphere: a constant normal load gives the exact sums of the springs' closed
        forms, a varying one (period 2π/ω, phase as given in the model's P) the springs'
        marched cycles. The half-plane and the half-space (d = 1): the driver's steady state
        of the displacement-driven system with ``active-set``.
    amplitudes : float or array_like
        Motion amplitudes a > 0.
    samples : int, optional
        Samples per period of the march (varying normal load only), >= 8.
    harmonics : int, optional
        Harmonics of the force kept in ``force_cos`` / ``force_sin`` (1 for the closed forms).
    steps : int, optional
        Increments per cycle of the driver's steady state (``method="active-set"``).
    method : str, optional
        None: the model's own (above): ``"closed-form"`` or ``"march"`` for the MDR sphere,
        ``"active-set"`` for the others; any method of the driver that takes the
        displacement-driven system (``"active-set"`` also for the MDR sphere, a check;
        ``"clarabel"`` for a half-space with d = 2 on a small grid, C formed from products).

    Returns
    -------
    DescribingFunctions
        k_eq, ω c_eq, the loss factor, W and the force amplitude per amplitude; ``method``
        ``"closed-form"``, ``"march"`` or ``"active-set"``.

    Raises
    ------
    InputError
        A model that is not a continuum contact, a half-space with d = 2 and
        ``method="active-set"``, an amplitude <= 0 or not finite, ``samples`` too small for
        the harmonics, a closed-form request for more than one harmonic, or a method that does
        not apply.
    """
    start = time.perf_counter()
    if not hasattr(model, "springs") or not hasattr(model, "normal_problem"):
        raise InputError(
            "model",
            f"must be a continuum contact (MDRSphere, HalfPlaneCylinder, HalfSpace), got "
            f"{type(model).__name__}",
        )
    a = np.atleast_1d(np.asarray(amplitudes, dtype=float))
    if a.ndim != 1 or a.size == 0 or not np.all(np.isfinite(a)) or np.any(a <= 0):
        raise InputError("amplitudes", "must be finite numbers > 0")
    omega = 2.0 * math.pi / model.period
    mdr = isinstance(model, MDRSphere)
    d = getattr(model, "dims", 1)
    own = ("closed-form" if model.P.is_constant else "march") if mdr else "active-set"
    if method is None:
        method = own
    if method in ("closed-form", "march") and method != own:
        raise InputError(
            "method",
            f"{method!r} does not apply to this model: {own!r} or a method of the driver "
            "('active-set', 'clarabel', ...)",
        )
    if method not in ("closed-form", "march"):  # the driver's: any method the system takes
        if d != 1 and method == "active-set":
            raise InputError(
                "method",
                "'active-set' is matrix-free for d = 1 only: for a half-space with d = 2 under "
                "a prescribed displacement give method='clarabel' (small grids: C is formed)",
            )
        out = _driven(model, a, int(steps), int(harmonics), method, d)
    elif model.P.is_constant:
        if harmonics != 1:
            raise InputError(
                "harmonics", "a constant normal load gives the first harmonic in closed form: 1"
            )
        out = _closed_forms(model, a)
    else:
        out = _march(model, a, int(samples), int(harmonics))
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


def _driven(model, a, steps, harmonics, method, d):
    """The displacement-driven system's steady state by the driver (``method``), for each
    amplitude: T = -Σ F_x at the records, its coefficients by the trapezoidal rule."""
    out = {key: np.zeros(a.size) for key in ("k_eq", "c_eq_omega", "W", "force_amplitude")}
    coef = np.zeros((a.size, 2 * harmonics + 1))
    for i, amp in enumerate(a):
        res = steady_state(displacement_system(model, amp), method, steps)
        F = np.asarray(res.F, dtype=float)
        T = -F.reshape(F.shape[0], -1, d)[:, :, 0].sum(axis=1)
        # the records: the grid's instants and the events between them (placed by the driver)
        coef[i] = trapezoid_coefficients(res.t, T, model.period, harmonics)
        out["W"][i] = res.W
        out["force_amplitude"][i] = np.abs(T).max()
    out["k_eq"] = coef[:, 1] / a
    out["c_eq_omega"] = -coef[:, 2] / a
    out["force_cos"] = np.concatenate([coef[:, :1], coef[:, 1::2]], axis=1)
    out["force_sin"] = np.concatenate([np.zeros((a.size, 1)), coef[:, 2::2]], axis=1)
    return out
