"""The cold-cache compile helper: its recorded order is current, and it changes no result.

Both tests compile from an empty Numba cache in subprocesses (about 20-30 s each).
"""

import json
import os
import subprocess
import sys
import tempfile

import numba
import numpy as np

import faultnet
from faultnet import _compile_helper, _compile_order
from faultnet._system import usable_cores


def test_recorded_order_is_what_a_cold_compile_does(tmp_path):
    """``_compile_order.ORDER`` is current (regenerate: ``python -m faultnet._compile_helper
    --record``); a stale list would only make the helper compile the wrong things."""
    order = _compile_helper.record(tmp_path / "order.py")
    assert _compile_order.ENTRY == "run_events_dopri5"
    assert [row[:3] for row in order] == [row[:3] for row in _compile_order.ORDER]
    assert len(order) > 20


def _cold_run(helper):
    code = (
        "import json, faultnet\n"
        "from numba.core import event\n"
        "from faultnet import _compile_helper as h\n"
        "compiled = []\n"
        "class L(event.Listener):\n"
        "    def on_start(self, e): compiled.append(e.data['dispatcher'].py_func.__name__)\n"
        "    def on_end(self, e): pass\n"
        "event.register('numba:compile', L())\n"
        "m = faultnet.CarlsonLanger(faultnet.graphs.ring(10), alpha=1.5)\n"
        "res = faultnet.simulate(m, 50, rng=3, progress=False)\n"
        "print(json.dumps([res.events.S.tolist(), h._proc is None, h._launched, compiled]))\n"
    )
    with tempfile.TemporaryDirectory() as cache:
        env = dict(os.environ, NUMBA_CACHE_DIR=cache, **{_compile_helper.ENV: helper})
        out = subprocess.check_output([sys.executable, "-c", code], env=env)
        files = os.listdir(cache)
    return json.loads(out.decode().strip().splitlines()[-1]), files


def test_helper_runs_on_a_cold_cache_and_changes_nothing():
    (s_helped, stopped, launched, compiled), files = _cold_run("1")
    assert launched == (usable_cores() >= 2)
    assert stopped  # the helper is gone once the run has its kernel
    mine = [name for name in compiled if name in {row[1] for row in _compile_order.ORDER}]
    if launched:  # the main process loaded what the helper compiled (the cache keys match)
        assert len(mine) < len(_compile_order.ORDER) - 5, mine
    assert files  # the cache was written
    m = faultnet.CarlsonLanger(faultnet.graphs.ring(10), alpha=1.5)
    ref = faultnet.simulate(m, 50, rng=3, progress=False).events.S.to_numpy()
    np.testing.assert_array_equal(s_helped, ref)


def test_helper_takes_the_list_in_order_without_the_spine():
    order = [
        ("m", "a", (), False),
        ("m", "b", (), False),
        ("m", "spine1", (), True),
        ("m", "c", (), False),
        ("m", "d", (), False),
        ("m", "spine2", (), True),
        ("m", "e", (), False),
    ]
    got = [row[1] for row in _compile_helper.helper_order(order)]
    assert got == ["a", "b", "c", "d", "e"]
    assert _compile_helper.helper_order([]) == []


@numba.njit(cache=True)
def _never_compiled(x):
    return x + 1


def test_cache_is_cold():
    assert _compile_helper.cache_is_cold(_never_compiled)  # nothing in its on-disk cache
    faultnet.simulate(faultnet.CarlsonLanger(faultnet.graphs.ring(10)), 2, rng=1, progress=False)
    from faultnet import _kernels

    assert not _compile_helper.cache_is_cold(_kernels.run_events_dopri5)  # just compiled
    assert not _compile_helper.cache_is_cold(_never_compiled.py_func)  # no JIT: never cold


def test_progress_bar_says_when_the_first_run_compiles(monkeypatch, capsys):
    from faultnet.engine import COMPILING_LABEL

    model = faultnet.CarlsonLanger(faultnet.graphs.ring(10))
    faultnet.simulate(model, 2, rng=1, progress=False)  # compiled and cached from here on
    capsys.readouterr()
    faultnet.simulate(model, 5, rng=1, progress=True)
    assert COMPILING_LABEL not in capsys.readouterr().err
    monkeypatch.setattr(_compile_helper, "cache_is_cold", lambda kernel: True)  # a cold cache
    faultnet.simulate(model, 5, rng=1, progress=True)
    assert COMPILING_LABEL in capsys.readouterr().err
