"""The kernels' on-disk cache: one stamp over all their sources (faultnet.solver._kernels.cache)."""

import hashlib
import os
import pickle
import subprocess
import sys
import textwrap
from pathlib import Path

import pytest

from faultnet.solver._kernels import cache

RUNNER = """
import sys
sys.path.insert(0, {pkg!r})
from faultnet.solver._kernels.cache import register
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
    assert cache.sources_stamp(tmp_path) == first
    (tmp_path / "c.py").write_text("")
    assert cache.sources_stamp(tmp_path) != first


def test_stamp_covers_the_folders_below(tmp_path):
    """The kernels live in subpackages (``carlson_langer/``): their sources count too, and
    where they are; caches and hidden folders do not."""
    (tmp_path / "a.py").write_text("x = 1\n")
    sub = tmp_path / "engine"
    sub.mkdir()
    (sub / "step.py").write_text("y = 2\n")
    first = cache.sources_stamp(tmp_path)
    (sub / "step.py").write_text("y = 3\n")
    changed = cache.sources_stamp(tmp_path)
    assert changed != first
    (sub / "step.py").write_text("y = 2\n")
    assert cache.sources_stamp(tmp_path) == first
    for skipped in ("__pycache__", ".hidden"):
        (tmp_path / skipped).mkdir()
        (tmp_path / skipped / "junk.py").write_text("z = 0\n")
        assert cache.sources_stamp(tmp_path) == first
    (sub / "step.py").rename(tmp_path / "step.py")  # the same file in another folder
    assert cache.sources_stamp(tmp_path) != first
    # a folder that cannot be listed has no stamp (not the stamp of no sources)
    with pytest.raises(OSError):
        cache.sources_stamp(tmp_path / "missing")


def test_every_kernel_is_cached_under_the_shared_stamp():
    """The entries and the inner kernels of ``carlson_langer/``, under one stamp of all the
    sources below ``faultnet/solver/_kernels`` and of the folder's import path."""
    from faultnet.solver._kernels.carlson_langer import dopri, events, physics

    stamp = cache.sources_stamp(cache.KERNELS_DIR)
    stamp = hashlib.sha256(f"faultnet.solver._kernels\0{stamp}".encode()).hexdigest()
    for dispatcher in (
        events.run_events_dopri5,
        events.run_events_dopri5_interpolated,
        dopri.dopri_step,
        physics.force,
    ):
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


# ---------------------------------------------------------------- sealed cache files

SEALED = """
import numba as nb
from faultnet.solver._kernels.cache import verified

def g(x):
    return x * 3.0 + 1.0

g = verified(nb.njit(cache=True)(g))
"""


def _run_sealed(pkg, cache_dir):
    if not (pkg / "sealed.py").exists():  # the same file: Numba < 0.68 stamps its mtime
        (pkg / "sealed.py").write_text(SEALED)
    env = dict(os.environ, NUMBA_CACHE_DIR=str(cache_dir))
    code = f"import sys; sys.path.insert(0, {str(pkg)!r}); from sealed import g; print(g(2.0))"
    out = subprocess.run([sys.executable, "-c", code], env=env, capture_output=True, text=True)
    assert out.returncode == 0, out.stderr
    return float(out.stdout.strip().splitlines()[-1]), out.stderr.strip()


