"""Statistics and text summaries of catalog files: b-value fits, ranges, formatting.

:func:`catalog_stats` streams a Parquet catalog (see :mod:`faultnet.io.parquet`) one
row group at a time, so memory stays O(chunk) whatever the catalog's length;
:func:`format_stats` and :func:`format_metadata` turn its output and the
run's metadata into the lines that ``faultnet info`` prints.

>>> import faultnet, tempfile, os
>>> from faultnet.io.parquet import write_catalog
>>> res = faultnet.simulate(faultnet.CarlsonLanger(faultnet.graphs.ring(20)), 300, rng=3,
...                         progress=False)
>>> path = os.path.join(tempfile.mkdtemp(), "cat.parquet")
>>> _ = write_catalog(res, path)
>>> st = catalog_stats(path, transient=100)
>>> st["events"], st["events_fit"], st["fit_step"]
(300, 200, 1)
"""

from __future__ import annotations

import math

import numpy as np
import pyarrow as pa
import pyarrow.parquet as pq

from faultnet import stats
from faultnet.exceptions import CatalogError, FaultnetError
from faultnet.io.catalog_file import (
    STATS_COLUMNS,
    check_event_count,
    check_event_numbers,
    open_catalog_file,
)

__all__ = [
    "MAX_FIT_EVENTS",
    "catalog_stats",
    "default_transient",
    "fit_b_values",
    "format_metadata",
    "kelvin_text",
    "format_stats",
    "read_magnitudes",
]

#: magnitudes beyond this many are thinned (every k-th event) for b fits
MAX_FIT_EVENTS = 2_000_000
#: plate time before which ``faultnet simulate`` leaves events out of its b fits by
#: default: the plate has moved twice the slip threshold, so on average every block
#: has slipped about twice and the random initial state is forgotten
TRANSIENT_PLATE_TIME = 2.0
#: default upper end of the least-squares window: this quantile of M above m_min
#: (the largest 1% of events, too few per bin and where finite-size humps sit, stay out)
LSQ_TOP_QUANTILE = 0.99


def _row_groups(pf, columns):
    """Yield one row group at a time as a Table.

    ``ParquetFile.iter_batches`` keeps read-ahead buffers that grew the
    resident memory of a 10^7-event summary to ~0.8 GB; reading row groups
    one by one (each at most one writer chunk) stays O(chunk).
    """
    for i in range(pf.metadata.num_row_groups):
        yield pf.read_row_group(i, columns=columns)


def _fit_step(n, skip, max_n):
    """Every how many events the fits keep, of the ``n - skip`` after the transient."""
    remaining = max(n - int(skip), 0)
    return max(1, math.ceil(remaining / max_n)) if max_n else 1


def _kept(m, start, skip, step):
    """The rows ``r >= skip`` with ``(r - skip) % step == 0`` of a batch that starts at row
    ``start`` (None if it ends before ``skip``)."""
    if start + len(m) <= skip:
        return None
    first = max(skip, start)
    offset = (-(first - skip)) % step
    return m[first - start + offset :: step].astype(np.float64, copy=True)


def read_magnitudes(path, skip=0, max_n=MAX_FIT_EVENTS):
    """Magnitudes ``M`` of a catalog after its first ``skip`` rows, streamed.

    Returns ``(M, step)``: when more than ``max_n`` remain, every ``step``-th
    event is kept so that memory stays bounded.
    """
    path, _ = open_catalog_file(path, ["M"])
    pf = pq.ParquetFile(path)
    step = _fit_step(pf.metadata.num_rows, skip, max_n)
    out, row = [], 0
    try:
        for batch in _row_groups(pf, ["M"]):
            m = batch.column(0).to_numpy()
            kept = _kept(m, row, int(skip), step)
            row += len(m)
            if kept is not None:
                out.append(kept)
    except (OSError, pa.ArrowException) as exc:
        raise CatalogError(f"cannot read magnitudes of {path}: {exc}") from exc
    return (np.concatenate(out) if out else np.zeros(0)), step


