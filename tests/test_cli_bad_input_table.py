"""Bad input of every option of every subcommand, in one table (issue 35).

Each row is ``(subcommand, option, argv_extra, kind, expected_exit, named)``: ``argv_extra``
is added to a base command line of the subcommand that is otherwise valid and fast (an option
given in ``argv_extra`` replaces the base's value; :data:`DROP` removes it), and the command must
exit with ``expected_exit`` (2: bad input) and one line on stderr, no traceback, naming
``named``, before any work: no output created, and in well under a second.

The meta-test at the end enumerates the parser's options: every value-taking option must have a
row, and every flag (no value, nothing to get wrong) is in :data:`EXEMPT` with the reason, so a
new option cannot appear without a row. A row that misbehaves is marked with :func:`xfail`
(strict, with what happens), so that a fix is noticed; none is today.
"""

from __future__ import annotations

import argparse
import json
import os
import re
import signal
import time
import warnings

import numpy as np
import pytest

from lcpfric.cli import COMMANDS, build_parser, main

#: removes the base's value of an option (the option is then not given at all)
DROP = object()
#: a row may take this long (seconds): every check runs before any work
FAST = 1.0
#: a row still running after this long is stopped (it has started the work)
STOP = 2.0

# -- the base command lines (valid and fast) --------------------------------------------------
CASE = (("--P1", "0.5"), ("--Q1", "0.6"))
CONTACT = (
    ("--R", "10"),
    ("--E", "200e3"),
    ("--nu", "0.3"),
    ("--mu", "0.5"),
    ("--P0", "100"),
    ("--P1", "50"),
    ("--Q1", "20"),
)
BASE = {
    "dissipation": (CASE, ()),
    "loop": (CASE, ()),
    "shakedown": (CASE, ()),
    "contact": (CONTACT, ("--no-progress",)),
    "methods": ((), ()),
    "map": (
        (("--P1", "0.5"), ("--Q1", "0.3"), ("--phi", "0"), ("--out", "{tmp}/m.nc")),
        ("--no-progress",),
    ),
    "figures": ((("--out", "{tmp}/f"),), ()),
    "paper-claims": ((), ()),
    "system": ((("--file", "{tmp}/sys.json"),), ()),
    "modal": ((("--file", "{tmp}/structure.npz"), ("--amplitude", "1")), ()),
    "describe": (
        (("--kt", "1"), ("--mu", "0.5"), ("--N0", "2"), ("--amplitude", "3")),
        (),
    ),
    "frf": (
        (("--P1", "0.5"), ("--Q1", "2"), ("--mass", "1"), ("--damping", "0.1"), ("--omega", "0.5")),
        (),
    ),
}

# configurations the rows add to the base
EXPLICIT = ("--method", "explicit", "--steps", "50")
HALFSPACE = ("--model", "halfspace")
#: a height map instead of the sphere (the base's --R dropped: it does not apply)
HEIGHTMAP = ("--R", DROP, "--heightmap", "{tmp}/h.npy", "--spacing", "0.02", "--steps", "8")
SPHERE = ("--contact", "sphere")
#: describe's sphere: the element's --kt dropped
DSPHERE = ("--kt", DROP, "--contact", "sphere", "--R", "10", "--E", "2e5", "--nu", "0.3")
SPHERE_HS = ("--contact", "sphere", "--contact-model", "halfspace")

NOT_NUMBER = "not a number"
NOT_FINITE = "not finite"
RANGE = "out of range"
NOT_INT = "not an integer"
NO_APPLY = "does not apply"
MISSING = "missing file"
UNUSABLE = "unusable path"
CHOICE = "bad choice"
DUPLICATE = "duplicate"
CONFLICT = "conflict"
NO_VALUE = "no value"
REQUIRED = "required"
UNKNOWN = "unknown option"


def xfail(row, reason):
    """A row that misbehaves today (kept in the table; strict, so a fix is noticed)."""
    return pytest.param(*row, marks=pytest.mark.xfail(strict=True, reason=reason))


def _overflow(sub):
    return (sub, "--P1", ("--P1", "1e308"), RANGE, 2, "--P1")  # amplitudes over 1e300


def _case_rows(sub):
    """The load-case options --P1, --Q1, --phi and the dimensional inputs (dissipation, loop,
    shakedown share them)."""
    return [
        (sub, "--P1", ("--P1", "abc"), NOT_NUMBER, 2, "--P1"),
        (sub, "--P1", ("--P1", "nan"), NOT_FINITE, 2, "--P1"),
        (sub, "--P1", ("--P1", "-0.5"), RANGE, 2, "--P1"),
        (sub, "--P1", ("--P1",), NO_VALUE, 2, "--P1"),
        (sub, "--P1", ("--P1", DROP), REQUIRED, 2, "--P1"),
        (sub, "--P1", ("--P1", "0.5", "--P1", "0.7"), DUPLICATE, 2, "--P1"),
        _overflow(sub),
        (sub, "--Q1", ("--Q1", "abc"), NOT_NUMBER, 2, "--Q1"),
        (sub, "--Q1", ("--Q1", "inf"), NOT_FINITE, 2, "--Q1"),
        (sub, "--Q1", ("--Q1", "-1"), RANGE, 2, "--Q1"),
        (sub, "--phi", ("--phi", "abc"), NOT_NUMBER, 2, "--phi"),
        (sub, "--phi", ("--phi", "inf"), NOT_FINITE, 2, "--phi"),
        (sub, "--phi", ("--phi", "pi/0"), NOT_NUMBER, 2, "--phi"),
        (sub, "--k11", ("--k11", "abc"), NOT_NUMBER, 2, "--k11"),
        (sub, "--k11", ("--k11", "-1"), RANGE, 2, "--k11"),
        (sub, "--k22", ("--k22", "nan"), NOT_FINITE, 2, "--k22"),
        (sub, "--k22", ("--k22", "-1", "--k11", "1", "--f", "0.3", "--P0", "1"), RANGE, 2, "--k22"),
        (sub, "--f", ("--f", "abc"), NOT_NUMBER, 2, "--f"),
        (sub, "--f", ("--f", "-0.3", "--k11", "1", "--P0", "1"), RANGE, 2, "--f"),
        (sub, "--P0", ("--P0", "abc"), NOT_NUMBER, 2, "--P0"),
        (sub, "--P0", ("--P0", "0", "--k11", "1", "--f", "0.3"), RANGE, 2, "--P0"),
        (sub, "--Q0", ("--Q0", "abc"), NOT_NUMBER, 2, "--Q0"),
        (sub, "--Q0", ("--Q0", "inf"), NOT_FINITE, 2, "--Q0"),
        (sub, "--omega", ("--omega", "abc"), NOT_NUMBER, 2, "--omega"),
        (
            sub,
            "--omega",
            ("--omega", "0", "--k11", "1", "--f", "0.3", "--P0", "1"),
            RANGE,
            2,
            "--omega",
        ),
        (sub, "--k11", ("--k22", "2"), CONFLICT, 2, "--k11"),
        (sub, "--json", ("--json", "yes"), UNKNOWN, 2, "yes"),
    ]


