"""The OFC automaton in long runs, resume, extension, the command line and sweeps."""

import os

import pandas as pd
import pytest
from crash_hooks import Crash, crash_after

import faultnet
from faultnet.__main__ import main
from faultnet.exceptions import ConfigError, InvalidParameterError
from faultnet.runs.checkpoint import checkpoint_dir
from faultnet.runs.long_run import simulate_to_parquet
from faultnet.runs.spec_run import run_from_spec
from faultnet.runs.specs import build_model
from faultnet.runs.sweep.config import SweepConfig

N = 6000


@pytest.fixture(scope="module")
def ofc():
    model = faultnet.OFC.from_alpha(faultnet.graphs.square_lattice(12, 12, boundary="fixed"), 0.2)
    return model, faultnet.simulate(model, N, rng=4, progress=False)


def _run(model, out, n=N, **kw):
    kw = {"rng": 4, "chunk_events": 1000, "checkpoint_interval": 0, "progress": False, **kw}
    return simulate_to_parquet(model, n, out, **kw)


def test_a_long_run_equals_the_run_in_memory(tmp_path, ofc):
    model, ref = ofc
    out = str(tmp_path / "ofc.parquet")
    rep = _run(model, out, transient=None)
    cat = faultnet.read_catalog(out)
    pd.testing.assert_frame_equal(cat.events, ref.events)
    md = cat.metadata
    assert md["model"] == "ofc" and md["alpha"] == 0.2 and md["dt"] == 0.0
    assert md["n_topplings"] == int(ref.events["n_topplings"].sum())
    assert md["n_generations"] == int(ref.events["n_generations"].sum())
    assert md["initial_state"] == "random U[0, 1)"
    assert "drive 240" in rep.metadata["transient_rule"]  # 20 sqrt(144)
    more = faultnet.simulate(model, 50, x0=out, progress=False)  # a catalog continues
    whole = faultnet.simulate(model, N + 50, rng=4, progress=False)
    pd.testing.assert_frame_equal(more.events, whole.events.iloc[N:].reset_index(drop=True))


def test_resume_and_extension_are_bit_identical(tmp_path, ofc):
    model, ref = ofc
    out = str(tmp_path / "ofc.parquet")
    with pytest.raises(Crash):
        _run(model, out, n=3000, on_commit=crash_after(2))
    assert os.path.isdir(checkpoint_dir(out))
    assert _run(model, out, n=3000, resume=True).status == "resumed"
    assert _run(model, out, n=3000, resume=True).status == "already complete"
    assert _run(model, out, extend=True).status == "resumed"
    pd.testing.assert_frame_equal(faultnet.read_catalog(out).events, ref.events)


def test_a_catalog_of_the_other_model_is_refused(tmp_path, ofc):
    model, _ = ofc
    out = str(tmp_path / "cl.parquet")
    lattice = faultnet.graphs.square_lattice(12, 12, boundary="fixed")
    _run(faultnet.CarlsonLanger(lattice), out, n=100)
    with pytest.raises(InvalidParameterError, match="another graph or other parameters"):
        faultnet.simulate(model, 10, x0=out, progress=False)


def test_options_that_do_not_apply_are_refused(tmp_path, ofc):
    model, _ = ofc
    out = str(tmp_path / "ofc.parquet")
    with pytest.raises(InvalidParameterError, match="dt do not apply to an OFC model"):
        _run(model, out, dt=0.01)
    with pytest.raises(InvalidParameterError, match="options do not apply to an OFC model"):
        _run(model, out, options={"rtol": 1e-6})
    with pytest.raises(InvalidParameterError, match="record_slips does not apply"):
        _run(model, out, record_slips=True)
    assert not os.listdir(tmp_path)


def test_a_network_of_faults_gets_fault_columns_and_no_per_fault_slips(tmp_path):
    graph = faultnet.graphs.parallel_faults(2, 30, k_coupling=0.5, periodic=True)
    model = faultnet.OFC(graph, k=1.0)
    out = str(tmp_path / "net.parquet")
    _run(model, out, n=2000)
    events = faultnet.read_catalog(out).events
    assert {"fault", "n_faults"} <= set(events.columns) and events["n_faults"].max() == 2
    assert os.listdir(tmp_path) == ["net.parquet"]


