"""The ``faultnet`` command line: simulate, info, sweep, summarize.

Exit status: 0 on success, 1 when a run or a file failed, 2 for bad input
(a malformed option, config or graph spec, or an output that would be
overwritten), 130 when interrupted.
"""

from __future__ import annotations

import argparse
import json
import math
import os
import signal
import sys
import time

from faultnet._version import __version__
from faultnet.exceptions import (
    FaultnetError,
    InvalidParameterError,
    OutputExistsError,
    SweepError,
)

__all__ = ["build_parser", "main"]

EXIT_OK, EXIT_FAILED, EXIT_USAGE, EXIT_INTERRUPTED = 0, 1, 2, 130


class _Formatter(argparse.RawDescriptionHelpFormatter):
    def __init__(self, prog):
        super().__init__(prog, max_help_position=32)


def _int_at_least(minimum, what):
    """argparse type: an integer >= ``minimum`` (underscores allowed)."""

    def parse(text):
        try:
            value = int(text.replace("_", ""))
        except ValueError:
            value = None
        if value is None or value < minimum:
            raise argparse.ArgumentTypeError(f"expected {what}, got {text!r}")
        return value

    return parse


_positive_int = _int_at_least(1, "a positive integer")
_nonneg_int = _int_at_least(0, "an integer >= 0")


def _count(text):
    """Integers like 1000000, 1_000_000 or 1e6."""
    try:
        value = float(text.replace("_", ""))
    except ValueError:
        raise argparse.ArgumentTypeError(f"expected a positive integer, got {text!r}") from None
    if not (math.isfinite(value) and value >= 1 and value == int(value)):
        raise argparse.ArgumentTypeError(f"expected a positive integer, got {text!r}")
    return int(value)


def _finite(text):
    try:
        value = float(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"expected a number, got {text!r}") from None
    if not math.isfinite(value):
        raise argparse.ArgumentTypeError(f"expected a finite number, got {text!r}")
    return value


SIMULATE_HELP = """\
Run a Carlson-Langer model on a graph and write its event catalog (Parquet).

GRAPH is a graph spec:
  chain:N | ring:N | square:RxC[:periodic] | triangular:RxC[:periodic]
  percolation:square|triangular:RxC[:periodic]:p=P|pc[:largest|:all][:prune][:seed=S]
  a GraphML (.graphml) or node-link JSON (.json) file; graph attributes k, sigma,
  alpha set the defaults, edge k and node sigma/alpha set single springs / blocks.

The catalog is written in chunks and checkpointed; after a kill, the same
command with --resume continues from the last checkpoint, and the catalog is
the same, bit for bit, as an uninterrupted run with the same seed.

examples:
  faultnet simulate ring:2000 --alpha 2 --events 1e6 --seed 1 --out ring.parquet
  faultnet simulate percolation:square:150x150:p=0.5927 --events 1e6 --out perc.parquet
  faultnet simulate --resume --out ring.parquet      # continue a killed run
"""

INFO_HELP = """\
Print a catalog's parameters, seed and provenance, and a summary of its
events: counts, plate time, magnitude range and both b-value fits.

examples:
  faultnet info ring.parquet
  faultnet info ring.parquet --transient 10000 --json
"""

SWEEP_HELP = """\
Run a parameter grid from a TOML file: the product of the listed values,
times replicas, one catalog part per point in the output folder.  Rerunning
skips finished parts and recomputes missing or corrupt ones.  Points run on
local processes (every core), or on a Dask cluster with --scheduler.

sweep file:
  [sweep]
  graph = ["ring:200", "square:16x16:periodic"]
  alpha = [0.5, 1.0, 2.0]
  k = 16
  sigma = 0.01
  events = 20000
  replicas = 2
  seed = 12345
  transient = 2000        # events left out of the b fits (optional)
  # optional: dt, chunk, checkpoint_interval, m_min, m_max, out, [sweep.vars]

examples:
  faultnet sweep alpha.toml
  faultnet sweep alpha.toml --out runs/alpha --workers 8 --csv alpha.csv
  faultnet sweep alpha.toml --scheduler tcp://10.0.0.1:8786
"""

SUMMARIZE_HELP = """\
Print one row per sweep point (or per catalog in a folder): parameters,
events, the MLE and least-squares b-values with their errors, wall time and
status (done / partial / missing / corrupt).

examples:
  faultnet summarize runs/alpha
  faultnet summarize runs/alpha --csv alpha.csv --transient 5000
"""