def _memory_overflow(sub):
    return (sub, "--max-memory", ("--max-memory", "1e999"), NOT_FINITE, 2, "--max-memory")


def _solve_rows(sub):
    """--method, --steps, --tol, --max-cycles, --placement, --max-memory (dissipation, loop)."""
    return [
        (sub, "--method", ("--method", "nope"), CHOICE, 2, "--method"),
        (sub, "--method", ("--method", ""), CHOICE, 2, "--method"),
        (sub, "--steps", ("--steps", "abc"), NOT_INT, 2, "--steps"),
        (sub, "--steps", ("--steps", "2.5"), NOT_INT, 2, "--steps"),
        (sub, "--steps", ("--steps", "3"), RANGE, 2, "--steps"),
        (sub, "--steps", ("--steps", "1e12"), RANGE, 2, "--steps"),
        (sub, "--tol", (*EXPLICIT, "--tol", "abc"), NOT_NUMBER, 2, "--tol"),
        (sub, "--tol", (*EXPLICIT, "--tol", "nan"), NOT_FINITE, 2, "--tol"),
        (sub, "--tol", (*EXPLICIT, "--tol", "0"), RANGE, 2, "--tol"),
        (sub, "--tol", ("--tol", "1e-8"), NO_APPLY, 2, "--tol"),
        (sub, "--max-cycles", (*EXPLICIT, "--max-cycles", "0"), RANGE, 2, "--max-cycles"),
        (sub, "--max-cycles", (*EXPLICIT, "--max-cycles", "2.5"), NOT_INT, 2, "--max-cycles"),
        (sub, "--max-cycles", ("--max-cycles", "10"), NO_APPLY, 2, "--max-cycles"),
        (sub, "--placement", ("--placement", "middle"), CHOICE, 2, "--placement"),
        (sub, "--placement", ("--placement", "uniform"), NO_APPLY, 2, "--placement"),
        (sub, "--max-memory", ("--max-memory", "abc"), NOT_NUMBER, 2, "--max-memory"),
        (sub, "--max-memory", ("--max-memory", "0G"), RANGE, 2, "--max-memory"),
        _memory_overflow(sub),
    ]


def _dynamics_rows(sub):
    """--mass and --damping (dissipation, loop)."""
    return [
        (sub, "--mass", ("--mass", "abc"), NOT_NUMBER, 2, "--mass"),
        (sub, "--mass", ("--mass", "nan"), NOT_FINITE, 2, "--mass"),
        (sub, "--mass", ("--mass", "-1"), RANGE, 2, "--mass"),
        (sub, "--mass", ("--mass", "0.5", "--method", "explicit"), CONFLICT, 2, "--method"),
        (sub, "--damping", ("--damping", "inf"), NOT_FINITE, 2, "--damping"),
        (sub, "--damping", ("--damping", "-0.1", "--mass", "1"), RANGE, 2, "--damping"),
        (sub, "--damping", ("--damping", "0.1"), CONFLICT, 2, "--damping"),
        # the undamped resonance: ω = Ω0 with no damping (unbounded)
        (sub, "--mass", ("--mass", "1"), RANGE, 2, "--omega"),
    ]