def test_the_command_line_runs_resumes_and_refuses_friction(tmp_path, capsys):
    out = str(tmp_path / "ofc.parquet")
    args = ["simulate", "square:12x12:fixed", "--model", "ofc", "--ofc-alpha", "0.2"]
    assert main([*args, "-n", "3000", "--seed", "4", "--out", out, "--no-progress"]) == 0
    text = capsys.readouterr().out
    assert "OFC automaton, k=1.0 alpha=0.2" in text and "drive" in text
    assert main(["simulate", "--resume", "--out", out, "--no-progress"]) == 0
    assert "already complete" in capsys.readouterr().out
    model, ref = build_model("square:12x12:fixed", model="ofc", ofc_alpha=0.2), None
    ref = faultnet.simulate(model, 3000, rng=4, progress=False)
    pd.testing.assert_frame_equal(faultnet.read_catalog(out).events, ref.events)
    assert main([*args, "-n", "10", "--sigma", "0.1"]) == 2
    assert "sigma (--sigma) are the Carlson-Langer model's friction" in capsys.readouterr().err
    assert main(["simulate", "ring:20", "-n", "10", "--ofc-alpha", "0.2"]) == 2
    assert "--model ofc" in capsys.readouterr().err


def test_build_model_and_run_from_spec(tmp_path):
    assert build_model("square:8x8:fixed", model="ofc").k == 1.0
    assert build_model("square:8x8:fixed", model="ofc", k=0.5).k == 0.5
    with pytest.raises(InvalidParameterError, match="not both"):
        build_model("square:8x8:fixed", model="ofc", k=1.0, ofc_alpha=0.2)
    with pytest.raises(InvalidParameterError, match="model must be one of"):
        build_model("ring:8", model="olami")
    out = str(tmp_path / "ofc.parquet")
    rep = run_from_spec("square:8x8:fixed", 500, out, model="ofc", ofc_alpha=0.2, seed=1,
                        progress=False)  # fmt: skip
    assert rep.metadata["request"]["model"] == "ofc"
    again = run_from_spec(None, None, out, resume=True, progress=False)
    assert again.status == "already complete"


def test_a_sweep_of_the_automaton(tmp_path):
    cfg = SweepConfig.from_dict(
        {
            "graph": "square:8x8:fixed",
            "model": "ofc",
            "ofc_alpha": [0.15, 0.2],
            "events": 800,
            "seed": 2,
        }  # fmt: skip
    )
    points = cfg.points()
    assert [(p["model"], p["ofc_alpha"]) for p in points] == [("ofc", 0.15), ("ofc", 0.2)]
    table = faultnet.sweep(cfg, str(tmp_path / "s"), workers=1, progress=False)
    assert list(table["model"]) == ["ofc", "ofc"] and list(table["alpha"]) == [0.15, 0.2]
    with pytest.raises(ConfigError, match="not parameters of the OFC automaton"):
        SweepConfig.from_dict({"graph": "ring:8", "model": "ofc", "sigma": 0.1, "events": 10})
    with pytest.raises(ConfigError, match='add model = "ofc"'):
        SweepConfig.from_dict({"graph": "ring:8", "ofc_alpha": 0.2, "events": 10})
    with pytest.raises(ConfigError, match="sweep.model: expected one of"):
        SweepConfig.from_dict({"graph": "ring:8", "model": "ofc2", "events": 10})


def test_the_sweep_command_shows_the_model(tmp_path, capsys):
    config = tmp_path / "ofc.toml"
    config.write_text(
        '[sweep]\ngraph = "square:8x8:fixed"\nmodel = "ofc"\nofc_alpha = 0.2\nevents = 500\n'
        "seed = 1\n"
    )
    assert main(["sweep", str(config), "-j", "1", "--no-progress"]) == 0
    lines = capsys.readouterr().out.splitlines()
    header = next(line.split() for line in lines if line.split()[:3] == ["point", "graph", "model"])
    assert "sigma" not in header