def events_before(path, t):
    """Number of events of a catalog file whose plate time is below ``t``, streamed."""
    path, _ = open_catalog_file(path, ["t"])
    count = 0
    try:
        for batch in _row_groups(pq.ParquetFile(path), ["t"]):
            times = batch.column(0).to_numpy()
            count += int(np.searchsorted(times, t))
            if len(times) and times[-1] >= t:
                break
    except (OSError, pa.ArrowException) as exc:
        raise CatalogError(f"cannot read catalog {path}: {exc}") from exc
    return count


def default_transient(times, n_events, t_min=TRANSIENT_PLATE_TIME, what="plate time"):
    """``(transient, rule)``: the events before ``t_min`` (:data:`TRANSIENT_PLATE_TIME`, or an
    automaton's drive) among the ``times`` (an iterable of sorted arrays, the run's in order),
    at most half of ``n_events``; ``rule`` is the sentence that says which applied, naming
    the time as ``what``."""
    count = 0
    for t in times:
        t = np.asarray(t)
        count += int(np.searchsorted(t, t_min))
        if len(t) and t[-1] >= t_min:
            break
    if count > n_events // 2:  # a short run: fit its second half
        return n_events // 2, (
            f"the first half of the run ({n_events // 2:,} events) is left out of the fits: "
            f"the run ends before {what} {t_min:g}, so it may not be in a steady state yet"
        )
    return count, f"the {count:,} events before {what} {t_min:g} are left out of the fits"


def fit_b_values(M, m_min=None, m_max=None) -> dict:
    """Both b-value fits of magnitudes ``M`` (non-finite values dropped).

    The MLE (:func:`faultnet.stats.fit_b_mle`) uses ``M >= m_min``, by
    default the maximum-curvature completeness magnitude; the least-squares
    fit (:func:`faultnet.stats.fit_b_lsq`) uses the window ``[m_min, m_max]``,
    by default up to the largest magnitude.

    Returns a dict with ``b_mle``, ``b_mle_err``, ``m_min``, ``m_max``,
    ``n_fit``, ``b_lsq``, ``b_lsq_err`` (NaN where a fit was impossible, with
    the reason under ``fit_note``).
    """
    M = np.asarray(M, dtype=np.float64)
    M = M[np.isfinite(M)]
    nan = float("nan")
    out = {
        "b_mle": nan,
        "b_mle_err": nan,
        "m_min": nan,
        "m_max": nan,
        "n_fit": 0,
        "b_lsq": nan,
        "b_lsq_err": nan,
    }
    notes = []
    try:
        mle = stats.fit_b_mle(M, m_min=m_min)
    except (ValueError, FaultnetError, ZeroDivisionError, FloatingPointError) as exc:
        notes.append(f"MLE fit failed: {exc}")
    else:
        above = M[M >= mle.m_min]
        hi = float(np.quantile(above, LSQ_TOP_QUANTILE)) if m_max is None else float(m_max)
        out["window"] = (
            ("maximum curvature" if m_min is None else "--m-min")
            + " to "
            + (
                f"the {LSQ_TOP_QUANTILE * 100:.0f}th percentile of M above it"
                if m_max is None
                else "--m-max"
            )
        )
        out.update(
            b_mle=float(mle.b),
            b_mle_err=float(mle.b_err),
            m_min=float(mle.m_min),
            m_max=hi,
            n_fit=int(mle.n),
        )
        try:
            lsq = stats.fit_b_lsq(M, mle.m_min, hi)
        except (ValueError, FaultnetError, ZeroDivisionError, FloatingPointError) as exc:
            notes.append(f"LSQ fit failed: {exc}")
        else:
            out.update(b_lsq=float(lsq.b), b_lsq_err=float(lsq.b_err))
    if notes:
        out["fit_note"] = "; ".join(notes)
    return out