TABLE = [
    *_case_rows("dissipation"),
    *_solve_rows("dissipation"),
    *_dynamics_rows("dissipation"),
    *_case_rows("loop"),
    *_solve_rows("loop"),
    *_dynamics_rows("loop"),
    ("loop", "--out", ("--out", "{tmp}/l.txt"), CHOICE, 2, "--out"),
    ("loop", "--out", ("--out", "{tmp}/nodir/l.png"), MISSING, 2, "--out"),
    ("loop", "--out", ("--out", ""), UNUSABLE, 2, "--out"),
    ("loop", "--out", ("--out", "{tmp}/dir"), UNUSABLE, 2, "--out"),
    ("loop", "--out", ("--out", "/proc/l.png"), UNUSABLE, 2, "--out"),
    ("loop", "--out", ("--out", "{tmp}/l.png", "--P1", "abc"), CONFLICT, 2, "--P1"),
    *_case_rows("shakedown"),
    # -- contact: the sphere by MDR (the base), and the configurations the options need
    ("contact", "--geometry", ("--geometry", "cube"), CHOICE, 2, "--geometry"),
    (
        "contact",
        "--geometry",
        ("--geometry", "cylinder", *HEIGHTMAP),
        CONFLICT,
        2,
        "--geometry",
    ),
    ("contact", "--model", ("--model", "fem"), CHOICE, 2, "--model"),
    ("contact", "--model", ("--model", "halfplane"), CONFLICT, 2, "--model"),
    ("contact", "--model", ("--geometry", "cylinder", "--model", "mdr"), CONFLICT, 2, "--model"),
    ("contact", "--R", ("--R", "abc"), NOT_NUMBER, 2, "--R"),
    ("contact", "--R", ("--R", "inf"), NOT_FINITE, 2, "--R"),
    ("contact", "--R", ("--R", "-10"), RANGE, 2, "--R"),
    ("contact", "--R", ("--R", DROP), REQUIRED, 2, "--R"),
    ("contact", "--R", ("--R", "1e308"), RANGE, 2, "--R"),
    ("contact", "--R", (*HALFSPACE, "--R", "0"), RANGE, 2, "--R"),
    ("contact", "--R", HEIGHTMAP[2:], NO_APPLY, 2, "--R"),
    ("contact", "--E", ("--E", "abc"), NOT_NUMBER, 2, "--E"),
    ("contact", "--E", ("--E", "inf"), NOT_FINITE, 2, "--E"),
    ("contact", "--E", ("--E", "0"), RANGE, 2, "--E"),
    ("contact", "--E", ("--E", DROP), REQUIRED, 2, "--E"),
    ("contact", "--nu", ("--nu", "abc"), NOT_NUMBER, 2, "--nu"),
    ("contact", "--nu", ("--nu", "0.5"), RANGE, 2, "--nu"),
    ("contact", "--nu", ("--nu", "-0.1"), RANGE, 2, "--nu"),
    ("contact", "--mu", ("--mu", "abc"), NOT_NUMBER, 2, "--mu"),
    ("contact", "--mu", ("--mu", "-0.5"), RANGE, 2, "--mu"),
    ("contact", "--mu", ("--mu", "nan"), NOT_FINITE, 2, "--mu"),
    ("contact", "--P0", ("--P0", "abc"), NOT_NUMBER, 2, "--P0"),
    ("contact", "--P0", ("--P0", "0"), RANGE, 2, "--P0"),
    ("contact", "--P0", ("--P0", "1e308"), RANGE, 2, "--P0"),
    ("contact", "--P1", ("--P1", "abc"), NOT_NUMBER, 2, "--P1"),
    ("contact", "--P1", ("--P1", "-1"), RANGE, 2, "--P1"),
    ("contact", "--Q1", ("--Q1", "nan"), NOT_FINITE, 2, "--Q1"),
    ("contact", "--Q1", ("--Q1", "-1"), RANGE, 2, "--Q1"),
    ("contact", "--Q1", ("--Q1", "60"), CONFLICT, 2, "--k-support"),
    ("contact", "--E", ("--E", "1e5", "--E", "2e5"), DUPLICATE, 2, "--E"),
    ("contact", "--phi", ("--phi", "abc"), NOT_NUMBER, 2, "--phi"),
    ("contact", "--phi", ("--phi", "inf"), NOT_FINITE, 2, "--phi"),
    ("contact", "--k-support", ("--k-support", "abc"), NOT_NUMBER, 2, "--k-support"),
    ("contact", "--k-support", ("--k-support", "-1"), RANGE, 2, "--k-support"),
    ("contact", "--nodes", ("--nodes", "abc"), NOT_INT, 2, "--nodes"),
    ("contact", "--nodes", ("--nodes", "12.5"), NOT_INT, 2, "--nodes"),
    ("contact", "--nodes", ("--nodes", "5"), RANGE, 2, "--nodes"),
    ("contact", "--nodes", ("--nodes", "1e12"), RANGE, 2, "--nodes"),
    ("contact", "--nodes", (*HALFSPACE, "--nodes", "100"), NO_APPLY, 2, "--nodes"),
    ("contact", "--steps", ("--steps", "abc"), NOT_INT, 2, "--steps"),
    ("contact", "--steps", ("--steps", "2.5"), NOT_INT, 2, "--steps"),
    ("contact", "--steps", ("--steps", "3"), RANGE, 2, "--steps"),
    ("contact", "--grid", ("--grid", "20"), NO_APPLY, 2, "--grid"),
    ("contact", "--grid", ("--geometry", "cylinder", "--grid", "20"), NO_APPLY, 2, "--grid"),
    ("contact", "--grid", (*HALFSPACE, "--grid", "abc"), NOT_INT, 2, "--grid"),
    ("contact", "--grid", (*HALFSPACE, "--grid", "4"), RANGE, 2, "--grid"),
    ("contact", "--grid", (*HEIGHTMAP, "--grid", "20"), NO_APPLY, 2, "--grid"),
    ("contact", "--dims", ("--dims", "3"), CHOICE, 2, "--dims"),
    ("contact", "--dims", ("--dims", "2"), NO_APPLY, 2, "--dims"),
    ("contact", "--radius", ("--radius", "1"), NO_APPLY, 2, "--radius"),
    ("contact", "--radius", (*HALFSPACE, "--radius", "1"), NO_APPLY, 2, "--radius"),
    ("contact", "--radius", (*HEIGHTMAP, "--radius", "1"), NO_APPLY, 2, "--radius"),
    ("contact", "--radius", ("--geometry", "punch", "--radius", "abc"), NOT_NUMBER, 2, "--radius"),
    ("contact", "--radius", ("--geometry", "punch", "--radius", "-1"), RANGE, 2, "--radius"),
    ("contact", "--radius", ("--geometry", "punch"), REQUIRED, 2, "--radius"),
    (
        "contact",
        "--heightmap",
        ("--heightmap", "{tmp}/none.npy", "--spacing", "1"),
        MISSING,
        2,
        "--heightmap",
    ),
    (
        "contact",
        "--heightmap",
        ("--heightmap", "{tmp}/text.npy", "--spacing", "1"),
        UNUSABLE,
        2,
        "--heightmap",
    ),
    (
        "contact",
        "--heightmap",
        ("--heightmap", "{tmp}/two.npz", "--spacing", "1"),
        UNUSABLE,
        2,
        "--heightmap",
    ),
    (
        "contact",
        "--heightmap",
        ("--heightmap", "{tmp}/dir", "--spacing", "1"),
        UNUSABLE,
        2,
        "--heightmap",
    ),
    (
        "contact",
        "--heightmap",
        ("--heightmap", "{tmp}/line.npy", "--spacing", "1"),
        RANGE,
        2,
        "--heightmap",
    ),
    (
        "contact",
        "--heightmap",
        ("--heightmap", "{tmp}/nan.npy", "--spacing", "1"),
        NOT_FINITE,
        2,
        "--heightmap",
    ),
    ("contact", "--model", ("--model", "mdr", *HEIGHTMAP), NO_APPLY, 2, "--model"),
    ("contact", "--spacing", ("--R", DROP, "--heightmap", "{tmp}/h.npy"), REQUIRED, 2, "--spacing"),
    ("contact", "--spacing", ("--spacing", "1"), NO_APPLY, 2, "--spacing"),
    ("contact", "--spacing", (*HALFSPACE, "--spacing", "1"), NO_APPLY, 2, "--spacing"),
    (
        "contact",
        "--spacing",
        ("--R", DROP, "--heightmap", "{tmp}/h.npy", "--spacing", "abc"),
        NOT_NUMBER,
        2,
        "--spacing",
    ),
    (
        "contact",
        "--spacing",
        ("--R", DROP, "--heightmap", "{tmp}/h.npy", "--spacing", "0"),
        RANGE,
        2,
        "--spacing",
    ),
    (
        "contact",
        "--spacing",
        ("--R", DROP, "--heightmap", "{tmp}/h.npy", "--spacing", "inf"),
        NOT_FINITE,
        2,
        "--spacing",
    ),
    ("contact", "--figures", ("--figures", "{tmp}/figs"), NO_APPLY, 2, "--figures"),
    (
        "contact",
        "--figures",
        (*HALFSPACE, "--figures", "{tmp}/nodir/figs"),
        MISSING,
        2,
        "--figures",
    ),
    ("contact", "--figures", (*HALFSPACE, "--figures", "{tmp}/file"), UNUSABLE, 2, "--figures"),
    ("contact", "--figures", (*HALFSPACE, "--figures", ""), UNUSABLE, 2, "--figures"),
    ("contact", "--instants", ("--instants", "0.5"), NO_APPLY, 2, "--instants"),
    ("contact", "--instants", (*HALFSPACE, "--instants", "0.5"), NO_APPLY, 2, "--instants"),
    (
        "contact",
        "--instants",
        (*HALFSPACE, "--figures", "{tmp}/figs", "--instants", "abc"),
        NOT_NUMBER,
        2,
        "--instants",
    ),
    (
        "contact",
        "--instants",
        (*HALFSPACE, "--figures", "{tmp}/figs", "--instants", "nan"),
        NOT_FINITE,
        2,
        "--instants",
    ),
    (
        "contact",
        "--instants",
        (*HALFSPACE, "--figures", "{tmp}/figs", "--instants", "0,2"),
        RANGE,
        2,
        "--instants",
    ),
    (
        "contact",
        "--instants",
        (*HALFSPACE, "--figures", "{tmp}/figs", "--instants", ","),
        RANGE,
        2,
        "--instants",
    ),
    ("contact", "--animation", ("--animation", "{tmp}/a.gif"), NO_APPLY, 2, "--animation"),
    (
        "contact",
        "--animation",
        (*HALFSPACE, "--animation", "{tmp}/a.mp4"),
        CHOICE,
        2,
        "--animation",
    ),
    (
        "contact",
        "--animation",
        (*HALFSPACE, "--animation", "{tmp}/nodir/a.gif"),
        MISSING,
        2,
        "--animation",
    ),
    (
        "contact",
        "--animation",
        (*HALFSPACE, "--animation", "{tmp}/dir"),
        UNUSABLE,
        2,
        "--animation",
    ),
    ("contact", "--method", ("--method", "nope"), CHOICE, 2, "--method"),
    ("contact", "--method", ("--method", "newton-cg"), NO_APPLY, 2, "--method"),
    ("contact", "--method", ("--method", "exact"), NO_APPLY, 2, "--method"),
    ("contact", "--method", (*HALFSPACE, "--method", "mdr-bar"), NO_APPLY, 2, "--method"),
    ("contact", "--max-memory", ("--max-memory", "abc"), NOT_NUMBER, 2, "--max-memory"),
    ("contact", "--max-memory", ("--max-memory", "0G"), RANGE, 2, "--max-memory"),
    _memory_overflow("contact"),
    ("contact", "--json", ("--json", "yes"), UNKNOWN, 2, "yes"),
    # -- methods and paper-claims take flags only
    ("methods", "--names", ("--names", "yes"), UNKNOWN, 2, "yes"),
    ("methods", "--bogus", ("--bogus",), UNKNOWN, 2, "--bogus"),
    ("paper-claims", "--quick", ("--quick", "yes"), UNKNOWN, 2, "yes"),
    ("paper-claims", "--bogus", ("--bogus",), UNKNOWN, 2, "--bogus"),
    # -- map: the single node (the base), and the contact map
    ("map", "--P1", ("--P1", "abc"), NOT_NUMBER, 2, "--P1"),
    ("map", "--P1", ("--P1", "nan"), NOT_FINITE, 2, "--P1"),
    ("map", "--P1", ("--P1", "-0.5"), RANGE, 2, "--P1"),
    ("map", "--P1", ("--P1", "0:1"), NOT_NUMBER, 2, "--P1"),
    ("map", "--P1", ("--P1", "0:1:0"), RANGE, 2, "--P1"),
    ("map", "--P1", ("--P1", "0:1:2.5"), NOT_INT, 2, "--P1"),
    ("map", "--P1", ("--P1", "0.5,0.5"), DUPLICATE, 2, "--P1"),
    ("map", "--P1", ("--P1", "1:1:3"), DUPLICATE, 2, "--P1"),
    ("map", "--P1", ("--P1", ","), NOT_NUMBER, 2, "--P1"),
    ("map", "--P1", ("--P1", DROP), REQUIRED, 2, "--P1"),
    ("map", "--Q1", ("--Q1", "abc"), NOT_NUMBER, 2, "--Q1"),
    ("map", "--Q1", ("--Q1", "inf"), NOT_FINITE, 2, "--Q1"),
    ("map", "--Q1", ("--Q1", "-1"), RANGE, 2, "--Q1"),
    ("map", "--Q1", ("--Q1", "0.3,0.3"), DUPLICATE, 2, "--Q1"),
    ("map", "--phi", ("--phi", "abc"), NOT_NUMBER, 2, "--phi"),
    ("map", "--phi", ("--phi", "inf"), NOT_FINITE, 2, "--phi"),
    ("map", "--phi", ("--phi", "0,0"), DUPLICATE, 2, "--phi"),
    ("map", "--phi", ("--phi", "0:pi:0"), RANGE, 2, "--phi"),
    ("map", "--out", ("--out", "{tmp}/m.txt"), CHOICE, 2, "--out"),
    ("map", "--out", ("--out", "{tmp}/nodir/m.nc"), MISSING, 2, "--out"),
    ("map", "--out", ("--out", ""), UNUSABLE, 2, "--out"),
    ("map", "--out", ("--out", "{tmp}/dir"), UNUSABLE, 2, "--out"),
    ("map", "--out", ("--out", "/proc/m.nc"), UNUSABLE, 2, "--out"),
    ("map", "--out", ("--out", "{tmp}/taken.nc"), CONFLICT, 2, "--out"),
    ("map", "--out", ("--out", "{tmp}/a.nc", "--out", "{tmp}/b.nc"), DUPLICATE, 2, "--out"),
    ("map", "--method", ("--method", "nope"), CHOICE, 2, "--method"),
    ("map", "--method", (*SPHERE, "--method", "exact"), NO_APPLY, 2, "--method"),
    ("map", "--method", (*SPHERE, "--method", "newton-cg"), NO_APPLY, 2, "--method"),
    ("map", "--contact", ("--contact", "cube"), CHOICE, 2, "--contact"),
    ("map", "--contact-model", (*SPHERE, "--contact-model", "fem"), CHOICE, 2, "--contact-model"),
    ("map", "--contact-model", ("--contact-model", "mdr"), NO_APPLY, 2, "--contact-model"),
    (
        "map",
        "--k-support-ratio",
        (*SPHERE, "--k-support-ratio", "abc"),
        NOT_NUMBER,
        2,
        "--k-support-ratio",
    ),
    (
        "map",
        "--k-support-ratio",
        (*SPHERE, "--k-support-ratio", "-1"),
        RANGE,
        2,
        "--k-support-ratio",
    ),
    (
        "map",
        "--k-support-ratio",
        (*SPHERE, "--k-support-ratio", "inf"),
        NOT_FINITE,
        2,
        "--k-support-ratio",
    ),
    ("map", "--k-support-ratio", ("--k-support-ratio", "1"), NO_APPLY, 2, "--k-support-ratio"),
    ("map", "--k-support", ("--k-support", "1"), NO_APPLY, 2, "--k-support"),
    ("map", "--k-support", (*SPHERE, "--k-support", "1"), NO_APPLY, 2, "--k-support"),
    ("map", "--nodes", ("--nodes", "100"), NO_APPLY, 2, "--nodes"),
    ("map", "--nodes", (*SPHERE_HS, "--nodes", "100"), NO_APPLY, 2, "--nodes"),
    ("map", "--nodes", (*SPHERE, "--nodes", "5"), RANGE, 2, "--nodes"),
    ("map", "--nodes", (*SPHERE, "--nodes", "abc"), NOT_INT, 2, "--nodes"),
    ("map", "--grid", ("--grid", "20"), NO_APPLY, 2, "--grid"),
    ("map", "--grid", (*SPHERE, "--grid", "20"), NO_APPLY, 2, "--grid"),
    ("map", "--grid", (*SPHERE_HS, "--grid", "4"), RANGE, 2, "--grid"),
    ("map", "--grid", (*SPHERE_HS, "--grid", "12.5"), NOT_INT, 2, "--grid"),
    ("map", "--dims", ("--dims", "3"), CHOICE, 2, "--dims"),
    ("map", "--dims", ("--dims", "2"), NO_APPLY, 2, "--dims"),
    ("map", "--dims", (*SPHERE, "--dims", "2"), NO_APPLY, 2, "--dims"),
    ("map", "--nu", ("--nu", "0.3"), NO_APPLY, 2, "--nu"),
    ("map", "--nu", (*SPHERE, "--nu", "0.3"), NO_APPLY, 2, "--nu"),
    ("map", "--nu", (*SPHERE_HS, "--nu", "0.5"), RANGE, 2, "--nu"),
    ("map", "--nu", (*SPHERE_HS, "--nu", "abc"), NOT_NUMBER, 2, "--nu"),
    ("map", "--steps", ("--steps", "abc"), NOT_INT, 2, "--steps"),
    ("map", "--steps", ("--steps", "2.5"), NOT_INT, 2, "--steps"),
    ("map", "--steps", ("--steps", "2"), RANGE, 2, "--steps"),
    ("map", "--steps", ("--steps", "100"), NO_APPLY, 2, "--steps"),
    ("map", "--scheduler", ("--scheduler", "not an address"), UNUSABLE, 2, "--scheduler"),
    ("map", "--scheduler", ("--scheduler", "tcp://127.0.0.1:99999"), RANGE, 2, "--scheduler"),
    ("map", "--scheduler", ("--scheduler", "127.0.0.1:1"), UNUSABLE, 2, "--scheduler"),
    ("map", "--processes", ("--processes", "0"), RANGE, 2, "--processes"),
    ("map", "--processes", ("--processes", "abc"), NOT_INT, 2, "--processes"),
    (
        "map",
        "--processes",
        ("--processes", "2", "--scheduler", "127.0.0.1:1"),
        CONFLICT,
        2,
        "--processes",
    ),
    ("map", "--chunk-size", ("--chunk-size", "0"), RANGE, 2, "--chunk-size"),
    ("map", "--chunk-size", ("--chunk-size", "abc"), NOT_INT, 2, "--chunk-size"),
    ("map", "--max-memory", ("--max-memory", "abc"), NOT_NUMBER, 2, "--max-memory"),
    ("map", "--max-memory", ("--max-memory", "0G"), RANGE, 2, "--max-memory"),
    _memory_overflow("map"),
    ("map", "--json", ("--json", "yes"), UNKNOWN, 2, "yes"),
    # -- figures
    ("figures", "--out", ("--out", ""), UNUSABLE, 2, "--out"),
    ("figures", "--out", ("--out", "{tmp}/nodir/f"), MISSING, 2, "--out"),
    ("figures", "--out", ("--out", "{tmp}/file"), UNUSABLE, 2, "--out"),
    ("figures", "--out", ("--out", "/proc/f"), UNUSABLE, 2, "--out"),
    ("figures", "--out", ("--out", DROP), REQUIRED, 2, "--out"),
    ("figures", "--grid", ("--grid", "abc"), NOT_INT, 2, "--grid"),
    ("figures", "--grid", ("--grid", "2.5"), NOT_INT, 2, "--grid"),
    ("figures", "--grid", ("--grid", "2"), RANGE, 2, "--grid"),
    ("figures", "--grid", ("--grid", "1e9"), RANGE, 2, "--grid"),
    ("figures", "--points", ("--points", "abc"), NOT_INT, 2, "--points"),
    ("figures", "--points", ("--points", "2"), RANGE, 2, "--points"),
    ("figures", "--points", ("--contact", "--points", "100"), NO_APPLY, 2, "--points"),
    ("figures", "--format", ("--format", "gif"), CHOICE, 2, "--format"),
    ("figures", "--format", ("--format", ","), CHOICE, 2, "--format"),
    ("figures", "--format", ("--format", "png,png"), DUPLICATE, 2, "--format"),
    ("figures", "--max-memory", ("--max-memory", "abc"), NOT_NUMBER, 2, "--max-memory"),
    ("figures", "--max-memory", ("--max-memory", "0G"), RANGE, 2, "--max-memory"),
    _memory_overflow("figures"),
    ("figures", "--contact", ("--contact", "yes"), UNKNOWN, 2, "yes"),
    # -- contact: a second body (--E2 --nu2, or --rigid; issue 38, item 6)
    ("contact", "--E2", ("--E2", "abc", "--nu2", "0.3"), NOT_NUMBER, 2, "--E2"),
    ("contact", "--E2", ("--E2", "-1", "--nu2", "0.3", *HALFSPACE), RANGE, 2, "--E2"),
    ("contact", "--E2", ("--nu2", "0.3"), REQUIRED, 2, "--E2"),
    ("contact", "--E2", ("--E2", "70e3", "--nu2", "0.33"), NO_APPLY, 2, "--E2"),  # mdr, beta != 0
    ("contact", "--E2", ("--geometry", "cylinder", "--E2", "1", "--nu2", "0"), NO_APPLY, 2, "--E2"),
    ("contact", "--nu2", ("--E2", "70e3"), REQUIRED, 2, "--nu2"),
    ("contact", "--nu2", ("--E2", "70e3", "--nu2", "0.5", *HALFSPACE), RANGE, 2, "--nu2"),
    ("contact", "--nu2", ("--E2", "70e3", "--nu2", "abc"), NOT_NUMBER, 2, "--nu2"),
    ("contact", "--nu2", ("--E2", "200e3", "--nu2", "0.2"), NO_APPLY, 2, "--nu2"),  # mdr
    ("contact", "--rigid", ("--rigid", "--E2", "1e5"), CONFLICT, 2, "--rigid"),
    ("contact", "--rigid", ("--rigid",), NO_APPLY, 2, "--rigid"),  # mdr: beta != 0
    ("contact", "--rigid", ("--geometry", "cylinder", "--rigid"), NO_APPLY, 2, "--rigid"),
    # -- options whose default is the only value that applies are refused when given
    ("contact", "--dims", ("--dims", "1"), NO_APPLY, 2, "--dims"),
    ("contact", "--geometry", ("--geometry", "sphere", *HEIGHTMAP), CONFLICT, 2, "--geometry"),
    # -- system: the file's fields are named after --file
    ("system", "--file", ("--file", "{tmp}/none.json"), MISSING, 2, "--file"),
    ("system", "--file", ("--file", "{tmp}/file"), UNUSABLE, 2, "--file"),
    ("system", "--file", ("--file", DROP), REQUIRED, 2, "--file"),
    ("system", "--file", ("--file", "{tmp}/sys_K.json"), RANGE, 2, "field K"),
    ("system", "--file", ("--file", "{tmp}/sys_ill.json"), RANGE, 2, "field coupling"),
    ("system", "--start", ("--start", "{tmp}/none.json"), MISSING, 2, "--start"),
    ("system", "--start", ("--start", "{tmp}/far.json"), RANGE, 2, "--start"),
    ("system", "--start", ("--start", "{tmp}/file"), NOT_NUMBER, 2, "--start"),
    ("system", "--starts", ("--starts", "0"), RANGE, 2, "--starts"),
    ("system", "--starts", ("--starts", "two"), NOT_INT, 2, "--starts"),
    ("system", "--seed", ("--seed", "x"), NOT_INT, 2, "--seed"),
    ("system", "--method", ("--method", "nosuch"), CHOICE, 2, "--method"),
    ("system", "--method", ("--method", "projection"), NO_APPLY, 2, "--method"),
    # -- modal: the file's fields are named after --file
    ("frf", "--P1", ("--P1", "abc"), NOT_NUMBER, 2, "--P1"),
    ("frf", "--P1", ("--P1", "-1"), RANGE, 2, "--P1"),
    ("frf", "--P1", ("--P1", DROP), REQUIRED, 2, "--P1"),
    ("frf", "--Q1", ("--Q1", "nan"), NOT_FINITE, 2, "--Q1"),
    ("frf", "--Q1", ("--Q1", "-2"), RANGE, 2, "--Q1"),
    ("frf", "--phi", ("--phi", "abc"), NOT_NUMBER, 2, "--phi"),
    ("frf", "--k11", ("--k11", "-1"), RANGE, 2, "--k11"),
    ("frf", "--f", ("--f", "0"), RANGE, 2, "--f"),
    ("frf", "--P0", ("--P0", "inf"), NOT_FINITE, 2, "--P0"),
    ("frf", "--mass", ("--mass", "0"), RANGE, 2, "--mass"),
    ("frf", "--mass", ("--mass", "abc"), NOT_NUMBER, 2, "--mass"),
    ("frf", "--mass", ("--mass", DROP), REQUIRED, 2, "--mass"),
    ("frf", "--damping", ("--damping", "-0.1"), RANGE, 2, "--damping"),
    ("frf", "--damping", ("--damping", "nan"), NOT_FINITE, 2, "--damping"),
    ("frf", "--omega", ("--omega", "0"), RANGE, 2, "--omega"),
    ("frf", "--omega", ("--omega", "abc"), NOT_NUMBER, 2, "--omega"),
    ("frf", "--omega", ("--omega", "1:2"), NOT_NUMBER, 2, "--omega"),
    ("frf", "--omega", ("--omega", DROP), REQUIRED, 2, "--omega"),
    # the undamped resonance inside the range: ω = Ω0 with no damping
    ("frf", "--omega", ("--omega", "0.5,1", "--damping", "0"), RANGE, 2, "--omega"),
    ("frf", "--samples", ("--samples", "8"), RANGE, 2, "--samples"),
    ("frf", "--samples", ("--samples", "2.5"), NOT_INT, 2, "--samples"),
    ("frf", "--out", ("--out", "{tmp}/r.txt"), CHOICE, 2, "--out"),
    ("frf", "--out", ("--out", "{tmp}/nodir/r.png"), MISSING, 2, "--out"),
    ("frf", "--out", ("--out", "{tmp}/dir"), UNUSABLE, 2, "--out"),
    ("frf", "--json", ("--json", "yes"), UNKNOWN, 2, "yes"),
    ("modal", "--file", ("--file", "{tmp}/none.npz"), MISSING, 2, "--file"),
    ("modal", "--file", ("--file", "{tmp}/file"), UNUSABLE, 2, "--file"),
    ("modal", "--file", ("--file", "{tmp}/h.npy"), UNUSABLE, 2, "--file"),
    ("modal", "--file", ("--file", DROP), REQUIRED, 2, "--file"),
    ("modal", "--file", ("--file", "{tmp}/structure_no_kt.npz"), REQUIRED, 2, "field kt"),
    ("modal", "--file", ("--file", "{tmp}/structure_K.npz"), RANGE, 2, "field K"),
    ("modal", "--file", ("--file", "{tmp}/structure_kt.npz"), RANGE, 2, "field kt"),
    ("modal", "--file", ("--file", "{tmp}/structure_M.npz"), NOT_FINITE, 2, "field M"),
    ("modal", "--file", ("--file", "{tmp}/structure_dofs.npz"), RANGE, 2, "field contact_dofs"),
    ("modal", "--file", ("--file", "{tmp}/structure_held.npz"), RANGE, 2, "field K"),
    ("modal", "--amplitude", ("--amplitude", "abc"), NOT_NUMBER, 2, "--amplitude"),
    ("modal", "--amplitude", ("--amplitude", "nan"), NOT_FINITE, 2, "--amplitude"),
    ("modal", "--amplitude", ("--amplitude", "0"), RANGE, 2, "--amplitude"),
    ("modal", "--amplitude", ("--amplitude", "-1:2:3"), RANGE, 2, "--amplitude"),
    ("modal", "--amplitude", ("--amplitude", "1:2"), NOT_NUMBER, 2, "--amplitude"),
    ("modal", "--amplitude", ("--amplitude", "1:2:0"), RANGE, 2, "--amplitude"),
    ("modal", "--amplitude", ("--amplitude", DROP), REQUIRED, 2, "--amplitude"),
    ("modal", "--mode", ("--mode", "abc"), NOT_INT, 2, "--mode"),
    ("modal", "--mode", ("--mode", "1.5"), NOT_INT, 2, "--mode"),
    ("modal", "--mode", ("--mode", "-1"), RANGE, 2, "--mode"),
    ("modal", "--mode", ("--mode", "2"), RANGE, 2, "--mode"),
    ("modal", "--json", ("--json", "yes"), UNKNOWN, 2, "yes"),
    # -- describe: the Jenkins element (the continuum sphere is refused for now)
    ("describe", "--kt", ("--kt", "abc"), NOT_NUMBER, 2, "--kt"),
    ("describe", "--kt", ("--kt", "nan"), NOT_FINITE, 2, "--kt"),
    ("describe", "--kt", ("--kt", "-1"), RANGE, 2, "--kt"),
    ("describe", "--kt", ("--kt", "0"), RANGE, 2, "--kt"),
    ("describe", "--kt", ("--kt", DROP), REQUIRED, 2, "--kt"),
    ("describe", "--kt", ("--kt", "1", "--kt", "2"), DUPLICATE, 2, "--kt"),
    ("describe", "--mu", ("--mu", "abc"), NOT_NUMBER, 2, "--mu"),
    ("describe", "--mu", ("--mu", "-0.5"), RANGE, 2, "--mu"),
    ("describe", "--mu", ("--mu", "inf"), NOT_FINITE, 2, "--mu"),
    ("describe", "--mu", ("--mu", DROP), REQUIRED, 2, "--mu"),
    ("describe", "--N0", ("--N0", "0"), RANGE, 2, "--N0"),
    ("describe", "--N0", ("--N0", "abc"), NOT_NUMBER, 2, "--N0"),
    ("describe", "--N0", ("--N0", DROP), REQUIRED, 2, "--N0"),
    ("describe", "--N1", ("--N1", "-1"), RANGE, 2, "--N1"),
    ("describe", "--N1", ("--N1", "nan"), NOT_FINITE, 2, "--N1"),
    ("describe", "--phi", ("--N1", "1", "--phi", "abc"), NOT_NUMBER, 2, "--phi"),
    ("describe", "--phi", ("--N1", "1", "--phi", "inf"), NOT_FINITE, 2, "--phi"),
    ("describe", "--phi", ("--phi", "0.5pi"), NO_APPLY, 2, "--phi"),
    ("describe", "--kn", ("--kn", "-1", "--un1", "0.1"), RANGE, 2, "--kn"),
    ("describe", "--kn", ("--kn", "abc", "--un1", "0.1"), NOT_NUMBER, 2, "--kn"),
    ("describe", "--kn", ("--kn", "10"), REQUIRED, 2, "--kn"),
    ("describe", "--kn", ("--kn", "10", "--N1", "1"), CONFLICT, 2, "--kn"),
    ("describe", "--un1", ("--un1", "0.1"), REQUIRED, 2, "--un1"),
    ("describe", "--un1", ("--kn", "10", "--un1", "-0.1"), RANGE, 2, "--un1"),
    ("describe", "--amplitude", ("--amplitude", "abc"), NOT_NUMBER, 2, "--amplitude"),
    ("describe", "--amplitude", ("--amplitude", "nan"), NOT_FINITE, 2, "--amplitude"),
    ("describe", "--amplitude", ("--amplitude", "0"), RANGE, 2, "--amplitude"),
    ("describe", "--amplitude", ("--amplitude", "-1"), RANGE, 2, "--amplitude"),
    ("describe", "--amplitude", ("--amplitude", "0:1:3"), RANGE, 2, "--amplitude"),
    ("describe", "--amplitude", ("--amplitude", "1:2"), NOT_NUMBER, 2, "--amplitude"),
    ("describe", "--amplitude", ("--amplitude", "1:2:0"), RANGE, 2, "--amplitude"),
    ("describe", "--amplitude", ("--amplitude", "1:2:2.5"), NOT_INT, 2, "--amplitude"),
    ("describe", "--amplitude", ("--amplitude", DROP), REQUIRED, 2, "--amplitude"),
    ("describe", "--harmonics", ("--harmonics", "0"), RANGE, 2, "--harmonics"),
    ("describe", "--harmonics", ("--harmonics", "abc"), NOT_INT, 2, "--harmonics"),
    ("describe", "--harmonics", ("--harmonics", "1.5"), NOT_INT, 2, "--harmonics"),
    ("describe", "--start", ("--start", "abc"), NOT_NUMBER, 2, "--start"),
    ("describe", "--start", ("--start", "nan"), NOT_FINITE, 2, "--start"),
    ("describe", "--method", ("--method", "fft"), CHOICE, 2, "--method"),
    ("describe", "--contact", ("--contact", "cone"), CHOICE, 2, "--contact"),
    ("describe", "--kt", DSPHERE[2:], NO_APPLY, 2, "--kt"),
    ("describe", "--kn", (*DSPHERE, "--kn", "1", "--un1", "0.1"), NO_APPLY, 2, "--kn"),
    ("describe", "--start", (*DSPHERE, "--start", "0.1"), NO_APPLY, 2, "--start"),
    ("describe", "--method", (*DSPHERE, "--method", "driven"), NO_APPLY, 2, "--method"),
    ("describe", "--R", (*DSPHERE[:4], *DSPHERE[6:]), REQUIRED, 2, "--R"),
    ("describe", "--R", (*DSPHERE, "--R", "-10"), RANGE, 2, "--R"),
    ("describe", "--E", (*DSPHERE, "--E", "0"), RANGE, 2, "--E"),
    ("describe", "--nu", (*DSPHERE, "--nu", "0.6"), RANGE, 2, "--nu"),
    ("describe", "--N1", (*DSPHERE, "--N1", "3"), RANGE, 2, "--N1"),
    ("describe", "--nodes", (*DSPHERE, "--nodes", "0"), RANGE, 2, "--nodes"),
    ("describe", "--nodes", (*DSPHERE, "--nodes", "abc"), NOT_INT, 2, "--nodes"),
    ("describe", "--samples", (*DSPHERE, "--N1", "1", "--samples", "4"), RANGE, 2, "--samples"),
    ("describe", "--samples", (*DSPHERE, "--samples", "x"), NOT_INT, 2, "--samples"),
    ("describe", "--harmonics", (*DSPHERE, "--harmonics", "2"), RANGE, 2, "--harmonics"),
    ("describe", "--R", ("--R", "10"), NO_APPLY, 2, "--R"),
    ("describe", "--E", ("--E", "2e5"), NO_APPLY, 2, "--E"),
    ("describe", "--nu", ("--nu", "0.3"), NO_APPLY, 2, "--nu"),
    ("describe", "--json", ("--json", "yes"), UNKNOWN, 2, "yes"),
]

