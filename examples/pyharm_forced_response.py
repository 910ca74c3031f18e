"""
A friction-damped resonance by harmonic balance, with pyHarm as the client
==========================================================================

One mass m on a spring k and a damper c, held to the ground by a Jenkins element (a spring kt in
series with a Coulomb slider at μN), forced by F cos ωt. Far from the resonance the element
sticks and the mass rides on k + kt; near it the element slips, softens the spring and
dissipates 4 μN (a - μN/kt) per cycle, which caps the peak.

The amplitude of the motion's first harmonic is followed through the resonance by harmonic
balance (5 harmonics, 128 samples per period) with pseudo-arclength continuation over ω:

* always, by lcpfric's minimal loop :func:`lcpfric.harmonic.balance.forced_response`, whose
  element forces and exact Jacobian come from lcpfric's AFT
  (:func:`lcpfric.harmonic.jenkins_aft`);
* when pyHarm is installed (``pip install pyharm-os``), also by pyHarm's own continuation, once
  with pyHarm's ``Jenkins`` element and once with lcpfric's element plugged into pyHarm's
  element factory (:mod:`lcpfric.harmonic.pyharm`, ``"type": "LcpfricJenkins"``). Without pyHarm
  (as when this documentation is built) these two curves are left out and the script says so.

At three points of the curve (stuck below the resonance, at the peak, slipping above it) the
element's force for the motion's first harmonic alone, ``a cos(ωt - φ)``, is compared with the
notes' closed form: in the motion's frame its first harmonic is ``(k_eq a, -ω c_eq a)``.

    python examples/pyharm_forced_response.py
"""

import os
import tempfile

import numpy as np

from lcpfric.analysis.describing import jenkins_closed_form
from lcpfric.harmonic import jenkins_aft
from lcpfric.harmonic.balance import forced_response

# importing pyHarm writes .pyHarm/context.json into the working directory: keep it out of it
os.environ.setdefault(
    "PYHARM_CONTEXT_FILE", os.path.join(tempfile.gettempdir(), "lcpfric-pyharm", "context.json")
)

M, C, K = 1.0, 0.02, 1.0  # mass, damping (ζ = 1 % on k alone), spring
KT, MU, N, F = 1.0, 0.3, 1.0, 0.3  # the Jenkins element and the forcing amplitude
H, NS = 5, 128  # harmonics, samples per period
BAND = (0.5, 2.0)  # the frequency range


def pyharm_curves():
    """pyHarm's continuation with its own element and with lcpfric's, or None without pyHarm."""
    try:
        import pyHarm  # noqa: F401
    except ImportError:
        return None
    from lcpfric.harmonic.pyharm import oscillator_input, pyharm_frequency_response

    out = {}
    for name in ("Jenkins", "LcpfricJenkins"):
        data = oscillator_input(
            M, C, K, F, BAND, kt=KT, mu=MU, normal_load=N, element=name, harmonics=H, samples=NS
        )
        out[name] = pyharm_frequency_response(data)
    return out


def first_harmonic_check(coefficients):
    """The element's first force harmonic for the motion's first harmonic alone, in the
    motion's frame, against the closed form: (a, phase, (in phase, quadrature), closed)."""
    a = np.hypot(coefficients[1], coefficients[2])
    phase = np.arctan2(coefficients[2], coefficients[1])
    x = np.zeros(2 * H + 1)
    x[1:3] = coefficients[1:3]
    T = jenkins_aft(x[None], NS, KT, MU, normal_load=N, jacobian=False).tangential_force[0, 0]
    ip = T[1] * np.cos(phase) + T[2] * np.sin(phase)
    qu = -T[1] * np.sin(phase) + T[2] * np.cos(phase)
    cf = jenkins_closed_form(KT, MU, N, [a])
    return a, phase, (ip, qu), (cf["k_eq"][0] * a, -cf["c_eq_omega"][0] * a)


