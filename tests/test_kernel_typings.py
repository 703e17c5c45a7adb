"""The kernels' typing context: Numba's typings of operators, remembered."""

import operator

import pytest
from numba.core import errors, types
from numba.core.registry import cpu_target

from faultnet._kernels import typings

NUMBA = cpu_target.typing_context
F8, I8, B = types.float64, types.int64, types.boolean
ARRAY2 = types.Array(F8, 2, "C")

CASES = [
    (operator.mul, (F8, F8)),
    (operator.add, (I8, F8)),
    (operator.lt, (F8, I8)),
    (operator.truediv, (I8, I8)),
    (operator.neg, (F8,)),
    (bool, (B,)),
    (abs, (F8,)),
    (operator.getitem, (ARRAY2, types.UniTuple(I8, 2))),
    (operator.getitem, (types.Array(I8, 1, "C"), I8)),
    (operator.setitem, (ARRAY2, types.UniTuple(I8, 2), F8)),
    (operator.add, (types.literal(3), I8)),
    (operator.getitem, (ARRAY2, types.Tuple([types.literal(2), I8]))),
    (range, (I8, I8)),
    (types.NumberClass(types.uint64), (I8,)),
]


def _fnty(fn):
    NUMBA.refresh()  # Numba's registries load on first use
    return NUMBA.resolve_value_type(fn)


def test_one_context_shares_numbas_state():
    ctx = typings.kernel_typing_context(NUMBA)
    assert typings.kernel_typing_context(NUMBA) is ctx
    assert isinstance(ctx, type(NUMBA))
    assert ctx.__dict__ is NUMBA.__dict__
    assert "_remembered" not in NUMBA.__dict__


@pytest.mark.parametrize(("fn", "args"), CASES)
def test_remembered_typings_are_numbas(fn, args):
    ctx = typings.kernel_typing_context(NUMBA)
    fnty = _fnty(fn)
    expected = NUMBA.resolve_function_type(fnty, args, {})
    first = ctx.resolve_function_type(fnty, args, {})
    assert first == expected
    assert ctx._remembered[(fnty, args)] is first
    assert ctx.resolve_function_type(fnty, args, {}) is first


def test_literal_values_are_part_of_what_is_remembered():
    ctx = typings.kernel_typing_context(NUMBA)
    fnty = _fnty(operator.add)
    three = ctx.resolve_function_type(fnty, (types.literal(3), I8), {})
    four = ctx.resolve_function_type(fnty, (types.literal(4), I8), {})
    assert (fnty, (types.literal(3), I8)) in ctx._remembered
    assert (fnty, (types.literal(4), I8)) in ctx._remembered
    assert three == NUMBA.resolve_function_type(fnty, (types.literal(3), I8), {})
    assert four == NUMBA.resolve_function_type(fnty, (types.literal(4), I8), {})


def test_other_functions_types_and_failures_are_not_remembered():
    ctx = typings.kernel_typing_context(NUMBA)
    before = dict(ctx._remembered)
    assert ctx.resolve_function_type(_fnty(min), (F8, F8), {}) is not None
    pair = types.UniTuple(F8, 2)  # a tuple of floats: its items' typing is not remembered
    assert ctx.resolve_function_type(_fnty(operator.getitem), (pair, types.literal(0)), {})
    with pytest.raises(errors.TypingError):
        ctx.resolve_function_type(_fnty(operator.add), (ARRAY2, types.UniTuple(I8, 2)), {})
    assert ctx._remembered == before