def _flip_byte(data):
    data = bytearray(data)
    data[len(data) // 2] ^= 0x01
    return bytes(data)


DAMAGES = {
    "empty": lambda data: b"",
    "truncated": lambda data: data[: len(data) // 2],
    "garbled": lambda data: b"\x80\x05garbage" * 50,
    "one byte": _flip_byte,
}


@pytest.mark.parametrize("suffix", [".nbi", ".nbc"])
@pytest.mark.parametrize("damage", sorted(DAMAGES))
def test_a_damaged_cache_file_is_discarded_with_one_line(tmp_path, damage, suffix):
    """Numba reads its files unchecked: EOFError, UnpicklingError, an abort or wrong code."""
    cache_dir = tmp_path / "numba_cache"
    assert _run_sealed(tmp_path, cache_dir) == (7.0, "")
    (path,) = [
        os.path.join(d, f) for d, _, fs in os.walk(cache_dir) for f in fs if f.endswith(suffix)
    ]
    with open(path, "rb") as fh:
        data = fh.read()
    assert data.startswith(cache.SEAL)
    with open(path, "wb") as fh:
        fh.write(DAMAGES[damage](data))
    value, err = _run_sealed(tmp_path, cache_dir)
    assert value == 7.0
    assert len(err.splitlines()) == 1 and "Traceback" not in err, err
    assert f"discarded the damaged kernel cache file {path}" in err and "recompiling" in err
    assert _run_sealed(tmp_path, cache_dir) == (7.0, "")  # cached anew, sealed


def test_an_index_written_under_another_import_path_is_recompiled_silently(tmp_path):
    """A kernel folder moved within the package leaves indexes that name a module now gone."""
    cache_dir = tmp_path / "numba_cache"
    assert _run_sealed(tmp_path, cache_dir) == (7.0, "")
    (path,) = [
        os.path.join(d, f) for d, _, fs in os.walk(cache_dir) for f in fs if f.endswith(".nbi")
    ]
    with open(path, "rb") as fh:
        payload = cache.unseal(fh.read())
    version = pickle.dumps(pickle.loads(payload), protocol=-1)  # the leading version string
    with open(path, "wb") as fh:  # an index whose pickle names a module that is not there
        fh.write(cache.seal(version + b"cfaultnet_moved_away\nBundle\n."))
    assert _run_sealed(tmp_path, cache_dir) == (7.0, "")
    with open(path, "rb") as fh:
        assert b"faultnet_moved_away" not in cache.unseal(fh.read())  # written anew


def test_seal_round_trip_and_rejections():
    payload = b"\x00compiled code\xff" * 10
    assert cache.unseal(cache.seal(payload)) == payload
    for bad in (b"", payload, cache.seal(payload)[:-1], _flip_byte(cache.seal(payload))):
        with pytest.raises(ValueError):
            cache.unseal(bad)


@pytest.fixture(scope="module")
def cold_catalog(tmp_path_factory):
    """A fresh Numba cache filled by one run of ``HASH``, and that run's catalog digest (one
    cold compile, shared by the tests below)."""
    cache_dir = tmp_path_factory.mktemp("cold") / "numba_cache"
    digest, _ = _catalog_hash(cache_dir)
    return cache_dir, digest


def test_a_real_kernel_with_one_byte_changed_gives_the_same_catalog(tmp_path, cold_catalog):
    """The severe case: one changed byte of machine code ran and gave a different catalog."""
    import shutil

    cache_dir = tmp_path / "numba_cache"
    shutil.copytree(cold_catalog[0], cache_dir)
    # every kernel has its files; the entry kernel's code holds the kernels it calls
    (path,) = [
        os.path.join(d, f)
        for d, _, fs in os.walk(cache_dir)
        for f in fs
        if f.startswith("events.run_events_") and f.endswith(".nbc")
    ]
    with open(path, "rb") as fh:
        data = fh.read()
    with open(path, "wb") as fh:
        fh.write(_flip_byte(data))
    second, err = _catalog_hash(cache_dir)
    assert second == cold_catalog[1]
    assert err.count("discarded the damaged kernel cache file") == 1, err


HASH = """
import hashlib, faultnet
model = faultnet.CarlsonLanger(faultnet.graphs.ring(100))
events = faultnet.simulate(model, 2000, rng=1, progress=False).events
print(hashlib.sha256(events.to_csv().encode()).hexdigest())
"""


def _catalog_hash(cache_dir, env=None, cwd=None):
    env = dict(os.environ, NUMBA_CACHE_DIR=str(cache_dir), **(env or {}))
    out = subprocess.run(
        [sys.executable, "-c", HASH], env=env, capture_output=True, text=True, cwd=cwd
    )
    assert out.returncode == 0, out.stderr
    return out.stdout.strip().splitlines()[-1], out.stderr.strip()


def test_no_writable_cache_folder_runs_with_one_line(tmp_path, cold_catalog):
    """A shared install whose HOME and NUMBA_CACHE_DIR are read-only: no traceback."""
    import shutil

    import faultnet

    src = os.path.dirname(faultnet.__file__)
    shutil.copytree(
        src, tmp_path / "pkg" / "faultnet", ignore=shutil.ignore_patterns("__pycache__")
    )
    # every folder of kernels (faultnet/solver/_kernels and its subpackages) is read-only: its
    # __pycache__ cannot be made
    for folder, _, files in os.walk(tmp_path / "pkg" / "faultnet" / "solver" / "_kernels"):
        if any(f.endswith(".py") for f in files):
            (Path(folder) / "__pycache__").write_text("not a folder")
    blocker = tmp_path / "a-file"
    blocker.write_text("")
    env = {
        "PYTHONPATH": str(tmp_path / "pkg"),
        "HOME": str(blocker),  # ~/.cache cannot be made
        "XDG_CACHE_HOME": str(blocker / "cache"),
        "PYTHONDONTWRITEBYTECODE": "1",
    }
    digest, err = _catalog_hash(blocker / "numba", env, cwd=tmp_path)
    assert len(err.splitlines()) == 1 and "Traceback" not in err, err
    assert "no writable folder for the kernel cache" in err and "NUMBA_CACHE_DIR" in err
    assert digest == cold_catalog[1]
