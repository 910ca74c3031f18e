"""``lcpfric map``: a dissipation map Ŵ(φ, P̂1, Q̂1) written to NetCDF (the single node), or
W k_t0/(μ² P0²) of the Hertz contact with ``--contact sphere``."""

from __future__ import annotations

import argparse
import json
import signal
import sys
from typing import TYPE_CHECKING

from . import _common
from ._scheduler import connect, scheduler_address
from ..errors import InputError

if TYPE_CHECKING:
    from pathlib import Path

HELP = "compute a dissipation map W_hat(phi, P1, Q1) and write it to NetCDF"
DESCRIPTION = (
    "Compute W_hat on the grid phi x P1 x Q1 and write it to a NetCDF file (with "
    "--contact sphere: W k_t0/(mu^2 P0^2) of the Hertz contact by dimensionality "
    "reduction over P1/P0, Q1/(mu P0) and phi). Finished "
    "chunks are saved next to the output (<out>.parts) and an interrupted run resumes "
    "when the same command is run again. " + _common.OUTPUT_RULE
)
#: API parameter names that differ from the option's name
OPTIONS = {
    "steps_per_cycle": "--steps",
    "store": "--out",
    "out": "--out",
    "k_support_ratio": "--k-support-ratio",
    "nodes": "--nodes",
    "grid": "--grid",
    "dims": "--dims",
}
#: the continuum-contact options and the contact models they apply to
CONTACT_OPTIONS = {
    "contact_model": ("mdr", "halfspace"),
    "k_support_ratio": ("mdr", "halfspace"),
    "nodes": ("mdr",),
    "grid": ("halfspace",),
    "dims": ("halfspace",),
    "nu": ("halfspace",),
}
DIMS = ("phi", "P1", "Q1")


def configure(p) -> None:
    p.add_argument(
        "--P1",
        required=True,
        metavar="START:STOP:NUM",
        help="normal amplitudes P1/P0: START:STOP:NUM (NUM points, ends included) or "
        "a comma-separated list",
    )
    p.add_argument(
        "--Q1",
        required=True,
        metavar="START:STOP:NUM",
        help="tangential amplitudes Q1/(f P0): START:STOP:NUM or a list",
    )
    p.add_argument(
        "--phi",
        required=True,
        metavar="LIST",
        help="phases: comma-separated radians or multiples of pi (0,0.6pi,pi/2; "
        "negative ones too: -0.5pi,0.5pi), or START:STOP:NUM (0:pi:11)",
    )
    p.add_argument(
        "--out",
        required=True,
        metavar="FILE.nc",
        help="output NetCDF file; must end in .nc, in an existing directory",
    )
    p.add_argument(
        "--method",
        default=None,
        help="method (default: exact; with --contact, the contact's own: mdr-bar or newton-cg)",
    )
    g = p.add_argument_group(
        "continuum contact", "map a continuum contact instead of the single node"
    )
    g.add_argument(
        "--contact",
        choices=("sphere",),
        default=None,
        help="sphere: the Hertz contact (then --Q1 is Q1/(mu P0))",
    )
    g.add_argument(
        "--contact-model",
        choices=("mdr", "halfspace"),
        default=None,
        help="mdr (dimensionality reduction, default) or halfspace (boundary elements on a grid)",
    )
    g.add_argument(
        "--k-support-ratio",
        default=None,
        metavar="X",
        help="tangential support stiffness as a multiple of the contact's k_t0 (default 0: "
        "pure load control; loads with |Q| > mu P at some instant are then NaN)",
    )
    g.add_argument("--k-support", default=None, help=argparse.SUPPRESS)  # refused: see run
    g.add_argument(
        "--nodes",
        default=None,
        metavar="N",
        help="mdr: springs across the largest contact radius (default 200, at least 10)",
    )
    g.add_argument(
        "--grid",
        default=None,
        metavar="N",
        help="halfspace: elements across the largest contact (default 20, at least 8)",
    )
    g.add_argument(
        "--dims",
        default=None,
        choices=("1", "2"),
        help="halfspace: tangential directions (default 1)",
    )
    g.add_argument("--nu", default=None, metavar="X", help="halfspace: Poisson's ratio (default 0)")
    p.add_argument(
        "--steps", default=None, metavar="N", help="steps per cycle for time-stepping methods"
    )
    p.add_argument(
        "--scheduler",
        default=None,
        metavar="ADDRESS",
        help="Dask scheduler address, tcp://HOST:PORT or HOST:PORT (default: local processes)",
    )
    p.add_argument(
        "--processes",
        default=None,
        metavar="N",
        help="local worker processes (default: all cores when it pays)",
    )
    p.add_argument("--chunk-size", default=None, metavar="N", help="grid points per saved chunk")
    p.add_argument(
        "--restart",
        action="store_true",
        help="delete the output and the saved chunks of an earlier run first, and "
        "compute everything again",
    )
    p.add_argument("--no-progress", action="store_true", help="no progress bar")
    p.add_argument("--json", action="store_true", help="print the summary as JSON")
    _common.add_memory_option(p)