def build_parser() -> argparse.ArgumentParser:

    parser = argparse.ArgumentParser(
        prog="faultnet",
        formatter_class=_Formatter,
        description="Carlson-Langer block-spring earthquake models on networks.",
        epilog="run 'faultnet COMMAND --help' for the options and examples of a command",
    )
    parser.add_argument("--version", action="version", version=f"faultnet {__version__}")
    sub = parser.add_subparsers(dest="command", metavar="COMMAND")
    sub.required = True

    p = sub.add_parser(
        "simulate",
        help="run a model and write its catalog",
        description=SIMULATE_HELP,
        formatter_class=_Formatter,
    )
    p.add_argument(
        "graph",
        nargs="?",
        metavar="GRAPH",
        help="graph spec or graph file (optional with --resume)",
    )
    p.add_argument(
        "--events",
        "-n",
        type=_count,
        metavar="N",
        help="number of events (1000000, 1_000_000 or 1e6)",
    )
    p.add_argument("--k", type=_finite, help="spring constant (default 16, or the graph file's)")
    p.add_argument("--sigma", type=_finite, help="friction drop in (0, 1) (default 0.01)")
    p.add_argument("--alpha", type=_finite, help="velocity weakening >= 0 (default 1)")
    p.add_argument(
        "--seed",
        type=_nonneg_int,
        help="seed of the initial state (and of percolation disorder); default: "
        "fresh entropy, recorded in the catalog",
    )
    p.add_argument("--dt", type=_finite, help="integration step (default: faultnet.default_dt)")
    _run_option_flags(p)
    p.add_argument(
        "--out",
        "-o",
        metavar="FILE",
        help="catalog to write (.parquet); without it nothing is saved",
    )
    p.add_argument(
        "--transient",
        type=_nonneg_int,
        default=None,
        metavar="N",
        help="events left out of the b fits (recorded in the catalog; default: the events "
        "before plate time 2)",
    )
    p.add_argument(
        "--chunk",
        type=_count,
        default=100_000,
        metavar="N",
        help="events per catalog chunk: memory is O(blocks + N) (default 100000)",
    )
    p.add_argument(
        "--checkpoint-every",
        type=_finite,
        default=60.0,
        metavar="SECONDS",
        help="seconds between checkpoints (default 60)",
    )
    p.add_argument(
        "--resume", action="store_true", help="continue the interrupted run of --out (or start it)"
    )
    p.add_argument(
        "--force", action="store_true", help="replace an existing --out or discard its checkpoint"
    )
    _fit_options(p)
    p.add_argument(
        "--progress",
        action=argparse.BooleanOptionalAction,
        default=None,
        help="progress bar (default: on a terminal)",
    )

    p = sub.add_parser(
        "info", help="describe a catalog file", description=INFO_HELP, formatter_class=_Formatter
    )
    p.add_argument("catalog", metavar="CATALOG", help="a .parquet catalog")
    p.add_argument(
        "--transient",
        type=_nonneg_int,
        default=None,
        metavar="N",
        help="events left out of the b fits (default: the catalog's)",
    )
    _fit_options(p)
    p.add_argument("--json", action="store_true", help="print metadata and summary as JSON")

    p = sub.add_parser(
        "sweep",
        help="run a parameter grid from a TOML file",
        description=SWEEP_HELP,
        formatter_class=_Formatter,
    )
    p.add_argument("config", metavar="SWEEP.toml", help="sweep file")
    p.add_argument(
        "--out",
        "-o",
        metavar="DIR",
        help="output folder (default: the file's 'out', else its name without .toml)",
    )
    p.add_argument(
        "--workers",
        "-j",
        type=_positive_int,
        metavar="N",
        help="local processes (default: every core)",
    )
    p.add_argument(
        "--scheduler",
        metavar="ADDRESS",
        help="run on a Dask cluster, e.g. tcp://HOST:8786 (output folder on a shared file system)",
    )
    p.add_argument(
        "--force",
        action="store_true",
        help="write into a folder with foreign files or another sweep's settings",
    )
    p.add_argument("--csv", metavar="FILE", help="also write the summary table as CSV")
    p.add_argument(
        "--progress",
        action=argparse.BooleanOptionalAction,
        default=None,
        help="progress bar (default: on a terminal)",
    )
    p.add_argument("--quiet", "-q", action="store_true", help="print only errors")

    p = sub.add_parser(
        "summarize",
        help="table of a sweep's points",
        description=SUMMARIZE_HELP,
        formatter_class=_Formatter,
    )
    p.add_argument("folder", metavar="DIR", help="sweep output folder (or a folder of catalogs)")
    p.add_argument("--csv", metavar="FILE", help="write the table as CSV")
    p.add_argument("--force", action="store_true", help="overwrite an existing --csv file")
    p.add_argument(
        "--transient",
        type=_nonneg_int,
        default=None,
        metavar="N",
        help="events left out of the b fits (default: the sweep's)",
    )
    _fit_options(p)
    return parser


