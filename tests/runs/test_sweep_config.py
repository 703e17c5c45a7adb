"""Sweep configuration (faultnet.runs.sweep.config): TOML schema, vars, defaults, errors."""

import textwrap

import pytest

from faultnet.exceptions import ConfigError
from faultnet.runs.sweep.config import SweepConfig, as_config, load_config


def _write(path, text):
    path.write_text(textwrap.dedent(text))
    return path


def test_toml_vars_and_defaults(tmp_path):
    path = _write(
        tmp_path / "perc.toml",
        """\
        [sweep]
        graph = ["percolation:square:{L}x{L}:p={p}", "ring:{L}"]
        k = [8, 16]
        events = 100
        replicas = 2
        [sweep.vars]
        L = [10, 12]
        p = [0.6, 0.8]
        """,
    )
    cfg = load_config(path)
    assert cfg.graphs == [
        "percolation:square:10x10:p=0.6",
        "percolation:square:10x10:p=0.8",
        "percolation:square:12x12:p=0.6",
        "percolation:square:12x12:p=0.8",
        "ring:10",
        "ring:12",
    ]
    assert cfg.out == str(tmp_path / "perc") and cfg.seed is None
    points = cfg.with_seed().points()
    assert len(points) == 6 * 2 * 2
    assert [p["spawn_key"] for p in points[:3]] == [[0], [1], [2]]
    assert points[1]["replica"] == 1 and points[2]["k"] == 16.0


@pytest.mark.parametrize(
    "table, match",
    [
        (
            {"graph": "ring:10", "events": 10, "alpah": 1},
            r"unknown key 'alpah'.*did you mean 'alpha'"
            r".*allowed keys: graph, events, alpha",
        ),
        ({"graph": "ring:10", "events": 10, "alpha": "fast"}, r"sweep\.alpha: expected a number"),
        (
            {"graph": "ring:10", "events": 10, "sigma": [0.5, 1.5]},
            r"sweep\.sigma: 1\.5 is not "
            r"allowed.*open interval \(0, 1\)",
        ),
        ({"graph": "ring:10", "events": 0}, r"sweep\.events: expected an integer >= 1"),
        ({"graph": "ring:10"}, r"sweep\.events is required"),
        ({"events": 10}, r"sweep\.graph is required"),
        (
            {"graph": "hex:10", "events": 10},
            r"(?s)sweep\.graph\[0\].*unknown graph kind 'hex'.*valid "
            r"forms:.*ring:N",
        ),
        ({"graph": "ring:{n}", "events": 10}, r"uses \{n\} but sweep\.vars has no 'n'"),
        ({"graph": "ring:10", "events": 10, "vars": {"n": [1]}}, r"sweep\.vars: 'n' not used"),
        (
            {"graph": "ring:10", "events": 10, "transient": 10},
            r"sweep\.transient.*less than events",
        ),
        (
            {"graph": "ring:10", "events": 10, "replicas": 1.5},
            r"sweep\.replicas: expected an integer",
        ),
    ],
)
def test_config_errors_name_the_field(table, match):
    with pytest.raises(ConfigError, match=match):
        SweepConfig.from_dict(table)


def test_toml_file_errors(tmp_path):
    with pytest.raises(ConfigError, match="not valid TOML"):
        load_config(_write(tmp_path / "a.toml", "[sweep\n"))
    with pytest.raises(ConfigError, match=r"unknown top-level key or table 'run'"):
        load_config(_write(tmp_path / "b.toml", "[run]\nx = 1\n"))
    with pytest.raises(ConfigError, match="does not exist"):
        load_config(tmp_path / "missing.toml")


def test_as_config_merges_overrides(tmp_path):
    cfg = as_config({"sweep": {"graph": "ring:10", "events": 50}}, {"alpha": [1.0, 2.0]})
    assert cfg.graphs == ["ring:10"] and cfg.alpha == [1.0, 2.0] and cfg.k == [None]
    again = as_config(cfg, {"events": 80})
    assert again.events == 80 and again.alpha == [1.0, 2.0]
    path = _write(tmp_path / "a.toml", "[sweep]\ngraph = 'ring:10'\nevents = 50\n")
    assert as_config(path, {}).out == str(tmp_path / "a")
    assert as_config(path, {"seed": 4}).seed == 4
    with pytest.raises(ConfigError, match="config must be a path to a TOML file"):
        as_config(3, {})


def test_points_need_a_seed():
    cfg = SweepConfig.from_dict({"graph": "ring:10", "events": 5, "replicas": 3})
    with pytest.raises(ConfigError, match="with_seed"):
        cfg.points()
    points = cfg.with_seed().points()
    assert [p["replica"] for p in points] == [0, 1, 2]
    assert len({p["seed_entropy"] for p in points}) == 1


def test_run_options_table_and_rtol():
    from faultnet.runs.sweep.config import SweepConfig

    cfg = SweepConfig.from_dict(
        {
            "graph": "ring:10",
            "events": 10,
            "seed": 1,
            "rtol": 2e-5,
            "options": {"crossings": "exact"},
        }
    )
    assert cfg.options == {"rtol": 2e-5, "crossings": "exact"}
    assert all(p["options"] == cfg.options for p in cfg.points())
    assert cfg.defining()["options"] == cfg.options
    plain = SweepConfig.from_dict({"graph": "ring:10", "events": 10, "seed": 1})
    assert "options" not in plain.points()[0] and "options" not in plain.defining()
    with pytest.raises(ConfigError, match=r"rtol must be between"):
        SweepConfig.from_dict({"graph": "ring:10", "events": 10, "rtol": 1.0})
    with pytest.raises(ConfigError, match=r"unknown run option.*speed"):
        SweepConfig.from_dict({"graph": "ring:10", "events": 10, "options": {"speed": 2}})
