"""Where a cold compile's time goes: Numba's passes, LLVM's, and each kernel's share.

    python benchmarks/compile_phases.py lattice
    python benchmarks/compile_phases.py ring --top 20
    python benchmarks/compile_phases.py lattice --rounds 3 --python /tmp/venv/bin/python
    python benchmarks/compile_phases.py lattice --rounds 4 --top 0 --against /tmp/other
    python benchmarks/compile_phases.py lattice --top 0 --count

Each round runs the first ``simulate`` call of one of ``benchmarks/run.py``'s compile models
(``COMPILE_GRAPHS``: ``ring``, ``lattice``, ``exact``) in a child process with an empty Numba
cache and the garbage collector off (its passes over the compiler's objects, 1.5-1.8 s, would
land in whichever phase they interrupt).  The child wraps Numba's compiler methods with timers,
for this measurement only, and prints:

- the time in each phase, each timed function counted without the timed functions it calls:
  Numba's passes (bytecode and IR passes, inlining, typing, lowering to LLVM IR) and LLVM's
  (function passes while lowering, each library's module passes and machine code);
- each kernel's own compile time (without the kernels it compiles in turn), the LLVM time of
  its library (module passes and machine code, over its own code and every kernel linked
  into it) and its number of Numba IR statements.

With ``--count`` it also counts the LLVM instructions that each library's module passes
start from, summed over all libraries: unlike the times, a number this machine's drift does
not move, for a change to the code that LLVM optimises and emits (the counting's own time is
left out).

With ``--against CHECKOUT`` the rounds alternate between this checkout and another one (ABBA:
the machine's speed drifts by 10-20% within an hour, more than most single changes move the
compile), and a summary gives each one's range, the mean of the paired differences and the
ratio of the means.  Against a checkout of the engine with its own compiler pipeline (the
commit before the public-API engine, ``faac467``), the ratio carries the cold-compile target
(12.9-13.2 s for that engine on the machine where it was set) over to this machine's hour.

The faultnet measured is this checkout's (its root goes first on the child's path), whatever
the interpreter has installed.  The interpreter is ``--python`` (default: this one).  A fresh
virtual environment with the README's install measures what a user gets: a globally installed
colorama, for instance, adds about 0.8 s to Numba's formatting of rejected typing candidates.
Run by hand; never a test.
"""

from __future__ import annotations

import argparse
import json
import os
import subprocess
import sys
import tempfile

_HERE = os.path.dirname(os.path.abspath(__file__))
# run.py's compile models, and the faultnet of this checkout (not an installed one)
#: the checkout whose faultnet a child measures (``--against`` sets it for the other one)
_ROOT = os.environ.get("COMPILE_PHASES_CHECKOUT", os.path.dirname(_HERE))
sys.path[:0] = [_HERE, _ROOT]

#: the phases, in the order printed: (key, label)
PHASES = (
    ("bytecode", "Numba: other passes (bytecode, IR, inlining)"),
    ("typing", "Numba: typing"),
    ("lowering", "Numba: lowering to LLVM IR"),
    ("fpass", "LLVM: function passes"),
    ("modpass", "LLVM: module passes (each library)"),
    ("mcode", "LLVM: machine code (each library)"),
    ("other", "other (caches, wrappers, the run itself)"),
)


def _child(graph, count=False):
    """Compile and run one model with timers on Numba's compiler; print the result as JSON.

    With ``count``, each library's LLVM instructions are counted before its module passes (the
    time of the counting is left out of every phase and of the total).
    """
    import collections
    import gc
    import time

    from numba.core import codegen, compiler_machinery, dispatcher, lowering

    gc.disable()
    phase = collections.Counter()
    own, llvm, stmts = collections.Counter(), collections.Counter(), {}
    stack, kstack = [], []

    def timed(cls, name, key_of):
        f = getattr(cls, name)

        def g(self, *a, **k):
            key = key_of(self, *a)
            t = time.perf_counter()
            stack.append(0.0)
            try:
                return f(self, *a, **k)
            finally:
                dt = time.perf_counter() - t
                phase[key] += dt - stack.pop()
                if stack:
                    stack[-1] += dt
                if key in ("modpass", "mcode"):
                    llvm[self.name] += dt

        setattr(cls, name, g)

    def pass_key(self, index, pss, state):
        name = pss.name()
        return (
            "typing"
            if name == "nopython_type_inference"
            else ("lowering" if name == "native_lowering" else "bytecode")
        )

    timed(compiler_machinery.PassManager, "_runPass", pass_key)
    timed(lowering.Lower, "lower", lambda self: "lowering")
    timed(codegen.CPUCodeLibrary, "_optimize_functions", lambda self, *a: "fpass")
    timed(codegen.CPUCodeLibrary, "_optimize_final_module", lambda self: "modpass")
    timed(codegen.JITCodeLibrary, "_finalize_specific", lambda self: "mcode")
    llvm_ir = {"instructions": 0, "libraries": 0, "seconds": 0.0}
    if count:
        optimize = codegen.CPUCodeLibrary._optimize_final_module

        def counted(self):
            t = time.perf_counter()
            module = self._final_module
            llvm_ir["instructions"] += sum(
                1 for f in module.functions for b in f.blocks for _ in b.instructions
            )
            llvm_ir["libraries"] += 1
            dt = time.perf_counter() - t
            llvm_ir["seconds"] += dt
            if stack:
                stack[-1] += dt  # not the enclosing phase's time
            return optimize(self)

        codegen.CPUCodeLibrary._optimize_final_module = counted

    compile_ = dispatcher.Dispatcher.compile

    def compile_timed(self, sig):
        t = time.perf_counter()
        kstack.append(0.0)
        try:
            return compile_(self, sig)
        finally:
            dt = time.perf_counter() - t
            own[self.py_func.__qualname__] += dt - kstack.pop()
            if kstack:
                kstack[-1] += dt

    dispatcher.Dispatcher.compile = compile_timed
    lower = lowering.Lower.lower

    def lower_counting(self):
        stmts[self.fndesc.qualname] = sum(len(b.body) for b in self.func_ir.blocks.values())
        return lower(self)

    lowering.Lower.lower = lower_counting

    from run import COMPILE_GRAPHS

    import faultnet

    t = time.perf_counter()
    model = eval(f"faultnet.CarlsonLanger({COMPILE_GRAPHS[graph]})")
    faultnet.simulate(model, 1, rng=1, progress=False)
    total = time.perf_counter() - t - llvm_ir["seconds"]
    phase["other"] = total - sum(phase.values())
    # a kernel's library is named after its function's qualified name
    kernels = {name: [own[name], llvm.get(name, 0.0), stmts.get(name)] for name in own}
    out = {"total": total, "phases": dict(phase), "kernels": kernels}
    print(json.dumps(dict(out, llvm_ir=llvm_ir) if count else out))


