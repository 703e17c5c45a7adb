"""A CLI-style run pays the fixed costs once: one Simulator, few calls, one solo integration."""

from faultnet.runs.spec_run import run_from_spec
from faultnet.solver import simulator as engine


def test_run_from_spec_pays_fixed_costs_once(tmp_path, monkeypatch):
    counts = {"init": 0, "advance": 0}
    real_init, real_advance = engine.Simulator.__init__, engine.Simulator.advance

    def init(self, *args, **kwargs):
        counts["init"] += 1
        real_init(self, *args, **kwargs)

    def advance(self, n, **kwargs):
        counts["advance"] += 1
        return real_advance(self, n, **kwargs)

    monkeypatch.setattr(engine.Simulator, "__init__", init)
    monkeypatch.setattr(engine.Simulator, "advance", advance)
    one = run_from_spec("chain:1", 1, None, alpha=1e3, seed=1, progress=False)
    rep = run_from_spec("chain:1", 3000, None, alpha=1e3, seed=1, progress=False)
    assert counts["init"] == 2  # one Simulator per run
    assert counts["advance"] <= 1 + 8  # calls grow from 256 events: not one call per event
    # every event of a lone block is the same solo slip: integrated once, reused after
    assert rep.metadata["n_steps"] <= 2 * one.metadata["n_steps"]
