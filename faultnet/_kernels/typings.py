"""Numba's typing context, remembering how it typed operators on numbers and arrays.

Numba types each operation of a kernel anew: for ``a * b`` on two floats it tries the
templates registered for ``operator.mul`` (those for arrays, lists, strings, ...) in turn
until one accepts the arguments, about ten per operation.  A lattice run's cold compile
resolves 7,200 calls and operators this way, 1.5-1.7 s of it, but only 216 distinct ones:
1,416 multiplications of two floats, 708 additions, 571 truth tests of a boolean, 410 reads
of a 2-D float array at an index pair, ...

:class:`KernelTypingContext` is Numba's typing context with the same state (it shares the
instance's attributes, so registries, caches and the call stack stay Numba's own) that
remembers the signature it found for an operator or builtin of :data:`REMEMBERED`, or a cast
to a number type, applied to numbers, booleans, arrays, ranges, slices or tuples of integers
(never a failed typing), and answers it again without trying the templates.  The typing of
these is a pure function of the argument types (NumPy's casting rules, the array's dtype and
dimensions; a literal constant's type holds its value), and the first typing has recorded
its implementation with the function type, as Numba does, for the lowering.  The code
generated is the same (catalogs bit-identical).

The memory lasts for the process and assumes that the templates registered for these
operators on plain types do not change after a first typing: an extension imported later
that registered one would change Numba's own answer, and not the remembered one.

:func:`kernel_typing_context` gives the one instance for a Numba typing context.
"""

import operator

from numba.core import types
from numba.core.typing.context import Context

__all__ = ["REMEMBERED", "KernelTypingContext", "kernel_typing_context"]

#: the functions whose typings on plain types are remembered
REMEMBERED = frozenset(
    [
        operator.add,
        operator.sub,
        operator.mul,
        operator.truediv,
        operator.floordiv,
        operator.mod,
        operator.pow,
        operator.neg,
        operator.pos,
        operator.not_,
        operator.lt,
        operator.le,
        operator.gt,
        operator.ge,
        operator.eq,
        operator.ne,
        operator.and_,
        operator.or_,
        operator.iadd,
        operator.isub,
        operator.imul,
        operator.itruediv,
        operator.getitem,
        operator.setitem,
        abs,
        bool,
        range,
        slice,
        "getiter",  # a loop over a range
        "iternext",
    ]
)


def _plain(t):
    """A number, boolean, array, range or slice, or a tuple of integers (literals included)."""
    if isinstance(
        t,
        (
            types.Number,
            types.Boolean,
            types.Array,
            types.RangeType,
            types.RangeIteratorType,
            types.SliceType,
        ),
    ):
        return True
    return isinstance(t, types.BaseTuple) and all(isinstance(e, types.Integer) for e in t.types)


def _key(func, args, kws):
    """What a typing is remembered by, or None where it is not remembered."""
    if kws or not all(_plain(a) for a in args):
        return None
    if not isinstance(func, types.NumberClass):  # a number type's cast: remembered
        fn = func.typing_key if isinstance(func, types.Function) else func
        try:
            if fn not in REMEMBERED:
                return None
        except TypeError:  # an unhashable key
            return None
    return (func, tuple(args))


class KernelTypingContext(Context):
    """Numba's typing context, remembering the typings of :data:`REMEMBERED` on plain types."""

    __slots__ = ("_remembered",)  # kept apart from the attributes shared with Numba's context

    def resolve_function_type(self, func, args, kws):
        """Numba's ``resolve_function_type``, answered from memory where it can be."""
        key = _key(func, args, kws)
        if key is None:
            return super().resolve_function_type(func, args, kws)
        sig = self._remembered.get(key)
        if sig is None:
            sig = super().resolve_function_type(func, args, kws)
            if sig is not None:
                self._remembered[key] = sig
        return sig


#: Numba's typing context -> the KernelTypingContext sharing its state
_CONTEXTS = {}


def kernel_typing_context(typingctx):
    """The :class:`KernelTypingContext` sharing the state of Numba's ``typingctx``."""
    if type(typingctx) is not Context:  # another target's context: left as it is
        return typingctx
    ctx = _CONTEXTS.get(typingctx)
    if ctx is None:
        ctx = KernelTypingContext.__new__(KernelTypingContext)
        ctx.__dict__ = typingctx.__dict__  # the same registries, caches and call stack
        ctx._remembered = {}
        _CONTEXTS[typingctx] = ctx
    return ctx