# -- checks before any work ------------------------------------------------------------------------
def grid_count(text) -> int | None:
    """How many values a grid option asks for, without building it (None: let the parser say
    what is wrong)."""
    text = str(text).strip()
    if ":" in text:
        parts = text.split(":")
        if len(parts) != 3:
            return None
        try:
            return int(parts[2].strip())
        except ValueError:
            return None
    return len([s for s in text.split(",") if s.strip()])


def _chunk_files(store: Path) -> list[Path]:
    return sorted(store.glob("chunk-*.npy")) if store.is_dir() else []


def remove_store(store: Path) -> None:
    """Delete a sweep's chunk store (only the files a sweep writes there)."""
    if not store.is_dir():
        return
    for pattern in ("chunk-*.npy", "manifest.json", ".*.tmp"):
        for f in store.glob(pattern):
            f.unlink(missing_ok=True)
    try:
        store.rmdir()
    except OSError:  # someone keeps other files there: leave them
        pass


# -- the command -----------------------------------------------------------------------------------
def _contact(args) -> dict | None:
    """The ``contact`` spec of the continuum-contact options; an option that does not apply
    (no --contact, or another --contact-model) is refused, naming why."""
    from .. import _checks

    if args.k_support is not None:
        raise InputError(
            "--k-support",
            "the map's support stiffness is a multiple of k_t0: give --k-support-ratio "
            "(lcpfric contact's --k-support is an absolute stiffness)",
        )
    given = [k for k in CONTACT_OPTIONS if getattr(args, k) is not None]
    if args.contact is None:
        if given:
            name = "--" + given[0].replace("_", "-")
            raise InputError(name, "applies to a continuum contact map only: add --contact sphere")
        return None
    model = args.contact_model or "mdr"
    for k in given:
        if model not in CONTACT_OPTIONS[k]:
            raise InputError(
                "--" + k.replace("_", "-"),
                f"applies to --contact-model {' or '.join(CONTACT_OPTIONS[k])} only, not {model}",
            )
    # the values are checked (and defaulted) by the map itself: one rule for the API and here
    contact = {"geometry": args.contact, **({"model": model} if model != "mdr" else {})}
    for key in ("k_support_ratio", "nu"):
        if getattr(args, key) is not None:
            option = "--" + key.replace("_", "-")
            contact[key] = _checks.parse_number(getattr(args, key), option)
    for key in ("nodes", "grid", "dims"):
        if getattr(args, key) is not None:
            contact[key] = getattr(args, key)
    return contact


def run(args) -> int:
    from .. import _checks

    method = None if args.method is None else str(args.method).strip()
    contact = _contact(args)
    if contact is not None:
        from ..analysis.contact_maps import map_spec

        own = map_spec(contact, None, method)[3]  # checks that the method solves it
        method = own if method is None else method
    elif method is None:
        method = "exact"
    modules = ["xarray"] + ([] if _common.installed("netCDF4") else ["h5netcdf", "h5py"])
    if args.scheduler is not None:
        modules.append("distributed")
    _common.require_extras("maps", modules)

    out = _common.output_file(args.out, "--out", ".nc")
    store = out.with_name(out.name + ".parts")
    if store.exists() and not store.is_dir():
        raise InputError(
            "--out",
            f"{str(store)!r} (where the finished chunks are saved) exists and is not a directory",
        )
    steps = None if args.steps is None else _checks.positive_int("--steps", args.steps, 4)
    processes = (
        None if args.processes is None else _checks.positive_int("--processes", args.processes)
    )
    if processes is not None and args.scheduler is not None:
        raise InputError(
            "--processes",
            "sets local workers; with --scheduler the cluster's workers run the chunks",
        )
    chunk_size = (
        None if args.chunk_size is None else _checks.positive_int("--chunk-size", args.chunk_size)
    )

    counts = {d: grid_count(getattr(args, d)) for d in DIMS}
    if all(c is not None and c > 0 for c in counts.values()):
        n = counts["phi"] * counts["P1"] * counts["Q1"]
        workers = 1 if args.scheduler is not None else _common.workers_for(processes)
        need = (
            _common.map_bytes(n, sum(counts.values()), method, steps, chunk_size, workers)
            if contact is None
            else 8.0 * 4 * n
        )  # the sweep checks its chunks itself
        _common.check_memory(
            need,
            args,
            "--P1, --Q1, --phi",
            f"a map of {counts['phi']} x {counts['P1']} x {counts['Q1']} = {n:.4g} points",
        )
    from ._grids import parse_grid

    P1 = parse_grid(args.P1, "--P1")
    Q1 = parse_grid(args.Q1, "--Q1")
    phi = parse_grid(args.phi, "--phi", angle=True)
    scheduler = None if args.scheduler is None else scheduler_address(args.scheduler)
    if contact is not None and not args.json:
        _announce(args, contact, steps, method, (P1, Q1, phi), processes, scheduler)

    if args.restart:  # nothing of the earlier run may survive an interrupted restart
        out.unlink(missing_ok=True)
        remove_store(store)
    store_existed = store.exists()
    progress = not args.no_progress and _common.installed("tqdm")

    from ..analysis.sweep import sweep

    client = None if scheduler is None else connect(scheduler)
    previous = _terminate_as_interrupt()
    try:
        ds = sweep(
            P1,
            Q1,
            phi,
            method=method,
            steps_per_cycle=steps,
            chunk_size=chunk_size,
            out=out,
            resume=not args.restart,
            scheduler=client,
            processes=processes,
            progress=progress,
            contact=contact,
        )
    except KeyboardInterrupt:
        saved = len(_chunk_files(store))
        if saved:
            print(
                f"interrupted: {saved} finished chunks are saved in {store}; run the same "
                "command again to resume",
                file=sys.stderr,
            )
        else:
            if not store_existed:
                remove_store(store)
            print("interrupted before any chunk finished; nothing was saved", file=sys.stderr)
        return 130
    except BaseException as exc:
        saved = len(_chunk_files(store))
        if saved:
            _common.add_note(
                exc,
                f"{saved} finished chunks are kept in {store}; run the same "
                "command again to resume",
            )
        elif not store_existed:
            remove_store(store)
        raise
    finally:
        if previous is not None:
            signal.signal(signal.SIGTERM, previous)
        if client is not None:
            client.close()
    return _report(ds, out, args.json)


