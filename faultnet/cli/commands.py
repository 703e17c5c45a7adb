"""The ``faultnet`` command line: simulate, info, sweep, summarize.

One ``cmd_*`` function per command, and :func:`main`, which parses the
arguments (the parser is in :mod:`faultnet.cli.parser`), runs the command and
turns its errors and interruptions into one line and an exit status.

Exit status: 0 on success, 1 when a run or a file failed, 2 for bad input
(a malformed option, config or graph spec, or an output that would be
overwritten), 130 when interrupted.
"""

from __future__ import annotations

import json
import os
import signal
import sys
import time

from faultnet.cli.parser import build_parser, run_options_from_args
from faultnet.exceptions import (
    FaultnetError,
    InvalidParameterError,
    OutputExistsError,
    SweepError,
)

__all__ = ["build_parser", "main"]

EXIT_OK, EXIT_FAILED, EXIT_USAGE, EXIT_INTERRUPTED = 0, 1, 2, 130


# --------------------------------------------------------------------------- commands


def _size(path):
    n = os.path.getsize(path)
    for unit in ("B", "kB", "MB", "GB"):
        if n < 1000 or unit == "GB":
            return f"{n:.0f} {unit}" if unit == "B" else f"{n:.1f} {unit}"
        n /= 1000.0
    return f"{n} B"  # pragma: no cover


def cmd_simulate(args, out):
    from faultnet.io.parquet import check_catalog_path
    from faultnet.io.summary import catalog_stats, format_stats
    from faultnet.runs.spec_run import run_from_spec

    stored = args.resume or args.extend  # the graph and parameters come from --out
    if args.graph is None and not stored:
        raise InvalidParameterError("GRAPH is required (e.g. ring:200); see faultnet simulate -h")
    if args.events is None and not args.resume:
        raise InvalidParameterError(
            "--events N is required" + (" (the total to extend to)" if args.extend else "")
        )
    if args.out is None and stored:
        flag = "--continue" if args.extend else "--resume"
        raise InvalidParameterError(f"{flag} needs --out FILE: the catalog to continue")
    if args.out is not None:
        check_catalog_path(args.out, "--out")
    elif args.record_slips:
        raise InvalidParameterError("--record-slips needs --out FILE: the slips go next to it")
    _check_kelvin(args)
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
        extend=args.extend,
        force=args.force,
        progress=args.progress,
        record_slips=args.record_slips,
        model=args.model,
        ofc_alpha=args.ofc_alpha,
        nu=args.nu,
        eta=args.eta,
    )
    _print_run(args, report, time.perf_counter() - tic, out)
    md = report.metadata
    transient, default_note = _fit_transient(args, report)
    if report.path is not None:
        st = catalog_stats(report.path, transient=transient, m_min=args.m_min, m_max=args.m_max)
    else:
        st = _stats_in_memory(report, transient, args.m_min, args.m_max)
    print(format_stats(md, st), file=out)
    if default_note:
        print(default_note, file=out)
    if report.path is None:
        print("(no --out given: the catalog was not saved)", file=out)
    elif report.status != "already complete":
        print(f"wrote {report.path} ({_size(report.path)})", file=out)
        for path in _side_files(report.path):
            print(f"wrote {path} ({_size(path)})", file=out)
    return EXIT_OK


def _check_kelvin(args):
    """Refuse ``--nu`` and ``--eta`` (the Carlson-Langer model's) with ``--model ofc``."""
    given = [f"--{name}" for name in ("nu", "eta") if getattr(args, name) is not None]
    if given and args.model == "ofc":
        raise InvalidParameterError(
            f"{' and '.join(given)} {'are' if len(given) > 1 else 'is'} the Carlson-Langer "
            "model's (the plate's velocity during events, the springs' viscous coupling): the "
            "OFC automaton (--model ofc) has neither; leave "
            f"{'them' if len(given) > 1 else 'it'} out"
        )


def _side_files(path):
    """The side tables written next to the catalog ``path`` (slips, per-fault slips)."""
    from faultnet.io.slips import SIDE_TABLES, side_path

    return [side_path(path, name) for name in SIDE_TABLES if os.path.isfile(side_path(path, name))]


