"""What every subcommand shares: the parser class, the load-case options, the one mapping from
API parameter names to option names, checks done before any work (extras, output paths, memory),
and the translation of errors into exit codes.

This module is imported for ``lcpfric --help``: it imports only the standard library and
:mod:`lcpfric.errors`. Anything numerical is imported inside the functions that need it.

Exit codes: 0 success; 1 a solver or the computation failed; 2 bad input, a missing extra, or a
request over the memory limit (one line on stderr naming the option, no traceback); 130
interrupted.
"""

from __future__ import annotations

import argparse
import contextlib
import os
import sys

from ..errors import ConvergenceError, InputError, LcpfricError, MissingDependency, SolverError

__all__ = [
    "Parser",
    "add_case_options",
    "case_from_args",
    "option_names",
    "option_for",
    "execute",
    "values_after_options",
    "repeated_option",
    "MissingExtras",
    "require_extras",
    "installed",
    "output_file",
    "output_dir",
    "written_files",
    "remove_created",
    "add_memory_option",
    "memory_limit",
    "parse_size",
    "format_bytes",
    "check_memory",
    "steady_state_bytes",
    "map_bytes",
    "add_note",
    "OUTPUT_RULE",
    "snapshot",
]

from ..memory import (
    MEMORY_ENV,
    check,
    default_limit,
    format_bytes,
    map_bytes,
    parse_size,
    steady_state_bytes,
)
from ._extras import EXTRA_OF, MissingExtras, installed, require_extras
from ._paths import (
    OUTPUT_RULE,
    output_dir,
    output_file,
    remove_created,
    snapshot,
    written_files,
)


# -- the parser ------------------------------------------------------------------------------------
class Parser(argparse.ArgumentParser):
    """argparse that exits with code 2 and one line (no usage dump) on a bad option."""

    def error(self, message):  # noqa: D401 - argparse API
        self.exit(2, f"{self.prog}: error: {one_line(message)} (see '{self.prog} --help')\n")


def one_line(text) -> str:
    """``text`` on one line (solvers' messages sometimes carry newlines)."""
    return " ".join(str(text).split())


def _value_options(parser: argparse.ArgumentParser) -> dict[str, argparse.Action]:
    """The option strings of ``parser`` that take exactly one value."""
    return {s: a for a in parser._actions for s in a.option_strings if a.nargs is None}


def _resolve(token: str, options: dict[str, argparse.Action], allow_abbrev: bool):
    """The value-taking option ``token`` names (exactly, or as an unambiguous abbreviation as
    argparse accepts it), or None."""
    if token in options:
        return token
    if not allow_abbrev or not token.startswith("--") or "=" in token:
        return None
    hits = [s for s in options if s.startswith(token)]
    return hits[0] if len(hits) == 1 else None


def values_after_options(parser: argparse.ArgumentParser, argv: list[str]) -> list[str]:
    """Make the token after a value-taking option its value, even when it starts with ``-``.

    argparse reads ``--phi -0.5pi`` or ``--Q0 -1e3`` as an option with no value ("expected one
    argument"); ``--phi=-0.5pi`` works. This rewrites ``--opt -value`` as ``--opt=-value`` for
    the options of the chosen subcommand that take one value, unless the next token is itself an
    option (starts with ``--``, or is one of the subcommand's short options such as ``-h``), so a
    forgotten value is still reported as such.
    """
    argv = list(argv)
    sub = next((a for a in parser._actions if isinstance(a, argparse._SubParsersAction)), None)
    if sub is None:
        return argv
    # the subcommand is the first token that is not an option (lcpfric's own options take no
    # values)
    index = next((i for i, tok in enumerate(argv) if not tok.startswith("-")), None)
    if index is None or argv[index] not in sub.choices:
        return argv
    subparser = sub.choices[argv[index]]
    options = _value_options(subparser)
    own = set(subparser._option_string_actions)
    out = argv[: index + 1]
    i = index + 1
    while i < len(argv):
        tok = argv[i]
        if tok == "--":
            out += argv[i:]
            break
        name = _resolve(tok, options, subparser.allow_abbrev)
        if name is not None and i + 1 < len(argv):
            value = argv[i + 1]
            if value.startswith("-") and not value.startswith("--") and value not in own:
                out.append(f"{tok}={value}")
            else:
                out += [tok, value]
            i += 2
            continue
        out.append(tok)
        i += 1
    return out