#: the flags (no value): nothing to get wrong but a value given to them, which the rows with
#: kind "unknown option" cover for some of them
EXEMPT = {
    ("dissipation", "--json"): "a flag: it has no value to be wrong",
    ("loop", "--json"): "a flag: it has no value to be wrong",
    ("shakedown", "--json"): "a flag: it has no value to be wrong",
    ("contact", "--json"): "a flag: it has no value to be wrong",
    ("contact", "--no-progress"): "a flag: it has no value to be wrong",
    ("contact", "--rigid"): "a flag: its conflicts have rows",
    ("methods", "--names"): "a flag: it has no value to be wrong",
    ("methods", "--json"): "a flag: it has no value to be wrong",
    ("map", "--restart"): "a flag: it has no value to be wrong",
    ("map", "--no-progress"): "a flag: it has no value to be wrong",
    ("map", "--json"): "a flag: it has no value to be wrong",
    ("figures", "--contact"): "a flag: it has no value to be wrong",
    ("figures", "--json"): "a flag: it has no value to be wrong",
    ("paper-claims", "--quick"): "a flag: it has no value to be wrong",
    ("paper-claims", "--json"): "a flag: it has no value to be wrong",
    ("system", "--json"): "a flag: it has no value to be wrong",
    ("modal", "--json"): "a flag: it has no value to be wrong",
    ("frf", "--json"): "a flag: it has no value to be wrong",
    ("describe", "--json"): "a flag: it has no value to be wrong",
}


