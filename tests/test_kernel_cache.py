"""The kernels' on-disk cache: one stamp over all their sources (faultnet._kernels.cache)."""

import os
import subprocess
import sys
import textwrap

import pytest

from faultnet._kernels import cache

RUNNER = """
import sys
sys.path.insert(0, {pkg!r})
from faultnet._kernels.cache import register
register({pkg!r})
from outer import g
print(g(1.0))
"""


def _run(pkg, cache_dir):
    env = dict(os.environ, NUMBA_CACHE_DIR=str(cache_dir))
    code = RUNNER.format(pkg=str(pkg))
    out = subprocess.run([sys.executable, "-c", code], env=env, capture_output=True, text=True)
    assert out.returncode == 0, out.stderr
    return float(out.stdout.strip().splitlines()[-1])


def test_a_change_to_a_called_function_recompiles_its_callers(tmp_path):
    """Numba alone stamps each file: the caller's cache would keep the old callee inside."""
    pkg = tmp_path / "kernels"
    pkg.mkdir()
    (pkg / "inner.py").write_text(
        textwrap.dedent(
            """
            import numba as nb
            @nb.njit(cache=True)
            def f(x):
                return x + 1.0
            """
        )
    )
    (pkg / "outer.py").write_text(
        textwrap.dedent(
            """
            import numba as nb
            from inner import f
            @nb.njit(cache=True)
            def g(x):
                return f(x) * 2.0
            """
        )
    )
    cache_dir = tmp_path / "numba_cache"
    assert _run(pkg, cache_dir) == 4.0
    assert any(name.endswith(".nbi") for _, _, files in os.walk(cache_dir) for name in files)
    (pkg / "inner.py").write_text((pkg / "inner.py").read_text().replace("x + 1.0", "x + 100.0"))
    assert _run(pkg, cache_dir) == 202.0  # not 4.0: outer's cached code had the old f inside
    assert _run(pkg, cache_dir) == 202.0  # and the new code is cached in turn


def test_stamp_follows_contents_not_file_times(tmp_path):
    (tmp_path / "a.py").write_text("x = 1\n")
    (tmp_path / "b.py").write_text("y = 2\n")
    (tmp_path / "notes.txt").write_text("not a source")
    first = cache.sources_stamp(tmp_path)
    os.utime(tmp_path / "a.py", (1e9, 1e9))
    (tmp_path / "notes.txt").write_text("changed")
    assert cache.sources_stamp(tmp_path) == first
    (tmp_path / "b.py").write_text("y = 3\n")
    assert cache.sources_stamp(tmp_path) != first
    (tmp_path / "b.py").write_text("y = 2\n")
    (tmp_path / "c.py").write_text("")
    assert cache.sources_stamp(tmp_path) != first


def test_every_entry_kernel_is_cached_under_the_shared_stamp():
    from faultnet._kernels import events

    stamp = cache.sources_stamp(cache.KERNELS_DIR)
    for dispatcher in (events.run_events_dopri5_interpolated, events.run_events_rk4):
        locator = dispatcher._cache._impl.locator
        assert isinstance(locator, cache.SourcesLocator)
        assert locator.get_source_stamp() == stamp


def test_register_warns_where_numba_has_no_locator_list(monkeypatch, tmp_path):
    monkeypatch.setattr(cache, "_IMPL", None)
    with pytest.warns(RuntimeWarning, match="delete the kernels' Numba cache"):
        assert cache.register(tmp_path) is False
    assert str(tmp_path) not in cache.SourcesLocator.directories


def test_unreadable_sources_leave_the_choice_to_numba(tmp_path):
    """A registered directory that cannot be listed (a zipped install) gets Numba's locators."""
    missing = tmp_path / "pkg.zip" / "kernels"
    cache.SourcesLocator.directories.add(str(missing))
    try:
        assert cache.SourcesLocator.from_function(len, str(missing / "mod.py")) is None
    finally:
        cache.SourcesLocator.directories.discard(str(missing))