def _print_round(graph, r, out, top):
    print(f"\n{graph}, round {r}: cold first simulate {out['total']:.2f} s (collector off)")
    for key, label in PHASES:
        print(f"  {label:44} {out['phases'].get(key, 0.0):6.2f} s")
    head = "kernel (compile time without its callees)"
    print(f"  {head:44} {'own s':>6} {'LLVM s':>7} {'stmts':>6}")
    rows = sorted(out["kernels"].items(), key=lambda kv: -kv[1][0])
    for name, (own_s, llvm_s, n) in rows[:top]:
        print(f"  {name[-44:]:44} {own_s:6.2f} {llvm_s:7.2f} {n if n else '-':>6}")
    rest = rows[top:]
    if rest:
        print(f"  {f'{len(rest)} more kernels':44} {sum(v[0] for _, v in rest):6.2f}")
    print(f"  {'IR statements lowered, all kernels':44} {sum(v[2] or 0 for _, v in rows):>21}")
    if "llvm_ir" in out:
        n, libs = out["llvm_ir"]["instructions"], out["llvm_ir"]["libraries"]
        print(f"  {f'LLVM instructions unoptimised, {libs} libraries':44} {n:>21}")


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawTextHelpFormatter)
    ap.add_argument("graph", choices=("ring", "lattice", "exact"), help="the compile model")
    ap.add_argument("--rounds", type=int, default=1, help="cold compiles, one per process")
    ap.add_argument("--top", type=int, default=12, help="kernels listed (default 12)")
    ap.add_argument("--python", default=sys.executable, help="interpreter of the child process")
    ap.add_argument("--against", metavar="CHECKOUT", help="another checkout, alternated with this")
    ap.add_argument(
        "--count", action="store_true", help="also count LLVM instructions (deterministic)"
    )
    ap.add_argument("--child", action="store_true", help=argparse.SUPPRESS)
    args = ap.parse_args(argv)
    if args.child:
        _child(args.graph, args.count)
        return
    roots = [os.path.dirname(_HERE)] + ([os.path.abspath(args.against)] if args.against else [])
    if len(set(roots)) < len(roots):
        ap.error(f"--against names this checkout ({roots[0]}): give another one")
    totals = {root: [] for root in roots}
    for r in range(1, args.rounds + 1):
        for root in roots if r % 2 else roots[::-1]:
            out = _measure(args, root)
            if args.against:
                print(f"\n[{root}]", end="")
            _print_round(args.graph, r, out, args.top)
            totals[root].append(out["total"])
    if args.against:
        _print_summary(totals)


def _measure(args, root):
    """One cold compile of the faultnet in ``root``, in a child with an empty cache."""
    with tempfile.TemporaryDirectory() as cache:
        env = dict(os.environ, NUMBA_CACHE_DIR=cache, COMPILE_PHASES_CHECKOUT=root)
        cmd = [args.python, os.path.abspath(__file__), args.graph, "--child"]
        cmd += ["--count"] if args.count else []
        lines = subprocess.check_output(cmd, env=env).decode()
    return json.loads(lines.strip().splitlines()[-1])


def _print_summary(totals):
    (a, ta), (b, tb) = totals.items()
    diff = [x - y for x, y in zip(ta, tb, strict=True)]
    print("\ncold first simulate, collector off:")
    for root, t in totals.items():
        print(f"  {root}: {min(t):.2f}-{max(t):.2f} s, mean {sum(t) / len(t):.2f} s")
    print(f"  paired differences ({a} minus {b}): " + ", ".join(f"{d:+.2f}" for d in diff))
    print(f"  mean difference {sum(diff) / len(diff):+.2f} s over {len(diff)} rounds")
    print(f"  mean ratio ({a} over {b}): {sum(ta) / sum(tb):.3f}")


if __name__ == "__main__":
    main()