# -- running a row ------------------------------------------------------------------------------
def _values(entry) -> tuple:
    return tuple(entry.values) if hasattr(entry, "values") else tuple(entry)


def _row_id(row) -> str:
    sub, option, extra, kind, _, _ = row
    shown = " ".join("<drop>" if t is DROP else (t if t != "" else "''") for t in extra)
    return f"{sub} {option} [{kind}] {shown}".replace("{tmp}/", "")


def _params():
    out = []
    for entry in TABLE:
        row = _values(entry)
        marks = getattr(entry, "marks", ())
        out.append(pytest.param(*row, marks=marks, id=_row_id(row)))
    return out


def argv_of(sub, extra, tmp) -> list[str]:
    """The base command line of ``sub`` with ``extra``: an option in ``extra`` replaces the
    base's (its value :data:`DROP` removes it); the rest of ``extra`` follows the base."""
    pairs, flags = BASE[sub]
    given = {t for t in extra if isinstance(t, str) and t.startswith("--")}
    argv = [sub]
    for option, value in pairs:
        if option not in given:
            argv += [option, value]
    argv += list(flags)
    tokens = list(extra)
    for i, t in enumerate(tokens):
        if t is DROP:
            tokens[i - 1] = tokens[i] = None
    argv += [t for t in tokens if t is not None]
    return [t.replace("{tmp}", str(tmp)) for t in argv]