def _print_run(args, report, elapsed, out):
    """The first lines of ``faultnet simulate``: what ran, how fast, with which parameters."""
    from faultnet.io.summary import kelvin_text

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
    if md.get("model") == "ofc":
        print(
            f"parameters  OFC automaton, k={md['k']} alpha={md.get('alpha')} "
            f"({md['update']} topplings) seed={md['seed_entropy']}",
            file=out,
        )
        return
    print(
        f"parameters  k={md['k']} sigma={md['sigma']} alpha={md['alpha']}{kelvin_text(md)} "
        f"seed={md['seed_entropy']}",
        file=out,
    )
    rtol = (md.get("options") or {}).get("rtol")
    print(
        f"numerics    {md['method']}, rtol={rtol if rtol is not None else 'none'}: "
        f"dt={md['dt']:.6g}, {md.get('crossings', 'exact')} crossings",
        file=out,
    )


def _fit_transient(args, report):
    """Events left out of the b fits, and the line that explains a default choice (or None).

    Without ``--transient`` the run recorded the events that its default rule left out
    (:func:`faultnet.io.summary.default_transient`), so ``faultnet info`` fits the same events.
    """
    md = report.metadata
    if args.transient is not None:
        return args.transient, None
    rule = md.get("transient_rule")
    note = f"transient   {rule} (--transient N to choose)" if rule else None
    return int(md.get("transient") or 0), note


def _stats_in_memory(report, transient, m_min, m_max):
    """``catalog_stats`` of a run without an output file, from its kept magnitudes."""
    import numpy as np

    from faultnet.io.summary import fit_b_values

    n = report.metadata["n_events"]
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
    st.update(fit_b_values(M[transient:], m_min=m_min, m_max=m_max))
    return st


def cmd_info(args, out):
    from faultnet.io.parquet import read_metadata
    from faultnet.io.summary import catalog_stats, format_metadata, format_stats
    from faultnet.runs.checkpoint import checkpoint_status

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
    for side in _side_files(path):
        what = "per-fault slips" if side.endswith(".fault_slips.parquet") else "per-block slips"
        print(f"{'slips':12}{side} ({what}, {_size(side)}; faultnet.read_slips)", file=out)
    return EXIT_OK


def _check_csv(path, force):
    """Refuse ``--csv`` before any work: a name not ending in .csv, or a file there without
    ``--force``."""
    if path is None:
        return
    if not path.endswith(".csv"):
        raise InvalidParameterError(f"--csv must name a .csv file; got {path!r}")
    if os.path.exists(path) and not force:
        raise OutputExistsError(f"{path} exists; refusing to overwrite it (use --force)")


def _write_csv(table, path, force):
    from faultnet.io.atomic import atomic_path

    _check_csv(path, force)
    with atomic_path(path) as tmp:
        table.to_csv(tmp, index=False)


_SHOW = [
    "point",
    "graph",
    "n_blocks",
    "k",
    "sigma",
    "alpha",
    "nu",
    "eta",
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

    show = list(_SHOW)
    if "model" in table and (table["model"] == "ofc").any():  # the automaton: no friction
        show[show.index("graph") + 1 : show.index("graph") + 1] = ["model"]
        show.remove("sigma")
    for name in ("nu", "eta"):  # shown where some point has them
        if name not in table or not (table[name].notna() & (table[name] != 0)).any():
            show.remove(name)
    shown = table[show].copy()
    with pd.option_context(
        "display.max_rows", None, "display.width", 200, "display.max_colwidth", 40
    ):
        print(shown.to_string(index=False, float_format=lambda x: f"{x:.4g}"), file=out)


def cmd_sweep(args, out):
    from faultnet.runs.sweep.driver import sweep

    if args.scheduler and args.workers:
        raise InvalidParameterError("give either --workers or --scheduler, not both")
    _check_csv(args.csv, args.force)

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
    from faultnet.runs.sweep.driver import summarize

    _check_csv(args.csv, args.force)
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
