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
import importlib.util
import math
import os
import re
import sys
from typing import TYPE_CHECKING

from ..errors import (ConvergenceError, InputError, LcpfricError, MissingDependency,
                      SolverError)

if TYPE_CHECKING:  # pathlib imports urllib and ipaddress: not for --help
    from pathlib import Path

__all__ = [
    "Parser", "add_case_options", "case_from_args", "option_names", "option_for", "execute",
    "values_after_options", "MissingExtras", "require_extras", "installed",
    "output_file", "output_dir", "written_files", "remove_created",
    "add_memory_option", "memory_limit", "parse_size", "format_bytes", "check_memory",
    "steady_state_bytes", "map_bytes", "add_note",
]

OUTPUT_RULE = ("The output's parent directory must exist; lcpfric creates only the output itself "
               "and removes what it created if the run fails.")


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
    out = argv[:index + 1]
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


# -- option names ----------------------------------------------------------------------------------
def option_names(parser: argparse.ArgumentParser, aliases: dict[str, str] | None = None
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


def execute(args) -> int:
    """Run the subcommand chosen in ``args``; turn every expected failure into one line on
    stderr and an exit code (see the module docstring)."""
    module, parser = args._module, args._parser
    prog = parser.prog
    try:
        return int(module.run(args) or 0)
    except InputError as exc:
        option = option_for(exc.parameter, option_names(parser, getattr(module, "OPTIONS", {})))
        notes = "".join(f"; {n}" for n in getattr(exc, "__notes__", ()) or ())
        return _fail(prog, "error", f"{option}: {exc.detail}{notes}", 2)
    except (MissingDependency, MissingExtras) as exc:  # a missing extra or solver package
        return _fail(prog, "error", _message(exc), 2)
    except (SolverError, ConvergenceError) as exc:
        status = getattr(exc, "status", "")
        return _fail(prog, "failed", _message(exc) + (f" (solver status: {status})" if status
                                                       else ""), 1)
    except LcpfricError as exc:
        return _fail(prog, "failed", _message(exc), 1)
    except ModuleNotFoundError as exc:  # an optional package imported deep inside a method
        name = (exc.name or "").split(".")[0]
        extra = _EXTRA_OF.get(name)
        hint = f': pip install "lcpfric[{extra}]"' if extra else ""
        return _fail(prog, "error", f"this needs the package {name!r}, which is not "
                                    f"installed{hint}", 2)
    except MemoryError:
        return _fail(prog, "failed", "ran out of memory; ask for less (fewer steps or points), "
                                     "or lower --max-memory so that lcpfric refuses such runs "
                                     "before it starts them", 1)
    except KeyboardInterrupt:
        print(f"{prog}: interrupted", file=sys.stderr)
        return 130
    except BrokenPipeError:  # the reader went away (lcpfric methods | head -1): stop quietly
        try:  # and keep the interpreter from complaining when it flushes stdout at exit
            os.dup2(os.open(os.devnull, os.O_WRONLY), sys.stdout.fileno())
        except (OSError, ValueError, AttributeError):
            pass
        return 1


def _fail(prog: str, kind: str, message: str, code: int) -> int:
    print(f"{prog}: {kind}: {one_line(message)}", file=sys.stderr)
    return code


# -- extras ----------------------------------------------------------------------------------------
#: importable module -> the extra that installs it
_EXTRA_OF = {"matplotlib": "plot", "xarray": "dist", "h5netcdf": "dist", "h5py": "dist",
             "distributed": "dist", "dask": "dist", "tqdm": "dist", "clarabel": "clarabel",
             "osqp": "osqp", "qpsolvers": "qpsolvers", "cvxpy": "cvxpy"}


class MissingExtras(LcpfricError):
    """Optional packages a subcommand needs are missing (all of them named at once)."""

    def __init__(self, what: str, missing: list[tuple[str, str]]):
        self.what = what
        self.missing = missing
        extras = ",".join(dict.fromkeys(extra for _, extra in missing))
        listed = " and ".join(f"{module} ({extra})" for module, extra in missing)
        super().__init__(f'{what} need {listed}: pip install "lcpfric[{extras}]"')


def installed(module: str) -> bool:
    """Whether ``module`` can be imported (found without importing it)."""
    try:
        return importlib.util.find_spec(module) is not None
    except (ImportError, ValueError):
        return False


def require_extras(what: str, modules) -> None:
    """Raise :class:`MissingExtras` naming every one of ``modules`` that is not installed.

    ``modules``: module names, or tuples of alternatives (the first one is named if none is
    installed).
    """
    missing = []
    for entry in modules:
        choices = (entry,) if isinstance(entry, str) else tuple(entry)
        if not any(installed(m) for m in choices):
            missing.append((choices[0], _EXTRA_OF.get(choices[0], choices[0])))
    if missing:
        raise MissingExtras(what, missing)


# -- the load case ---------------------------------------------------------------------------------
DIMENSIONAL = ("k11", "k22", "f", "P0", "Q0", "omega")
#: the dimensional inputs that set P̂1 = P1/P0, Q̂1 = Q1/(f P0) and W = f P0 Q1 Ŵ / k11
REQUIRED_DIMENSIONAL = ("k11", "f", "P0")
#: the others, with the values assumed when they are not given (they do not change W)
ASSUMED = {"k22": 1.0, "Q0": 0.0, "omega": 1.0}


def add_case_options(p: argparse.ArgumentParser) -> None:
    """--P1, --Q1, --phi, the dimensional inputs and --json."""
    p.add_argument("--P1", required=True, metavar="X",
                   help="normal load amplitude (P̂1 = P1/P0 unless dimensional inputs are given)")
    p.add_argument("--Q1", required=True, metavar="X",
                   help="tangential load amplitude (Q̂1 = Q1/(f P0) unless dimensional)")
    p.add_argument("--phi", default="0", metavar="ANGLE",
                   help="phase of Q relative to P: radians, or a multiple of pi such as 0.6pi, "
                        "pi/2, -0.5pi (negative values may follow the option directly)")
    g = p.add_argument_group(
        "dimensional inputs", "Giving any of these makes --P1 and --Q1 dimensional amplitudes. "
        "Then --k11, --f and --P0 are required (they set P̂1 = P1/P0, Q̂1 = Q1/(f P0) and "
        "W = f P0 Q1 Ŵ / k11); --k22, --Q0 and --omega default to 1, 0 and 1 (they do not "
        "change W) and the defaults used are printed.")
    for name, text in (("k11", "tangential stiffness"), ("k22", "normal stiffness"),
                       ("f", "coefficient of friction"), ("P0", "mean normal load"),
                       ("Q0", "mean tangential load"), ("omega", "angular frequency")):
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
    given = {k: _checks.parse_number(getattr(args, k), f"--{k}") for k in DIMENSIONAL
             if getattr(args, k) is not None}
    if not given:
        return SingleNode.normalized(P1=P1, Q1=Q1, phi=phi), {}
    # validate what was given first (SingleNode names the parameter), then ask for what is missing
    node = SingleNode(P1=P1, Q1=Q1, phi=phi, **given)
    missing = [k for k in REQUIRED_DIMENSIONAL if k not in given]
    if missing:
        options = ", ".join(f"--{k}" for k in missing)
        raise InputError(options, (
            f"required with dimensional input (--{next(iter(given))} was given): --k11, --f and "
            "--P0 set P̂1 = P1/P0, Q̂1 = Q1/(f P0) and W = f P0 Q1 Ŵ / k11; give them, or "
            "leave out every dimensional option to give P̂1 and Q̂1 directly"))
    return node, {k: v for k, v in ASSUMED.items() if k not in given}


def assumed_line(assumed: dict) -> str:
    return ("assumed: " + ", ".join(f"{k} = {v:g}" for k, v in assumed.items())
            + " (not given; they do not change W)")


# -- output paths ----------------------------------------------------------------------------------
def _parent_writable(path: Path, option: str) -> None:
    parent = path.parent
    if not parent.is_dir():
        raise InputError(option, f"the directory {str(parent)!r} does not exist; create it "
                                 "first (lcpfric creates only the output itself)")
    if not os.access(parent, os.W_OK | os.X_OK):
        raise InputError(option, f"cannot write in the directory {str(parent)!r} (permission "
                                 "denied)")


def output_file(text, option: str, suffix: str) -> Path:
    """Check an output file path before any work: not empty, ending in ``suffix``, not a
    directory, in an existing writable directory."""
    from pathlib import Path

    text = "" if text is None else str(text)
    if not text.strip():
        raise InputError(option, f"is empty; give a file name ending in {suffix}, e.g. "
                                 f"map{suffix}")
    path = Path(text)
    if path.is_dir() or text.endswith(("/", os.sep)):
        raise InputError(option, f"{text!r} is a directory; give a file name ending in {suffix}, "
                                 f"e.g. {str(path / ('map' + suffix))!r}")
    if path.suffix.lower() != suffix:
        raise InputError(option, f"must end in {suffix} (the file is written as NetCDF-4), got "
                                 f"{text!r}")
    if path.exists() and not path.is_file():
        raise InputError(option, f"{text!r} exists and is not a regular file")
    _parent_writable(path, option)
    if path.exists() and not os.access(path, os.R_OK):
        raise InputError(option, f"{text!r} exists and cannot be read (permission denied)")
    return path


def output_dir(text, option: str) -> Path:
    """Check an output directory path before any work: not empty, not an existing file, its
    parent an existing writable directory (or itself an existing writable directory)."""
    from pathlib import Path

    text = "" if text is None else str(text)
    if not text.strip():
        raise InputError(option, "is empty; give a directory, e.g. figures (use . for the "
                                 "working directory)")
    path = Path(text)
    if path.exists() and not path.is_dir():
        raise InputError(option, f"{text!r} exists and is not a directory")
    if path.is_dir():
        if not os.access(path, os.W_OK | os.X_OK):
            raise InputError(option, f"cannot write in {text!r} (permission denied)")
        return path
    _parent_writable(path, option)
    return path


def _stat_key(path: Path):
    try:
        st = path.stat()
    except OSError:
        return None
    return (st.st_ino, st.st_size, st.st_mtime_ns)


def snapshot(directory: Path) -> dict:
    """What files ``directory`` holds now (to tell afterwards which ones a run wrote)."""
    if not directory.is_dir():
        return {}
    return {p.name: _stat_key(p) for p in directory.iterdir()}


def written_files(directory: Path, before: dict, names=None) -> list[Path]:
    """The files of ``directory`` (among ``names`` if given) that are new or changed since the
    ``before`` snapshot."""
    if not directory.is_dir():
        return []
    out = []
    for p in sorted(directory.iterdir()):
        if names is not None and p.name not in names:
            continue
        if p.is_file() and before.get(p.name) != _stat_key(p):
            out.append(p)
    return out


def remove_created(directory: Path, before: dict, existed: bool) -> None:
    """After a failed run: delete the files the run created in ``directory`` (never one that
    was there before), and the directory itself if the run created it and it is now empty."""
    if not directory.is_dir():
        return
    for p in directory.iterdir():
        if p.name not in before and p.is_file():
            p.unlink(missing_ok=True)
    if not existed:
        try:
            directory.rmdir()
        except OSError:
            pass


# -- memory ----------------------------------------------------------------------------------------
MEMORY_ENV = "LCPFRIC_MAX_MEMORY"
_DEFAULT_FRACTION = 0.5
_UNITS = {"": 1, "b": 1, "k": 1e3, "kb": 1e3, "kib": 2**10, "m": 1e6, "mb": 1e6, "mib": 2**20,
          "g": 1e9, "gb": 1e9, "gib": 2**30, "t": 1e12, "tb": 1e12, "tib": 2**40,
          "p": 1e15, "pb": 1e15, "pib": 2**50, "e": 1e18, "eb": 1e18, "eib": 2**60}
_SIZE = re.compile(r"^\s*(\d+(?:\.\d*)?|\.\d+)(?:[eE]([+-]?\d+))?\s*([A-Za-z]*)\s*$")

#: float64 values held per time step (per tangential degree of freedom) by a steady state: the
#: scene's t, Q, N, the cycle's u, F, state, the previous cycle's u and the result's series.
#: Each method's factor is in its registry entry (``Method.floats_per_step``; measured peaks with
#: tracemalloc, single node: exact 10, explicit and projection 26, the convex solver backends 83
#: to 116, rounded up); this one serves a name the registry does not know.
_FLOATS_PER_STEP_SOLVER = 128
#: float64 values per grid point of a map: the values (1), and the copies made to build, write
#: and read back the dataset (3).
_FLOATS_PER_MAP_POINT = 4
#: float64 values per point of a chunk in evaluation (exact_W_hat: 39 measured; the batched
#: projection: 37; plus the chunk's coordinates and indices)
_FLOATS_PER_CHUNK_POINT = 64
_DEFAULT_CHUNK = 2_000_000  # an upper bound on the sweep's default chunk size


def parse_size(text, name: str) -> float:
    """Bytes from ``8G``, ``500MB``, ``2GiB``, ``1e10``; ``none`` (or ``0``) for no limit (inf)."""
    s = str(text).strip()
    if s.lower() in ("none", "off", "unlimited", "inf", "0"):
        return math.inf
    m = _SIZE.match(s)
    unit = m.group(3).lower() if m else None
    if m is None or unit not in _UNITS:
        raise InputError(name, f"cannot parse {text!r} as a memory size; give e.g. 8G, 500M, "
                               "2GiB, or none for no limit")
    value = float(m.group(1)) * 10.0 ** int(m.group(2) or 0) * _UNITS[unit]
    if not math.isfinite(value) or value <= 0:
        raise InputError(name, f"must be a positive size, got {text!r}")
    return value


def format_bytes(n: float) -> str:
    if math.isinf(n):
        return "unlimited"
    for unit, size in (("EB", 1e18), ("PB", 1e15), ("TB", 1e12), ("GB", 1e9), ("MB", 1e6),
                       ("kB", 1e3)):
        if n >= size:
            return f"{n / size:.3g} {unit}"
    return f"{int(n)} B"


def physical_memory() -> int | None:
    try:
        return int(os.sysconf("SC_PHYS_PAGES")) * int(os.sysconf("SC_PAGE_SIZE"))
    except (AttributeError, ValueError, OSError):
        return None


def add_memory_option(p: argparse.ArgumentParser) -> None:
    p.add_argument("--max-memory", default=None, metavar="SIZE",
                   help=f"refuse runs estimated to need more memory than this (e.g. 8G, 500M, "
                        f"none); default: ${MEMORY_ENV}, else half the physical memory")


def memory_limit(args) -> tuple[float, str]:
    """(limit in bytes, where it comes from) for ``--max-memory``, ``$LCPFRIC_MAX_MEMORY`` or
    half the physical memory."""
    given = getattr(args, "max_memory", None)
    if given is not None:
        return parse_size(given, "--max-memory"), "--max-memory"
    env = os.environ.get(MEMORY_ENV)
    if env is not None and env.strip():
        return parse_size(env, MEMORY_ENV), MEMORY_ENV
    phys = physical_memory()
    if phys is None:
        return 8e9, "the default when the physical memory is unknown"
    return _DEFAULT_FRACTION * phys, f"half the physical memory of {format_bytes(phys)}"


def steady_state_bytes(steps: int, method: str = "exact", dofs: int = 1) -> float:
    """Estimated peak bytes of one steady state with ``steps`` steps per cycle."""
    return 8.0 * _entry(method, "floats_per_step", _FLOATS_PER_STEP_SOLVER) * \
        (float(steps) + 1.0) * max(1, dofs)


def _entry(method, attr: str, default):
    """An attribute of ``method``'s registry entry (``default`` for an unknown name: the name
    itself is checked, and reported, where the method is resolved)."""
    from ..methods import get_method

    try:
        return getattr(get_method(str(method))[0], attr)
    except InputError:
        return default


def map_bytes(points: float, axes: float = 0.0, method: str = "exact", steps: int | None = None,
              chunk_size: int | None = None, workers: int = 1) -> float:
    """Estimated peak bytes of a map of ``points`` grid points (``axes``: the total length of
    its coordinate axes) run with ``workers`` chunks in flight at once."""
    points = float(points)
    chunk = min(points, float(chunk_size or _DEFAULT_CHUNK))
    in_flight = min(points, chunk * max(1, workers))
    if _entry(method, "grid", None) is not None:  # vectorized: a chunk in one pass
        work = 8.0 * _FLOATS_PER_CHUNK_POINT * in_flight
    else:  # point by point: one steady state per worker at a time
        work = max(1, workers) * steady_state_bytes(steps or 2000, method)
    return 8.0 * (_FLOATS_PER_MAP_POINT * points + axes) + work


def check_memory(need: float, args, option: str, what: str) -> None:
    """Raise InputError naming ``option`` when ``need`` bytes exceed the memory limit."""
    limit, source = memory_limit(args)
    if need <= limit:
        return
    raise InputError(option, (
        f"{what} needs about {format_bytes(need)} of memory, over the limit of "
        f"{format_bytes(limit)} ({source}); ask for less, or raise the limit with "
        f"--max-memory {format_bytes(need * 1.25).replace(' ', '')} (or ${MEMORY_ENV})"))


def workers_for(processes) -> int:
    if processes:
        return int(processes)
    try:
        return len(os.sched_getaffinity(0))
    except AttributeError:  # pragma: no cover - not Linux
        return os.cpu_count() or 1