class _StillRunning(BaseException):
    """Raised in the main thread when a row runs past :data:`STOP` seconds."""


def _stop(signum, frame):
    raise _StillRunning


def _tree(path) -> set:
    return {
        os.path.relpath(os.path.join(d, n), path) for d, ds, fs in os.walk(path) for n in ds + fs
    }


@pytest.fixture
def workdir(tmp_path, monkeypatch):
    """A directory with the files the rows name, as the working directory."""
    monkeypatch.delenv("LCPFRIC_MAX_MEMORY", raising=False)
    monkeypatch.chdir(tmp_path)
    (tmp_path / "dir").mkdir()
    (tmp_path / "file").write_text("a file, not a directory\n")
    (tmp_path / "text.npy").write_text("not a numpy file\n")
    (tmp_path / "taken.nc.parts").write_text("a file where the chunks would go\n")
    x = (np.arange(32) - 15.5) * 0.02  # a sphere of radius 10 on a 32 x 32 grid, spacing 0.02
    h = (x[:, None] ** 2 + x[None, :] ** 2) / 20.0
    np.save(tmp_path / "h.npy", h)
    np.save(tmp_path / "line.npy", x)
    h_nan = h.copy()
    h_nan[3, 3] = np.nan
    np.save(tmp_path / "nan.npy", h_nan)
    np.savez(tmp_path / "two.npz", a=h, b=h)
    system = dict(K=[[4.0, -1.0], [-1.0, 3.0]], B=[[0.9, -1.2], [1.1, 0.3]], friction=[0.5, 0.6],
                  P0=[4.0, 3.5], P1=[1.0, 0.5], psi=[0, 1], Q0=[0, 0], Q1=[2.5, 2.0],
                  phi=[0.3, 2.0])  # fmt: skip
    (tmp_path / "sys.json").write_text(json.dumps(system))
    (tmp_path / "sys_K.json").write_text(json.dumps(dict(system, K=[[4.0, -1.0]])))
    (tmp_path / "sys_ill.json").write_text(json.dumps(dict(system, B=[[30.0, 0], [0, 0]])))
    (tmp_path / "far.json").write_text("[50, 0]")
    # a jointed structure (lcpfric modal): two masses, a Jenkins element between them
    structure = dict(M=np.diag([1.0, 0.5]), K=[[3.0, -1.0], [-1.0, 1.0]], contact_dofs=[[0, 1]],
                     kt=3.0, mu=0.4, N=0.5)  # fmt: skip
    np.savez(tmp_path / "structure.npz", **structure)
    np.savez(tmp_path / "structure_no_kt.npz", **{k: v for k, v in structure.items() if k != "kt"})
    np.savez(tmp_path / "structure_K.npz", **dict(structure, K=[[-3.0, 1.0], [1.0, -1.0]]))
    np.savez(tmp_path / "structure_kt.npz", **dict(structure, kt=-3.0))
    np.savez(tmp_path / "structure_M.npz", **dict(structure, M=np.diag([1.0, np.nan])))
    np.savez(tmp_path / "structure_dofs.npz", **dict(structure, contact_dofs=[[0, 2]]))
    held = dict(structure, K=[[1.0, 0.0], [0.0, 0.0]])  # the second mass hangs on the joint
    np.savez(tmp_path / "structure_held.npz", **held)
    return tmp_path


