#!/usr/bin/env python3
"""Critical speed of the shallow arch: the speed above which the travelling load no longer
snaps it, found by bisection on v.

Each trial runs inputs/arch/shallow_arch_v1.0.yaml with --set loads.F.speed=v (dt = ds / v,
so every run has L / ds steps) and --set mesh.ds=DS, and applies the collapse criterion of
postprocessing/arches.py (collapse()): the arch has snapped when the right end has rotated
towards the snap by more than its initial inclination alpha0 (the end tangent has turned
through the horizontal) at some output step while the load is on the arch.

The bracket [LO, HI] must have LO snapping and HI not (checked first); each round then runs
POINTS evenly spaced speeds inside it in one `traverse sweep` (its cases spread over --ranks
MPI ranks; POINTS = 1, the default with one of each, is bisection) and keeps the sub-interval where the snap
stops, until HI - LO <= TOL. Reported per ds: the bracket, the snap position at LO and the
largest end rotation at HI. The bisection assumes one transition between LO and HI: use
--scan to check that on a list of speeds first.

Usage:
  collapse_speed.py --traverse BUILD/traverse [--ds 0.02 0.01 ...] [--lo 0.5] [--hi 5]
                    [--tol 0.01] [--threshold-deg T] [--work DIR] [--set KEY=VALUE ...]
                    [--ranks K] [--points P]
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
    """Runs speeds in rounds: each round is one `traverse sweep` over its speeds (spread over
    `ranks` MPI ranks); results are kept per speed."""

    def __init__(self, exe, work, ds, sets, threshold, ranks=1):
        self.exe, self.work, self.ds, self.sets, self.threshold, self.ranks = exe, work, ds, sets, threshold, ranks
        self.count = 0
        self.rounds = 0
        self.seconds = 0.0
        self.results = {}

    def __call__(self, v):
        return self.batch([v])[0]

    def batch(self, speeds):
        todo = [v for v in dict.fromkeys(speeds) if v not in self.results]
        if todo:
            self._sweep(todo)
        return [self.results[v] for v in speeds]

    def _sweep(self, speeds):
        self.rounds += 1
        out = os.path.join(self.work, f"shallow_ds{self.ds:g}_round{self.rounds}")
        cmd = traverse_io.command(self.exe, "sweep", self.ranks) + [
            SCENE, "-o", out, "--overwrite", "-q",
            "--vary", "loads.F.speed=" + ",".join(repr(v) for v in speeds),
            "--set", f"mesh.ds={self.ds!r}", "--set", "output.fields=[]"]
        for s in self.sets:
            cmd += ["--set", s]
        t0 = time.time()
        p = subprocess.run(cmd, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
        self.seconds += time.time() - t0
        self.count += len(speeds)
        if not os.path.exists(os.path.join(out, "index.csv")):
            raise SystemExit(f"collapse_speed: {' '.join(cmd)} exited with {p.returncode}:\n{p.stdout}")
        for v, row in zip(speeds, traverse_io.sweep_index(out)):
            if row["exit_code"] not in ("0", "3"):
                raise SystemExit(f"collapse_speed: v = {v}: {row['status']}: {row['message']}")
            r = traverse_io.load(os.path.join(out, row["output"]), allow_incomplete=True)
            c = arches.collapse(r, self.threshold)
            if row["exit_code"] == "3" and not c["snapped"]:
                # A failed run that had not snapped yet says nothing about the rest of the passage.
                raise SystemExit(f"collapse_speed: v = {v} failed before any snap ({r.status}); "
                                 "try --set scheme.rho_inf=0.8")
            c["status"] = r.status
            self.results[v] = c
            print(f"  ds = {self.ds:g}  v = {v:<10.6g} " + describe(c), flush=True)


def describe(c):
    rot = f"largest end rotation {math.degrees(c['max_rotation']):6.1f} deg"
    return (f"snaps at sigma = {c['sigma']:.3f} m ({rot})" if c["snapped"] else f"no snap ({rot})")


def bisect(trial, lo, hi, tol, points=1):
    """Shrinks [lo, hi] (lo snaps, hi does not) until hi - lo <= tol; each round runs `points`
    evenly spaced speeds inside the bracket in one sweep (points = 1: bisection)."""
    a, b = trial.batch([lo, hi])
    if not a["snapped"]:
        raise SystemExit(f"collapse_speed: v = {lo} does not snap; give a lower --lo")
    if b["snapped"]:
        raise SystemExit(f"collapse_speed: v = {hi} snaps; give a higher --hi")
    while hi - lo > tol * (1.0 + 1e-9):
        inner = [lo + (hi - lo) * (k + 1) / (points + 1) for k in range(points)]
        snapped = [c["snapped"] for c in trial.batch(inner)]
        speeds = [lo] + inner + [hi]
        first_no = next(k for k, s in enumerate(snapped + [False]) if not s) + 1  # index in speeds
        lo, hi = speeds[first_no - 1], speeds[first_no]
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
    ap.add_argument("--ranks", type=int, default=1, help="MPI ranks of each round's sweep")
    ap.add_argument("--points", type=int,
                    help="speeds per round inside the bracket (default: --ranks; 1: bisection)")
    a = ap.parse_args(argv)
    points = max(1, a.points or a.ranks)
    os.makedirs(a.work, exist_ok=True)
    thr = None if a.threshold_deg is None else math.radians(a.threshold_deg)
    rows = []
    for ds in a.ds:
        trial = Trial(a.traverse, a.work, ds, a.set, thr, a.ranks)
        if a.scan:
            trial.batch(a.scan)
            continue
        lo, hi = bisect(trial, a.lo, a.hi, a.tol, points)
        rows.append((ds, lo, hi, trial.results[lo], trial.results[hi], trial.count, trial.rounds, trial.seconds))
    if rows:
        alpha0 = math.degrees(rows[0][3]["alpha0"])
        print(f"\ncritical speed of the shallow arch (threshold "
              f"{math.degrees(rows[0][3]['threshold']):.2f} deg, alpha0 = {alpha0:.2f} deg"
              + (f", overrides {a.set}" if a.set else "") + ")")
        print("| ds [m] | snaps at v [m/s] (snap sigma [m]) | no snap at v [m/s] (largest end rotation [deg]) "
              "| midpoint [m/s] | runs | sweeps | run time [s] |")
        print("|---|---|---|---|---|---|---|")
        for ds, lo, hi, cl, ch, n, rounds, sec in rows:
            print(f"| {ds:g} | {lo:.4f} ({cl['sigma']:.3f}) | {hi:.4f} ({math.degrees(ch['max_rotation']):.1f}) "
                  f"| {0.5 * (lo + hi):.4f} | {n} | {rounds} | {sec:.0f} |")


if __name__ == "__main__":
    main()
