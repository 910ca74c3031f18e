"""``lcpfric figures``: the paper's Figs. 3-7 and 9, computed and drawn."""

from __future__ import annotations

import json
import sys
import time

from . import _common
from ..errors import InputError

HELP = "compute and draw the paper's Figs. 3-7 and 9, or the contact figures (PNG and PDF)"
DESCRIPTION = (
    "Compute the data of the paper's figures with the exact solution and write them as "
    "PNG and PDF files into a directory; with --contact, the continuum contact "
    "figures instead (Hertz maps over the phases, W against the phase and where it "
    "peaks, stick/slip/separation zones over the cycle, plane tractions beside "
    "Cattaneo's). " + _common.OUTPUT_RULE
)
#: API parameter names that differ from the option's name
OPTIONS = {"formats": "--format"}
#: phases of the maps of Figs. 3 and 4 (φ = kπ/10, k = 0..10)
MAP_PHASES = 11
#: curves of Figs. 5-7 and 9 drawn with --points points each (at most)
CURVES = 8


def configure(p) -> None:
    p.add_argument(
        "--out",
        required=True,
        metavar="DIR",
        help="output directory (created; its parent must exist)",
    )
    p.add_argument(
        "--grid",
        default=None,
        metavar="N",
        help="points per axis of the maps (default 101, as in the paper; 41 with --contact)",
    )
    p.add_argument(
        "--contact",
        action="store_true",
        help="the continuum contact figures (Hertz contact by MDR, cylinder by "
        "half-plane elements)",
    )
    p.add_argument(
        "--points",
        default=None,
        metavar="N",
        help="points per curve of the paper's figures (default 361; not with --contact)",
    )
    p.add_argument(
        "--format",
        default="png,pdf",
        metavar="LIST",
        help="comma-separated file formats among png, pdf, svg (default png,pdf)",
    )
    p.add_argument("--json", action="store_true", help="print the files written as JSON")
    _common.add_memory_option(p)


def run(args) -> int:
    _common.require_extras("figures", ["matplotlib", "xarray"])
    out = _common.output_dir(args.out, "--out")
    from .. import _checks

    grid = _checks.positive_int("--grid", args.grid or ("41" if args.contact else "101"), minimum=3)
    if args.contact and args.points is not None:
        raise InputError("--points", "applies to the paper's figures, not to --contact")
    points = _checks.positive_int("--points", args.points or "361", minimum=3)
    formats = [f.strip().lower() for f in str(args.format).split(",") if f.strip()]
    if len(set(formats)) < len(formats):
        raise InputError("--format", f"names a format more than once: {args.format!r}")
    need = _common.map_bytes(
        float(grid) ** 2 * MAP_PHASES, 2 * grid + MAP_PHASES
    ) + _common.map_bytes(float(points) * CURVES)
    _common.check_memory(
        need,
        args,
        "--grid" if grid**2 * MAP_PHASES > points * CURVES else "--points",
        f"figures with --grid {grid} and --points {points}",
    )

    if args.contact:
        from ..figures.contact import write_contact_figures as write_figures
    else:
        from ..paper.figures import write_figures
    existed = out.is_dir()
    before = _common.snapshot(out)
    t0 = time.perf_counter()
    try:
        extra = {} if args.contact else {"points": points}
        paths = write_figures(
            out,
            grid=grid,
            formats=formats,
            **extra,
            progress=lambda line: print(line, file=sys.stderr, flush=True),
        )
    except BaseException:
        _common.remove_created(out, before, existed)
        raise
    seconds = time.perf_counter() - t0
    if args.json:
        print(json.dumps({"out": str(out), "files": [str(p) for p in paths], "seconds": seconds}))
    else:
        print(
            f"wrote {len(paths)} files to {out} in {seconds:.2f} s: "
            + ", ".join(p.name for p in paths)
        )
    return 0
