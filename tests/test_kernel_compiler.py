"""The kernels' compiler: Numba's, with compile flags read as one dictionary."""

import numba as nb
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from numba.core.compiler import Flags

from faultnet._kernels import compiler, events, linking

pytestmark = pytest.mark.skipif(compiler.PIPELINE is None, reason="this Numba's layout differs")

#: options of every kind of value that kernels set: booleans, a string, and one left unset
SETTINGS = {
    "nrt": st.booleans(),
    "release_gil": st.booleans(),
    "no_cpython_wrapper": st.booleans(),
    "no_compile": st.booleans(),
    "error_model": st.sampled_from(["python", "numpy"]),
    "inline": st.sampled_from(["never", "always"]),
}


def _flags(cls, values):
    flags = cls()
    for name, value in values.items():
        if value is not None:
            setattr(flags, name, value)
    return flags


@settings(deadline=None, max_examples=60)
@given(
    st.fixed_dictionaries({k: st.none() | v for k, v in SETTINGS.items()}),
    st.fixed_dictionaries({k: st.none() | v for k, v in SETTINGS.items()}),
)
def test_kernel_flags_read_compare_and_hash_as_numbas(a, b):
    numba_a, ours_a = _flags(Flags, a), _flags(compiler.KernelFlags, a)
    numba_b, ours_b = _flags(Flags, b), _flags(compiler.KernelFlags, b)
    assert ours_a.values() == numba_a.values()
    assert hash(ours_a) == hash(numba_a)
    assert (ours_a == ours_b) == (numba_a == numba_b)
    assert (ours_a == numba_b) == (numba_a == numba_b)
    copied = compiler.KernelFlags(numba_a)
    assert type(copied.copy()) is compiler.KernelFlags and copied == numba_a
    if a["nrt"] is not None:
        assert ours_a.nrt == a["nrt"]


def test_kernel_compiler_compiles_under_kernel_flags(monkeypatch):
    seen = []
    original = compiler.KernelCompiler._compile_core

    def spy(self):
        seen.append(type(self.state.flags))
        return original(self)

    monkeypatch.setattr(compiler.KernelCompiler, "_compile_core", spy)

    @nb.njit(pipeline_class=compiler.PIPELINE)
    def plus(x, y):
        return x + y * 2.0

    assert plus(1.0, 2.5) == 6.0
    assert seen == [compiler.KernelFlags]


def test_faultnet_kernels_use_the_kernel_compiler():
    assert events.run_events_dopri5_interpolated._compiler.pipeline_class is compiler.PIPELINE
    if linking.PIPELINE is not None:
        assert issubclass(linking.PIPELINE, compiler.KernelCompiler)


def test_kernel_compiler_leaves_out_the_unused_passes():
    @nb.njit(pipeline_class=compiler.PIPELINE)
    def twice(x):
        return 2.0 * x

    assert twice(3.0) == 6.0
    (cres,) = twice.overloads.values()
    ran = " ".join(cres.metadata["pipeline_times"]["nopython"])
    assert "nopython_type_inference" in ran and "native_lowering" in ran
    for unused in compiler.UNUSED_PASSES:
        assert f"_{unused._name}" not in ran


def test_a_closure_fails_to_compile_instead_of_compiling_differently():
    def with_closure(x):
        def add(y):
            return x + y

        return add(1.0)

    assert nb.njit(with_closure)(2.0) == 3.0  # Numba's own pipeline inlines the closure
    with pytest.raises(nb.core.errors.NumbaError):
        nb.njit(pipeline_class=compiler.PIPELINE)(with_closure)(2.0)


def test_forced_kernels_are_marked_for_llvm_to_inline():
    from faultnet._kernels import dopri, jit

    forced = jit.forced_kernel(lambda x: x * 3.0)
    plain = jit.kernel(lambda x: x * 5.0)

    @nb.njit
    def outer(x):
        return forced(x) + plain(x)

    assert outer(1.0) == 8.0
    (f,) = forced.overloads.values()
    (p,) = plain.overloads.values()
    assert "alwaysinline" in f.library.get_llvm_str()
    assert "alwaysinline" not in p.library.get_llvm_str()
    assert dopri._acc.targetoptions["forceinline"] is True
    assert dopri.dopri_step.targetoptions["forceinline"] is False
