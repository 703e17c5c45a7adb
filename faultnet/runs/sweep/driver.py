"""Parameter sweeps: a grid of runs, one Parquet catalog per point.

A sweep is the product of its parameter lists, times ``replicas`` (the
configuration: :mod:`faultnet.runs.sweep.config`).  Each *point* is a pure task --
its configuration plus the child ``SeedSequence(seed, spawn_key=(index,))``
of the sweep's seed -- that writes its own catalog (``part-00007.parquet``
for point 7, see :mod:`faultnet.runs.sweep.folder`), checkpointed like a long
``faultnet simulate`` (see :mod:`faultnet.runs.long_run`).  Rerunning a sweep skips
the finished points, resumes interrupted ones and recomputes missing or
corrupt ones (a truncated file, say).  Points run on local processes (every
core by default), on any :class:`concurrent.futures.Executor`, or on a Dask
cluster (``scheduler="tcp://HOST:PORT"``; the output folder must then be on
a file system every worker sees).  Changing a parameter that defines the
points (anything but transient, chunk, checkpoint_interval, m_min, m_max
and out) in a folder that holds a sweep is refused unless forced.

>>> import faultnet, tempfile
>>> from faultnet.runs.sweep.driver import sweep
>>> table = sweep(graph="ring:30", alpha=[1.0, 2.0], events=200, seed=1,
...               out=tempfile.mkdtemp(), workers=1, progress=False)
>>> table[["point", "alpha", "events", "status"]].to_string(index=False)
' point  alpha  events status\\n     0    1.0     200   done\\n     1    2.0     200   done'
"""

from __future__ import annotations

import concurrent.futures as cf
import contextlib
import os
from concurrent.futures.process import BrokenProcessPool

import numpy as np
import pandas as pd
from tqdm.auto import tqdm

from faultnet.exceptions import (
    CatalogError,
    ConfigError,
    InvalidParameterError,
    OutputExistsError,
    SweepError,
)
from faultnet.io.lock import output_lock
from faultnet.runs.sweep.config import SweepConfig, as_config, load_config
from faultnet.runs.sweep.folder import SWEEP_LOCK, point_file_name, point_state, prepare_out
from faultnet.runs.sweep.summary import failed_row, point_row, summarize, summary_table

#: a point whose worker process dies this many times fails (the others are run again)
MAX_LOSSES = 3

__all__ = [
    "ConfigError",
    "SweepConfig",
    "SweepError",
    "load_config",
    "run_point",
    "summarize",
    "sweep",
]


def run_point(
    point,
    path,
    transient=0,
    chunk=100_000,
    checkpoint_interval=60.0,
    m_min=None,
    m_max=None,
    *,
    on_commit=None,
):
    """Run one sweep point into ``path`` (resuming its checkpoint) and return its summary row.

    A pure task: the result depends only on ``point`` (its parameters and
    seed), never on where or when it runs.  ``on_commit`` is passed to
    :func:`~faultnet.runs.long_run.simulate_to_parquet` (called after each committed chunk).
    """
    from faultnet.runs.spec_run import run_from_spec

    seq = np.random.SeedSequence(point["seed_entropy"], spawn_key=tuple(point["spawn_key"]))
    run_from_spec(
        point["graph"],
        point["events"],
        path,
        k=point["k"],
        sigma=point["sigma"],
        alpha=point["alpha"],
        dt=point["dt"],
        model=point.get("model"),
        ofc_alpha=point.get("ofc_alpha"),
        nu=point.get("nu"),
        eta=point.get("eta"),
        options=point.get("options"),
        seed=seq,
        chunk_events=chunk,
        checkpoint_interval=checkpoint_interval,
        transient=transient,
        resume=True,
        progress=False,
        extra={"sweep_point": point},
        on_commit=on_commit,
    )
    return point_row(point, path, transient, m_min, m_max)


# --------------------------------------------------------------------------- executors


class SerialExecutor(cf.Executor):
    """Runs each task at submission, in this process (``workers=1``)."""

    def submit(self, fn, /, *args, **kwargs):
        fut = cf.Future()
        try:
            fut.set_result(fn(*args, **kwargs))
        except BaseException as exc:  # noqa: B036 - handed to the future like a real executor
            if isinstance(exc, (KeyboardInterrupt, SystemExit)):
                raise
            fut.set_exception(exc)
        return fut


def _local_pool(workers):
    import multiprocessing as mp

    method = "forkserver" if "forkserver" in mp.get_all_start_methods() else "spawn"
    ctx = mp.get_context(method)
    if method == "forkserver":
        ctx.set_forkserver_preload(["faultnet.runs.sweep.driver"])
    return cf.ProcessPoolExecutor(
        max_workers=workers, mp_context=ctx, initializer=_init_worker, initargs=(os.getpid(),)
    )