def _fit_options(p):
    p.add_argument(
        "--m-min",
        type=_finite,
        default=None,
        metavar="M",
        help="lower end of the b fits (default: maximum curvature)",
    )
    p.add_argument(
        "--m-max",
        type=_finite,
        default=None,
        metavar="M",
        help="upper end of the least-squares fit (default: the 99th percentile of M above --m-min)",
    )


# --------------------------------------------------------------------------- commands


def _size(path):
    n = os.path.getsize(path)
    for unit in ("B", "kB", "MB", "GB"):
        if n < 1000 or unit == "GB":
            return f"{n:.0f} {unit}" if unit == "B" else f"{n:.1f} {unit}"
        n /= 1000.0
    return f"{n} B"  # pragma: no cover


def _run_option_flags(p):
    g = p.add_argument_group("run options (faultnet.RunOptions; default: as recorded on --resume)")
    g.add_argument("--method", choices=["dopri5", "rk4"], help="scheme inside events (dopri5)")
    g.add_argument(
        "--rtol",
        type=_finite,
        help="target relative accuracy of an event's slip, 1e-8..1e-4 (sets the step and the "
        "crossing treatment; --dt overrides the step)",
    )
    g.add_argument(
        "--crossings",
        choices=["exact", "interpolated"],
        help="stops and joins: redo the step to each (exact) or place them on the step's "
        "dense output (interpolated); default: exact, or the --rtol calibration's",
    )
    g.add_argument(
        "--solo-cache",
        action=argparse.BooleanOptionalAction,
        default=None,
        help="reuse the cached slip of a block slipping alone (on)",
    )
    g.add_argument(
        "--local-regions-from",
        type=_local_from,
        metavar="N|inf",
        help="slipping blocks from which crossings are handled in local regions (32)",
    )
    g.add_argument("--max-event-duration", type=_finite, metavar="T", help="guard (1e4)")
    g.add_argument("--max-velocity", type=_finite, metavar="V", help="guard (1e3)")


def _local_from(text):
    if text.strip().lower() in ("inf", "infinity"):
        return float("inf")
    return _int_at_least(1, "an integer >= 1 or inf")(text)


def run_options_from_args(args):
    """The RunOptions the flags ask for, or None when no run-option flag is given."""
    from faultnet.options import RunOptions

    names = (
        "method",
        "rtol",
        "crossings",
        "solo_cache",
        "local_regions_from",
        "max_event_duration",
        "max_velocity",
    )
    given = {n: getattr(args, n) for n in names if getattr(args, n, None) is not None}
    return RunOptions(**given) if given else None


