"""nu and eta in what carries a run: its identity (resume, extension, finished output), the
request of a spec run, and sweeps.  No run here has nu or eta other than 0."""

import json
import os
import types

import numpy as np
import pytest
from crash_hooks import Crash, crash_after

import faultnet
from faultnet.exceptions import ConfigError, InvalidParameterError, OutputExistsError
from faultnet.io.parquet import read_catalog, read_metadata
from faultnet.model.identity import graph_hash
from faultnet.runs import spec_run
from faultnet.runs.checkpoint import checkpoint_dir, prepare_resume
from faultnet.runs.identity import IDENTITY, IDENTITY_DEFAULTS, mismatch, run_identity
from faultnet.runs.long_run import simulate_to_parquet
from faultnet.runs.sweep import driver
from faultnet.runs.sweep.config import SweepConfig, as_config
from faultnet.runs.sweep.folder import prepare_out
from faultnet.runs.sweep.summary import SUMMARY_COLUMNS, failed_row, summarize

SEQ = np.random.SeedSequence(5)


def _identity(model, n_events=100):
    """The identity of a run of ``model`` (with one step for all, which the models here would
    choose apart)."""
    return run_identity(model, n_events, 0.01, faultnet.RunOptions(), SEQ)


@pytest.fixture
def ring():
    return faultnet.CarlsonLanger(faultnet.graphs.ring(30), alpha=1.5)


# --------------------------------------------------------------------------- identity


def test_identity_records_nu_and_eta_only_where_not_zero(ring):
    plain = _identity(ring)
    assert "nu" not in plain and "eta" not in plain
    assert set(plain) == set(IDENTITY) - {"nu", "eta"}
    assert _identity(ring.with_params(nu=0.0, eta=0.0)) == plain
    both = _identity(ring.with_params(nu=0.01, eta=0.1))
    assert (both["nu"], both["eta"]) == (0.01, 0.1)
    assert type(both["nu"]) is float
    assert IDENTITY_DEFAULTS["nu"] == IDENTITY_DEFAULTS["eta"] == 0.0


def test_files_without_nu_and_eta_read_as_zero(ring):
    plain = _identity(ring)
    old = {key: value for key, value in plain.items()}  # as written before nu and eta
    assert mismatch(old, plain) == []
    assert mismatch(dict(old, nu=0.0, eta=0.0), plain) == []  # an extension's run.json
    assert mismatch(plain, dict(old, nu=0.0)) == []


@pytest.mark.parametrize(
    "stored, call, names",
    [
        ({"nu": 0.01}, {}, ["nu", "graph_hash"]),
        ({}, {"nu": 0.01}, ["nu", "graph_hash"]),
        ({"nu": 0.01}, {"nu": 0.02}, ["nu", "graph_hash"]),
        ({"eta": 0.1}, {}, ["eta", "graph_hash"]),
        ({"eta": 0.1}, {"eta": 0.2}, ["eta", "graph_hash"]),
        ({"nu": 0.01, "eta": 0.1}, {"nu": 0.01}, ["eta", "graph_hash"]),
    ],
)
def test_another_nu_or_eta_is_another_run(ring, stored, call, names):
    a, b = _identity(ring.with_params(**stored)), _identity(ring.with_params(**call))
    diffs = mismatch(a, b)
    assert [d.split(":")[0] for d in diffs] == names
    first = names[0]
    assert diffs[0] == (
        f"{first}: checkpoint has {float(stored.get(first, 0.0))!r}, this call "
        f"{float(call.get(first, 0.0))!r}"
    )


def test_per_edge_eta_is_in_the_graph_hash():
    g = faultnet.graphs.ring(10)
    g.edges[0, 1]["eta"] = 0.5
    h = faultnet.graphs.ring(10)
    h.edges[0, 1]["eta"] = 0.6
    a = _identity(faultnet.CarlsonLanger(g, eta=0.1))
    b = _identity(faultnet.CarlsonLanger(h, eta=0.1))
    assert [d.split(":")[0] for d in mismatch(a, b)] == ["graph_hash"]


