"""The ``lcpfric`` command line.

One module per subcommand, each with ``HELP``, ``DESCRIPTION``, ``OPTIONS`` (the API parameter
names that differ from its option names), ``configure(parser)`` and ``run(args)``:

=================  ===================  =======================================================
subcommand         module               what it does
=================  ===================  =======================================================
``dissipation``    :mod:`.dissipation`  Ŵ (and W) of one load case
``loop``           :mod:`.loop`         its hysteresis loop (F against v), area = W
``shakedown``      :mod:`.shakedown`    the exact shakedown test of one load case
``system``         :mod:`.system`       W of a system file (coupled or not), over starts
``contact``        :mod:`.contact`      W of a continuum contact (Hertz sphere, MDR)
``modal``          :mod:`.modal`        ω(a), ζ(a) of a jointed structure's mode (.npz file)
``describe``       :mod:`.describe`     a Jenkins element's k_eq, ω c_eq, W against amplitude
``frf``            :mod:`.frf`          the node with a mass: W, amplitude, phase against ω
``methods``        :mod:`.methods`      the methods usable on this installation
``map``            :mod:`.map`          a dissipation map over (φ, P̂1, Q̂1), to NetCDF
``figures``        :mod:`.figures`      the paper's figures
``paper-claims``   :mod:`.claims`       the paper's quantitative claims, recomputed
=================  ===================  =======================================================

What they share is in :mod:`._common`. The subcommand modules import only the standard library
at module level, so every subcommand is always listed in ``lcpfric --help`` and a command imports
the numerical parts it needs (and the optional extras) only when it runs; a missing extra is
reported in one line naming what to install. Bad input prints one line naming the option and
exits with code 2 (no traceback); a solver failure exits with code 1.

To add a subcommand: write ``lcpfric/cli/<name>.py`` with the four names above and add it to
:data:`COMMANDS` (``loop`` was added so).
"""

from __future__ import annotations

import argparse
import importlib
import sys

from ._common import Parser, execute, repeated_option, values_after_options

__all__ = ["main", "build_parser", "COMMANDS"]

#: subcommand -> module under lcpfric.cli, in the order ``--help`` lists them
COMMANDS = {
    "dissipation": "dissipation",
    "loop": "loop",
    "shakedown": "shakedown",
    "system": "system",
    "contact": "contact",
    "modal": "modal",
    "describe": "describe",
    "frf": "frf",
    "methods": "methods",
    "map": "map",
    "figures": "figures",
    "paper-claims": "claims",
}


class _Version(argparse.Action):
    """``--version``, reading the version only when asked."""

    def __init__(
        self,
        option_strings,
        dest=argparse.SUPPRESS,
        default=argparse.SUPPRESS,
        help="print the version and exit",
    ):
        super().__init__(option_strings, dest=dest, default=default, nargs=0, help=help)

    def __call__(self, parser, namespace, values, option_string=None):
        try:
            from .. import __version__ as version
        except ImportError:  # pragma: no cover - a package without the attribute
            from importlib.metadata import version as _version

            version = _version("lcpfric")
        print(f"lcpfric {version}")  # on stdout, as the GNU standards ask
        parser.exit(0)


def build_parser() -> argparse.ArgumentParser:
    """The ``lcpfric`` parser with every subcommand (standard library only)."""
    parser = Parser(
        prog="lcpfric",
        description="Frictional dissipation per load cycle in "
        "elastic contact systems under periodic loads.",
        epilog="Negative values may follow an option directly (--phi -0.5pi). Bad "
        "input exits with code 2 and one line naming the option; a solver "
        "failure exits with code 1.",
    )
    parser.add_argument("--version", action=_Version)
    sub = parser.add_subparsers(
        dest="command", required=True, metavar="COMMAND", parser_class=Parser
    )
    for name, module_name in COMMANDS.items():
        module = importlib.import_module(f"{__name__}.{module_name}")
        p = sub.add_parser(name, help=module.HELP, description=module.DESCRIPTION)
        module.configure(p)
        p.set_defaults(_module=module, _parser=p)
    return parser


def main(argv=None) -> int:
    """Run ``lcpfric`` with ``argv`` (default: ``sys.argv[1:]``); return the exit code."""
    parser = build_parser()
    argv = values_after_options(parser, list(sys.argv[1:] if argv is None else argv))
    twice = repeated_option(parser, argv)
    if twice is not None:
        print(twice, file=sys.stderr)
        return 2
    try:
        args = parser.parse_args(argv)
    except SystemExit as exc:  # --help, --version, or a parse error (already printed)
        return exc.code if isinstance(exc.code, int) else (0 if exc.code is None else 2)
    return execute(args)


if __name__ == "__main__":  # pragma: no cover
    sys.exit(main())
