"""A second process that compiles kernels while the first ``simulate`` call compiles them too.

With an empty Numba cache the first ``simulate`` call compiles some 40 kernels one after the
other, depth first from the entry kernel (25-30 s on one core of the reference machine).
Where a second core is free, :func:`start` launches a helper process that compiles part of
the same (kernel, signature) list: each process writes what it compiled to the on-disk cache
and first looks there before compiling (Numba's ``cache=True``), so the main process loads
what the helper finished instead of compiling it.  The main process keeps the *spine*: the
few big kernels on its own path (the entry, ``_integrate``, ``dopri_step``), which it reaches
through the entry's typing before the helper could finish them.  The helper goes through the
rest of the list in the main process's order (:func:`helper_order`), keeping ahead of it while
the main process compiles a spine kernel.  Nothing else is shared: if the helper cannot
start, dies or falls behind, the main process compiles everything itself, as without it; it is
stopped as soon as the main process has its kernel.

The list (:data:`faultnet._compile_order.ORDER`) is what a cold compile of the default scheme
does, recorded by ``python -m faultnet._compile_helper --record``;
``tests/test_compile_helper.py`` checks that it is current.  ``FAULTNET_COMPILE_HELPER=0``
turns the helper off (sweep workers do: they are one process per core already).
"""

from __future__ import annotations

import atexit
import importlib
import os
import subprocess
import sys

from faultnet._system import usable_cores

__all__ = [
    "ENV",
    "SPINE_SHARE",
    "SPINE_START",
    "cache_is_cold",
    "helper_order",
    "record",
    "start",
    "stop",
]

#: set to "0" to never start the helper
ENV = "FAULTNET_COMPILE_HELPER"
_PKG = "faultnet._kernels."
#: a kernel whose own compile takes this share of the whole is left to the main process ...
SPINE_SHARE = 0.08
#: ... if the main process starts it within this share of the compile's span (``dopri_step``,
#: ``_integrate``; ``land`` starts half-way: the helper has it by then)
SPINE_START = 0.4
_proc = None
#: whether this process ever started a helper (for tests and benchmarks)
_launched = False


def _types():
    from numba import types

    f8, i8 = types.float64, types.int64
    return {
        "f8": f8,
        "i8": i8,
        "b1": types.boolean,
        "f8[::1]": types.Array(f8, 1, "C"),
        "f8[:,::1]": types.Array(f8, 2, "C"),
        "i8[::1]": types.Array(i8, 1, "C"),
        "i8[:,::1]": types.Array(i8, 2, "C"),
        "lit0": types.literal(0),
        "lit1": types.literal(1),
    }


def _token(ty, table):
    for tok, known in table.items():
        if ty == known and type(ty) is type(known):
            return tok
    raise ValueError(f"no token for the kernel argument type {ty!r}; add it to _types()")


def cache_is_cold(dispatcher):
    """True if the on-disk cache holds nothing for ``dispatcher`` (internals: any doubt, False).

    An index written by other source code (an upgraded faultnet) counts as empty: Numba's
    index check compares the source file's stamp.
    """
    try:
        return not dispatcher._cache._cache_file._load_index()
    except Exception:  # noqa: BLE001 - a Numba internal moved (or JIT is off): not cold
        return False


def start(entry):
    """Start the helper if ``entry`` (an entry kernel) is about to compile from a cold cache."""
    global _proc, _launched
    if _proc is not None or os.environ.get(ENV, "1") == "0" or usable_cores() < 2:
        return
    from faultnet import _compile_order

    name = getattr(getattr(entry, "py_func", None), "__name__", None)  # None: JIT disabled
    if name != _compile_order.ENTRY or not cache_is_cold(entry):
        return
    env = dict(os.environ, **{ENV: "0"})
    try:
        _proc = subprocess.Popen(
            [sys.executable, "-c", _BOOT.format(path=os.path.dirname(__file__))],
            stdin=subprocess.DEVNULL,
            stdout=subprocess.DEVNULL,
            stderr=subprocess.DEVNULL,
            env=env,
        )
    except OSError:
        return
    _launched = True
    atexit.register(stop)


def stop():
    """Stop the helper (the main process has compiled everything it needs)."""
    global _proc
    proc, _proc = _proc, None
    if proc is not None and proc.poll() is None:
        proc.kill()
        proc.wait()


