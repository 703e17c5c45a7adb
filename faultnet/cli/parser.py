"""The ``faultnet`` argument parser: commands, options, their types and help texts.

:func:`build_parser` is what :func:`faultnet.cli.commands.main` parses with (and what
the documentation prints); :func:`run_options_from_args` turns the run-option
flags into a :class:`faultnet.RunOptions`.  The commands themselves are in
:mod:`faultnet.cli.commands`.
"""

from __future__ import annotations

import argparse
import math

from faultnet._version import __version__

__all__ = ["build_parser", "run_options_from_args"]


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
  chain:N[:reach=R][:kc=K] | ring:N[:reach=R][:kc=K] (springs to the R nearest
  neighbours on each side, each k_c/2R with kc) | square:RxC[:periodic|:fixed] |
  triangular:RxC[:periodic|:fixed]
  percolation:square|triangular:RxC[:periodic]:p=P|pc[:largest|:all][:prune][:seed=S]
  a GraphML (.graphml) or node-link JSON (.json) file; graph attributes k, sigma,
  alpha set the defaults, edge k/eta and node sigma/alpha set single springs / blocks.

The catalog is written in chunks and checkpointed; after a kill, the same
command with --resume continues from the last checkpoint, and the catalog is
the same, bit for bit, as an uninterrupted run with the same seed.

examples:
  faultnet simulate ring:2000 --alpha 2 --events 1e6 --seed 1 --out ring.parquet
  faultnet simulate ring:2000 --nu 1e-4 --eta 0.1 --events 1e5 --out viscous.parquet
  faultnet simulate percolation:square:150x150:p=0.5927 --events 1e6 --out perc.parquet
  faultnet simulate --resume --out ring.parquet      # continue a killed run
  faultnet simulate --continue --out ring.parquet -n 200000   # extend a finished run
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
  # nu = [0.0, 0.01]; eta = 0.1   (the plate during events, viscous springs; default 0)
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
    """The ``faultnet`` argument parser: one subcommand per command of the command line."""
    parser = argparse.ArgumentParser(
        prog="faultnet",
        formatter_class=_Formatter,
        description="Carlson-Langer block-spring earthquake models on networks.",
        epilog="run 'faultnet COMMAND --help' for the options and examples of a command",
    )
    parser.add_argument("--version", action="version", version=f"faultnet {__version__}")
    sub = parser.add_subparsers(dest="command", metavar="COMMAND")
    sub.required = True
    _add_simulate(sub)
    _add_info(sub)
    _add_sweep(sub)
    _add_summarize(sub)
    return parser


def _add_simulate(sub):
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
    p.add_argument("--nu", type=_finite, help="plate velocity >= 0 during events (default 0)")
    p.add_argument("--eta", type=_finite, help="viscous coupling >= 0 of springs (default 0)")
    p.add_argument(
        "--seed",
        type=_nonneg_int,
        help="seed of the initial state (and of percolation disorder); default: "
        "fresh entropy, recorded in the catalog",
    )
    p.add_argument("--dt", type=_finite, help="integration step (default: faultnet.default_dt)")
    p.add_argument(
        "--model",
        choices=("carlson-langer", "ofc"),
        default=None,
        help="the model: the Carlson-Langer blocks (default) or the OFC automaton, which takes "
        "--k or --ofc-alpha (its conservation, alpha = k / (q k + 1)) and no friction",
    )
    p.add_argument(
        "--ofc-alpha",
        type=_finite,
        default=None,
        metavar="ALPHA",
        help="OFC only: the conservation parameter (0.2 on a fixed square lattice with k = 1)",
    )
    _run_option_flags(p)
    _output_flags(p)
    _fit_options(p)
    _progress_flag(p)


def _output_flags(p):
    """--out, --transient, --chunk, --checkpoint-every, --record-slips, --resume and --force of
    simulate."""
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
        "before plate time 2; for --model ofc, before the drive 20 sqrt(N))",
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
        "--record-slips",
        action="store_true",
        default=None,
        help="also write the per-block slips of every event next to --out "
        "(FILE.slips.parquet; read them with faultnet.read_slips)",
    )
    p.add_argument(
        "--resume", action="store_true", help="continue the interrupted run of --out (or start it)"
    )
    p.add_argument(
        "--continue",
        dest="extend",
        action="store_true",
        help="extend the finished catalog --out to --events N events (as one longer run)",
    )
    p.add_argument(
        "--force", action="store_true", help="replace an existing --out or discard its checkpoint"
    )


def _add_info(sub):
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


def _add_sweep(sub):
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
    p.add_argument("--csv", metavar="FILE", help="also write the summary table to this .csv file")
    _progress_flag(p)
    p.add_argument("--quiet", "-q", action="store_true", help="print only errors")


def _add_summarize(sub):
    p = sub.add_parser(
        "summarize",
        help="table of a sweep's points",
        description=SUMMARIZE_HELP,
        formatter_class=_Formatter,
    )
    p.add_argument("folder", metavar="DIR", help="sweep output folder (or a folder of catalogs)")
    p.add_argument("--csv", metavar="FILE", help="write the table to this .csv file")
    p.add_argument("--force", action="store_true", help="overwrite an existing --csv file")
    p.add_argument(
        "--transient",
        type=_nonneg_int,
        default=None,
        metavar="N",
        help="events left out of the b fits (default: the sweep's)",
    )
    _fit_options(p)


def _progress_flag(p):
    p.add_argument(
        "--progress",
        action=argparse.BooleanOptionalAction,
        default=None,
        help="progress bar (default: on a terminal)",
    )


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


def _run_option_flags(p):
    g = p.add_argument_group("run options (faultnet.RunOptions; default: as recorded on --resume)")
    g.add_argument("--method", metavar="{dopri5}", help="scheme inside events (dopri5)")
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
        help=argparse.SUPPRESS,
    )
    # removed: RunOptions answers these with what to use instead
    g.add_argument("--local-regions-from", help=argparse.SUPPRESS)
    g.add_argument("--max-event-duration", type=_finite, metavar="T", help="guard (1e4)")
    g.add_argument("--max-velocity", type=_finite, metavar="V", help="guard (1e3)")


def run_options_from_args(args):
    """The RunOptions the flags ask for, or None when no run-option flag is given."""
    from faultnet.solver.options import RunOptions

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
