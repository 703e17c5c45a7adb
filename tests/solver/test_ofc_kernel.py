"""The OFC kernel and its simulator: continuation, ties, guards, options and uncompiled runs."""

import json
import os
import subprocess
import sys

import numpy as np
import pytest

import faultnet
from faultnet.exceptions import CatalogError, EventTooLongError, InvalidParameterError
from faultnet.solver import _kernels
from faultnet.solver.ofc import OFC_COLUMNS, OFCSimulator


def _fixed(L=12, alpha=0.2):
    return faultnet.OFC.from_alpha(faultnet.graphs.square_lattice(L, L, boundary="fixed"), alpha)


def test_two_halves_equal_one_run_bit_for_bit():
    model = _fixed(10)
    whole = faultnet.simulate(model, 4000, rng=11, progress=False)
    assert whole.state.offset > 0  # the frame moved (the drive passed OFC_RECENTRE_AT)
    first = faultnet.simulate(model, 2000, rng=11, progress=False)
    second = faultnet.simulate(model, 2000, x0=first.state, progress=False)
    assert second.events.event.iloc[0] == 2000
    joined = np.concatenate([first.events.to_numpy(), second.events.to_numpy()])
    assert np.array_equal(joined, whole.events.to_numpy())
    assert np.array_equal(second.state.z, whole.state.z)
    assert (second.state.offset, second.state.w) == (whole.state.offset, whole.state.w)
    # from a result too, and a simulator advanced in parts
    again = faultnet.simulate(model, 2000, x0=first, progress=False)
    assert again.events.equals(second.events)
    sim = OFCSimulator(model, rng=11)
    parts = [sim.advance(n, progress=False).events for n in (1, 999, 3000)]
    assert np.array_equal(np.concatenate([p.to_numpy() for p in parts]), whole.events.to_numpy())


def test_drive_is_recentred_exactly():
    model = faultnet.OFC(faultnet.graphs.chain(1), k=1.0)
    res = faultnet.simulate(model, 20, x0=[0.5], progress=False)
    np.testing.assert_array_equal(res.events.t, 0.5 + np.arange(20))
    assert res.state.offset == 16.0 and res.state.w == 3.5
    assert model.forces(res.state)[0] == 0.0


def test_a_uniform_start_topples_every_block_in_one_generation():
    model = faultnet.OFC(faultnet.graphs.square_lattice(6, 6, periodic=True), k=1.0)
    row = faultnet.simulate(model, 1, x0=np.full(36, 0.5), progress=False).events.iloc[0]
    assert (row.n_topplings, row.n_blocks, row.n_generations, row.hypocenter) == (36, 36, 1, 0)
    assert row.S == pytest.approx(36 / 5) and row.t == 0.5


def test_metadata_and_columns():
    model = _fixed(8)
    res = faultnet.simulate(model, 300, rng=np.random.default_rng(5), progress=False)
    assert list(res.events.columns) == OFC_COLUMNS
    md = res.metadata
    assert md["model"] == "ofc" and md["alpha"] == 0.2 and md["initial_state"] == "random U[0, 1)"
    assert md["n_topplings"] == res.events.n_topplings.sum() and md["n_events"] == 300
    assert md["options"] == {"max_topplings": None} and md["wall_time_s"] >= 0
    # a Generator tells its SeedSequence from NumPy 1.25 on (bit_generator.seed_seq)
    has_seq = hasattr(np.random.default_rng(0).bit_generator, "seed_seq")
    assert md["seed_entropy"] == (5 if has_seq else None)
    assert res.dt == 0.0 and res.events.S.gt(0).all() and res.events.t.is_monotonic_increasing
    np.testing.assert_allclose(res.events.M, np.log(res.events.S))
    seeded = faultnet.simulate(model, 10, rng=7, progress=False)
    assert seeded.metadata["seed_entropy"] == 7 and seeded.seed == 7
    assert faultnet.simulate(model, 10, rng=7, progress=False).events.equals(seeded.events)
    given = faultnet.simulate(model, 10, x0=np.zeros(64), progress=False)
    assert given.metadata["seed_entropy"] is None and given.metadata["initial_state"] == "given"


def test_forces_stay_below_the_threshold_and_non_negative():
    model = _fixed(9)
    res = faultnet.simulate(model, 3000, rng=2, progress=False)
    F = model.forces(res.state)
    assert F.max() < 1.0 and F.min() > -1e-12


def test_progress_bar_and_compiles_flag(capsys):
    model = _fixed(5)
    sim = OFCSimulator(model, rng=1)
    assert sim.compiles in (True, False)
    sim.advance(50, progress=True)
    assert sim.compiles is False
    assert sim.model is model and sim.seed.entropy == 1


def test_max_topplings_stops_with_a_clear_error():
    model = faultnet.OFC(faultnet.graphs.square_lattice(6, 6, periodic=True), k=1.0)
    with pytest.raises(EventTooLongError, match=r"avalanche 0 \(hypocentre 0\) took more than"):
        faultnet.simulate(model, 5, x0=np.full(36, 0.5), max_topplings=10, progress=False)
    ok = faultnet.simulate(model, 5, x0=np.full(36, 0.5), max_topplings=36, progress=False)
    assert ok.metadata["options"] == {"max_topplings": 36}