def cmd_simulate(args, out):
    import numpy as np

    from faultnet.spec_run import run_from_spec
    from faultnet.summary import (
        TRANSIENT_PLATE_TIME,
        catalog_stats,
        events_before,
        fit_b_values,
        format_stats,
    )

    if args.graph is None and not args.resume:
        raise InvalidParameterError("GRAPH is required (e.g. ring:200); see faultnet simulate -h")
    if args.events is None and not args.resume:
        raise InvalidParameterError("--events N is required")
    if args.out is None and args.resume:
        raise InvalidParameterError("--resume needs --out FILE: the catalog to continue")
    tic = time.perf_counter()
    report = run_from_spec(
        args.graph,
        args.events,
        args.out,
        k=args.k,
        sigma=args.sigma,
        alpha=args.alpha,
        dt=args.dt,
        options=run_options_from_args(args),
        seed=args.seed,
        chunk_events=args.chunk,
        checkpoint_interval=args.checkpoint_every,
        transient=args.transient,
        resume=args.resume,
        force=args.force,
        progress=args.progress,
    )
    elapsed = time.perf_counter() - tic
    md = report.metadata
    n = md["n_events"]
    if report.status == "already complete":
        print(f"{args.out} is already complete ({n:,} events); nothing to do", file=out)
    else:
        wall = md.get("wall_time_s") or float("nan")
        resumed = (
            f", resumed at event {report.resumed_from:,}" if report.status == "resumed" else ""
        )
        done = n - report.resumed_from
        print(
            f"{md['graph']}: {done:,} events in {elapsed:.2f} s{resumed} "
            f"({done / max(elapsed, 1e-9):,.0f} events/s; simulating alone "
            f"{n / wall:,.0f} events/s)",
            file=out,
        )
    print(
        f"parameters  k={md['k']} sigma={md['sigma']} alpha={md['alpha']} dt={md['dt']:.6g} "
        f"method={md['method']} seed={md['seed_entropy']}",
        file=out,
    )
    transient = args.transient if args.transient is not None else md.get("transient") or None
    default_note = None
    if transient is None:  # default: leave out the events before plate time 2
        if report.path is not None:
            transient = events_before(report.path, TRANSIENT_PLATE_TIME)
        else:
            transient = int(np.searchsorted(report.plate_times, TRANSIENT_PLATE_TIME))
        default_note = (
            f"transient   the {transient:,} events before plate time {TRANSIENT_PLATE_TIME:g} "
            "are left out of the fits (--transient N to choose)"
        )
        if transient > md["n_events"] // 2:  # a short run: fit its second half
            transient = md["n_events"] // 2
            default_note = (
                f"transient   the first half of the run ({transient:,} events) is left out of "
                f"the fits: the run ends before plate time {TRANSIENT_PLATE_TIME:g}, so it may "
                "not be in a steady state yet (--transient N to choose)"
            )
    if report.path is not None:
        st = catalog_stats(report.path, transient=transient, m_min=args.m_min, m_max=args.m_max)
        print(format_stats(md, st), file=out)
        if default_note:
            print(default_note, file=out)
        if report.status != "already complete":
            print(f"wrote {report.path} ({_size(report.path)})", file=out)
        return EXIT_OK
    M = report.magnitudes
    fin = M[np.isfinite(M)]
    st = {
        "events": n,
        "transient": transient,
        "events_fit": max(n - transient, 0),
        "M_min": float(fin.min()) if fin.size else float("nan"),
        "M_max": float(fin.max()) if fin.size else float("nan"),
        **report.seen,
    }
    st.update(fit_b_values(M[transient:], m_min=args.m_min, m_max=args.m_max))
    print(format_stats(md, st), file=out)
    if default_note:
        print(default_note, file=out)
    print("(no --out given: the catalog was not saved)", file=out)
    return EXIT_OK


def cmd_info(args, out):
    from faultnet.checkpoint import checkpoint_status
    from faultnet.io import read_metadata
    from faultnet.summary import catalog_stats, format_metadata, format_stats

    path = args.catalog
    if os.path.isdir(path):
        if os.path.isfile(os.path.join(path, "sweep.json")):
            raise InvalidParameterError(f"{path} is a sweep folder; use: faultnet summarize {path}")
        raise InvalidParameterError(f"{path} is a folder; give a .parquet catalog file")
    if not os.path.exists(path):
        st = checkpoint_status(path, verify=True)
        if st is not None:
            print(
                f"{path}: interrupted run, {st['events_done']:,} of {st['n_events'] or '?':,} "
                f"events committed in {st['chunks']} chunks; continue it with\n"
                f"  faultnet simulate --resume --out {path}",
                file=out,
            )
            return EXIT_OK
        raise InvalidParameterError(f"catalog {path} does not exist")
    md = read_metadata(path)
    stats = catalog_stats(path, transient=args.transient, m_min=args.m_min, m_max=args.m_max)
    if args.json:
        print(json.dumps({"metadata": md, "summary": stats}, indent=2, default=str), file=out)
        return EXIT_OK
    print(f"{path} ({_size(path)})", file=out)
    print(format_metadata(md), file=out)
    print(format_stats(md, stats), file=out)
    return EXIT_OK


