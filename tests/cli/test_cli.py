"""The `faultnet` command line, as a subprocess and in process through main()."""

import json
import os
import shutil
import subprocess
import sys

import networkx as nx
import pandas as pd
import pytest

import faultnet
from faultnet.__main__ import main
from faultnet.io.parquet import read_catalog, read_metadata
from faultnet.model.identity import graph_hash
from faultnet.runs.spec_run import run_from_spec
from faultnet.runs.specs import build_model

PY = [sys.executable, "-m", "faultnet"]


def run_cli(*args, timeout=120):
    return subprocess.run([*PY, *map(str, args)], capture_output=True, text=True, timeout=timeout)


def test_simulate_and_info_subprocess(tmp_path):
    out = tmp_path / "ring.parquet"
    res = run_cli(
        "simulate",
        "ring:100",
        "--alpha",
        "2",
        "--events",
        "3e3",
        "--seed",
        "42",
        "--chunk",
        "1000",
        "--transient",
        "300",
        "--out",
        out,
        timeout=600,  # the first run compiles the kernels: minutes on the oldest Numba
    )
    assert res.returncode == 0, res.stderr
    text = res.stdout
    assert "3,000 events in" in text and "events/s" in text
    assert "M = ln S in [" in text and "b (MLE)" in text and "b (LSQ)" in text
    assert f"wrote {out}" in text
    model = faultnet.CarlsonLanger(faultnet.graphs.ring(100), alpha=2.0)
    ref = faultnet.simulate(model, 3000, rng=42, progress=False)
    cat = read_catalog(out)
    pd.testing.assert_frame_equal(cat.events, ref.events, check_exact=True)
    md = cat.metadata
    assert md["graph_spec"] == "ring:100" and md["graph_hash"] == graph_hash(model)
    assert md["alpha"] == 2.0 and md["seed_entropy"] == 42 and md["transient"] == 300
    assert md["dt"] == ref.metadata["dt"]
    info = run_cli("info", out)
    assert info.returncode == 0, info.stderr
    for piece in (
        "ring(100)",
        "spec ring:100",
        f"sha256:{md['graph_hash']}",
        "alpha=2.0",
        "SeedSequence entropy 42",
        f"faultnet    {faultnet.__version__}",
        "3,000",
        "after a transient of 300",
        "b (MLE)",
        "b (LSQ)",
    ):
        assert piece in info.stdout, piece
    # nothing is silently overwritten
    again = run_cli("simulate", "ring:100", "--events", "100", "--out", out)
    assert again.returncode == 2 and "refusing to overwrite" in again.stderr
    assert read_metadata(out) == md


def test_console_script_help():
    exe = shutil.which("faultnet", path=os.path.dirname(sys.executable))
    cmd = [exe] if exe else PY
    res = subprocess.run([*cmd, "--help"], capture_output=True, text=True, timeout=60)
    assert res.returncode == 0
    for name in ("simulate", "info", "sweep", "summarize"):
        assert name in res.stdout


@pytest.mark.parametrize("command", ["simulate", "info", "sweep", "summarize"])
def test_every_command_has_help_with_examples(command, capsys):
    assert main([command, "--help"]) == 0
    text = capsys.readouterr().out
    assert "examples:" in text and f"faultnet {command} " in text


def test_bad_input_exit_codes(tmp_path, capsys):
    assert main(["simulate", "hexagon:12", "--events", "10"]) == 2
    err = capsys.readouterr().err
    assert "unknown graph kind 'hexagon'" in err and "valid forms:" in err
    assert "percolation:LATTICE:RxC" in err and "ring:N" in err
    assert main(["simulate", "square:10y10", "--events", "10"]) == 2
    assert "ROWSxCOLS" in capsys.readouterr().err
    assert main(["simulate", "percolation:square:10x10", "--events", "10"]) == 2
    assert "needs p=P" in capsys.readouterr().err
    assert main(["simulate", "ring:10", "--events", "ten"]) == 2
    assert "expected a positive integer" in capsys.readouterr().err
    assert main(["simulate", "ring:10", "--events", "10", "--sigma", "2"]) == 2
    assert "sigma must lie in the open interval" in capsys.readouterr().err
    assert main(["simulate", "ring:10"]) == 2
    assert "--events N is required" in capsys.readouterr().err
    assert main(["simulate", "--resume", "--events", "10"]) == 2
    assert main(["simulate", "ring:10", "--events", "10", "--out", str(tmp_path / "c.csv")]) == 2
    assert "--out must name a .parquet file" in capsys.readouterr().err
    assert not (tmp_path / "c.csv").exists()
    assert main(["info", str(tmp_path / "nope.parquet")]) == 2
    (tmp_path / "junk.parquet").write_bytes(b"PAR1 not really")
    assert main(["info", str(tmp_path / "junk.parquet")]) == 1
    assert "truncated or corrupt" in capsys.readouterr().err
    assert main(["frobnicate"]) == 2