def test_a_checkpoint_of_another_nu_is_not_resumed(ring, tmp_path):
    wd = tmp_path / "cat.parquet.checkpoint"
    wd.mkdir()
    stored = _identity(ring.with_params(nu=0.01))
    with pytest.raises(InvalidParameterError) as err:
        prepare_resume(str(wd), _identity(ring), stored)
    assert str(err.value).startswith(f"cannot resume {wd}: it is another run (nu: checkpoint has ")
    assert "nu: checkpoint has 0.01, this call 0.0" in str(err.value)
    assert "force" in str(err.value)


def _run(model, out, **kw):
    kw = {"rng": 5, "chunk_events": 100, "checkpoint_interval": 0, "progress": False, **kw}
    kw.setdefault("dt", 0.02)  # one step for all models: only nu and eta differ
    return simulate_to_parquet(model, 400, out, **kw)


def test_a_run_with_nu_and_eta_zero_writes_what_it_wrote(ring, tmp_path):
    out = tmp_path / "cat.parquet"
    with pytest.raises(Crash):
        _run(ring, out, on_commit=crash_after(2))
    with open(os.path.join(checkpoint_dir(out), "run.json"), encoding="utf-8") as fh:
        run = json.load(fh)
    assert "nu" not in run and "eta" not in run
    rep = _run(ring, out, resume=True)
    assert rep.status == "resumed"
    md = read_metadata(out)
    assert not {"nu", "eta", "eta_heterogeneous"} & set(md)
    assert md["graph_hash"] == graph_hash(ring)
    assert _run(ring.with_params(nu=0.0, eta=0.0), out, resume=True).status == "already complete"


def test_resuming_with_another_nu_or_eta_is_refused(ring, tmp_path):
    """The refusals come before any event of the model with nu or eta is run."""
    out = tmp_path / "cat.parquet"
    with pytest.raises(Crash):
        _run(ring, out, on_commit=crash_after(2))
    with pytest.raises(InvalidParameterError, match=r"another run \(nu: checkpoint has 0\.0, this"):
        _run(ring.with_params(nu=0.01), out, resume=True)
    with pytest.raises(InvalidParameterError, match=r"another run \(eta: checkpoint has 0\.0, th"):
        _run(ring.with_params(eta=0.1), out, resume=True)
    # a checkpoint written with nu = 0.01 (its run.json says so) refuses nu = 0
    run_json = os.path.join(checkpoint_dir(out), "run.json")
    with open(run_json, encoding="utf-8") as fh:
        run = json.load(fh)
    with open(run_json, "w", encoding="utf-8") as fh:
        json.dump(dict(run, nu=0.01), fh)
    with pytest.raises(
        InvalidParameterError, match=r"\(nu: checkpoint has 0\.01, this call 0\.0\)"
    ):
        _run(ring, out, resume=True)
    with open(run_json, "w", encoding="utf-8") as fh:
        json.dump(run, fh)
    assert _run(ring, out, resume=True).status == "resumed"
    with pytest.raises(OutputExistsError, match=r"holds another run \(nu: checkpoint has 0\.0"):
        _run(ring.with_params(nu=0.01), out, resume=True)  # the finished output


# --------------------------------------------------------------------------- spec runs


def test_spec_run_refuses_nu_and_eta_of_the_automaton():
    with pytest.raises(InvalidParameterError, match=r"^nu and eta \(--nu and --eta\) belong"):
        spec_run.run_from_spec("square:8x8:fixed", 10, None, model="ofc", nu=0.01, eta=0.0)
    with pytest.raises(InvalidParameterError, match=r"^eta \(--eta\) belongs .* OFC automaton"):
        spec_run.run_from_spec("square:8x8:fixed", 10, None, model="ofc", eta=0.1)


