#!/usr/bin/env python3
"""Critical speed of the shallow arch: the speed above which the travelling load no longer
snaps it, found by bisection on v.

Each trial runs inputs/arch/shallow_arch_v1.0.yaml with --set loads.F.speed=v (dt = ds / v,
so every run has L / ds steps) and --set mesh.ds=DS, and applies the collapse criterion of
postprocessing/arches.py (collapse()): the arch has snapped when the right end has rotated
towards the snap by more than its initial inclination alpha0 (the end tangent has turned
through the horizontal) at some output step while the load is on the arch.

The bracket [LO, HI] must have LO snapping and HI not (checked first); the bisection then
halves it until HI - LO <= TOL. Reported per ds: the bracket, the snap position at LO and the
largest end rotation at HI. The bisection assumes one transition between LO and HI: use
--scan to check that on a list of speeds first.

Usage:
  collapse_speed.py --traverse BUILD/traverse [--ds 0.02 0.01 ...] [--lo 0.5] [--hi 5]
                    [--tol 0.01] [--threshold-deg T] [--work DIR] [--set KEY=VALUE ...]
  collapse_speed.py --traverse BUILD/traverse --ds 0.01 --scan 0.5 1 2 2.5 3 5 20
"""
import argparse
import math
import os
import subprocess
import sys
import time

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import arches  # noqa: E402
import traverse_io  # noqa: E402

SCENE = os.path.join(arches.INPUTS, "shallow_arch_v1.0.yaml")


class Trial:
    def __init__(self, exe, work, ds, sets, threshold):
        self.exe, self.work, self.ds, self.sets, self.threshold = exe, work, ds, sets, threshold
        self.count = 0
        self.seconds = 0.0
        self.results = {}

    def __call__(self, v):
        if v in self.results:
            return self.results[v]
        out = os.path.join(self.work, f"shallow_ds{self.ds:g}_v{v:.6g}.h5")
        cmd = [self.exe, "run", SCENE, "-o", out, "--overwrite", "-q",
               "--set", f"loads.F.speed={v!r}", "--set", f"mesh.ds={self.ds!r}",
               "--set", "output.fields=[]"]
        for s in self.sets:
            cmd += ["--set", s]
        t0 = time.time()
        p = subprocess.run(cmd, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
        self.seconds += time.time() - t0
        self.count += 1
        if p.returncode not in (0, 3):
            raise SystemExit(f"collapse_speed: {' '.join(cmd)} exited with {p.returncode}:\n{p.stdout}")
        r = traverse_io.load(out, allow_incomplete=True)
        c = arches.collapse(r, self.threshold)
        if p.returncode == 3 and not c["snapped"]:
            # A failed run that had not snapped yet says nothing about the rest of the passage.
            raise SystemExit(f"collapse_speed: v = {v} failed before any snap ({r.status}); "
                             "try --set scheme.rho_inf=0.8")
        c["status"] = r.status
        self.results[v] = c
        print(f"  ds = {self.ds:g}  v = {v:<10.6g} " + describe(c), flush=True)
        return c


def describe(c):
    rot = f"largest end rotation {math.degrees(c['max_rotation']):6.1f} deg"
    return (f"snaps at sigma = {c['sigma']:.3f} m ({rot})" if c["snapped"] else f"no snap ({rot})")


def bisect(trial, lo, hi, tol):
    a, b = trial(lo), trial(hi)
    if not a["snapped"]:
        raise SystemExit(f"collapse_speed: v = {lo} does not snap; give a lower --lo")
    if b["snapped"]:
        raise SystemExit(f"collapse_speed: v = {hi} snaps; give a higher --hi")
    while hi - lo > tol * (1.0 + 1e-9):
        mid = 0.5 * (lo + hi)
        if trial(mid)["snapped"]:
            lo = mid
        else:
            hi = mid
    return lo, hi


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--traverse", required=True)
    ap.add_argument("--ds", type=float, nargs="+", default=[0.02, 0.01, 0.005])
    ap.add_argument("--lo", type=float, default=0.5, help="a speed that snaps [m/s]")
    ap.add_argument("--hi", type=float, default=5.0, help="a speed that does not snap [m/s]")
    ap.add_argument("--tol", type=float, default=0.01, help="final bracket width [m/s]")
    ap.add_argument("--threshold-deg", type=float,
                    help="collapse threshold on the right-end rotation [deg] (default: its initial inclination)")
    ap.add_argument("--scan", type=float, nargs="+", help="only run these speeds and report each")
    ap.add_argument("--work", default="out/collapse_speed", help="folder for the runs' outputs")
    ap.add_argument("--set", action="append", default=[], help="extra scene override (repeatable)")
    a = ap.parse_args(argv)
    os.makedirs(a.work, exist_ok=True)
    thr = None if a.threshold_deg is None else math.radians(a.threshold_deg)
    rows = []
    for ds in a.ds:
        trial = Trial(a.traverse, a.work, ds, a.set, thr)
        if a.scan:
            for v in a.scan:
                trial(v)
            continue
        lo, hi = bisect(trial, a.lo, a.hi, a.tol)
        rows.append((ds, lo, hi, trial.results[lo], trial.results[hi], trial.count, trial.seconds))
    if rows:
        alpha0 = math.degrees(rows[0][3]["alpha0"])
        print(f"\ncritical speed of the shallow arch (threshold "
              f"{math.degrees(rows[0][3]['threshold']):.2f} deg, alpha0 = {alpha0:.2f} deg"
              + (f", overrides {a.set}" if a.set else "") + ")")
        print("| ds [m] | snaps at v [m/s] (snap sigma [m]) | no snap at v [m/s] (largest end rotation [deg]) "
              "| midpoint [m/s] | runs | run time [s] |")
        print("|---|---|---|---|---|---|")
        for ds, lo, hi, cl, ch, n, sec in rows:
            print(f"| {ds:g} | {lo:.4f} ({cl['sigma']:.3f}) | {hi:.4f} ({math.degrees(ch['max_rotation']):.1f}) "
                  f"| {0.5 * (lo + hi):.4f} | {n} | {sec:.0f} |")


if __name__ == "__main__":
    main()
