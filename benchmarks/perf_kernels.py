"""Where a workload's time goes, kernel by kernel: Linux ``perf`` with the kernels' symbols.

Numba's compiled code has no symbols that ``perf`` can see.  Each kernel keeps a function of
its own where LLVM does not inline it into its callers; an inlined kernel counts as its caller.

This script runs a workload under ``perf record`` in a child process that compiles the kernels
into a fresh Numba cache (so each kernel's object code is at hand), writes
``/tmp/perf-PID.map`` (address, size and name of every function of every compiled kernel, read
with ``nm``), then simulates; the parent prints each kernel's share of the samples taken in
compiled code.  Kernels inlined into another (``inline="always"``) count as their caller.

    python benchmarks/perf_kernels.py W4 --rtol 2e-5 --events 300000
    python benchmarks/perf_kernels.py L1024 --events 60000        # a tiled 1024^2 lattice
    python benchmarks/perf_kernels.py W1 --rtol 2e-5 --crossings interpolated
    python benchmarks/perf_kernels.py W1 --eta 0.1 --events 100000  # viscous coupling

Needs ``perf`` and ``nm`` (binutils) on the PATH and permission to sample (``perf_event_paranoid``
of 2 or less).  Run by hand; never a test.
"""

from __future__ import annotations

import argparse
import importlib
import os
import re
import shutil
import subprocess
import sys
import tempfile
import time

#: kernel modules whose compiled functions get symbols
MODULES = (
    "events", "slip", "solo", "physics", "interp", "late_joins", "stepping", "roots",
    "dopri", "crossing", "tree", "tableau", "response", "work",
)  # fmt: skip


def _symbols(obj):
    """(name, offset, size) of the functions defined in an object file's bytes."""
    with tempfile.NamedTemporaryFile(suffix=".o", delete=False) as fh:
        fh.write(obj)
    try:
        out = subprocess.run(
            ["nm", "-S", "--defined-only", fh.name], capture_output=True, text=True
        )
    finally:
        os.unlink(fh.name)
    rows = []
    for line in out.stdout.splitlines():
        parts = line.split()
        if len(parts) == 4 and parts[2] in "tT":
            rows.append((parts[3], int(parts[0], 16), int(parts[1], 16)))
    return rows


def _short(name):
    """``dopri.dopri_step`` from a Numba-mangled ``..._kernels5dopri10dopri_stepB3v13...``."""
    at = name.find("_kernels")
    if at < 0:
        return name[:60]
    rest, parts = name[at + len("_kernels") :], []
    for _ in range(2):  # length-prefixed: module, then function
        m = re.match(r"(\d+)", rest)
        if not m:
            return name[:60]
        n = int(m.group(1))
        parts.append(rest[len(m.group(1)) : len(m.group(1)) + n])
        rest = rest[len(m.group(1)) + n :]
    return ".".join(parts)


def write_perf_map():
    """Write /tmp/perf-PID.map for every compiled kernel of this process; return its rows."""
    import numba

    rows = {}
    for mod_name in MODULES:
        mod = importlib.import_module(f"faultnet.solver._kernels.carlson_langer.{mod_name}")
        for value in vars(mod).values():
            if not isinstance(value, numba.core.registry.CPUDispatcher):
                continue
            for cres in value.overloads.values():
                name = cres.fndesc.llvm_func_name
                try:
                    ptr = cres.library.get_pointer_to_function(name)
                    syms = _symbols(cres.library._get_compiled_object())
                except Exception:  # noqa: BLE001 - loaded from a cache: no object code
                    continue
                base = next((ptr - off for s, off, _ in syms if s == name), None)
                if base is None:
                    continue
                for s, off, size in syms:
                    if size:
                        rows[base + off] = (size, _short(s))
    with open(f"/tmp/perf-{os.getpid()}.map", "w") as fh:
        for addr in sorted(rows):
            fh.write(f"{addr:x} {rows[addr][0]:x} {rows[addr][1]}\n")
    return len(rows)


def _child(wid, rtol, events, crossings, nu, eta):
    here = os.path.dirname(os.path.abspath(__file__))
    sys.path[:0] = [here, os.path.dirname(here)]  # run.py, and this checkout's faultnet
    from run import SIGMA, WORKLOADS, K, _tiled_state, _warm_state, build_graph

    import faultnet

    alpha = WORKLOADS[wid][1] if wid in WORKLOADS else 1.0
    model = faultnet.CarlsonLanger(build_graph(wid), k=K, sigma=SIGMA, alpha=alpha)
    n = int(wid[1:]) if wid.startswith("L") else 0
    start = _tiled_state(128, n, 2.0)[0] if n >= 256 else _warm_state(model, 2.0)[0]
    model = model.with_params(nu=nu, eta=eta)  # from the plain model's steady state
    opts = faultnet.RunOptions(rtol=rtol, crossings=crossings)
    faultnet.simulate(model, 100, x0=start, progress=False, options=opts)  # compile
    print(f"{write_perf_map()} kernel symbols", file=sys.stderr)
    tic = time.perf_counter()
    faultnet.simulate(model, events, x0=start, progress=False, options=opts, record_slips=False)
    print(f"{events / (time.perf_counter() - tic):,.0f} events/s under perf", file=sys.stderr)


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawTextHelpFormatter)
    ap.add_argument("workload", help="W1..W6 or L<size> (periodic square lattice)")
    ap.add_argument("--rtol", type=float, default=1e-6)
    ap.add_argument("--events", type=int, default=200_000)
    ap.add_argument("--crossings", choices=["exact", "interpolated"], help="default: rtol's choice")
    ap.add_argument("--nu", type=float, default=0.0, help="the plate's velocity during events")
    ap.add_argument("--eta", type=float, default=0.0, help="viscous coupling of every spring")
    ap.add_argument("--child", action="store_true", help=argparse.SUPPRESS)
    args = ap.parse_args(argv)
    if args.child:
        _child(args.workload, args.rtol, args.events, args.crossings, args.nu, args.eta)
        return
    for tool in ("perf", "nm"):
        if shutil.which(tool) is None:
            ap.error(f"{tool} is not on the PATH (install linux-perf and binutils)")
    with tempfile.TemporaryDirectory() as tmp:
        env = dict(os.environ, NUMBA_CACHE_DIR=os.path.join(tmp, "numba"))
        data = os.path.join(tmp, "perf.data")
        cmd = [sys.executable, os.path.abspath(__file__), args.workload, "--child",
               "--rtol", str(args.rtol), "--events", str(args.events),
               "--nu", str(args.nu), "--eta", str(args.eta)]  # fmt: skip
        if args.crossings:
            cmd += ["--crossings", args.crossings]
        subprocess.run(["perf", "record", "-q", "-F", "999", "-o", data, "--", *cmd], env=env,
                       check=True)  # fmt: skip
        report = subprocess.run(
            ["perf", "report", "-i", data, "--no-children", "--sort", "dso,sym", "--stdio"],
            capture_output=True, text=True, check=True,
        ).stdout  # fmt: skip
    shares = {}
    for line in report.splitlines():
        if "[JIT]" in line:
            pct = float(line.split("%")[0])
            name = line.split("[.]")[-1].strip()
            shares[name] = shares.get(name, 0.0) + pct
    total = sum(shares.values())
    print(f"{args.workload} at rtol {args.rtol:g}: share of the samples in compiled code")
    for name, pct in sorted(shares.items(), key=lambda kv: -kv[1])[:20]:
        print(f"{100 * pct / total:6.1f}%  {name}")


if __name__ == "__main__":
    main()