def test_graph_files(tmp_path, capsys):
    g = faultnet.graphs.ring(24)
    for node in g:
        del g.nodes[node]["pos"]  # GraphML holds no tuples
    g.graph.update(k=8.0, sigma=0.02, alpha=1.5)
    nx.set_node_attributes(g, {3: 2.5}, "alpha")  # one heterogeneous block
    g.edges[0, 1]["k"] = 4.0
    nx.write_graphml(g, tmp_path / "asp.graphml")
    out = tmp_path / "g.parquet"
    assert (
        main(
            [
                "simulate",
                str(tmp_path / "asp.graphml"),
                "--events",
                "200",
                "--seed",
                "1",
                "--out",
                str(out),
            ]
        )
        == 0
    )
    md = read_metadata(out)
    assert (md["k"], md["sigma"], md["alpha"], md["heterogeneous"]) == (8.0, 0.02, 1.5, True)
    model = build_model(str(tmp_path / "asp.graphml"))
    assert model.nodes == list(range(24))  # integer ids come back as ints
    assert model.alpha_values[3] == 2.5 and model.adjacency[0, 1] == 4.0
    ref = faultnet.simulate(model, 200, rng=1, progress=False)
    pd.testing.assert_frame_equal(read_catalog(out).events, ref.events, check_exact=True)
    # node-link JSON with the older "links" key; --alpha overrides the graph's default
    data = nx.node_link_data(g)  # "links" before networkx 3.4's "edges"
    data["links"] = data.pop("edges", None) or data["links"]
    (tmp_path / "asp.json").write_text(json.dumps(data))
    out2 = tmp_path / "j.parquet"
    assert (
        main(
            [
                "simulate",
                f"file:{tmp_path / 'asp.json'}",
                "--events",
                "200",
                "--seed",
                "1",
                "--alpha",
                "0.5",
                "--out",
                str(out2),
            ]
        )
        == 0
    )
    md2 = read_metadata(out2)
    assert md2["alpha"] == 0.5 and md2["k"] == 8.0
    capsys.readouterr()
    (tmp_path / "bad.json").write_text('{"nodes": [{"id": 0}], "edges": [], "directed": true}')
    assert main(["simulate", str(tmp_path / "bad.json"), "--events", "5"]) == 2
    assert "directed" in capsys.readouterr().err
    assert main(["simulate", str(tmp_path / "none.graphml"), "--events", "5"]) == 2
    assert "does not exist" in capsys.readouterr().err


class Crash(BaseException):
    pass


def _stop_after(n):
    """An ``on_commit`` hook: the run is killed right after its ``n``-th committed chunk."""

    def on_commit(n_chunks):
        if n_chunks == n:
            raise Crash

    return on_commit


def test_resume_from_the_command_line(tmp_path, capsys):
    out = tmp_path / "r.parquet"
    args = [
        "simulate",
        "ring:50",
        "--alpha",
        "1.5",
        "--events",
        "2000",
        "--seed",
        "8",
        "--chunk",
        "200",
        "--checkpoint-every",
        "0",
        "--out",
        str(out),
    ]
    with pytest.raises(Crash):  # what `faultnet simulate ARGS` runs, killed after 3 chunks
        run_from_spec("ring:50", 2000, out, alpha=1.5, seed=8, chunk_events=200,
                      checkpoint_interval=0, progress=False, on_commit=_stop_after(3))  # fmt: skip
    capsys.readouterr()
    assert main(args) == 2  # a checkpoint exists: neither restarted nor overwritten
    assert "pass --resume" in capsys.readouterr().err
    assert main(["info", str(out)]) == 0
    assert "600 of 2,000 events committed" in capsys.readouterr().out
    assert main(["simulate", "--resume", "--alpha", "2", "--out", str(out)]) == 2
    assert "alpha: checkpoint has 1.5, this call 2.0" in capsys.readouterr().err
    assert main(["simulate", "--resume", "--crossings", "exact", "--out", str(out)]) == 2
    assert "options: checkpoint has" in capsys.readouterr().err  # other run options refused
    assert main(["simulate", "--resume", "--out", str(out)]) == 0  # the rest comes from run.json
    assert "resumed at event 600" in capsys.readouterr().out
    model = faultnet.CarlsonLanger(faultnet.graphs.ring(50), alpha=1.5)
    ref = faultnet.simulate(model, 2000, rng=8, progress=False)
    pd.testing.assert_frame_equal(read_catalog(out).events, ref.events, check_exact=True)
    assert main([*args, "--resume"]) == 0
    assert "already complete" in capsys.readouterr().out