def _write_csv(table, path, force):
    from faultnet.atomic import atomic_path

    if os.path.exists(path) and not force:
        raise OutputExistsError(f"{path} exists; refusing to overwrite it (use --force)")
    with atomic_path(path) as tmp:
        table.to_csv(tmp, index=False)


_SHOW = [
    "point",
    "graph",
    "n_blocks",
    "k",
    "sigma",
    "alpha",
    "replica",
    "events",
    "b_mle",
    "b_mle_err",
    "b_lsq",
    "b_lsq_err",
    "m_min",
    "wall_time_s",
    "status",
]


def _print_table(table, out):
    import pandas as pd

    shown = table[_SHOW].copy()
    with pd.option_context(
        "display.max_rows", None, "display.width", 200, "display.max_colwidth", 40
    ):
        print(shown.to_string(index=False, float_format=lambda x: f"{x:.4g}"), file=out)


def cmd_sweep(args, out):
    from faultnet.sweep import sweep

    if args.scheduler and args.workers:
        raise InvalidParameterError("give either --workers or --scheduler, not both")

    def log(msg):
        if not args.quiet:
            print(msg, file=sys.stderr)

    try:
        table = sweep(
            args.config,
            out=args.out,
            scheduler=args.scheduler,
            workers=args.workers,
            force=args.force,
            progress=args.progress,
            log=log,
        )
        status = EXIT_OK
    except SweepError as exc:
        table, status = exc.summary, EXIT_FAILED
        print(f"faultnet: error: {exc}", file=sys.stderr)
    if not args.quiet:
        _print_table(table, out)
        print(
            f"{int((table['status'] == 'done').sum())} of {len(table)} points done in "
            f"{table.attrs.get('out')}",
            file=out,
        )
    if args.csv:
        _write_csv(table, args.csv, args.force)
        if not args.quiet:
            print(f"wrote {args.csv}", file=out)
    return status


def cmd_summarize(args, out):
    from faultnet.sweep import summarize

    table = summarize(args.folder, transient=args.transient, m_min=args.m_min, m_max=args.m_max)
    _print_table(table, out)
    if args.csv:
        _write_csv(table, args.csv, args.force)
        print(f"wrote {args.csv}", file=out)
    return EXIT_OK


COMMANDS = {
    "simulate": cmd_simulate,
    "info": cmd_info,
    "sweep": cmd_sweep,
    "summarize": cmd_summarize,
}


def main(argv=None) -> int:
    """Run the command line with ``argv`` (default ``sys.argv[1:]``); return the exit status."""
    parser = build_parser()
    try:
        args = parser.parse_args(argv)
    except SystemExit as exc:  # --help, --version, usage errors
        return int(exc.code or 0)
    out = sys.stdout
    previous = _sigterm_as_interrupt()
    try:
        return COMMANDS[args.command](args, out)
    except KeyboardInterrupt:
        hint = ""
        if args.command == "simulate" and getattr(args, "out", None):
            hint = f"; continue with: faultnet simulate --resume --out {args.out}"
        elif args.command == "sweep":
            hint = "; rerun the same command to continue"
        print(f"\nfaultnet: interrupted{hint}", file=sys.stderr)
        return EXIT_INTERRUPTED
    except BrokenPipeError:  # the reader went away (e.g. `| head`); the work itself is done
        try:
            devnull = os.open(os.devnull, os.O_WRONLY)
            os.dup2(devnull, sys.stdout.fileno())
        except (OSError, ValueError, AttributeError):
            pass
        return EXIT_FAILED
    except InvalidParameterError as exc:
        print(f"faultnet {args.command}: error: {exc}", file=sys.stderr)
        return EXIT_USAGE
    except (FaultnetError, OSError) as exc:
        print(f"faultnet {args.command}: error: {exc}", file=sys.stderr)
        return EXIT_FAILED
    finally:
        if previous is not None:
            signal.signal(signal.SIGTERM, previous)


def _interrupt(signum, frame):
    raise KeyboardInterrupt


def _sigterm_as_interrupt():
    """SIGTERM stops a command as Ctrl-C does (checkpoint kept, locks and workers released)."""
    try:
        return signal.signal(signal.SIGTERM, _interrupt)
    except ValueError:  # not the main thread: leave SIGTERM alone
        return None