def _usable_cores():
    """Cores this process may run on (its CPU affinity where the OS tells), at least 1."""
    try:
        return max(1, len(os.sched_getaffinity(0)))
    except (AttributeError, OSError):
        return os.cpu_count() or 1


def _init_worker(sweep_pid):
    """Set up a pool worker: exit when the sweep's process dies.

    A thread watches the sweep's process (and the
    worker's own parent): when either is gone, the worker exits at once
    instead of writing on as an orphan.  Its chunk and checkpoint writes are
    atomic, and its lock is stale once it is gone, so a rerun resumes.
    """
    import threading
    import time

    from faultnet.io.lock import alive

    parent = os.getppid()

    def watch():
        while os.getppid() == parent and alive(sweep_pid):
            time.sleep(0.2)
        os._exit(1)

    threading.Thread(target=watch, name="faultnet-orphan-watch", daemon=True).start()


class LocalPool:
    """Local worker processes, replaced by a fresh pool when one of them dies.

    A worker killed from outside (SIGKILL, the OOM killer) breaks a
    :class:`~concurrent.futures.ProcessPoolExecutor`: every point it had not finished fails
    with ``BrokenProcessPool``, also those that never started.  :func:`_run_points` runs
    such lost points again on :meth:`renew`'s fresh pool; they resume their checkpoints.
    """

    def __init__(self, workers):
        self.workers = workers
        self.executor = _local_pool(workers)

    def renew(self):
        """Shut the broken pool down and start a fresh one; return it."""
        self.executor.shutdown(wait=False, cancel_futures=True)
        self.executor = _local_pool(self.workers)
        return self.executor

    def stop(self):
        """Stop the workers now, as Ctrl-C on a terminal does (their writes are atomic)."""
        for proc in list((getattr(self.executor, "_processes", None) or {}).values()):
            with contextlib.suppress(OSError, AttributeError):
                proc.terminate()
        self.executor.shutdown(wait=False, cancel_futures=True)


@contextlib.contextmanager
def _executor(executor, scheduler, workers, n_tasks):
    """``(executor, where, renew)``: ``renew`` gives a fresh local pool (None elsewhere)."""
    if executor is not None:
        yield executor, "the given executor", None
        return
    if scheduler is not None:
        try:
            from distributed import Client
        except ImportError:  # pragma: no cover
            raise InvalidParameterError(
                "scheduler= needs Dask: pip install 'dask[distributed]'"
            ) from None
        client = Client(scheduler)
        try:
            yield client.get_executor(pure=False), f"Dask scheduler {scheduler}", None
        finally:
            client.close()
        return
    n = workers if workers is not None else _usable_cores()
    n = max(1, min(int(n), n_tasks))
    if n == 1:
        yield SerialExecutor(), "this process", None
        return
    pool = LocalPool(n)
    try:
        yield pool.executor, f"{n} local processes", pool.renew
    except BaseException:
        pool.stop()  # interrupted (Ctrl-C, SIGTERM) or failed: a rerun resumes the points
        raise
    pool.executor.shutdown(wait=True, cancel_futures=True)


def sweep(
    config=None,
    out=None,
    *,
    executor=None,
    scheduler=None,
    workers=None,
    force=False,
    progress=None,
    log=None,
    **params,
) -> pd.DataFrame:
    """Run a parameter sweep; return the summary table (one row per point).

    Parameters
    ----------
    config : path, dict, SweepConfig or None
        A sweep TOML file, a ``[sweep]`` table as a dict, or None to give the
        keys as keyword arguments (``graph=..., alpha=[...], events=...``).
    out : path, optional
        Output folder (default: the config's ``out``; for a TOML file, a
        folder named after it next to it).
    executor : concurrent.futures.Executor, optional
        Where to run the points, e.g. ``distributed.Client(...).get_executor()``.
    scheduler : str, optional
        Address of a Dask scheduler (``tcp://HOST:PORT``), instead of ``executor``.
    workers : int, optional
        Local processes (default: every core; 1 runs in this process).
    force : bool
        Write into a folder that holds foreign files or another sweep,
        recomputing the points whose settings changed.
    progress : bool or None
        Progress bar over points (None: on a terminal).
    log : callable, optional
        Called with one line per notable step (skipped / recomputed points).
    **params
        Keys of the ``[sweep]`` table, overriding ``config``.

    Returns
    -------
    pandas.DataFrame
        :func:`summarize`'s table.  ``attrs["out"]`` is the folder.

    Raises
    ------
    ConfigError
        For a malformed configuration (naming the field and allowed values).
    SweepError
        If points failed; the finished points are kept and a rerun retries the rest.
    """
    if executor is not None and scheduler is not None:
        raise InvalidParameterError("give either executor= or scheduler=, not both")
    cfg = as_config(config, params)
    out = os.fspath(out) if out is not None else cfg.out
    if out is None:
        raise ConfigError("sweep needs an output folder: out=... (or sweep.out in the config)")
    log = log or (lambda msg: None)
    if not os.path.isdir(out):
        if os.path.exists(out):
            raise OutputExistsError(f"sweep output {out} exists and is not a folder")
        os.makedirs(out, exist_ok=True)
    with output_lock(os.path.join(out, SWEEP_LOCK), what=f"sweep folder {out}"):
        return _sweep_locked(cfg, out, executor, scheduler, workers, force, progress, log)