def catalog_stats(path, transient=None, m_min=None, m_max=None, max_n=MAX_FIT_EVENTS) -> dict:
    """Summary of a catalog file, read once, row group by row group.

    ``transient`` events at the start are left out of the fits (default:
    the ``transient`` recorded in the metadata, else 0).  Returns events,
    plate-time range, magnitude range, the largest event's blocks and the b
    fits of :func:`fit_b_values` (``m_min``, ``m_max``: its fit window) over
    at most ``max_n`` magnitudes (every ``fit_step``-th event beyond that).
    """
    path, md = open_catalog_file(path, STATS_COLUMNS)
    transient = int(md.get("transient") or 0) if transient is None else int(transient)
    pf = pq.ParquetFile(path)
    n = pf.metadata.num_rows
    check_event_count(path, md, n)
    step = _fit_step(n, transient, max_n)
    out = {"events": n, "transient": transient, "events_fit": max(n - transient, 0)}
    out.update(fit_step=step, t_first=float("nan"), t_last=float("nan"))
    out.update(M_min=math.inf, M_max=-math.inf, largest_n_blocks=0, sum_n_blocks=0)
    columns = ["t", "M", "n_blocks", "event"]
    if md.get("nu"):  # the events' durations, for plate_note (other catalogs may lack them)
        columns.append("duration")
        out["sum_duration"] = 0.0
    fits, seen, row = [], 0, 0
    try:
        for batch in _row_groups(pf, columns):
            if "n_events" in md:
                seen = check_event_numbers(path, md, batch.column(3).to_numpy(), seen)
            m = batch.column(1).to_numpy()
            kept = _kept(m, row, transient, step)
            row += len(m)
            duration = batch.column(4).to_numpy() if len(columns) > 4 else None
            _see(out, batch.column(0).to_numpy(), m, batch.column(2).to_numpy(), duration)
            if kept is not None:
                fits.append(kept)
    except (OSError, pa.ArrowException) as exc:
        raise CatalogError(f"cannot read catalog {path}: {exc}") from exc
    if not n:
        out.update(M_min=float("nan"), M_max=float("nan"))
    out.update(fit_b_values(np.concatenate(fits) if fits else np.zeros(0), m_min, m_max))
    return out


def _see(out, t, m, n_blocks, duration=None):
    """Fold one row group's plate times, magnitudes, sizes (and durations) into ``out``."""
    if len(t) == 0:
        return
    if math.isnan(out["t_first"]):
        out["t_first"] = float(t[0])
    out["t_last"] = float(t[-1])
    fin = m[np.isfinite(m)]
    if fin.size:
        out["M_min"] = min(out["M_min"], float(fin.min()))
        out["M_max"] = max(out["M_max"], float(fin.max()))
    out["largest_n_blocks"] = max(out["largest_n_blocks"], int(n_blocks.max()))
    out["sum_n_blocks"] += int(n_blocks.sum())
    if duration is not None:
        out["sum_duration"] += float(duration.sum())


def _fmt(x, spec=".3f"):
    return "nan" if x is None or (isinstance(x, float) and math.isnan(x)) else format(x, spec)


def format_stats(md, st) -> str:
    """Human-readable lines for :func:`catalog_stats` output."""
    lines = [
        f"events      {st['events']:,} (first {md.get('first_event', 0)}); "
        f"{'drive' if md.get('model') == 'ofc' else 'plate time'} "
        f"{_fmt(st['t_first'], '.6g')} .. {_fmt(st['t_last'], '.6g')}",
        f"magnitude   M = ln S in [{_fmt(st['M_min'])}, {_fmt(st['M_max'])}]; largest event "
        f"{st['largest_n_blocks']} blocks",
    ]
    fit_on = f"{st['events_fit']:,} events after a transient of {st['transient']:,}"
    if st.get("fit_step", 1) > 1:
        fit_on += f", every {st['fit_step']}th"
    lines.append(
        f"b (MLE)     {stats.format_pm(st['b_mle'], st['b_mle_err'])} for M >= {_fmt(st['m_min'])} "
        f"(n = {st['n_fit']:,}; {fit_on})"
    )
    window = f" ({st['window']})" if st.get("window") else ""
    lines.append(
        f"b (LSQ)     {stats.format_pm(st['b_lsq'], st['b_lsq_err'])} on "
        f"[{_fmt(st['m_min'])}, {_fmt(st['m_max'])}]{window}"
    )
    if st.get("fit_note"):
        lines.append(f"note        {st['fit_note']}")
    plate = plate_note(md, st)
    if plate:
        lines.append(f"note        {plate}")
    return "\n".join(lines)


#: the share of the plate's advance made during events above which :func:`plate_note` speaks
MERGED_SHARE = 0.9