def test_spec_run_builds_the_model_with_nu_and_eta(monkeypatch):
    seen = {}

    def fake(model, n_events, out, **kw):
        seen.update(model=model, request=kw["metadata"]["request"])
        return "report"

    monkeypatch.setattr(spec_run, "simulate_to_parquet", fake)
    assert spec_run.run_from_spec("ring:10", 5, None, alpha=2.0, nu=0.01, eta=0.1) == "report"
    assert (seen["model"].nu, seen["model"].eta, seen["model"].alpha) == (0.01, 0.1, 2.0)
    assert (seen["request"]["nu"], seen["request"]["eta"]) == (0.01, 0.1)
    spec_run.run_from_spec("ring:10", 5, None, nu=0.0)  # 0: the request of before
    assert "nu" not in seen["request"] and "eta" not in seen["request"]
    assert seen["model"].nu == 0.0
    with pytest.raises(InvalidParameterError, match="nu must be finite and >= 0"):
        spec_run.run_from_spec("ring:10", 5, None, nu=-1.0)


def test_resume_takes_the_stored_nu_and_refuses_another():
    run = types.SimpleNamespace(
        stored={"request": {"graph": "ring:10", "n_events": 5, "nu": 0.01, "eta": 0.1}},
        out="cat.parquet",
        stored_seed=lambda: None,
    )
    given = dict.fromkeys(spec_run._REQUEST_KEYS)
    spec_run._take_stored(given, None, None, run)
    assert (given["nu"], given["eta"]) == (0.01, 0.1)
    given = dict.fromkeys(spec_run._REQUEST_KEYS)
    given["nu"] = 0.0
    with pytest.raises(InvalidParameterError, match=r"nu: checkpoint has 0\.01, this call 0\.0"):
        spec_run._take_stored(given, None, None, run)


# --------------------------------------------------------------------------- sweeps


def test_sweep_lists_nu_and_eta():
    cfg = SweepConfig.from_dict(
        {"graph": "ring:10", "alpha": [1.0, 2.0], "nu": [0, 0.01], "eta": 0.1, "events": 10,
         "seed": 3}
    )  # fmt: skip
    assert cfg.nu == [0.0, 0.01] and cfg.eta == [0.1]
    points = cfg.points()
    assert [(p["alpha"], p["nu"], p["eta"]) for p in points] == [
        (1.0, 0.0, 0.1), (1.0, 0.01, 0.1), (2.0, 0.0, 0.1), (2.0, 0.01, 0.1),
    ]  # fmt: skip
    assert cfg.defining()["nu"] == [0.0, 0.01] and cfg.defining()["eta"] == [0.1]
    assert as_config(cfg, {"events": 10}).points() == points  # rebuilt from its settings


def test_sweeps_without_nu_and_eta_keep_their_points():
    cfg = SweepConfig.from_dict({"graph": "ring:10", "alpha": [1.0, 2.0], "events": 10, "seed": 3})
    assert cfg.nu == [None] and cfg.eta == [None]
    assert all("nu" not in p and "eta" not in p for p in cfg.points())
    assert "nu" not in cfg.defining() and "eta" not in cfg.defining()
    assert set(cfg.points()[0]) == {
        "index", "graph", "k", "sigma", "alpha", "dt", "replica", "events", "seed_entropy",
        "spawn_key",
    }  # fmt: skip


@pytest.mark.parametrize(
    "table, match",
    [
        ({"nu": -0.1}, r"sweep\.nu: -0\.1 is not allowed; nu must be >= 0"),
        ({"eta": [0.1, "x"]}, r"sweep\.eta: expected a number or a list of numbers"),
        ({"eta": []}, r"sweep\.eta: expected a number or a non-empty list"),
        ({"nu": float("nan")}, r"sweep\.nu: expected a number"),
        ({"model": "ofc", "nu": 0.01}, r"sweep\.nu: not parameters of the OFC automaton"),
        ({"model": "ofc", "eta": [0.0, 0.1]}, r"sweep\.eta: not parameters of the OFC"),
        ({"model": "ofc", "nu": 0.01, "eta": 0.1}, r"sweep\.nu, sweep\.eta: not parameters"),
    ],
)
def test_bad_or_misplaced_nu_and_eta_in_a_sweep(table, match):
    with pytest.raises(ConfigError, match=match):
        SweepConfig.from_dict({"graph": "square:8x8:fixed", "events": 10, **table})