def _sweep_locked(cfg, out, executor, scheduler, workers, force, progress, log):
    """The body of :func:`sweep`, run while holding the folder's lock."""
    cfg = prepare_out(cfg, out, force)
    n_points = len(cfg.points())
    rows, todo = _plan(cfg, out, force, log)
    failures = []
    if todo:
        with _executor(executor, scheduler, workers, len(todo)) as (ex, where, renew):
            log(f"running {len(todo)} points on {where}")
            failures = _run_points(ex, renew, cfg, todo, rows, n_points, progress, log)
    table = summary_table([rows[i] for i in sorted(rows)])
    table.attrs["out"] = out
    if failures:
        first = "; ".join(
            f"point {p['index']} ({p['graph']}, alpha={p['alpha']}): {type(e).__name__}: {e}"
            for p, e in failures[:3]
        )
        raise SweepError(
            f"{len(failures)} of {n_points} points failed: {first}. The finished "
            f"points are kept in {out}; rerun to retry the rest",
            summary=table,
        )
    return table


def _plan(cfg, out, force, log):
    """Summary rows of the finished points, and the ``(point, path)`` pairs still to run."""
    points = cfg.points()
    rows, todo = {}, []
    for point in points:
        path = os.path.join(out, point_file_name(point["index"], len(points)))
        state, why = point_state(point, path, force)
        if state == "done":
            try:
                rows[point["index"]] = point_row(point, path, cfg.transient, cfg.m_min, cfg.m_max)
                continue
            except CatalogError:
                os.remove(path)
                why = "corrupt"
        if why in ("corrupt", "stale", "resume"):
            log(
                f"point {point['index']}: {'resuming' if why == 'resume' else 'recomputing'} "
                f"{os.path.basename(path)} ({why})"
            )
        todo.append((point, path))
    if rows:
        log(f"{len(rows)} of {len(points)} points already done; skipping them")
    return rows, todo


def _run_points(ex, renew, cfg, todo, rows, n_points, progress, log):
    """Run the ``todo`` points on ``ex``, filling ``rows``; return the ``(point, exc)`` failures.

    Where a worker process dies (``BrokenProcessPool``) and ``renew`` gives a fresh pool, the
    points lost with it run again there, each at most :data:`MAX_LOSSES` times in all: only a
    point that keeps killing its worker fails, and the others run to the end.
    """
    settings = (cfg.transient, cfg.chunk, cfg.checkpoint_interval, cfg.m_min, cfg.m_max)
    failures, losses = [], {}
    with tqdm(
        total=n_points,
        initial=len(rows),
        unit="pt",
        desc="sweep",
        disable=(None if progress is None else not progress),
    ) as bar:
        while todo:
            futures = {
                ex.submit(run_point, point, os.path.abspath(path), *settings): (point, path)
                for point, path in todo
            }
            todo = []
            for fut in cf.as_completed(futures):
                point, path = futures[fut]
                try:
                    rows[point["index"]] = fut.result()
                except BrokenProcessPool as exc:
                    losses[point["index"]] = losses.get(point["index"], 0) + 1
                    if renew is not None and losses[point["index"]] < MAX_LOSSES:
                        todo.append((point, path))
                        continue
                    exc = SweepError(
                        f"a worker process died while running it, {losses[point['index']]} "
                        f"time(s) (killed by a signal or out of memory?): {exc}"
                    )
                    failures.append((point, exc))
                    rows[point["index"]] = failed_row(point, path, exc)
                    log(f"point {point['index']} failed: {exc}")
                except Exception as exc:  # a failed point must not stop the others
                    failures.append((point, exc))
                    rows[point["index"]] = failed_row(point, path, exc)
                    log(f"point {point['index']} failed: {type(exc).__name__}: {exc}")
                bar.update(1)
            if todo:
                log(f"a worker process died; running its {len(todo)} lost points on a fresh pool")
                ex = renew()
    return failures
