#!/usr/bin/env python3
"""Checks postprocessing/work_precision.py on its cheapest study, the bead sliding down the
hanging cable (a coupled mass; the error of its leaving time against fixed dt / 1024):
  - the CSV has the four fixed and the four adaptive runs, each with its steps and CPU;
  - the fixed errors fall at second order in dt (at least 8 times per refinement by 4 from dt / 4,
    where the scheme is in its asymptotic range), the adaptive ones at least in proportion to the
    tolerance (at least 5 times per decade, at least 50 times from 1e-3 to 1e-5), and the adaptive
    steps grow as the tolerance falls;
  - the reference is read at each run's output times (the leaving time is an event, independent
    of the outputs, so the same reference serves all);
  - --summary draws the work-precision panels and the tolerance-proportionality figure.

Usage: check_work_precision.py TRAVERSE POSTPROCESSING_DIR OUT_DIR   (exit status 1 on any failure)
"""
import csv
import os
import subprocess
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from check_figure import Checks, png_checks  # noqa: E402

check = Checks()


def main():
    exe, pp, out = sys.argv[1:4]
    os.makedirs(out, exist_ok=True)
    script = os.path.join(pp, "work_precision.py")
    subprocess.run([sys.executable, script, "--traverse", exe, "--study", "bead", "--out", out], check=True)
    with open(os.path.join(out, "bead.csv")) as f:
        rows = list(csv.DictReader(f))
    fixed = [r for r in rows if r["method"] == "fixed"]
    adaptive = [r for r in rows if r["method"] == "adaptive"]
    check([float(r["parameter"]) for r in fixed] == [1, 4, 16, 64], "fixed runs at dt / 1, 4, 16, 64")
    check([float(r["parameter"]) for r in adaptive] == [1e-2, 1e-3, 1e-4, 1e-5], "adaptive runs at 1e-2 .. 1e-5")
    check(all(float(r["cpu_s"]) > 0 and int(r["steps"]) > 0 for r in rows), "every run has its CPU and steps")
    ef = [float(r["error"]) for r in fixed]
    ea = [float(r["error"]) for r in adaptive]
    print("fixed errors", ef, "adaptive errors", ea)
    check(all(ef[k] / ef[k + 1] > 8.0 for k in (1, 2)), f"fixed: second order from dt / 4 (ratios {ef[1] / ef[2]:.1f}, "
          f"{ef[2] / ef[3]:.1f} per refinement by 4)")
    check(all(ea[k] / ea[k + 1] > 5.0 for k in range(3)) and ea[1] / ea[3] > 50.0,
          "adaptive: the error falls at least in proportion to the tolerance (" +
          ", ".join(f"{ea[k] / ea[k + 1]:.1f}" for k in range(3)) + " times per decade)")
    steps = [int(r["steps"]) for r in adaptive]
    check(steps == sorted(steps), f"adaptive: more steps at tighter tolerances ({steps})")
    figs = os.path.join(out, "figures")
    os.makedirs(figs, exist_ok=True)
    subprocess.run([sys.executable, script, "--traverse", exe, "--out", out, "--summary", figs], check=True)
    for name in ("adaptive_work_precision.png", "adaptive_tolerance_proportionality.png"):
        png_checks(os.path.join(figs, name), check)
    check.finish()


if __name__ == "__main__":
    main()