@pytest.mark.parametrize(("sub", "option", "extra", "kind", "expected", "named"), _params())
def test_bad_input_is_refused(workdir, capsys, sub, option, extra, kind, expected, named):
    argv = argv_of(sub, extra, workdir)
    before = _tree(workdir)
    capsys.readouterr()
    old = signal.signal(signal.SIGALRM, _stop)
    signal.setitimer(signal.ITIMER_REAL, STOP)
    t0 = time.perf_counter()
    # Python's warnings (numpy's RuntimeWarning, say) are printed on stderr by the command, as
    # more lines; pytest would record them instead, so they are recorded here and counted
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("default")
        try:
            code = main(argv)
        except _StillRunning:
            code = "still running"
        except Exception as exc:  # the command would print a traceback
            code = f"Traceback: {type(exc).__name__}: {exc}"
        finally:
            signal.setitimer(signal.ITIMER_REAL, 0)
            signal.signal(signal.SIGALRM, old)
    seconds = time.perf_counter() - t0
    out, err = capsys.readouterr()
    err += "".join(f"{w.filename}:{w.lineno}: {w.category.__name__}: {w.message}\n" for w in caught)
    shown = f"lcpfric {' '.join(argv[:])}\nexit {code} after {seconds:.2f} s\nstderr: {err!r}"
    assert "Traceback" not in f"{code} {err}", shown
    assert code == expected, shown
    lines = err.strip().splitlines()
    assert len(lines) == 1, shown
    if "pip install" in lines[0] and named not in lines[0]:  # a missing extra is said first
        pytest.skip(lines[0].split("error: ", 1)[-1])
    assert re.search(rf"(?<![\w-]){re.escape(named)}(?![\w-])", lines[0]), shown
    assert _tree(workdir) == before, f"created {_tree(workdir) - before}\n{shown}"
    assert seconds < FAST, shown


