"""The kernels' Numba compiler: Numba's own, with compile flags that compare in one step.

While it types a kernel, Numba looks up each ``@overload`` template it tries (an operator's
or a builtin's, for every call and arithmetic operation) in a cache keyed on the current
compile flags.  Each lookup hashes the flags and compares them with the cached ones, and
Numba's ``Flags`` build the dictionary of their 40-odd options for that, one Python property
call per option: on a lattice run's cold compile, 30,000 lookups and 2.3 million property
calls, 1.6-2 s of 13 s.

:class:`KernelFlags` are Numba's ``Flags`` with the same options, values, equality and hash,
read at once: the defaults of the class merged with the options set.  :class:`KernelCompiler`
is Numba's default compiler (a ``pipeline_class``, Numba's documented hook for custom
compilers) that compiles under them.  The generated code is the same (catalogs bit-identical).

Where this Numba lacks the names used here, :data:`PIPELINE` is None and the kernels compile
through Numba's default compiler.
"""

__all__ = ["PIPELINE", "KernelCompiler", "KernelFlags"]

try:
    from numba.core.compiler import Compiler, Flags
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

    _DEFAULTS = {name: option.default for name, option in Flags.options.items()}
    _HASH = hash(tuple(sorted(_DEFAULTS)))

    class KernelCompiler(Compiler):
        """Numba's default compiler, compiling under :class:`KernelFlags`."""

        def __init__(self, typingctx, targetctx, library, args, return_type, flags, locals):
            flags = KernelFlags(flags)
            super().__init__(typingctx, targetctx, library, args, return_type, flags, locals)

    #: the ``pipeline_class`` of the entry kernels
    PIPELINE = KernelCompiler
else:  # pragma: no cover
    KernelFlags = KernelCompiler = PIPELINE = None
