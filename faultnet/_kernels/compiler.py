"""The kernels' Numba compiler: Numba's nopython pipeline, with less Python work per kernel.

While it types a kernel, Numba looks up each ``@overload`` template it tries (an operator's
or a builtin's, for every call and arithmetic operation) in a cache keyed on the current
compile flags.  Each lookup hashes the flags and compares them with the cached ones, and
Numba's ``Flags`` build the dictionary of their 40-odd options for that, one Python property
call per option: on a lattice run's cold compile, 30,000 lookups and 2.3 million property
calls, 1.3-1.5 s of what was then 13 s.

:class:`KernelFlags` are Numba's ``Flags`` with the same options, values, equality and hash,
read at once: the defaults of the class merged with the options set.

:class:`KernelCompiler` is Numba's default compiler (a ``pipeline_class``, Numba's documented
hook for custom compilers) that compiles under them, and without five passes that scan every
kernel for Python features the kernels do not use (:data:`UNUSED_PASSES`; 0.5-1 s of a lattice
run's cold compile):

- ``with`` blocks (``with_lifting``), closures and comprehensions (``inline_closure_likes``,
  ``make_function_op_code_to_jit_function``) and ``literal_unroll`` (``literal_unroll``);
- array expressions and string-literal indexing (``nopython_rewrites``): the kernels allocate
  nothing and hold no strings.

A kernel that used one of them fails to compile, with Numba's typing or lowering error;
nothing is compiled differently.  The generated code is the same as under Numba's default
compiler (catalogs bit-identical).

Where this Numba lacks the names used here, :data:`PIPELINE` is None and the kernels compile
through Numba's default compiler.
"""

__all__ = ["PIPELINE", "UNUSED_PASSES", "KernelCompiler", "KernelFlags"]

try:
    from numba.core import typed_passes, untyped_passes
    from numba.core.compiler import Compiler, DefaultPassBuilder, Flags

    from faultnet._kernels.typings import kernel_typing_context
except ImportError:  # pragma: no cover - another Numba's layout
    Compiler = None


if Compiler is not None:

    class KernelFlags(Flags):
        """Numba's compile ``Flags``, whose options are read as one dictionary merge."""

        __slots__ = ()

        def values(self):
            """All the options' values, by name (as Numba's ``values``)."""
            return {**_DEFAULTS, **self._values}

        def __hash__(self):
            # Numba's hash: over the sorted option names only (a constant of the class)
            return _HASH

    #: Numba's passes for Python features that no kernel uses (see the module's docstring)
    UNUSED_PASSES = (
        untyped_passes.WithLifting,
        untyped_passes.InlineClosureLikes,
        untyped_passes.MakeFunctionToJitFunction,
        untyped_passes.LiteralUnroll,
        typed_passes.NopythonRewrites,
    )

    _DEFAULTS = {name: option.default for name, option in Flags.options.items()}
    _HASH = hash(tuple(sorted(_DEFAULTS)))

    class KernelCompiler(Compiler):
        """Numba's default compiler, compiling under :class:`KernelFlags`, without
        :data:`UNUSED_PASSES`, and typing in a
        :class:`~faultnet._kernels.typings.KernelTypingContext`."""

        def __init__(self, typingctx, targetctx, library, args, return_type, flags, locals):
            flags = KernelFlags(flags)
            typingctx = kernel_typing_context(typingctx)
            super().__init__(typingctx, targetctx, library, args, return_type, flags, locals)

        def define_pipelines(self):
            pm = DefaultPassBuilder.define_nopython_pipeline(self.state)
            pm.passes = [(p, d) for p, d in pm.passes if p not in UNUSED_PASSES]
            pm.finalize()
            return [pm]

    #: the ``pipeline_class`` of the entry kernels
    PIPELINE = KernelCompiler
else:  # pragma: no cover
    KernelFlags = KernelCompiler = PIPELINE = UNUSED_PASSES = None
