"""The decorators of the kernels: Numba's ``njit`` with a few documented options.

Every kernel is compiled without Numba's reference counting (``_nrt=False``: no allocation
happens inside them) and without its rewrite passes (``no_rewrites``: folding a tuple's ``len``
and an array's ``ndim`` into constants, pruning the branches they decide, fusing array
expressions; no kernel has any of these, and a model's kinds are chosen by type,
:func:`kelvin_kernel`), and releases the GIL. Only the entry kernels
(:mod:`.carlson_langer.events`) are called from Python; the others are built without the Python
and C wrappers (``no_cpython_wrapper``, ``no_cfunc_wrapper``), which saves compile time, and so
can be called from compiled code only (from Python they would crash). Every kernel is cached on
disk under one stamp of all the kernels' sources together (:mod:`.cache`), so that a change to
any kernel recompiles the entries that contain it.

The rewrites ran over every kernel's IR and again over every inlined helper's: without them
Numba's passes before typing take 0.44 s less of a lattice's cold compile (1.76 s against
2.20 s, four alternating rounds; the same LLVM IR and catalogs). One rewrite did matter: it
typed a constant index into a tuple (``a.shape[0]``) without Numba's ``getitem`` overloads,
which otherwise compile a function per tuple type; so the kernels write ``len(a)`` and unpack
``_, n = a.shape``. Nor do they call ``min``, ``max`` or ``int``: Numba compiles its overloads
of them once per argument types and compile flags, a library each (nine in a lattice run), so
the kernels compare (``b if b < a else a`` is what Numba's ``min(a, b)`` computes) and cast
with ``np.int64``: 0.69 s less cold compile over four alternating rounds, the same catalogs.
``tests/solver/test_kernel_docs.py`` keeps both out.  Integer powers are written as the
products Numba's power loop forms (``x * (x * x)`` for ``x**3``), which without the rewrites
is a loop at run time.

Which helpers are inlined by Numba (:data:`inline_kernel`) and which are kernels of their
own (:data:`kernel`, :data:`forced_kernel`) is a trade between compile time and speed,
measured on the cold compile of a lattice run (``benchmarks/run.py --compile-only``) and
on events/s (``benchmarks/README.md``):

- Numba types an inlined helper again at each call site, so a small helper called from
  many places (:func:`~.carlson_langer.physics.force`, the dense output of one block, the
  neighbours' answers) is a kernel: typed once, and LLVM inlines the small ones into their
  callers;
- the DP5 stages' acceleration (:func:`~.carlson_langer.physics.accel_hot`, six sites in one
  kernel) is a :data:`forced_kernel`: typed once, and marked for LLVM to inline at every site;
  so are small helpers called from two or three sites (the hot force, a root of a quadratic,
  the crossing list's sort key, the late joins' check): inlined by Numba, each site held the
  helper's statements again, and each of its ``return`` statements became a tuple and an
  assignment in the caller (1,100 IR statements of the lattice run's 16,835, the same
  events/s); what such a helper rarely does is a kernel of its own, so that the copies hold
  only the common path (the late joins' check lists the join it finds through a kernel: with
  a join's placement inlined there, each of the check's two copies held 812 IR statements,
  and the ring of 2000 ran 3-6% fewer events/s);
- a helper with one call site is typed once either way, and inlined by Numba it needs no
  library of its own (each library costs its own LLVM module passes and machine code, and
  is linked into its callers' again): a helper called once from a kernel is inlined (0.4 s,
  0.4 s and 0.3 s less cold compile on the lattice in three rounds of such changes, the same
  events/s), as is the event's integration (:mod:`.carlson_langer.slip`) into the event
  loop.  Chains of inlined helpers are avoided: the inliner reruns its passes at every level
  (inlining 26 single-caller kernels along such chains once compiled the lattice in 32 s
  against 17 s); where a single-caller helper is itself inlined, its own single-caller
  helpers stay kernels, or it becomes a kernel into which they are inlined (the stops'
  position and shift into :func:`~.carlson_langer.interp._stop`);
- the entry kernel, the event loop with the event's integration inlined, is the largest and
  is not grown: the interpolated crossings, or the event's end and the solo cache's kernels,
  inlined into it compiled the lattice 0.8 s and 0.4 s slower; nor is a second kernel made
  whose closure is nearly the whole program (the integrations as kernels: 1.1 s slower, its
  library optimised and emitted once more).

A kernel compiles once per signature, and Numba types a Python ``int`` or ``bool`` constant
argument as a literal, one signature per value.  So the constants that kernels pass to one
another (the work columns ``work.D``, ``P``, ..., the stage columns ``tableau.KV``, ``KA``,
the late joins' check's ``joining``) are NumPy scalars, typed ``int64`` or ``boolean``.
"""