def _terminate_as_interrupt():
    """SIGTERM (``timeout``, ``kill``, batch schedulers) stops a map as Ctrl-C does: workers
    stopped, finished chunks kept, exit 130. Returns the previous handler (None where signals
    cannot be set: not the main thread)."""

    def _stop(signum, frame):
        raise KeyboardInterrupt

    try:
        return signal.signal(signal.SIGTERM, _stop)
    except ValueError:
        return None


def _announce(args, contact, steps, method, axes, processes, scheduler) -> None:
    """Say on stderr how long a contact map is expected to take, when that is over a minute
    (the registry's measured cost per point; Ctrl-C keeps the finished chunks), after the
    sweep's own memory check (so that a refused map is not announced)."""
    from .. import memory
    from ..analysis.sweep_plan import chunk_bounds, plan_sweep, sweep_memory

    P1, Q1, phi = axes
    points = P1.size * Q1.size * phi.size
    workers = 1 if scheduler is not None else min(_common.workers_for(processes), points)
    plan = plan_sweep(P1, Q1, phi, method, steps, contact)
    chunks = chunk_bounds(points, args.chunk_size and int(args.chunk_size), plan["cost"], False)
    memory.check(*sweep_memory(plan, chunks, phi, P1, Q1, scheduler, workers))
    seconds = plan["cost"] * points / max(1, workers)
    if seconds > 60:
        took = f"{seconds / 60:.0f} min" if seconds < 7200 else f"{seconds / 3600:.1f} h"
        print(
            f"lcpfric map: about {took} of work expected ({points} points, {workers} "
            "workers); Ctrl-C keeps the finished chunks, and the same command resumes",
            file=sys.stderr,
        )


def _report(ds, out: Path, as_json: bool) -> int:
    import numpy as np

    name = "W_hat" if "W_hat" in ds else "W_normalized"
    W = ds[name]
    defined = int(W.count())
    summary = {
        "out": str(out),
        "method": ds.attrs["method"],
        "shape": {d: int(ds.sizes[d]) for d in DIMS},
        "points": int(W.size),
        "seconds": round(float(ds.attrs["seconds"]), 4),
        "executor": ds.attrs["executor"],
        "chunks_computed": int(ds.attrs["chunks_computed"]),
        "chunks_reused": int(ds.attrs["chunks_reused"]),
        f"{name}_max": None,
        "undefined_points": int(W.size) - defined,
        "at": None,
    }
    for key in ("unconverged_points", "no_equilibrium_points"):
        if key in ds.attrs:
            summary[key] = int(ds.attrs[key])
    if defined:  # NaN points are skipped (and counted)
        where = W.fillna(-np.inf).argmax(...)
        summary[f"{name}_max"] = float(W.max(skipna=True))
        summary["at"] = {d: float(ds[d][where[d]]) for d in DIMS}
    if as_json:
        print(json.dumps(summary))
        return 0
    best = (
        f"max {name} = {summary[name + '_max']:.6g} at "
        f"{', '.join(f'{d}={v:.4g}' for d, v in summary['at'].items())}"
        if defined
        else f"no point has a {name}"
    )
    nan = ""
    if summary["undefined_points"]:
        parts = []
        if summary.get("no_equilibrium_points"):
            parts.append(f"{summary['no_equilibrium_points']} without equilibrium")
        if summary.get("unconverged_points"):
            parts.append(f"{summary['unconverged_points']} that reached no steady state")
        nan = f"; NaN at {summary['undefined_points']} points" + (
            f" ({', '.join(parts)})" if parts else ""
        )
    print(
        f"wrote {out}: {name} on {W.size} points (phi x P1 x Q1 = "
        f"{' x '.join(str(v) for v in summary['shape'].values())}) by {summary['method']} "
        f"in {summary['seconds']:.3g} s [{summary['executor']}; "
        f"{summary['chunks_reused']} of {ds.attrs['chunks']} chunks reused]; {best}{nan}"
    )
    return 0
