"""``--nu`` and ``--eta`` of ``faultnet simulate``, and where the command line shows them.
No run here has nu or eta other than 0."""

import pandas as pd
import pytest

from faultnet.__main__ import main
from faultnet.cli import commands
from faultnet.cli.parser import build_parser
from faultnet.io.summary import format_metadata, kelvin_text
from faultnet.runs import spec_run

SIMULATE = ["simulate", "ring:10", "--events", "10"]


class Stop(Exception):
    """Ends a command where the run would start."""


def test_nu_and_eta_parse_as_floats():
    args = build_parser().parse_args([*SIMULATE, "--nu", "0.01", "--eta", "1e-1"])
    assert (args.nu, args.eta) == (0.01, 0.1)
    args = build_parser().parse_args(SIMULATE)
    assert args.nu is None and args.eta is None  # 0, or on --resume the stored values


@pytest.mark.parametrize("flag", ["--nu", "--eta"])
@pytest.mark.parametrize("value", ["nan", "inf", "fast"])
def test_nu_and_eta_must_be_finite_numbers(flag, value, capsys):
    assert main([*SIMULATE, flag, value]) == 2
    assert f"argument {flag}: expected a" in capsys.readouterr().err


def test_negative_values_are_refused_by_the_model(one_line):
    assert main([*SIMULATE, "--nu", "-0.5"]) == 2
    assert one_line() == "faultnet simulate: error: nu must be finite and >= 0; got -0.5"
    assert main([*SIMULATE, "--eta", "-1"]) == 2
    assert one_line() == "faultnet simulate: error: eta must be finite and >= 0; got -1.0"


@pytest.mark.parametrize(
    "flags, named",
    [
        (["--nu", "0.01"], "--nu is"),
        (["--eta", "0.1"], "--eta is"),
        (["--nu", "0", "--eta", "0.1"], "--nu and --eta are"),
    ],
)
def test_the_automaton_refuses_nu_and_eta(flags, named, one_line, monkeypatch, tmp_path):
    def never(*args, **kwargs):
        raise AssertionError("no run may start")

    monkeypatch.setattr(spec_run, "run_from_spec", never)
    out = tmp_path / "ofc.parquet"
    argv = ["simulate", "square:8x8:fixed", "-n", "10", "--model", "ofc", "--out", str(out)]
    assert main([*argv, *flags]) == 2
    err = one_line()
    assert err.startswith(f"faultnet simulate: error: {named} the Carlson-Langer model's")
    assert "OFC automaton (--model ofc) has neither" in err
    assert not list(tmp_path.iterdir())


def test_simulate_passes_nu_and_eta_on(monkeypatch):
    seen = {}

    def fake(graph, n_events, out, **kw):
        seen.update(kw)
        raise Stop

    monkeypatch.setattr(spec_run, "run_from_spec", fake)
    with pytest.raises(Stop):
        commands.cmd_simulate(build_parser().parse_args([*SIMULATE, "--nu", "0.01"]), None)
    assert seen["nu"] == 0.01 and seen["eta"] is None
    with pytest.raises(Stop):
        commands.cmd_simulate(build_parser().parse_args(SIMULATE), None)
    assert seen["nu"] is None and seen["eta"] is None


def test_a_finished_run_is_not_resumed_with_another_nu(tmp_path, capsys, one_line):
    out = tmp_path / "ring.parquet"
    argv = ["simulate", "ring:20", "-n", "200", "--seed", "1", "--dt", "0.02", "--out", str(out)]
    assert main([*argv, "--no-progress"]) == 0
    printed = capsys.readouterr().out
    assert "parameters  k=16.0 sigma=0.01 alpha=1.0 seed=1" in printed  # as before
    assert main(["simulate", "--resume", "--out", str(out), "--nu", "0.01"]) == 2
    err = one_line()
    assert "holds another run (nu: checkpoint has 0.0, this call 0.01; graph_hash:" in err
    assert main(["simulate", "--resume", "--out", str(out), "--no-progress"]) == 0
    assert "already complete" in capsys.readouterr().out


def test_parameters_lines_show_nu_and_eta_where_not_zero():
    md = {"k": 16.0, "sigma": 0.01, "alpha": 1.0, "dt": 0.02, "graph": "ring(5)"}
    assert "parameters  k=16.0 sigma=0.01 alpha=1.0 dt=0.02\n" in format_metadata(md) + "\n"
    assert kelvin_text(md) == ""
    md.update(nu=0.01, eta=0.1, eta_heterogeneous=False)
    assert "parameters  k=16.0 sigma=0.01 alpha=1.0 nu=0.01 eta=0.1 dt=0.02" in format_metadata(md)
    assert kelvin_text(md) == " nu=0.01 eta=0.1"
    md.update(eta_heterogeneous=True)
    assert kelvin_text(md) == " nu=0.01 eta=0.1 (per-edge eta)"
    assert "(per-edge eta)" in format_metadata(md)


def _table(**columns):
    n = len(next(iter(columns.values())))
    base = {name: [0] * n for name in commands._SHOW}
    base.update(graph=["ring:10"] * n, status=["done"] * n, model=["carlson-langer"] * n)
    return pd.DataFrame({**base, **columns})


def test_the_sweep_table_shows_nu_and_eta_where_some_point_has_them(capsys):
    commands._print_table(_table(nu=[0.0, 0.0], eta=[0.0, 0.0]), None)
    header = capsys.readouterr().out.splitlines()[0].split()
    assert "nu" not in header and "eta" not in header and "alpha" in header
    commands._print_table(_table(nu=[0.0, 0.01], eta=[0.0, 0.0]), None)
    header = capsys.readouterr().out.splitlines()[0].split()
    assert header[header.index("alpha") + 1] == "nu" and "eta" not in header
    ofc = _table(nu=[None], eta=[None], model=["ofc"])
    commands._print_table(ofc, None)
    header = capsys.readouterr().out.splitlines()[0].split()
    assert "nu" not in header and "sigma" not in header and "model" in header