def repeated_option(parser: argparse.ArgumentParser, argv: list[str]) -> str | None:
    """The one-line error for a value-taking option given twice (argparse keeps the last value
    and drops the first without a word), or None. ``argv`` as :func:`values_after_options`
    returns it."""
    sub = next((a for a in parser._actions if isinstance(a, argparse._SubParsersAction)), None)
    index = next((i for i, tok in enumerate(argv) if not tok.startswith("-")), None)
    if sub is None or index is None or argv[index] not in sub.choices:
        return None
    subparser = sub.choices[argv[index]]
    options = _value_options(subparser)
    seen: dict[str, str] = {}
    i = index + 1
    while i < len(argv):
        tok = argv[i]
        if tok == "--":
            break
        head, eq, value = tok.partition("=")
        name = _resolve(head, options, subparser.allow_abbrev)
        if name is None:
            i += 1
            continue
        if not eq:
            value = argv[i + 1] if i + 1 < len(argv) else ""
            i += 1
        i += 1
        dest = options[name].dest
        if dest in seen:
            return (
                f"{subparser.prog}: error: {name}: given twice ({seen[dest]!r}, then "
                f"{value!r}); give it once (see '{subparser.prog} --help')"
            )
        seen[dest] = value
    return None


# -- option names ----------------------------------------------------------------------------------
def option_names(
    parser: argparse.ArgumentParser, aliases: dict[str, str] | None = None
) -> dict[str, str]:
    """API parameter name -> the subcommand's option.

    Every option maps from its ``dest`` (``max_cycles`` -> ``--max-cycles``, ``P1`` -> ``--P1``);
    ``aliases`` adds the API names that differ from the option's (``steps_per_cycle`` ->
    ``--steps``).
    """
    names = {}
    for action in parser._actions:
        longs = [s for s in action.option_strings if s.startswith("--")]
        if longs and action.dest not in ("help", argparse.SUPPRESS):
            names.setdefault(action.dest, longs[0])
    names.update(aliases or {})
    return names


def option_for(parameter: str, names: dict[str, str]) -> str:
    """The option to name in a message about the API parameter ``parameter``."""
    parameter = str(parameter)
    if parameter.startswith("-"):
        return parameter
    if parameter in names:
        return names[parameter]
    head, sep, tail = parameter.partition(" ")  # "P1 (NUM)"
    if sep and head in names:
        return f"{names[head]} {tail}"
    return parameter


def add_note(exc: BaseException, note: str) -> None:
    """Attach a note to ``exc`` (``BaseException.add_note`` where it exists: Python >= 3.11)."""
    if hasattr(exc, "add_note"):
        exc.add_note(note)
    else:  # pragma: no cover - Python 3.10
        exc.__notes__ = [*getattr(exc, "__notes__", []), note]


def _message(exc: BaseException) -> str:
    notes = [str(n) for n in getattr(exc, "__notes__", ()) or ()]
    return one_line("; ".join([str(exc), *notes]))


@contextlib.contextmanager
def _one_line_warnings(prog):
    """lcpfric's own warnings (a result the grid cannot resolve, say) as one line on stderr,
    ``prog: warning: ...``, like its errors; other warnings as Python shows them."""
    import warnings

    from ..errors import ConvergenceWarning, ResolutionWarning

    with warnings.catch_warnings():
        default = warnings.showwarning

        def show(message, category, filename, lineno, file=None, line=None):
            if issubclass(category, (ConvergenceWarning, ResolutionWarning)):
                print(f"{prog}: warning: {message}", file=sys.stderr)
            else:
                default(message, category, filename, lineno, file, line)

        warnings.showwarning = show
        for category in (ConvergenceWarning, ResolutionWarning):  # shown, never raised
            warnings.simplefilter("default", category)
        yield