def helper_order(order):
    """The helper's share of ``order`` (callees before callers), in the helper's order.

    Front to back, without the spine kernels (the main process's): while the main process
    compiles ``dopri_step`` (3-4 s) the helper gets ahead of it, and the main process then
    loads the region code and the landing instead of compiling them (a first call of 21-22 s
    against 29-32 s when the helper took the rest of the list from the back and reached the
    landing and the region code too late).
    """
    return [row for row in order if not row[3]]


#: the helper's start: the kernel modules without ``faultnet/__init__`` (pandas and the rest
#: of the Python layer would delay the helper's first compile by 0.6 s)
_BOOT = """
import sys, types
pkg = types.ModuleType("faultnet")
pkg.__path__ = [{path!r}]
sys.modules["faultnet"] = pkg
from faultnet import _compile_helper
_compile_helper._compile_all()
"""


def _compile_all():
    """The helper's job: compile its share of :data:`ORDER`."""
    from faultnet._compile_order import ORDER

    table = _types()
    for module, name, sig, _ in helper_order(ORDER):
        dispatcher = getattr(importlib.import_module(_PKG + module), name)
        dispatcher.compile(tuple(table[t] for t in sig))


_RECORDER = """
import json, time, faultnet
from numba.core import event
from faultnet import _compile_helper as h
done, stack, table = [], [], h._types()
t00 = time.perf_counter()
class L(event.Listener):
    def on_start(self, e):
        stack.append([time.perf_counter(), 0.0])
    def on_end(self, e):
        start = stack[-1][0] - t00
        t0, inner = stack.pop()
        total = time.perf_counter() - t0
        if stack:
            stack[-1][1] += total
        d = e.data["dispatcher"]; f = d.py_func; mod = f.__module__
        m = __import__(mod, fromlist=["_"])
        if mod.startswith(h._PKG) and getattr(m, f.__name__, None) is d:
            sig = [h._token(t, table) for t in e.data["args"]]
            done.append((mod[len(h._PKG):], f.__name__, sig, total - inner, start))
event.register("numba:compile", L())
m = faultnet.CarlsonLanger(faultnet.graphs.ring(10))
faultnet.simulate(m, 1, rng=1, progress=False)
print(json.dumps(done))
"""


def record(path=None):
    """Rewrite ``_compile_order.py`` from a cold compile of one simulate call (a subprocess).

    The kernels are listed in the order their compilation *ends* (callees before callers), so
    the helper, going front to back, always finds a kernel's callees compiled.  A kernel whose
    own compile (callees excluded) takes at least :data:`SPINE_SHARE` of the whole, and whose
    compile starts within :data:`SPINE_START` of the span, is marked ``spine``: the main
    process is bound to compile it itself (it reaches it early, through the entry kernel's
    typing), so the helper leaves it alone.
    """
    import json
    import tempfile

    with tempfile.TemporaryDirectory() as cache:
        env = dict(os.environ, NUMBA_CACHE_DIR=cache, **{ENV: "0"})
        out = subprocess.check_output([sys.executable, "-c", _RECORDER], env=env)
    done = json.loads(out.decode().strip().splitlines()[-1])
    entry = next(row for row in done if row[1].startswith("run_events"))
    total = sum(row[3] for row in done)
    t0 = min(row[4] for row in done)
    span = max(row[4] for row in done) - t0  # to the last kernel's start
    order = [
        (mod, name, tuple(sig), excl >= SPINE_SHARE * total and start - t0 <= SPINE_START * span)
        for mod, name, sig, excl, start in done
        if name != entry[1]
    ]
    path = path or os.path.join(os.path.dirname(__file__), "_compile_order.py")
    lines = [
        '"""What a cold compile of the default scheme compiles, in order (generated: do not edit).',
        "",
        "(module, kernel, argument types, spine), callees before callers; regenerate with",
        "``python -m faultnet._compile_helper --record`` after changing kernels (a test fails",
        "while this list is stale).",
        '"""',
        "",
        '__all__ = ["ENTRY", "ORDER"]',
        "",
        f"ENTRY = {entry[1]!r}",
        "ORDER = [",
        *(f"    {row!r}," for row in order),
        "]",
        "",
    ]
    with open(path, "w") as fh:
        fh.write("\n".join(lines))
    return order


if __name__ == "__main__":
    if sys.argv[1:] != ["--record"]:
        raise SystemExit("usage: python -m faultnet._compile_helper --record")
    print(f"{len(record())} kernel signatures recorded")
