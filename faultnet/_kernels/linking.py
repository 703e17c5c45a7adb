"""The inner kernels' compiler: LLVM IR linked into the entry kernels, never machine code.

Only the entry kernels (:mod:`faultnet._kernels.events`) run.
Every other kernel runs inlined into, or called from, an entry's machine code.  Numba's own
pipeline nevertheless finishes each kernel on its own: it optimises the kernel's module (with
the code of every kernel it calls linked in) and emits machine code for it, and then the entry
links that optimised code in and optimises and emits it again.  On a lattice run's cold
compile that was about 3 s of 15 s, for machine code that never ran.

:class:`LinkedCompiler` is Numba's nopython pipeline (a ``pipeline_class``, Numba's documented
hook for custom compilers) with one pass changed: the lowering puts the kernel's LLVM IR into a
:class:`LinkOnlyLibrary`, which links in its callees when a caller asks for it and does nothing
more.  The entry's library then optimises all the code it links once, as one module, and emits
it once.  LLVM's inliner sees the callees before any optimisation of their own: the entries'
code is also the faster for it (events/s on W1 and W4-W6, measured in
``docs/guide/performance.rst``), with the same floating-point operations (catalogs are
bit-identical).

Such a kernel has no machine code of its own, so it cannot be called from Python and is not
cached on disk: the entries' cache holds all of its code.  The price: an entry compiled in a
later process than the first (the exact treatment after a lattice run's interpolated one)
types and lowers the kernels it shares with the cached entries again, where Numba's pipeline
would have loaded them from the cache: the exact ring after a lattice run compiles in
9.0 s, as long as on a cold cache.

Where this Numba lacks the names used here (or those of :mod:`faultnet._kernels.compiler`),
:data:`PIPELINE` is None and the kernels compile through Numba's own pipeline.
"""

from numba.core import codegen

from faultnet._kernels.compiler import KernelCompiler

__all__ = ["PIPELINE", "LinkOnlyLibrary", "LinkedCompiler"]

try:
    from numba import _dynfunc
    from numba.core.compiler_machinery import register_pass
    from numba.core.typed_passes import NativeLowering
except ImportError:  # pragma: no cover - another Numba's layout
    KernelCompiler = None


class LinkOnlyLibrary(codegen.JITCodeLibrary):
    """A kernel's code library that is only ever linked into its callers' libraries.

    Numba's ``finalize`` (called when a caller links this library in) links in the libraries
    of the kernels this one calls, then optimises the module and emits machine code; here
    those last two steps do nothing: the caller's library optimises and emits the code.
    """

    def _optimize_final_module(self):
        pass

    def _finalize_final_module(self):
        self._finalized = True


if KernelCompiler is not None:

    @register_pass(mutates_CFG=True, analysis_only=False)
    class LinkOnlyLowering(NativeLowering):
        """Numba's lowering into a :class:`LinkOnlyLibrary`, with no executable made.

        The compile result gets a function object without code (address 0, as Numba gives a
        kernel compiled without its Python wrapper), registered with the target context so
        that callers lower their calls to this kernel and link its library.
        """

        _name = "faultnet_link_only_lowering"

        def run_pass(self, state):
            name = state.func_id.func_qualname
            state.library = LinkOnlyLibrary(state.targetctx.codegen(), name)
            state.flags.no_compile = True  # Numba's lowering then stops at the LLVM IR
            NativeLowering.run_pass(self, state)
            lowered = state["cr"]
            fndesc = lowered.fndesc
            cfunc = _dynfunc.make_function(
                fndesc.lookup_module(),
                fndesc.qualname.split(".")[-1],
                f"inner kernel {fndesc.qualname!r} (no machine code of its own)",
                0,
                lowered.env,
                (state.library,),
            )
            state.targetctx.insert_user_function(cfunc, fndesc, [state.library])
            state.reload_init.extend(state.library._reload_init)
            state["cr"] = lowered._replace(cfunc=cfunc)
            return True

    class LinkedCompiler(KernelCompiler):
        """The kernels' compiler (:mod:`faultnet._kernels.compiler`), lowering into a
        :class:`LinkOnlyLibrary`."""

        def define_pipelines(self):
            (pm,) = KernelCompiler.define_pipelines(self)
            pm.passes = [(LinkOnlyLowering if p is NativeLowering else p, d) for p, d in pm.passes]
            pm.finalize()
            return [pm]

    #: the ``pipeline_class`` of the inner kernels
    PIPELINE = LinkedCompiler
else:  # pragma: no cover
    LinkOnlyLowering = LinkedCompiler = PIPELINE = None