def execute(args) -> int:
    """Run the subcommand chosen in ``args``; turn every expected failure into one line on
    stderr and an exit code (see the module docstring)."""
    module, parser = args._module, args._parser
    prog = parser.prog
    try:
        with _one_line_warnings(prog):
            if "--max-memory" not in parser._option_string_actions:
                return int(module.run(args) or 0)
            from .. import memory  # --max-memory holds for the library's own checks too

            given = getattr(args, "max_memory", None)
            size = None if given is None else parse_size(given, "--max-memory")
            with memory.limit(size, "--max-memory"):
                return int(module.run(args) or 0)
    except InputError as exc:
        option = option_for(exc.parameter, option_names(parser, getattr(module, "OPTIONS", {})))
        notes = "".join(f"; {n}" for n in getattr(exc, "__notes__", ()) or ())
        return _fail(prog, "error", f"{option}: {exc.detail}{notes}", 2)
    except (MissingDependency, MissingExtras) as exc:  # a missing extra or solver package
        return _fail(prog, "error", _message(exc), 2)
    except (SolverError, ConvergenceError) as exc:
        status = getattr(exc, "status", "")
        return _fail(
            prog, "failed", _message(exc) + (f" (solver status: {status})" if status else ""), 1
        )
    except LcpfricError as exc:
        return _fail(prog, "failed", _message(exc), 1)
    except ModuleNotFoundError as exc:  # an optional package imported deep inside a method
        name = (exc.name or "").split(".")[0]
        extra = EXTRA_OF.get(name)
        hint = f': pip install "lcpfric[{extra}]"' if extra else ""
        return _fail(
            prog, "error", f"this needs the package {name!r}, which is not installed{hint}", 2
        )
    except MemoryError:
        lower = (
            ", or lower --max-memory so that lcpfric refuses such runs before it starts them"
            if "--max-memory" in parser._option_string_actions
            else ""
        )
        return _fail(
            prog, "failed", f"ran out of memory; ask for less (fewer steps or points){lower}", 1
        )
    except KeyboardInterrupt:
        print(f"{prog}: interrupted", file=sys.stderr)
        return 130
    except BrokenPipeError:  # the reader went away (lcpfric methods | head -1): stop quietly
        try:  # and keep the interpreter from complaining when it flushes stdout at exit
            os.dup2(os.open(os.devnull, os.O_WRONLY), sys.stdout.fileno())
        except (OSError, ValueError, AttributeError):
            pass
        return 1
    except OSError as exc:  # a file the checks let through that the system refused
        option = _option_of_path(args, parser, exc.filename)
        what = f"cannot write {str(exc.filename)!r}" if exc.filename else "input/output failed"
        reason = exc.strerror or type(exc).__name__
        if option is None:
            return _fail(prog, "failed", f"{what}: {reason}", 1)
        return _fail(prog, "error", f"{option}: {what}: {reason}", 2)


def _option_of_path(args, parser, filename) -> str | None:
    """The output option whose path holds ``filename`` (None if no option does)."""
    if not filename:
        return None
    filename = os.path.abspath(os.fsdecode(filename))
    for action in parser._actions:
        value = getattr(args, action.dest, None)
        longs = [o for o in action.option_strings if o.startswith("--")]
        if not longs or not isinstance(value, str) or not value.strip():
            continue
        path = os.path.abspath(value)
        if filename == path or filename.startswith(path.rstrip(os.sep) + os.sep):
            return longs[0]
    return None


def _fail(prog: str, kind: str, message: str, code: int) -> int:
    print(f"{prog}: {kind}: {one_line(message)}", file=sys.stderr)
    return code


# -- the load case ---------------------------------------------------------------------------------
DIMENSIONAL = ("k11", "k22", "f", "P0", "Q0", "omega")
#: the dimensional inputs that set P̂1 = P1/P0, Q̂1 = Q1/(f P0) and W = f P0 Q1 Ŵ / k11
REQUIRED_DIMENSIONAL = ("k11", "f", "P0")
#: the others, with the values assumed when they are not given (they do not change W)
ASSUMED = {"k22": 1.0, "Q0": 0.0, "omega": 1.0}