@pytest.mark.parametrize(
    "kwargs, match",
    [
        ({"dt": 0.1}, "dt does not apply to an OFC model"),
        ({"rtol": 1e-6}, "rtol does not apply"),
        ({"method": "dopri5"}, "method does not apply"),
        ({"options": {}}, "options does not apply"),
        ({"record_slips": True}, "record_slips does not apply"),
        ({"record_profiles": True}, "record_profiles does not apply"),
        ({"trace_nodes": [0]}, "trace_nodes does not apply"),
        ({"max_topplings": 0}, "max_topplings must be an integer >= 1"),
        ({"x0": np.zeros(5)}, r"shape \(16,\)"),
        ({"x0": np.full(16, 1.0)}, r"forces in \[0, 1\)"),
        ({"x0": np.full(16, -0.1)}, r"forces in \[0, 1\)"),
        ({"x0": np.full(16, np.nan)}, r"forces in \[0, 1\)"),
        ({"x0": ["a"] * 16}, "real numbers in"),
        ({"x0": faultnet.State(np.zeros(16), 0.0, 0.0)}, "at or over the threshold"),
        ({"x0": faultnet.State(np.ones(16), 0.5, 0.0)}, "offset must be a whole number"),
        ({"rng": -1}, "rng must be"),
    ],
)
def test_bad_run_arguments_get_one_clear_error(kwargs, match):
    with pytest.raises(InvalidParameterError, match=match):
        faultnet.simulate(_fixed(4), 3, progress=False, **kwargs)


def test_a_missing_catalog_is_named():
    with pytest.raises(CatalogError, match="catalog missing.parquet does not exist"):
        faultnet.simulate(_fixed(4), 3, x0="missing.parquet", progress=False)


def test_other_models_and_results_are_refused():
    cl = faultnet.CarlsonLanger(faultnet.graphs.square_lattice(4, 4))
    with pytest.raises(InvalidParameterError, match="model must be an OFC"):
        OFCSimulator(cl)
    cl_result = faultnet.simulate(cl, 3, rng=1, progress=False)
    with pytest.raises(InvalidParameterError, match="result of a CarlsonLanger cannot start"):
        faultnet.simulate(_fixed(4), 3, x0=cl_result, progress=False)
    with pytest.raises(InvalidParameterError, match="max_topplings applies to an OFC model"):
        faultnet.simulate(cl, 3, rng=1, max_topplings=5, progress=False)
    with pytest.raises(InvalidParameterError, match="n_events must be an integer"):
        faultnet.simulate(_fixed(4), 0, progress=False)


def test_the_kernel_names_are_registered():
    assert _kernels.OFC_STATUS_OK == 0 and _kernels.OFC_STATUS_TOO_MANY_TOPPLINGS != 0
    assert callable(_kernels.run_ofc) and _kernels.OFC_RECENTRE_AT == 4.0


UNCOMPILED = """
import json, sys
import numba
import faultnet
from faultnet.solver._kernels import ofc

assert numba.config.DISABLE_JIT and not hasattr(ofc.run_ofc, "py_func")
g = faultnet.graphs.parallel_faults(2, 12, k_coupling=0.5)
for v in list(g)[:6]:
    g.nodes[v]["wall"] = 1
model = faultnet.OFC(g, k=1.3)
r = faultnet.simulate(model, int(sys.argv[1]), rng=4, progress=False)
ev = r.events
print(json.dumps({
    "S": [float(x).hex() for x in ev.S],
    "t": [float(x).hex() for x in ev.t],
    "counts": ev[["n_topplings", "n_blocks", "n_generations", "n_faults"]].values.tolist(),
    "z": [float(x).hex() for x in r.state.z],
    "offset": r.state.offset,
}))
"""


def test_uncompiled_run_gives_the_compiled_catalog():
    n = 400
    env = dict(os.environ, NUMBA_DISABLE_JIT="1")
    out = subprocess.run(
        [sys.executable, "-c", UNCOMPILED, str(n)],
        env=env,
        capture_output=True,
        text=True,
        timeout=600,
    )
    assert out.returncode == 0, out.stderr
    plain = json.loads(out.stdout.strip().splitlines()[-1])
    g = faultnet.graphs.parallel_faults(2, 12, k_coupling=0.5)
    for v in list(g)[:6]:
        g.nodes[v]["wall"] = 1
    r = faultnet.simulate(faultnet.OFC(g, k=1.3), n, rng=4, progress=False)
    ev = r.events
    assert r.state.offset > 0 and plain["offset"] == r.state.offset
    assert plain["S"] == [float(x).hex() for x in ev.S]
    assert plain["t"] == [float(x).hex() for x in ev.t]
    assert (
        plain["counts"]
        == ev[["n_topplings", "n_blocks", "n_generations", "n_faults"]].values.tolist()
    )
    assert plain["z"] == [float(x).hex() for x in r.state.z]
