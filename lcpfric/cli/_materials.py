"""``lcpfric contact``'s second body: ``--E2 --nu2`` (another material) or ``--rigid`` (a rigid
base), its options and their checks before any work (:mod:`.contact`)."""

from __future__ import annotations

import math

__all__ = ["add_options", "second"]


def add_options(p) -> None:
    """Add ``--E2``, ``--nu2`` and ``--rigid`` to the parser ``p``."""
    p.add_argument(
        "--E2",
        default=None,
        metavar="X",
        help="Young's modulus of a second body of another material (the base; --E and --nu "
        "are then the loaded body's); with --nu2",
    )
    p.add_argument("--nu2", default=None, metavar="X", help="the second body's Poisson's ratio")
    p.add_argument(
        "--rigid",
        action="store_true",
        help="the second body is rigid (an elastic body of --E --nu on a rigid base)",
    )


def second(args, model_name: str, num: dict, scaled) -> dict:
    """The second body as keywords of the model (``E2``, ``nu2``; empty: two identical bodies),
    checked before any work: both of ``--E2 --nu2`` or ``--rigid`` alone, their ranges, a model
    that takes them (the half-space; the MDR sphere only where Dundurs' β = 0). ``num``: the
    parsed --E and --nu; ``scaled``: the command's number parser."""
    from ..errors import InputError
    from ..model.continuum.dissimilar import pair

    given = [o for o in ("E2", "nu2") if getattr(args, o) is not None]
    if args.rigid:
        if given:
            raise InputError("--rigid", f"a rigid second body takes no --{given[0]}")
        out = {"E2": math.inf}
    elif not given:
        return {}
    else:
        for option, other in (("E2", "nu2"), ("nu2", "E2")):
            if getattr(args, option) is None:
                raise InputError(f"--{option}", f"the second body needs --{option} with --{other}")
        out = {"E2": scaled(args.E2, "--E2"), "nu2": scaled(args.nu2, "--nu2")}
    named = "--rigid" if args.rigid else "--E2"
    if model_name == "halfplane":
        raise InputError(
            named,
            "a second material applies to --model halfspace (or mdr where Dundurs' beta = 0) "
            "only, not the half-plane cylinder",
        )
    try:
        pair(1.0, 0.0, out["E2"], out.get("nu2"))  # the values alone
    except InputError as exc:
        raise InputError(f"--{exc.parameter}", exc.detail) from None
    E, nu = num["E"], num["nu"]
    if model_name == "mdr" and E > 0 and 0 <= nu < 0.5:
        materials = pair(E, nu, out["E2"], out.get("nu2"))
        if materials is not None and materials["beta"] != 0.0:
            if not args.rigid and out["E2"] == E:
                named = "--nu2"
            raise InputError(
                named,
                f"makes Dundurs' beta = {materials['beta']:.4g} (not 0): the pressure couples "
                "with the shear and the contact loses its axial symmetry, which the MDR "
                "model's independent springs cannot carry; use --model halfspace",
            )
    return out