def add_case_options(p: argparse.ArgumentParser) -> None:
    """--P1, --Q1, --phi, the dimensional inputs and --json."""
    p.add_argument(
        "--P1",
        required=True,
        metavar="X",
        help="normal load amplitude (P̂1 = P1/P0 unless dimensional inputs are given)",
    )
    p.add_argument(
        "--Q1",
        required=True,
        metavar="X",
        help="tangential load amplitude (Q̂1 = Q1/(f P0) unless dimensional)",
    )
    p.add_argument(
        "--phi",
        default="0",
        metavar="ANGLE",
        help="phase of Q relative to P: radians, or a multiple of pi such as 0.6pi, "
        "pi/2, -0.5pi (negative values may follow the option directly)",
    )
    g = p.add_argument_group(
        "dimensional inputs",
        "Giving any of these makes --P1 and --Q1 dimensional amplitudes. "
        "Then --k11, --f and --P0 are required (they set P̂1 = P1/P0, Q̂1 = Q1/(f P0) and "
        "W = f P0 Q1 Ŵ / k11); --k22, --Q0 and --omega default to 1, 0 and 1 (they do not "
        "change W) and the defaults used are printed.",
    )
    for name, text in (
        ("k11", "tangential stiffness"),
        ("k22", "normal stiffness"),
        ("f", "coefficient of friction"),
        ("P0", "mean normal load"),
        ("Q0", "mean tangential load"),
        ("omega", "angular frequency"),
    ):
        g.add_argument(f"--{name}", default=None, metavar="X", help=text)
    p.add_argument("--json", action="store_true", help="print one JSON object")


def case_from_args(args):
    """The :class:`~lcpfric.model.SingleNode` of the case options, and the dimensional defaults
    assumed (``{}`` for a normalized case)."""
    from .. import _checks
    from ..model import SingleNode

    phi = _checks.parse_angle(args.phi, "--phi")
    P1 = _checks.parse_number(args.P1, "--P1")
    Q1 = _checks.parse_number(args.Q1, "--Q1")
    given = {
        k: _checks.parse_number(getattr(args, k), f"--{k}")
        for k in DIMENSIONAL
        if getattr(args, k) is not None
    }
    if not given:
        return SingleNode.normalized(P1=P1, Q1=Q1, phi=phi), {}
    # validate what was given first (SingleNode names the parameter), then ask for what is missing
    node = SingleNode(P1=P1, Q1=Q1, phi=phi, **given)
    missing = [k for k in REQUIRED_DIMENSIONAL if k not in given]
    if missing:
        options = ", ".join(f"--{k}" for k in missing)
        raise InputError(
            options,
            (
                f"required with dimensional input (--{next(iter(given))} was given): "
                "--k11, --f and --P0 set P̂1 = P1/P0, Q̂1 = Q1/(f P0) and W = f P0 Q1 Ŵ / k11; "
                "give them, or leave out every dimensional option to give P̂1 and Q̂1 directly"
            ),
        )
    return node, {k: v for k, v in ASSUMED.items() if k not in given}


def assumed_line(assumed: dict) -> str:
    return (
        "assumed: "
        + ", ".join(f"{k} = {v:g}" for k, v in assumed.items())
        + " (not given; they do not change W)"
    )


# -- memory ----------------------------------------------------------------------------------------
def add_memory_option(p: argparse.ArgumentParser) -> None:
    p.add_argument(
        "--max-memory",
        default=None,
        metavar="SIZE",
        help=f"refuse runs estimated to need more memory than this (e.g. 8G, 500M, "
        f"none); default: ${MEMORY_ENV}, else half the physical memory",
    )


def memory_limit(args) -> tuple[float, str]:
    """(limit in bytes, where it comes from) for ``--max-memory``, ``$LCPFRIC_MAX_MEMORY`` or
    half the physical memory."""
    given = getattr(args, "max_memory", None)
    if given is not None:
        return parse_size(given, "--max-memory"), "--max-memory"
    return default_limit()


def check_memory(need: float, args, option: str, what: str) -> None:
    """Raise InputError naming ``option`` when ``need`` bytes exceed the memory limit."""
    size = format_bytes(need * 1.25).replace(" ", "")
    check(need, option, what, memory_limit(args), how=f"--max-memory {size} (or ${MEMORY_ENV})")


def workers_for(processes) -> int:
    if processes:
        return int(processes)
    try:
        return len(os.sched_getaffinity(0))
    except AttributeError:  # pragma: no cover - not Linux
        return os.cpu_count() or 1