def test_sweep_and_summarize_commands(tmp_path, capsys):
    toml = tmp_path / "a.toml"
    toml.write_text('[sweep]\ngraph = "ring:30"\nalpha = [1.0, 2.0]\nevents = 300\nseed = 2\n')
    assert main(["sweep", str(toml), "--workers", "1", "--csv", str(tmp_path / "a.csv")]) == 0
    out = capsys.readouterr().out
    assert "2 of 2 points done" in out and "b_mle" in out
    table = pd.read_csv(tmp_path / "a.csv")
    assert list(table["alpha"]) == [1.0, 2.0] and list(table["status"]) == ["done", "done"]
    assert main(["summarize", str(tmp_path / "a"), "--csv", str(tmp_path / "a.csv")]) == 2
    assert "refusing to overwrite" in capsys.readouterr().err
    assert (
        main(["summarize", str(tmp_path / "a"), "--csv", str(tmp_path / "a.csv"), "--force"]) == 0
    )
    assert main(["info", str(tmp_path / "a")]) == 2
    assert "faultnet summarize" in capsys.readouterr().err
    # a --csv the sweep could not write is refused before any point runs
    toml.with_name("b.toml").write_text(toml.read_text())
    b = ["sweep", str(toml.with_name("b.toml")), "--workers", "1", "--csv"]
    assert main([*b, str(tmp_path / "a.csv")]) == 2
    assert "refusing to overwrite" in capsys.readouterr().err
    assert main([*b, str(tmp_path / "b.parquet")]) == 2
    assert "--csv must name a .csv file" in capsys.readouterr().err
    assert not (tmp_path / "b").exists() and not (tmp_path / "b.parquet").exists()
    toml.write_text('[sweep]\ngraph = "ring:30"\nalpah = 1\nevents = 300\n')
    assert main(["sweep", str(toml)]) == 2
    assert "unknown key 'alpah'" in capsys.readouterr().err


def test_run_option_flags_reach_the_catalog(tmp_path, capsys):
    out = tmp_path / "exact.parquet"
    args = ["simulate", "ring:20", "--events", "300", "--seed", "2", "--out", str(out)]
    flags = ["--method", "dopri5", "--crossings", "exact", "--rtol", "1e-5"]
    assert main([*args, *flags, "--no-progress"]) == 0
    assert "numerics    dopri5, rtol=1e-05: dt=" in capsys.readouterr().out
    md = read_catalog(out).metadata
    assert md["options"]["method"] == "dopri5" and md["solo_cache"] is True
    assert md["options"]["crossings"] == "exact" and md["options"]["rtol"] == 1e-5
    assert "local_regions_from" not in md["options"]
    model = faultnet.CarlsonLanger(faultnet.graphs.ring(20))
    opts = faultnet.RunOptions(crossings="exact", rtol=1e-5)
    ref = faultnet.simulate(model, 300, rng=2, progress=False, options=opts)
    pd.testing.assert_frame_equal(read_catalog(out).events, ref.events, check_exact=True)


@pytest.mark.parametrize(
    "flags, removed",
    [
        (["--method", "rk4"], "method='rk4'"),
        (["--local-regions-from", "inf"], "local_regions_from"),
        (["--local-regions-from", "32"], "local_regions_from"),
    ],
)
def test_removed_run_options_name_what_to_use_instead(tmp_path, capsys, flags, removed):
    """RK4 and local regions are gone: the flags still parse, and the run is refused with
    RunOptions' message, which names the alternative, before anything is written."""
    from faultnet.solver.step_size import REMOVED

    out = tmp_path / "c.parquet"
    args = ["simulate", "ring:20", "--events", "5", "--out", str(out), *flags]
    assert main(args) == 2
    err = capsys.readouterr().err
    assert REMOVED[removed] in err
    assert ("'dopri5'" if removed.startswith("method") else "crossings='interpolated'") in err
    assert not out.exists()


def test_method_flag_lists_dopri5_and_local_regions_flag_is_hidden(capsys):
    assert main(["simulate", "--help"]) == 0
    text = capsys.readouterr().out
    assert "--local-regions-from" not in text and "--method {dopri5}" in text
    assert main(["simulate", "ring:20", "--events", "5", "--method", "euler"]) == 2
    assert "method must be one of ['dopri5']; got 'euler'" in capsys.readouterr().err


