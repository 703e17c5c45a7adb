"""Where a block stops inside a step: ``stick_theta`` on velocities whose stop is known.

Each case is a polynomial velocity ``v(t)`` of degree at most 3 over one step of length 1,
with the step's stage derivatives set to ``v'`` at the DP5 stages' times: the dense output
then reproduces ``v`` exactly, and the stop is the first root of ``v`` where it falls to 0,
written down by hand.  The kernel runs uncompiled (``NUMBA_DISABLE_JIT=1``, a subprocess):
compiled kernels are callable from other kernels only.
"""

import json
import os
import subprocess
import sys

import pytest

#: name: (v(t) coefficients, lowest power first; the stop's fraction of the step, 2.0: none)
CASES = {
    # slipping through the step's end: the root where v falls through 0
    "falls": ([1.0, -2.0], 0.5),
    "falls_cubic": ([1.0, -1.0, 0.0, -1.0], 0.6823278038280193),
    # from rest, rising first (a block that joined at rest): the root of v / t
    "from_rest": ([0.0, 1.0, -1.5], 2.0 / 3.0),
    # from rest, never rising: it stops at once
    "from_rest_falling": ([0.0, 0.0, -1.0], 0.0),
    # both ends positive, dipping below zero between: the first root, before the minimum
    "dip": ([0.5, -3.0, 3.0], (3.0 - 3.0**0.5) / 6.0),
    # both ends positive, the minimum above zero: no stop
    "dip_above": ([1.0, -3.0, 2.5], 2.0),
    # rising: no stop
    "rising": ([1.0, 1.0], 2.0),
}

SCRIPT = """
import json, sys
import numpy as np
import numba
from faultnet.solver._kernels.carlson_langer.crossing import stick_theta
from faultnet.solver._kernels.carlson_langer.tableau import KA, N_STAGE
from faultnet.solver._kernels.carlson_langer.work import N_WORK, A, AN, V, VN

assert numba.config.DISABLE_JIT
STAGE_TIMES = (0.0, 0.2, 0.3, 0.8, 8.0 / 9.0, 1.0)  # DP5's c1 ... c6
out = {}
for name, coeffs in json.loads(sys.argv[1]).items():
    v = np.polynomial.Polynomial(coeffs)
    dv = v.deriv()
    W = np.zeros((1, N_WORK))
    K = np.zeros((1, N_STAGE))
    W[0, V], W[0, VN], W[0, A], W[0, AN] = v(0.0), v(1.0), dv(0.0), dv(1.0)
    for s, c in enumerate(STAGE_TIMES):
        K[0, KA + s] = dv(c)
    out[name] = stick_theta(1.0, 0, 0, W, K)
print(json.dumps(out))
"""


@pytest.fixture(scope="module")
def thetas():
    env = dict(os.environ, NUMBA_DISABLE_JIT="1")
    cases = json.dumps({name: coeffs for name, (coeffs, _) in CASES.items()})
    run = subprocess.run(
        [sys.executable, "-c", SCRIPT, cases], env=env, capture_output=True, text=True, timeout=300
    )
    assert run.returncode == 0, run.stderr
    return json.loads(run.stdout.strip().splitlines()[-1])


@pytest.mark.parametrize("name", sorted(CASES))
def test_the_stop_is_the_first_root_where_the_velocity_falls_to_zero(thetas, name):
    _, expected = CASES[name]
    assert thetas[name] == pytest.approx(expected, abs=1e-12), (name, thetas[name])