def main():
    res = forced_response(
        M, C, K, F, BAND, kt=KT, mu=MU, normal_load=N, harmonics=H, samples=NS, tol=1e-12
    )
    amplitude = res.amplitude()
    peak = int(amplitude.argmax())
    slip = MU * N / KT
    print(
        f"lcpfric's harmonic-balance loop: {res.omega.size} points over ω = {BAND[0]} .. "
        f"{BAND[1]} in {res.seconds:.2f} s ({res.status}: {res.message}); peak a = "
        f"{amplitude[peak]:.5f} = {amplitude[peak] / slip:.2f} slip limits at ω = "
        f"{res.omega[peak]:.4f}"
    )

    above = peak + int(np.abs(amplitude[peak:] - 2 * slip).argmin())
    picks = {"stuck": 0, "peak": peak, "slipping": above}
    print("\nthe first force harmonic for a cos(ωt - φ) against the closed form (units of μN):")
    for label, i in picks.items():
        a, phase, (ip, qu), (kc, cq) = first_harmonic_check(res.coefficients[i, 0])
        err = max(abs(ip - kc), abs(qu - cq)) / (MU * N)
        print(
            f"  {label:>8}: ω = {res.omega[i]:.4f}, a = {a / slip:.3f} slip limits, φ = "
            f"{phase:+.3f}: in phase {ip / (MU * N):+.6f} (closed {kc / (MU * N):+.6f}), "
            f"quadrature {qu / (MU * N):+.6f} (closed {cq / (MU * N):+.6f}); error {err:.1e}"
        )

    curves = pyharm_curves()
    if curves is None:
        print(
            "\npyHarm is not installed (pip install pyharm-os): its curves are left out; "
            "with it, this script adds pyHarm's continuation with its own Jenkins element and "
            "with lcpfric's."
        )
    else:
        a, b = curves["Jenkins"], curves["LcpfricJenkins"]
        same = a["omega"].size == b["omega"].size
        diff = np.abs(a["x"] - b["x"]).max() / np.abs(a["x"]).max() if same else np.nan
        print(
            f"\npyHarm, its own Jenkins element: {a['omega'].size} points in "
            f"{a['seconds']:.2f} s; with lcpfric's element: {b['omega'].size} points in "
            f"{b['seconds']:.2f} s; the two curves differ by {diff:.1e} (relative, point by "
            "point)"
        )
        system = a["system"]
        worst = max(
            np.linalg.norm(system.Residual(np.append(q.ravel(), w))) / F
            for q, w in zip(res.coefficients, res.omega)
        )
        print(
            f"lcpfric's loop's points in pyHarm's equations (its own element): largest "
            f"residual {worst:.1e} of F"
        )

    import matplotlib.pyplot as plt

    from lcpfric.figures.style import COLUMN_WIDTH, SMALL, finish, style

    lim = (BAND[0] - 0.03, BAND[1] + 0.03)  # room for the marks at the ends
    w = np.linspace(*lim, 600)
    with style():
        fig, ax = plt.subplots(figsize=(COLUMN_WIDTH, 2.9), layout="constrained")
        ax.plot(w, F / np.hypot(K + KT - M * w**2, C * w) / slip, color="0.6", lw=0.7, ls=":",
                label="element stuck (linear, $k + k_t$)")  # fmt: skip
        ax.plot(w, F / np.hypot(K - M * w**2, C * w) / slip, color="0.6", lw=0.7, ls="--",
                label="no element (linear, $k$)")  # fmt: skip
        ax.plot(res.omega, amplitude / slip, color="black", lw=1.0,
                label="lcpfric: harmonic balance + AFT")  # fmt: skip
        if curves is not None:
            for name, kw in (
                ("Jenkins", dict(marker="o", ms=3.2, mfc="none", mew=0.6, color="C0",
                                 label="pyHarm, its Jenkins element")),
                ("LcpfricJenkins", dict(marker="+", ms=3.2, mew=0.6, color="C3",
                                        label="pyHarm, lcpfric's element")),
            ):  # fmt: skip
                c = curves[name]
                ax.plot(c["omega"], np.hypot(c["x"][:, 1], c["x"][:, 2]) / slip, ls="none", **kw)
        i = list(picks.values())
        ax.plot(res.omega[i], amplitude[i] / slip, ls="none", marker="D", ms=3.5, color="C2",
                label="force harmonics checked (closed form)")  # fmt: skip
        ax.axhline(1.0, color="0.3", lw=0.6, ls="-.")
        ax.text(BAND[0], 1.02, r"slip limit $\mu N/k_t$", fontsize=SMALL, color="0.3",
                ha="left", va="bottom")  # fmt: skip
        ax.set_xlim(*lim)
        ax.set_ylim(0.0, 1.9 * amplitude.max() / slip)
        ax.set_xlabel(r"forcing frequency $\omega\ /\ \sqrt{k/m}$")
        ax.set_ylabel(r"first-harmonic amplitude $a\ /\ (\mu N/k_t)$")
        ax.legend(loc="upper left", fontsize=SMALL, frameon=False)
        finish(fig)
    plt.show()


if __name__ == "__main__":
    main()
