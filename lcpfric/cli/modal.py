"""``lcpfric modal``: the amplitude-dependent frequency and damping of a mode of a jointed
structure (quasi-static modal analysis, :mod:`lcpfric.analysis.modal`), from a ``.npz`` file."""

from __future__ import annotations

import json

HELP = "frequency and damping against amplitude of a jointed structure's mode (.npz file)"
DESCRIPTION = (
    "Read a structure with Jenkins contacts from FILE (a NumPy .npz archive with the keys M and "
    "K: n x n mass and stiffness, dense; contact_dofs: n_c x 2 degrees of freedom joined by "
    "each contact, 0-based, -1 for the ground; kt, mu, N: each contact's tangential stiffness, "
    "friction coefficient and constant normal load, one number or n_c), load it quasi-"
    "statically along the mode --mode of the stuck structure, and print, per modal amplitude "
    "a, the frequency ratio omega/omega0 (omega^2 = alpha_max/a, the backbone's secant), the "
    "damping ratio zeta = W/(2 pi omega^2 a^2) and the dissipation per cycle W of the exact "
    "steady hysteresis cycle."
)
OPTIONS = {"amplitude": "--amplitude", "mode": "--mode"}
#: the file's key of each parameter of lcpfric.model.structure.JointedStructure
KEYS = {
    "mass": "M",
    "stiffness": "K",
    "contact_dofs": "contact_dofs",
    "contact_stiffness": "kt",
    "friction": "mu",
    "normal_load": "N",
}


def configure(p) -> None:
    p.add_argument("--file", required=True, metavar="FILE", help="the structure (.npz)")
    p.add_argument(
        "--mode",
        default="0",
        metavar="K",
        help="the stuck structure's mode, by index from the lowest (0, the default)",
    )
    p.add_argument(
        "--amplitude",
        required=True,
        metavar="A[:B:N]",
        help="modal amplitudes a > 0: one value, a comma list, or A:B:N for N values from A to "
        "B, log-spaced",
    )
    p.add_argument("--json", action="store_true", help="print one JSON object")


def _field(exc, key=None):
    """The InputError of a file's field, named after --file."""
    from ..errors import InputError

    key = key or KEYS.get(exc.parameter, exc.parameter)
    return InputError("--file", f"field {key}: {exc.detail}")


def read_structure(path: str):
    """The :class:`~lcpfric.model.structure.JointedStructure` a ``.npz`` file describes (the
    keys of :data:`KEYS`), or InputError naming ``--file`` and the field."""
    from pathlib import Path

    import numpy as np

    from ..errors import InputError
    from ..model.structure import JointedStructure

    p = Path(path)
    if not p.is_file():
        raise InputError("--file", f"{path!r} is not a readable file")
    try:
        archive = np.load(p, allow_pickle=False)
    except (OSError, ValueError, EOFError) as exc:
        raise InputError("--file", f"{path!r} is not a NumPy .npz archive ({exc})") from None
    if not isinstance(archive, np.lib.npyio.NpzFile):  # a .npy file: one array
        raise InputError("--file", f"{path!r} holds one array, not a .npz archive of named arrays")
    try:
        with archive:
            data = {k: archive[k] for k in archive.files}
    except (OSError, ValueError, EOFError) as exc:
        raise InputError("--file", f"{path!r} is not a readable .npz archive ({exc})") from None
    missing = [k for k in KEYS.values() if k not in data]
    if missing:
        raise InputError(
            "--file", f"field {missing[0]}: missing (the file needs {', '.join(KEYS.values())})"
        )
    try:
        return JointedStructure(**{name: data[key] for name, key in KEYS.items()})
    except InputError as exc:
        raise _field(exc) from None


def run(args) -> int:
    from .. import _checks
    from ..analysis.modal import modal_damping
    from ..errors import InputError
    from ._grids import parse_amplitudes

    amplitudes = parse_amplitudes(args.amplitude, "--amplitude")
    mode = _checks.positive_int("--mode", args.mode, 0)
    structure = read_structure(args.file)
    if mode >= structure.n:
        raise InputError("--mode", f"must be a mode index in [0, {structure.n - 1}], got {mode}")
    try:
        res = modal_damping(structure, amplitudes, mode=mode)
    except InputError as exc:
        if exc.parameter in KEYS:  # K not definite on its own
            raise _field(exc) from None
        raise
    fields = {
        "a": res.a.tolist(),
        "omega_ratio": res.omega_ratio.tolist(),
        "zeta": res.zeta.tolist(),
        "W": res.W.tolist(),
        "omega": res.omega.tolist(),
        "alpha_max": res.alpha_max.tolist(),
        "sticks": res.sticks.tolist(),
    }
    if args.json:
        one = len(amplitudes) == 1
        out = {k: (v[0] if one else v) for k, v in fields.items()}
        out.update(mode=mode, omega0=res.omega0, seconds=sum(res.stats[k] for k in
                   ("condense_seconds", "cycle_seconds")))  # fmt: skip
        print(json.dumps(out))
        return 0
    print(
        f"mode {mode} of the stuck structure: omega0 = {res.omega0:.10g} ({structure.n} degrees "
        f"of freedom, {structure.n_contacts} contacts)"
    )
    print(f"{'a':>16} {'omega/omega0':>14} {'zeta':>16} {'W':>16}")
    for a, ratio, zeta, W, still in zip(*(fields[k] for k in ("a", "omega_ratio", "zeta", "W",
                                                              "sticks"))):  # fmt: skip
        note = "  (sticks)" if still else ""
        print(f"{a:16.10g} {ratio:14.10f} {zeta:16.10g} {W:16.10g}{note}")
    return 0
