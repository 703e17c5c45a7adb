"""The kernels run as plain Python under ``NUMBA_DISABLE_JIT=1``, with the compiled results.

Every kernel is written so that it also runs uncompiled (its decorators then return the
Python function itself): a debugger or a coverage tool can step through the engine.  The
uncompiled run must give the compiled run's catalog bit for bit, for both crossing
treatments: a 6 x 6 periodic lattice (interpolated crossings) and a ring of 12 at
alpha 2.5 (exact crossings, with partial steps), and the ring of 12 with the plate moving
during events and viscous coupling (exact crossings, joins through the plate).
"""

import json
import os
import subprocess
import sys

import pytest

import faultnet

#: the model's graph (a faultnet.graphs.builders function and its arguments), its alpha, the
#: crossing treatment that its default options take, and its plate velocity and viscosity
CASES = {
    "lattice": (["square_lattice", [6, 6], {"periodic": True}], 1.0, "interpolated", {}),
    "ring": (["ring", [12], {}], 2.5, "exact", {}),
    "plate": (["ring", [12], {}], 1.0, "exact", {"nu": 0.05, "eta": 0.2}),
}
N_EVENTS = 60
#: the metadata counters that say which paths of the engine a run took
COUNTERS = (
    "n_steps",
    "block_steps",
    "solo_events",
    "partial_block_steps",
    "interpolated_crossings",
)

SCRIPT = """
import json, sys
import numba
import faultnet
from faultnet.solver._kernels.carlson_langer import dopri, events

# the kernels really are plain Python functions here
assert numba.config.DISABLE_JIT
assert not hasattr(events.run_events_dopri5, "py_func")
assert not hasattr(dopri.dopri_step, "py_func")
(name, args, kwargs), alpha = json.loads(sys.argv[1]), float(sys.argv[2])
n_events, extra = int(sys.argv[3]), json.loads(sys.argv[4])
g = getattr(faultnet.graphs.builders, name)(*args, **kwargs)
model = faultnet.CarlsonLanger(g, k=4, sigma=0.01, alpha=alpha, **extra)
r = faultnet.simulate(model, n_events, rng=3, progress=False)
ev = r.events
print(json.dumps({
    "crossings": r.metadata["crossings"],
    "counters": {c: r.metadata[c] for c in sys.argv[5:]},
    "t": [float(x).hex() for x in ev.t],
    "duration": [float(x).hex() for x in ev.duration],
    "S": [float(x).hex() for x in ev.S],
    "n_blocks": [int(x) for x in ev.n_blocks],
    "hypocenter": [int(x) for x in ev.hypocenter],
    "n_steps": [int(x) for x in ev.n_steps],
    "z": [float(x).hex() for x in r.state.z],
}))
"""


def _uncompiled(graph, alpha, extra):
    env = dict(os.environ, NUMBA_DISABLE_JIT="1")
    spec = json.dumps(graph)
    args = [sys.executable, "-c", SCRIPT, spec, str(alpha), str(N_EVENTS), json.dumps(extra)]
    args += COUNTERS
    out = subprocess.run(args, env=env, capture_output=True, text=True, timeout=600)
    assert out.returncode == 0, out.stderr
    return json.loads(out.stdout.strip().splitlines()[-1])


@pytest.mark.parametrize("case", sorted(CASES))
def test_uncompiled_run_gives_the_compiled_catalog(case):
    graph, alpha, crossings, extra = CASES[case]
    plain = _uncompiled(graph, alpha, extra)
    name, args, kwargs = graph
    g = getattr(faultnet.graphs.builders, name)(*args, **kwargs)
    model = faultnet.CarlsonLanger(g, k=4, sigma=0.01, alpha=alpha, **extra)
    r = faultnet.simulate(model, N_EVENTS, rng=3, progress=False)
    ev = r.events
    assert r.metadata["crossings"] == plain["crossings"] == crossings
    assert len(ev) == N_EVENTS
    # the run takes the paths it is meant to test: events of several blocks, and the crossing
    # treatment's own code (interpolated crossings; partial steps)
    assert (ev.n_blocks > 1).sum() >= 10
    if crossings == "interpolated":
        assert r.metadata["interpolated_crossings"] > 0
    else:
        assert r.metadata["partial_block_steps"] > 0
    assert plain["counters"] == {c: r.metadata[c] for c in COUNTERS}
    for col in ("t", "duration", "S"):
        assert plain[col] == [float(x).hex() for x in ev[col]], col
    for col in ("n_blocks", "hypocenter", "n_steps"):
        assert plain[col] == [int(x) for x in ev[col]], col
    assert plain["z"] == [float(x).hex() for x in r.state.z]
