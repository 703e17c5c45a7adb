"""RunOptions: validated once, recorded whole, round-tripped through plain values."""

import math

import networkx as nx
import pytest

import faultnet
from faultnet import InvalidParameterError, RunOptions
from faultnet.accuracy import graph_class, step_for_rtol


@pytest.mark.parametrize(
    "kwargs, match",
    [
        ({"method": "euler"}, "method must be one of"),
        ({"method": None}, "method must be one of"),
        ({"dt": "abc"}, "dt must be a finite real number; got 'abc'"),
        ({"dt": 0.0}, "dt must be finite and > 0"),
        ({"dt": True}, "dt must be a finite real number"),
        ({"solo_cache": "yes"}, "solo_cache must be True or False"),
        ({"local_regions_from": 0}, "local_regions_from must be an integer >= 1"),
        ({"local_regions_from": 2.5}, "local_regions_from must be an integer >= 1"),
        ({"max_velocity": -1.0}, "max_velocity must be finite and > 0"),
        ({"max_event_duration": float("nan")}, "max_event_duration must be a finite"),
    ],
)
def test_bad_options_name_the_option(kwargs, match):
    with pytest.raises(InvalidParameterError, match=match):
        RunOptions(**kwargs)


def test_round_trip_and_replace():
    opts = RunOptions(method="rk4", dt=0.01, local_regions_from=math.inf)
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
    # rk4 is not calibrated: the default rtol gives way to its fixed step, another is refused
    assert RunOptions(method="rk4").rtol is None
    assert RunOptions(method="rk4").step(model) == faultnet.default_dt(model, "rk4")
    with pytest.raises(InvalidParameterError, match="calibrated for method 'dopri5'"):
        RunOptions(method="rk4", rtol=1e-5)
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


def test_each_run_gets_the_entry_kernel_of_its_scheme_and_treatment():
    ring = faultnet.CarlsonLanger(faultnet.graphs.ring(2000))
    lattice = faultnet.CarlsonLanger(faultnet.graphs.square_lattice(30, 30, periodic=True))
    small = faultnet.CarlsonLanger(faultnet.graphs.square_lattice(8, 8, periodic=True))
    default = RunOptions()
    # rings: interpolated crossings where calibrated; exact elsewhere, without local regions
    assert default.treatment(ring) == "interpolated"
    assert default.entry(ring) == "run_events_dopri5_interpolated"
    slow = faultnet.CarlsonLanger(faultnet.graphs.ring(2000), alpha=0.1)
    assert default.treatment(slow) == "exact"
    assert default.regions_from(slow) == math.inf
    assert default.entry(slow) == "run_events_dopri5"
    # 2-D graphs: interpolated at the default rtol; regions from 32 blocks with exact crossings,
    # also on a sparse graph that the calibration counts as ring-like (mean degree <= 2.5)
    tree = faultnet.CarlsonLanger(nx.balanced_tree(2, 8))
    exact = RunOptions(crossings="exact")
    assert graph_class(tree) == "ring" and exact.entry(tree) == "run_events_dopri5_local"
    assert default.entry(lattice) == "run_events_dopri5_interpolated"
    assert default.regions_from(lattice) == 32
    assert RunOptions(crossings="exact").entry(lattice) == "run_events_dopri5_local"
    # a graph too small for any region (4 x 32 blocks or fewer) skips their code
    assert RunOptions(crossings="exact").entry(small) == "run_events_dopri5"
    # an explicit value holds on any graph
    assert RunOptions(local_regions_from=8, crossings="exact").entry(ring) == (
        "run_events_dopri5_local"
    )
    # ... and with interpolated crossings it has no effect, which a warning says
    with pytest.warns(UserWarning, match="local_regions_from=8 has no effect"):
        assert RunOptions(local_regions_from=8).entry(lattice) == "run_events_dopri5_interpolated"
    assert RunOptions(method="rk4").entry(lattice) == "run_events_rk4"
