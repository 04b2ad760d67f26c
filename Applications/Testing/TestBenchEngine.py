"""scripts/bench-engine.py --quick end to end (Bonsai, 400x300, two frames):
the runs, the report and the JSON rows exist and hold what the methods
promise, not timings (CI cannot pin those): the fixed-point mapper, Riemann,
and the piecewise, coupled and decoupled methods at eps 0.01 and 0.001 are
all measured; the fixed-point mapper's ratio to itself is 1; every one of
our methods reports rays and samples; the piecewise method at eps 0.001
leaves no pixel more than 1e-3 off the reference and its largest error is
within eps; Riemann's error is larger than the piecewise method's.

    python3 TestBenchEngine.py BENCH_SCRIPT AVOS_RENDER SHARED_DATA_DIR SCRATCH_DIR
"""

import json
import os
import shutil
import subprocess
import sys

SCRIPT, RENDER, DATA, SCRATCH = sys.argv[1:5]
if not os.path.exists(os.path.join(DATA, "volumes", "bonsai_zfp.vti")):
    print("shared data absent: skipping")
    sys.exit(125)
shutil.rmtree(SCRATCH, ignore_errors=True)
result = subprocess.run([sys.executable, SCRIPT, "--quick", "--render", RENDER, "--data", DATA,
                         "--output", SCRATCH], capture_output=True, text=True, timeout=1200)
failures = []


def check(ok, what):
    if not ok:
        failures.append(what)
        print("FAIL", what)


check(result.returncode == 0, "the script runs: " + result.stdout + result.stderr)
rows = json.load(open(os.path.join(SCRATCH, "results.json"))) if result.returncode == 0 else []
by = {r["method"]: r for r in rows}
methods = ["vtk-fixed-point h 0.5", "riemann h 0.5"] + [
    "%s eps %s" % (m, e) for m in ("piecewise", "coupled", "decoupled") for e in ("0.01", "0.001")]
check(sorted(by) == sorted(methods) and len(rows) == len(methods),
      "the eight methods measured: %r" % sorted(by))
check(os.path.exists(os.path.join(SCRATCH, "report.md")), "the report is written")
if rows:
    check(by["vtk-fixed-point h 0.5"]["ratio"] == 1.0, "the baseline's ratio is 1")
    for label, r in by.items():
        if not label.startswith("vtk"):
            check(r["rays"] > 0 and r["samples_per_ray"] > 0 and r["ratio"] > 0,
                  label + " reports rays, samples and a ratio")
    piecewise = by["piecewise eps 0.001"]
    check(piecewise["over_1e-3"] == 0.0 and piecewise["max_error"] <= 1e-3,
          "piecewise eps 0.001 within eps: %r" % piecewise)
    check(by["riemann h 0.5"]["max_error"] > piecewise["max_error"],
          "Riemann h 0.5 errs more than piecewise eps 0.001")
sys.exit(1 if failures else 0)
