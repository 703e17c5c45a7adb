"""Inputs that must be refused with a message naming the argument and the allowed values."""

import numpy as np
import pytest

import faultnet
from faultnet import InvalidParameterError
from faultnet.__main__ import main
from faultnet.model.state import State
from faultnet.solver.arrays import position_limit


@pytest.fixture(scope="module")
def ring10():
    return faultnet.CarlsonLanger(faultnet.graphs.ring(10))


def test_tiny_dt_refused_in_the_api(ring10):
    with pytest.raises(InvalidParameterError, match=r"dt=1e-300 is too small.*steps"):
        faultnet.simulate(ring10, 5, dt=1e-300, progress=False)


def test_tiny_dt_refused_on_the_command_line(capsys):
    rc = main(["simulate", "ring:10", "--events", "10", "--dt", "1e-12"])
    err = capsys.readouterr().err
    assert rc == 2
    assert "dt=1e-12 is too small" in err and "max_event_duration" in err
    assert "Traceback" not in err


@pytest.mark.parametrize(
    "x0, match",
    [
        (np.array(["a"] * 10), r"x0 must hold real numbers.*got an array of str"),
        (np.full(10, 1 + 1j), r"x0 must hold real numbers.*complex"),
        (["0.1"] * 10, r"x0 must hold real numbers"),
        (np.full(10, True), r"x0 must hold real numbers.*bool"),
    ],
)
def test_x0_of_strings_or_complex_numbers_refused(ring10, x0, match):
    with pytest.raises(InvalidParameterError, match=match):
        faultnet.simulate(ring10, 5, x0=x0, progress=False)


@pytest.mark.parametrize(
    "state, name",
    [
        (State(np.full(10, np.nan)), "x0.z"),
        (State(np.zeros(10), w=np.nan), "x0.w"),
        (State(np.zeros(10), offset=np.inf), "x0.offset"),
        (State(np.zeros(10), offset=0.5), "x0.offset"),
    ],
)
def test_state_with_nan_is_an_input_error_not_a_step_problem(ring10, state, name):
    with pytest.raises(InvalidParameterError) as info:
        faultnet.simulate(ring10, 5, x0=state, progress=False)
    assert name in str(info.value)
    assert "reduce dt" not in str(info.value)


@pytest.mark.parametrize("rng", [object(), "abc", True, 1.5])
def test_bad_rng_names_rng(ring10, rng):
    with pytest.raises(InvalidParameterError, match=r"rng must be None, an int >= 0"):
        faultnet.simulate(ring10, 5, rng=rng, progress=False)


def test_dt_string_names_dt(ring10):
    with pytest.raises(InvalidParameterError, match=r"dt must be a finite real number; got 'abc'"):
        faultnet.simulate(ring10, 5, dt="abc", progress=False)


def test_position_limit_follows_the_slip_scale(ring10):
    # ring(10), k=16, sigma=0.01: slip scale sigma/(1+2k) = 3.03e-4; ulp(x) <= 1e-6 of it
    scale = 0.01 / 33.0
    assert position_limit(ring10) == pytest.approx(1e-6 * scale / np.finfo(float).eps, rel=0.01)
    soft = faultnet.CarlsonLanger(faultnet.graphs.ring(10), k=1.0, sigma=0.5)
    assert position_limit(soft) > position_limit(ring10)


@pytest.mark.parametrize("value", [1e16, 1e20, -1e16])
def test_huge_displacements_refused_naming_the_limit(ring10, value):
    limit = position_limit(ring10)
    with pytest.raises(InvalidParameterError) as info:
        faultnet.simulate(ring10, 5, x0=np.full(10, value), progress=False)
    msg = str(info.value)
    assert "x0" in msg and f"{limit:.3g}" in msg and "float64" in msg


def test_huge_state_positions_refused(ring10):
    with pytest.raises(InvalidParameterError, match=r"x0\.z"):
        faultnet.simulate(ring10, 5, x0=State(np.full(10, 1e16)), progress=False)
    with pytest.raises(InvalidParameterError, match=r"x0\.offset"):
        faultnet.simulate(ring10, 5, x0=State(np.zeros(10), offset=1e20), progress=False)


def test_large_plate_offsets_of_long_runs_still_work(ring10):
    base = faultnet.simulate(ring10, 30, rng=4, progress=False)
    st = base.state
    shifted = State(st.z.copy(), st.offset + 1e7, st.w, st.n_events)
    a = faultnet.simulate(ring10, 20, x0=st, progress=False).events
    b = faultnet.simulate(ring10, 20, x0=shifted, progress=False).events
    # the frame keeps the dynamics exact: same sizes, times shifted by the offset
    np.testing.assert_array_equal(a["S"].to_numpy(), b["S"].to_numpy())
    np.testing.assert_allclose(b["t"].to_numpy() - 1e7, a["t"].to_numpy(), atol=1e-8)
    # absolute positions near a plate at 1e7 (x = u + small) are accepted too
    x = st.x + 1e7
    c = faultnet.simulate(ring10, 5, x0=State.from_x(x, u=st.u + 1e7), progress=False)
    assert len(c.events) == 5
    # ordinary large x0 (blocks far ahead of the plate) within the limit still run
    x0 = 1e3 + np.random.default_rng(1).uniform(0, 0.01, 10)
    d = faultnet.simulate(ring10, 3, x0=x0, progress=False)
    assert len(d.events) == 3 and d.events["t"].iloc[0] > 999.0


def test_state_from_x_checks_its_displacements():
    """A state is built only from one finite displacement per block."""
    with pytest.raises(InvalidParameterError, match=r"x must be 1-D.*\(2, 2\)"):
        State.from_x(np.zeros((2, 2)))
    with pytest.raises(InvalidParameterError, match=r"x must be 1-D.*\(0,\)"):
        State.from_x([])
    with pytest.raises(InvalidParameterError, match=r"non-finite entries at positions \[1\]"):
        State.from_x([0.0, np.inf, 0.1])
    st = State.from_x([0.1, 0.2], u=1.5)
    np.testing.assert_allclose(st.x, [0.1, 0.2])
    assert st.u == 1.5
