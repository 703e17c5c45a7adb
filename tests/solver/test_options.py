"""RunOptions: validated once, recorded whole, round-tripped through plain values."""

import math

import networkx as nx
import pytest

import faultnet
from faultnet import InvalidParameterError, RunOptions
from faultnet.solver.accuracy import graph_class, step_for_rtol
from faultnet.solver.step_size import REMOVED


@pytest.mark.parametrize(
    "kwargs, match",
    [
        ({"method": "euler"}, "method must be one of"),
        ({"method": None}, "method must be one of"),
        ({"dt": "abc"}, "dt must be a finite real number; got 'abc'"),
        ({"dt": 0.0}, "dt must be finite and > 0"),
        ({"dt": True}, "dt must be a finite real number"),
        ({"solo_cache": False}, "solo_cache is no longer a run option"),
        ({"max_velocity": -1.0}, "max_velocity must be finite and > 0"),
        ({"max_event_duration": float("nan")}, "max_event_duration must be a finite"),
    ],
)
def test_bad_options_name_the_option(kwargs, match):
    with pytest.raises(InvalidParameterError, match=match):
        RunOptions(**kwargs)


def test_removed_method_rk4_names_what_to_use_instead():
    with pytest.raises(InvalidParameterError) as err:
        RunOptions(method="rk4")
    msg = str(err.value)
    assert msg == REMOVED["method='rk4'"]
    assert "removed" in msg and "'dopri5'" in msg and "dt=" in msg and "rtol=" in msg
    # everywhere a method is taken
    model = faultnet.CarlsonLanger(faultnet.graphs.ring(10), k=16, sigma=0.01, alpha=1.0)
    with pytest.raises(InvalidParameterError, match=r"method='rk4' was removed"):
        faultnet.default_dt(model, "rk4")
    with pytest.raises(InvalidParameterError, match=r"method='rk4' was removed"):
        RunOptions().replace(method="rk4")
    with pytest.raises(InvalidParameterError, match=r"method='rk4' was removed"):
        RunOptions.from_dict({"method": "rk4", "dt": 0.01})
    with pytest.raises(InvalidParameterError, match=r"method='rk4' was removed"):
        faultnet.simulate(model, 5, rng=1, progress=False, method="rk4")
    # another unknown method gets the list of methods, not the removal notice
    with pytest.raises(InvalidParameterError, match=r"method must be one of \['dopri5'\]"):
        RunOptions(method="rk45")


@pytest.mark.parametrize("value", [None, 8, math.inf, 0])
def test_removed_local_regions_from_names_what_to_use_instead(value):
    with pytest.raises(InvalidParameterError) as err:
        RunOptions(local_regions_from=value)
    msg = str(err.value)
    assert msg == REMOVED["local_regions_from"]
    assert "removed" in msg and "crossings='interpolated'" in msg and "crossings='exact'" in msg
    with pytest.raises(InvalidParameterError, match="local_regions_from was removed"):
        RunOptions(dt=0.01).replace(local_regions_from=value)


def test_records_of_faultnet_0_2_load_where_local_regions_had_no_effect():
    """``from_dict`` drops ``local_regions_from`` when it was None or inf, refuses a number."""
    want = RunOptions(dt=0.01, crossings="exact")
    for value in (None, "inf", "Infinity", math.inf):
        old = dict(want.to_dict(), local_regions_from=value)
        assert RunOptions.from_dict(old) == want
    for value in (8, 32.0, "8"):
        with pytest.raises(InvalidParameterError, match="local_regions_from was removed"):
            RunOptions.from_dict(dict(want.to_dict(), local_regions_from=value))
    assert "local_regions_from" not in want.to_dict()