import numba as nb
from numba.extending import overload

from faultnet.solver._kernels.bundles import KelvinGraph, kelvin
from faultnet.solver._kernels.cache import disk_cache_available, register, verified

__all__ = ["CACHE", "INNER", "entry", "forced_kernel", "inline_kernel", "kelvin_kernel", "kernel"]

# one cache stamp for all kernels (faultnet.solver._kernels.cache), before any kernel is decorated
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
    "no_rewrites": True,
}

#: a kernel called from other kernels
kernel = _cached(**INNER)
#: a kernel that LLVM always inlines where it is called (typed once, unlike an inline_kernel)
forced_kernel = _cached(**dict(INNER, forceinline=True))
#: a kernel inlined into its callers (Numba IR inlining, before typing)
inline_kernel = _cached(inline="always", **INNER)
#: a kernel called from Python (through its CPython wrapper only)
entry = _cached(nogil=True, _nrt=False, no_rewrites=True, no_cfunc_wrapper=True)
#: options of the functions that an ``overload`` compiles (:func:`kelvin_kernel`,
#: :func:`~faultnet.solver._kernels.bundles.kelvin`), called from compiled code only: an
#: overload compiles one function (and library) per signature, with the Python and C wrappers
#: unless told otherwise (a C wrapper was most of such a library's LLVM instructions, 2,100
#: of a lattice run's 32,330: 0.24 s of its cold compile, with the entry's C wrapper).  Not
#: ``no_rewrites``: ``args[0]`` of a star-args tuple then compiles a ``getitem`` function per
#: tuple type (seven more libraries on a lattice run).
OVERLOAD = {k: INNER[k] for k in ("nogil", "_nrt", "no_cpython_wrapper", "no_cfunc_wrapper")}


@overload(kelvin, inline="always", jit_options=OVERLOAD)
def _kelvin_typed(graph):
    flag = getattr(graph, "instance_class", None) is KelvinGraph
    return lambda graph: flag


def _first(*args):
    return args[0]


def kelvin_kernel(func=None, *, plain=_first):
    """A kernel of the plate's and the viscous terms, ``func(first, ..., graph, ...)``.

    Compiled and run (LLVM inlines it, as a :data:`forced_kernel`) where an argument is a
    :data:`~faultnet.solver._kernels.bundles.KelvinGraph`; for a plain ``Graph`` a call is
    ``plain(*args)``, by default its first argument (the force before those terms, for
    instance), and types nothing else.  ``if kelvin(graph): f = terms(f, ...)`` would still
    type (and lower) ``terms`` for a plain model, which LLVM then drops: an ``overload``
    chooses by the bundle's type instead, so that a plain model's kernels are compiled
    without that code at all.  ``@kelvin_kernel(plain=lambda ...: ...)`` gives what a plain
    model gets where that is not the first argument.
    """
    if func is None:
        return lambda f: kelvin_kernel(f, plain=plain)
    compiled = forced_kernel(func)
    plain_compiled = None if plain is _first else nb.njit(**INNER)(plain)

    def call(*args):
        return func(*args) if any(kelvin(a) for a in args) else plain(*args)

    @overload(call, jit_options=OVERLOAD)
    def _typed(*args):
        if any(getattr(a, "instance_class", None) is KelvinGraph for a in args):
            return lambda *args: compiled(*args)
        if plain_compiled is None:  # no kernel to call: 0.05 s less compile per call site
            return lambda *args: args[0]
        return lambda *args: plain_compiled(*args)

    call.__doc__, call.__name__, call.__wrapped__ = func.__doc__, func.__name__, func
    call.kernel = compiled  # the compiled kernel, for tests (its signatures)
    return call