# -- the table covers every option ----------------------------------------------------------------
def _options() -> dict[tuple[str, str], argparse.Action]:
    parser = build_parser()
    sub = next(a for a in parser._actions if isinstance(a, argparse._SubParsersAction))
    found = {}
    for name in COMMANDS:
        for action in sub.choices[name]._actions:
            for s in action.option_strings:
                if s.startswith("--") and s != "--help":
                    found[(name, s)] = action
    return found


def test_the_table_covers_every_option():
    options = _options()
    rows = [_values(e) for e in TABLE]
    covered = {(r[0], r[1]) for r in rows}
    takes_value = {k for k, a in options.items() if a.nargs != 0}
    flags = {k for k, a in options.items() if a.nargs == 0}
    assert sorted(takes_value - covered) == [], "value-taking options without a row"
    assert sorted(flags - set(EXEMPT)) == [], "flags neither in EXEMPT nor with a reason"
    assert sorted(set(EXEMPT) - flags) == [], "EXEMPT names what is not a flag (any more)"
    assert all(EXEMPT.values())
    unknown = {k for k in covered if k not in options and k[1] != "--bogus"}
    assert sorted(unknown) == [], "rows of options the parser does not have"


def test_the_rows_are_well_formed():
    kinds = {
        NOT_NUMBER, NOT_FINITE, RANGE, NOT_INT, NO_APPLY, MISSING, UNUSABLE,
        CHOICE, DUPLICATE, CONFLICT, NO_VALUE, REQUIRED, UNKNOWN,
    }  # fmt: skip
    rows = [_values(e) for e in TABLE]
    ids = [_row_id(r) for r in rows]
    assert len(ids) == len(set(ids)), "two rows with the same id"
    for sub, option, extra, kind, expected, named in rows:
        assert sub in COMMANDS and kind in kinds and expected == 2 and named
        assert isinstance(extra, tuple)