def plate_note(md, st):
    """A line for a run whose plate moves during events (``nu``) and is nearly always inside one.

    The plate advances ``nu`` times an event's duration during it; when that is most of its
    advance (at least :data:`MERGED_SHARE`), the failures the plate brings on fall inside
    the event under way and join it: events merge into long, large ones.  That is the
    model's physics at such a ``nu`` (on a ring of 2000 at ``nu = 1e-3``, 576 blocks per
    event), not a slowdown of the engine, and the note says so.  None otherwise.

    >>> md = {"nu": 1e-3, "n_blocks": 2000}
    >>> st = {"events": 201, "t_first": 0.0, "t_last": 40.4, "sum_duration": 40400.0,
    ...       "sum_n_blocks": 115800}
    >>> print(plate_note(md, st))  # doctest: +NORMALIZE_WHITESPACE
    with nu = 0.001 the plate made 99.5% of its advance during events: the failures it brings
    on join the event under way, and events merge (576.1 of 2000 blocks on average); a
    smaller nu or a smaller system keeps them apart
    """
    nu, n = md.get("nu"), st.get("events", 0)
    if not nu or n < 2 or "sum_duration" not in st:
        return None
    travel = st["t_last"] - st["t_first"] + nu * st["sum_duration"] / n  # to the last one's end
    share = nu * st["sum_duration"] / travel if travel > 0 else 0.0
    if share < MERGED_SHARE:
        return None
    mean = st["sum_n_blocks"] / n
    return (
        f"with nu = {nu:g} the plate made {share:.1%} of its advance during events: the "
        "failures it brings on join the event under way, and events merge "
        f"({mean:.1f} of {md.get('n_blocks', '?')} blocks on average); a smaller nu or a "
        "smaller system keeps them apart"
    )


def kelvin_text(md) -> str:
    """`` nu=... eta=...`` of a run's metadata, each only where the run has it (not 0)."""
    parts = [f" {name}={md[name]}" for name in ("nu", "eta") if md.get(name) is not None]
    return "".join(parts) + (" (per-edge eta)" if md.get("eta_heterogeneous") else "")


def format_metadata(md) -> str:
    """Human-readable lines for a catalog's parameters and provenance."""
    lines = []
    graph = f"{md.get('graph')}"
    if md.get("graph_spec"):
        graph += f"  (spec {md['graph_spec']})"
    lines.append(f"graph       {graph}: {md.get('n_blocks')} blocks, {md.get('n_springs')} springs")
    if md.get("graph_hash"):
        lines.append(f"graph hash  sha256:{md['graph_hash']}")
    het = "  (per-edge/per-node values in the graph)" if md.get("heterogeneous") else ""
    if md.get("model") == "ofc":
        lines.append(
            f"parameters  OFC automaton, k={md.get('k')} alpha={md.get('alpha')} "
            f"({md.get('update')} topplings){het}"
        )
    else:
        lines.append(
            f"parameters  k={md.get('k')} sigma={md.get('sigma')} alpha={md.get('alpha')}"
            f"{kelvin_text(md)} dt={md.get('dt')}{het}"
        )
    seed = f"SeedSequence entropy {md.get('seed_entropy')}, spawn key {md.get('seed_spawn_key')}"
    if md.get("graph_seed_entropy") is not None:
        seed += (
            f"; graph disorder: entropy {md['graph_seed_entropy']}, spawn key "
            f"{md.get('graph_seed_spawn_key')}"
        )
    lines.append(f"seed        {seed}")
    prov = md.get("provenance") or {}
    extra = ", ".join(f"{k} {prov[k]}" for k in ("python", "numpy", "numba") if k in prov)
    lines.append(f"faultnet    {md.get('faultnet_version')}" + (f" ({extra})" if extra else ""))
    wall = md.get("wall_time_s")
    run = []
    if md.get("created"):
        run.append(f"started {md['created']}")
    if md.get("finished"):
        run.append(f"finished {md['finished']}")
    if wall:
        rate = f" = {md.get('n_events', 0) / wall:,.0f} events/s" if md.get("n_events") else ""
        run.append(f"{wall:.2f} s simulating{rate}")
    runs = md.get("runs", md.get("sessions", 1))  # "sessions" in catalogs of faultnet 0.2
    if runs > 1:
        run.append(f"written in {runs} runs (resumed {runs - 1} times)")
    if run:
        lines.append("run         " + "; ".join(run))
    return "\n".join(lines)