def test_sweep_points_pass_nu_and_eta_on(monkeypatch):
    seen = []
    monkeypatch.setattr(spec_run, "run_from_spec", lambda *a, **kw: seen.append(kw))
    monkeypatch.setattr(driver, "point_row", lambda point, *a: point)
    cfg = SweepConfig.from_dict({"graph": "ring:10", "nu": 0.01, "eta": [0.1], "events": 10,
                                 "seed": 3})  # fmt: skip
    driver.run_point(cfg.points()[0], "part-00000.parquet")
    assert (seen[0]["nu"], seen[0]["eta"]) == (0.01, 0.1)
    plain = SweepConfig.from_dict({"graph": "ring:10", "events": 10, "seed": 3})
    driver.run_point(plain.points()[0], "part-00000.parquet")
    assert seen[1]["nu"] is None and seen[1]["eta"] is None


def test_summary_columns_and_rows_of_nu_and_eta(tmp_path):
    assert SUMMARY_COLUMNS.index("nu") == SUMMARY_COLUMNS.index("alpha") + 1
    assert SUMMARY_COLUMNS.index("eta") == SUMMARY_COLUMNS.index("nu") + 1
    cfg = SweepConfig.from_dict({"graph": "ring:10", "nu": [0.0, 0.01], "eta": 0.1,
                                 "events": 10, "seed": 3})  # fmt: skip
    prepare_out(cfg, tmp_path, force=False)  # the manifest: no point has run
    table = summarize(tmp_path)
    assert table["nu"].tolist() == [0.0, 0.01] and table["eta"].tolist() == [0.1, 0.1]
    assert table["status"].tolist() == ["missing", "missing"]
    plain = SweepConfig.from_dict({"graph": "ring:10", "events": 10, "seed": 3}).points()[0]
    row = failed_row(plain, "part-00000.parquet", RuntimeError("x"))
    assert (row["nu"], row["eta"]) == (0.0, 0.0)
    ofc = SweepConfig.from_dict({"graph": "square:8x8:fixed", "model": "ofc", "events": 10,
                                 "seed": 3}).points()[0]  # fmt: skip
    row = failed_row(ofc, "part-00000.parquet", RuntimeError("x"))
    assert row["nu"] is None and row["eta"] is None


def test_summarize_rebuilds_every_point_of_an_ofc_sweep(tmp_path):
    cfg = SweepConfig.from_dict({"graph": "square:8x8:fixed", "model": "ofc",
                                 "ofc_alpha": [0.15, 0.2], "events": 10, "seed": 3})  # fmt: skip
    prepare_out(cfg, tmp_path, force=False)
    table = summarize(tmp_path)
    assert table["point"].tolist() == [0, 1]
    assert table["model"].tolist() == ["ofc", "ofc"]


def test_long_run_resumes_bit_identically(tmp_path):
    model = faultnet.CarlsonLanger(faultnet.graphs.ring(80), alpha=1.0, nu=0.001, eta=0.1)
    kw = {"rng": 9, "chunk_events": 500, "progress": False}
    faultnet.simulate_to_parquet(model, 3000, tmp_path / "ref.parquet", **kw)
    out = tmp_path / "run.parquet"
    with pytest.raises(Crash):
        faultnet.simulate_to_parquet(model, 3000, out, on_commit=crash_after(3), **kw)
    faultnet.simulate_to_parquet(model, 3000, out, resume=True, **kw)
    a, b = read_catalog(tmp_path / "ref.parquet"), read_catalog(out)
    assert a.events.equals(b.events)
    assert b.metadata["nu"] == 0.001 and b.metadata["eta"] == 0.1