def test_simulate_default_fits_leave_out_transient_and_top_percent(tmp_path, capsys):
    """Without --transient / --m-max the printout drops the events before plate time 2 and
    fits b by least squares up to the 99th percentile of M, and says so; with --out the
    same numbers come from the catalog file."""
    import numpy as np

    from faultnet.stats import fit_b_lsq, fit_b_mle

    args = ["simulate", "ring:200", "--alpha", "1", "--events", "4000", "--seed", "3"]
    assert main(args) == 0
    text = capsys.readouterr().out
    ref = faultnet.simulate(
        faultnet.CarlsonLanger(faultnet.graphs.ring(200), alpha=1.0), 4000, rng=3, progress=False
    )
    t, M = ref.events["t"].to_numpy(), ref.events["M"].to_numpy()
    skip = int((t < 2.0).sum())
    assert 0 < skip < 4000
    assert f"the {skip:,} events before plate time 2 are left out of the fits" in text
    assert f"after a transient of {skip:,}" in text
    kept = M[skip:]
    mle = fit_b_mle(kept)
    top = float(np.quantile(kept[kept >= mle.m_min], 0.99))
    assert top < kept.max()
    lsq = fit_b_lsq(kept, mle.m_min, top)
    assert f"b (LSQ)     {lsq.b:.3f} ± {lsq.b_err:.3f} on [{mle.m_min:.3f}, {top:.3f}]" in text
    assert "(maximum curvature to the 99th percentile of M above it)" in text
    assert f"b (MLE)     {mle.b:.3f}" in text

    out = tmp_path / "ring.parquet"
    assert main([*args, "--out", str(out)]) == 0
    from_file = capsys.readouterr().out
    for line in text.splitlines()[2:-1]:  # the same fit lines, read back from the catalog
        assert line in from_file, line

    # chosen values: no default note, the window says where it came from
    assert main([*args, "--transient", "100", "--m-max", "1.5"]) == 0
    chosen = capsys.readouterr().out
    assert "before plate time" not in chosen and "after a transient of 100" in chosen
    assert "(maximum curvature to --m-max)" in chosen


def test_simulate_default_transient_of_a_short_run_is_half_of_it(capsys):
    """A run that ends before plate time 2 is fitted on its second half, and says so."""
    assert main(["simulate", "ring:100", "--events", "300", "--seed", "1"]) == 0
    text = capsys.readouterr().out
    assert "the first half of the run (150 events) is left out" in text
    assert "after a transient of 150" in text


def test_the_first_run_says_once_on_stderr_that_it_compiles(monkeypatch, capsys):
    """Not a progress bar that looks hung for seconds: one line, on a terminal or not."""
    from faultnet.solver import simulator as engine

    model = faultnet.CarlsonLanger(faultnet.graphs.ring(10))
    sim = engine.Simulator(model, rng=1)
    sim.advance(2, progress=False)
    assert not sim.compiles  # compiled (or loaded) in this process
    monkeypatch.setattr(engine.Simulator, "compiles", property(lambda self: True))
    assert main(["simulate", "ring:10", "-n", "50"]) == 0
    err = capsys.readouterr().err
    assert err.count(engine.COMPILING_LABEL) == 1 and "Traceback" not in err
    assert main(["simulate", "ring:10", "-n", "50", "--no-progress"]) == 0
    assert engine.COMPILING_LABEL not in capsys.readouterr().err


def test_record_slips_writes_resumes_and_continues_the_slips(tmp_path, capsys):
    out = str(tmp_path / "ring.parquet")
    args = ["simulate", "ring:40", "--seed", "3", "--out", out, "--no-progress"]
    assert main([*args, "--events", "600", "--record-slips"]) == 0
    assert "ring.slips.parquet" in capsys.readouterr().out
    assert main(["simulate", "--continue", "--out", out, "--events", "900"]) == 0
    model = build_model("ring:40")
    ref = faultnet.simulate(model, 900, rng=3, record_slips=True, progress=False)
    pd.testing.assert_frame_equal(faultnet.read_slips(out), ref.slips)
    assert main(["simulate", "ring:40", "--events", "10", "--record-slips"]) == 2
    assert "--record-slips needs --out" in capsys.readouterr().err


def test_info_names_the_slips_next_to_a_catalog(tmp_path, capsys):
    out = str(tmp_path / "net.parquet")
    graph = faultnet.graphs.parallel_faults(2, 10, k_coupling=1.0)
    model = faultnet.CarlsonLanger(graph, k=16, sigma=0.01, alpha=1.0)
    faultnet.simulate_to_parquet(model, 200, out, rng=1, record_slips=True, progress=False)
    capsys.readouterr()
    assert main(["info", out]) == 0
    text = capsys.readouterr().out
    assert "net.slips.parquet (per-block slips" in text
    assert "net.fault_slips.parquet (per-fault slips" in text
