"""The decorators of the kernels.

Every kernel is compiled without Numba's reference counting (``_nrt=False``:
no allocation happens inside them) and releases the GIL.  Only the entry kernels
(:mod:`faultnet._kernels.events`) are called from Python; the others are built without the
Python and C wrappers (``no_cpython_wrapper``), which saves compile time, and so can be
called from compiled code only (from Python they would crash).  Their LLVM IR is linked into the
entries' code and has no machine code of its own (:mod:`faultnet._kernels.linking`): LLVM
optimises and emits each piece of code once, in the entry that runs it.  The entries are
cached on disk under one stamp of the kernels' sources together
(:mod:`faultnet._kernels.cache`), so that a change to any kernel recompiles the entries that
contain it.

Which helpers are inlined by Numba (:data:`inline_kernel`) and which are kernels of their
own (:data:`kernel`, :data:`forced_kernel`) is a trade between compile time and speed,
measured on the cold compile of a lattice run (``benchmarks/run.py --compile-only``) and
on events/s:

- Numba types an inlined helper again at each call site, so a small helper called from
  many places (:func:`~faultnet._kernels.integrate.force`, the dense output of one block,
  the neighbours' answers) is a kernel: typed once, and LLVM inlines the small ones into
  their callers (catalogs bit-identical, events/s within 1%); together 2.5 s of a cold
  compile.  :func:`~faultnet._kernels.integrate.accel`, the landing's septic helpers and
  the dense output's coefficients are kernels: 0.3-0.6 s less than inlined, events/s
  within 1%, catalogs bit-identical;
- the DP5 stages' acceleration (``dopri._acc``, six sites in one kernel) is a
  :data:`forced_kernel`: typed once, and marked for LLVM to inline at every site, which
  gives the code of Numba's inlining (catalogs bit-identical, events/s within 2%) for
  0.6-0.9 s less of a cold compile; as a plain kernel, W1 ran 2-4% fewer events/s;
- a helper with one call site is typed once either way; inlined by Numba, its IR is copied
  and its caller grows (the event's integration, :mod:`faultnet._kernels.slip`, is inlined
  into the event loop; ``interpolated_crossings`` is a kernel).  Every inlined helper as a
  forced kernel compiled 2-3 s slower: the event loop ``events._run_events`` alone 1.5 s
  (it takes the integration as an argument); the crossing scan
  ``crossing.block_crossings``, inlined at two sites, made no difference.

A kernel compiles once per signature, and Numba types a Python ``int`` or ``bool`` constant
argument as a literal, one signature per value.  So the constants that kernels pass to one
another (the work columns ``integrate.D``, ``P``, ..., the stage columns ``tableau.KV``,
``KA``, ``response.COMMITTED``) are NumPy scalars, typed ``int64`` or ``boolean``: on a
lattice run 7 fewer compiled kernels, bit-identical catalogs.
"""

import numba as nb

from faultnet._kernels import compiler
from faultnet._kernels.cache import disk_cache_available, register, verified
from faultnet._kernels.linking import PIPELINE

__all__ = ["CACHE", "INNER", "entry", "forced_kernel", "inline_kernel", "kernel"]

# one cache stamp for all kernels (faultnet._kernels.cache), before any kernel is decorated
register()
#: whether the kernels are cached on disk (False, after one line saying why, where no cache
#: folder is writable); every cached file is checked before it is loaded
CACHE = disk_cache_available()


def _cached(**options):
    """Numba's ``njit`` with the disk cache where there is one, its files checked."""
    decorate = nb.njit(cache=CACHE, **options)
    return lambda func: verified(decorate(func))


#: options of the kernels called from compiled code only
#: (``forceinline`` is set so that a kernel's flags never depend on the caller it is first
#: compiled for: Numba's kernels inherit an unset ``forceinline`` from that caller)
INNER = {
    "nogil": True,
    "_nrt": False,
    "no_cpython_wrapper": True,
    "no_cfunc_wrapper": True,
    "forceinline": False,
}


def _linked(options):
    """The decorator of link-only kernels (Numba's own, cached, where PIPELINE is None)."""
    if PIPELINE:
        return nb.njit(pipeline_class=PIPELINE, **options)
    return _cached(**options)


#: a kernel called from other kernels: its LLVM IR is linked into the entries' code
#: (:mod:`faultnet._kernels.linking`), so it has no machine code of its own to cache
kernel = _linked(INNER)
#: a kernel that LLVM always inlines where it is called (typed once, unlike an inline_kernel)
forced_kernel = _linked(dict(INNER, forceinline=True))
#: a kernel inlined into its callers (Numba IR inlining, before typing)
inline_kernel = _cached(inline="always", **INNER)
#: a kernel called from Python, compiled by :mod:`faultnet._kernels.compiler`
entry = _cached(
    nogil=True,
    _nrt=False,
    **({"pipeline_class": compiler.PIPELINE} if compiler.PIPELINE else {}),
)