def test_records_with_the_solo_cache_option_load_where_it_was_on():
    want = RunOptions(dt=0.01, crossings="exact")
    assert RunOptions.from_dict(dict(want.to_dict(), solo_cache=True)) == want
    with pytest.raises(InvalidParameterError, match=r"Simulator\(model, ..., solo_cache=False\)"):
        RunOptions.from_dict(dict(want.to_dict(), solo_cache=False))
    assert "solo_cache" not in want.to_dict() and "solo_cache" not in repr(want)
    ring = faultnet.CarlsonLanger(faultnet.graphs.ring(10))
    with pytest.raises(InvalidParameterError, match="solo_cache must be True or False; got 'no'"):
        faultnet.Simulator(ring, rng=1, solo_cache="no")


def test_round_trip_and_replace():
    opts = RunOptions(dt=0.01, crossings="exact")
    assert RunOptions.from_dict(opts.to_dict()) == opts
    assert opts.replace(dt=None).dt is None and opts.dt == 0.01  # frozen
    with pytest.raises(InvalidParameterError, match="unknown run option"):
        RunOptions.from_dict({"dt": 0.1, "tol": 1})


def test_step_resolution():
    model = faultnet.CarlsonLanger(faultnet.graphs.ring(10), k=16, sigma=0.01, alpha=1.0)
    calibrated = step_for_rtol(model, 1e-6)  # the default rtol
    assert RunOptions().step(model) == calibrated.dt
    assert RunOptions().treatment(model) == calibrated.crossings
    assert RunOptions(rtol=None).step(model) == faultnet.default_dt(model)
    assert RunOptions(rtol=None).treatment(model) == "exact"
    assert RunOptions(dt=1e-3).step(model) == 1e-3
    # a chosen treatment runs at its own calibrated step, not the other one's
    for crossings in ("exact", "interpolated"):
        own = step_for_rtol(model, 2e-5, crossings=crossings)
        opts = RunOptions(rtol=2e-5, crossings=crossings)
        assert (opts.step(model), opts.treatment(model)) == (own.dt, crossings)
    assert (
        step_for_rtol(model, 2e-5, crossings="interpolated").dt
        < step_for_rtol(model, 2e-5, crossings="exact").dt
    )
    with pytest.raises(InvalidParameterError, match="crossings must be one of"):
        step_for_rtol(model, 1e-6, crossings="linear")
    with pytest.raises(InvalidParameterError, match="stability limit"):
        RunOptions(dt=1.0).step(model)
    # a step that cannot finish an event in a bounded number of steps is refused
    with pytest.raises(InvalidParameterError, match="too small"):
        RunOptions(dt=1e-300).step(model)


def test_each_run_gets_the_entry_kernel_of_its_treatment():
    ring = faultnet.CarlsonLanger(faultnet.graphs.ring(2000))
    lattice = faultnet.CarlsonLanger(faultnet.graphs.square_lattice(30, 30, periodic=True))
    small = faultnet.CarlsonLanger(faultnet.graphs.square_lattice(8, 8, periodic=True))
    default = RunOptions()
    # rings: interpolated crossings where calibrated; exact elsewhere
    assert default.treatment(ring) == "interpolated"
    assert default.entry(ring) == "run_events_dopri5_interpolated"
    slow = faultnet.CarlsonLanger(faultnet.graphs.ring(2000), alpha=0.1)
    assert default.treatment(slow) == "exact"
    assert default.entry(slow) == "run_events_dopri5"
    # 2-D graphs: interpolated at the default rtol, whatever their size; also a sparse graph
    # that the calibration counts as ring-like (mean degree <= 2.5)
    tree = faultnet.CarlsonLanger(nx.balanced_tree(2, 8))
    assert graph_class(tree) == "ring"
    for model in (lattice, small, tree):
        assert default.entry(model) == "run_events_dopri5_interpolated"
        # an explicit treatment holds on any graph
        assert RunOptions(crossings="exact").entry(model) == "run_events_dopri5"
    assert RunOptions(crossings="interpolated").entry(slow) == "run_events_dopri5_interpolated"
    # a fixed step without a treatment: exact crossings
    assert RunOptions(rtol=None).entry(lattice) == "run_events_dopri5"
