#!/usr/bin/env python3
"""Arch dynamics at reduced resolution (docs/results.md, "Hinged arches
under a travelling load"). Runs the traverse executable on inputs/arch and inputs/statics
scenes with --set overrides and checks the outputs with the analysis of
postprocessing/arches.py (the same code the figures and collapse_speed.py use).

    test_arch_dynamics.py TRAVERSE_EXE SCRATCH_DIR {shallow,deep,n2}

shallow  The slow load (v = 0.02 m/s) snaps the shallow arch close to the static fold
         computed at the same ds (0.01); v = 0.5 m/s snaps later; v = 5 and 20 m/s do not
         snap; the collapse criterion separates snap from no snap by a wide margin.
deep     With the lateral trigger (1e-6 F), the slowest load (v = 0.005 m/s) flops the deep
         arch sideways to the size of the static out-of-plane branch at the same ds (0.01);
         the lateral amplitude falls as the speed rises to 0.05 and 0.1 m/s; the static
         continuation from the pin finds the pitchfork pair at ds = 0.005 too.
n2       The step of n2 = n . d2 at the load equals -F . d2 at every output step.
Each prints what it measured. Exit status 0 when every check passes, 1 otherwise.
"""
import math
import os
import sys

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.normpath(os.path.join(HERE, "..", ".."))
sys.path.insert(0, os.path.join(ROOT, "postprocessing"))
import arches  # noqa: E402
import traverse_io  # noqa: E402

import cli_checks  # noqa: E402

import numpy as np  # noqa: E402

ARCH = os.path.join(ROOT, "inputs", "arch")
STATICS = os.path.join(ROOT, "inputs", "statics")
DAMPED = ["scheme.rho_inf=0.8", "solver.Max Subdivision Depth=10"]


def fmt(x):
    return "none" if x is None else f"{x:.3f}"


def run(exe, scratch, scene, name, sets):
    return cli_checks.run(exe, scratch, scene, name, sets, "test_arch_dynamics")


def shallow(exe, scratch, check):
    ds = 0.01
    # Static fold at the same ds: small continuation steps from sigma = 0.2 (the primary branch
    # is stable there), no branch switching.
    st = run(exe, scratch, os.path.join(STATICS, "shallow_arch_sigma.yaml"), "shallow_static",
             [f"mesh.ds={ds}", "continuation.start=0.2", "continuation.stop=0.4",
              "continuation.step=0.003", "continuation.max_step=0.003", "continuation.switch_branches=false"])
    fold = arches.static_fold(st)
    check(fold is not None, f"static fold found at ds = {ds}: sigma = {fold} m")
    if fold is None:
        return
    scene = os.path.join(ARCH, "shallow_arch_v1.0.yaml")
    res = {}
    # The slow load to t = 20 s (sigma = 0.4 m), past its snap: its steps of ds / v = 0.5 s do not
    # resolve the motion after the snap, which Newton may then fail to follow.
    for v, extra in ((0.02, DAMPED + ["time.end=20"]), (0.5, []), (5.0, []), (20.0, [])):
        out = run(exe, scratch, scene, f"shallow_v{v}",
                  [f"loads.F.speed={v}", f"mesh.ds={ds}", "output.fields=[]"] + extra)
        res[v] = arches.collapse(traverse_io.load(out))
        c = res[v]
        print(f"  v = {v} m/s: " + (f"snaps at sigma = {c['sigma']:.3f} m" if c["snapped"] else "no snap")
              + f", largest end rotation {math.degrees(c['max_rotation']):.1f} deg "
              f"(threshold alpha0 = {math.degrees(c['alpha0']):.1f} deg)")
    slow = res[0.02]
    # Tolerance: the snap is seen at the first output step past the threshold, and output steps
    # are ds = 0.01 apart in sigma (dt = ds / v); the dynamic snap also lags the fold by a delay
    # that vanishes as v -> 0 (measured at ds = 0.01: 0.035, 0.075, 0.135 m at v = 0.05, 0.1,
    # 0.2 m/s, roughly proportional to v, i.e. about 0.015 m at v = 0.02). Allowed: 3 ds after
    # the fold, and half a step before it (the fold itself is located to about 1e-3 m).
    check(slow["snapped"] and fold - 0.5 * ds <= slow["sigma"] <= fold + 3 * ds,
          f"v = 0.02 m/s snaps at sigma = {fmt(slow['sigma'])} m, static fold {fold:.4f} m "
          f"(allowed [{fold - 0.5 * ds:.4f}, {fold + 3 * ds:.4f}])")
    check(res[0.5]["snapped"] and res[0.5]["sigma"] > slow["sigma"] + 0.05,
          f"v = 0.5 m/s snaps later than the slow load: sigma = {fmt(res[0.5]['sigma'])} m")
    for v in (5.0, 20.0):
        check(not res[v]["snapped"], f"v = {v} m/s does not snap")
    # Wide margin: snapping runs rotate the end far beyond alpha0, the others stay far below it.
    a0 = slow["alpha0"]
    check(min(res[v]["max_rotation"] for v in (0.02, 0.5)) > 1.5 * a0,
          "snapping runs rotate the right end by more than 1.5 alpha0")
    check(max(res[v]["max_rotation"] for v in (5.0, 20.0)) < 0.25 * a0,
          "runs that do not snap rotate it by less than 0.25 alpha0")


def deep(exe, scratch, check):
    ds = 0.01
    st = run(exe, scratch, os.path.join(STATICS, "deep_arch_sigma.yaml"), "deep_static", [f"mesh.ds={ds}"])
    s = arches.static_out_of_plane(st)
    # From the pin the load enters the rod over the first cell, where the branch's tangent is
    # almost all state and the arclength corrector can slide to the far end (where the load has
    # left and the state is the same): at ds = 0.005 too the continuation finds the pitchfork
    # pair, symmetric about L / 2.
    fine = arches.static_out_of_plane(run(exe, scratch, os.path.join(STATICS, "deep_arch_sigma.yaml"),
                                          "deep_static_fine", ["mesh.ds=0.005"]))
    check(abs(fine["sigma1"] + fine["sigma2"] - 1.0) < 1e-6 and 0.4 < fine["sigma1"] < 0.45,
          f"ds = 0.005: pitchforks at sigma = {fine['sigma1']:.4f}, {fine['sigma2']:.4f} m (sum L to 1e-6)")
    print(f"  static (ds = {ds}): pitchforks at sigma = {s['sigma1']:.4f}, {s['sigma2']:.4f} m; "
          f"largest |x(L/2)| on the stable out-of-plane branch {s['amplitude']:.4f} m ({len(s['x']) - 2} states)")
    check(len(s["x"]) >= 5, "the static out-of-plane branch has at least 3 stable states between the pitchforks")
    amp = {}
    lat = {}
    for v in (0.005, 0.01, 0.05, 0.1):
        out = run(exe, scratch, os.path.join(ARCH, f"deep_arch_v{v}.yaml"), f"deep_v{v}",
                  [f"mesh.ds={ds}", "output.every=1", "output.fields=[]"] + DAMPED)
        lat[v] = arches.lateral(traverse_io.load(out))
        amp[v] = lat[v]["amplitude"]
        print(f"  v = {v} m/s: max |x(L/2)| = {amp[v]:.4g} m at sigma = {lat[v]['sigma_max']:.3f} m")
    d = lat[0.005]
    before = np.abs(d["x"][d["sigma"] < s["sigma1"] - 0.03]).max()
    check(before < 1e-3, f"v = 0.005: planar before the pitchfork (|x| <= {before:.2g} m for sigma < sigma1 - 0.03)")
    # The slow load releases the arch near the unstable planar state with little kinetic energy:
    # it oscillates about the stable static branch. For the pitchfork's normal form
    # V = -a x^2 / 2 + b x^4 / 4 released at rest from x = 0 the motion spans 0..sqrt(2) x_s;
    # allowed: 0.8 x_s (the size of the branch, less 20 %) to 1.5 x_s (sqrt 2 and the change of
    # the branch while the load moves on).
    xs = s["amplitude"]
    check(0.8 * xs <= amp[0.005] <= 1.5 * xs,
          f"v = 0.005: max |x| = {amp[0.005]:.4f} m is the size of the static branch "
          f"{xs:.4f} m (ratio {amp[0.005] / xs:.3f}, allowed 0.8-1.5)")
    # ... and oscillates about it: the mean of x from the flop (|x| first reaching x_s / 2) to
    # sigma2 - 0.02 against the static branch's mean over the same sigma (interpolated).
    k0 = int(np.argmax(np.abs(d["x"]) >= 0.5 * xs))
    w = (np.arange(len(d["x"])) >= k0) & (d["sigma"] <= s["sigma2"] - 0.02)
    dyn_mean = float(np.mean(np.abs(d["x"][w])))
    st_mean = float(np.mean(np.interp(d["sigma"][w], s["sigma"], s["x"])))
    check(w.sum() >= 5 and abs(dyn_mean - st_mean) <= 0.25 * st_mean,
          f"v = 0.005: mean |x| over sigma {d['sigma'][k0]:.3f}..{s['sigma2'] - 0.02:.3f} = {dyn_mean:.4f} m, "
          f"static branch {st_mean:.4f} m (allowed +/- 25 %)")
    check(amp[0.05] < 0.2 * min(amp[0.005], amp[0.01]),
          f"amplitude falls: v = 0.05 ({amp[0.05]:.2g} m) below 0.2 x that at v = 0.005 and 0.01")
    check(amp[0.1] < amp[0.05], f"amplitude falls: v = 0.1 ({amp[0.1]:.2g} m) below v = 0.05 ({amp[0.05]:.2g} m)")


def n2(exe, scratch, check):
    # Tolerance: 5 % of |F|. The measured step extrapolates n2 linearly from two nodes on each
    # side of the load, which leaves O(ds^2 n2'') of the smooth variation of n2 (gravity,
    # curvature coupling, inertia); the check that the difference falls with ds shows it is
    # that discretisation error and not a missing part of the load.
    worst = {}
    for ds in (0.01, 0.005):
        out = run(exe, scratch, os.path.join(ARCH, "shallow_arch_v0.5.yaml"), f"n2_shallow_ds{ds}",
                  [f"mesh.ds={ds}", "output.fields=[n, R]"])
        r = traverse_io.load(out)
        sig, meas, exp = arches.n2_step(r)
        F = np.linalg.norm(arches.scene_force(r))
        err = np.abs(meas - exp)
        worst[ds] = err.max()
        k = int(np.argmax(err))
        check(len(sig) >= round(0.9 / ds) and err.max() <= 0.05 * F,
              f"shallow v = 0.5, ds = {ds}: {len(sig)} output steps (sigma {sig[0]:.3f}..{sig[-1]:.3f}, "
              f"through the snap), step {meas.min():.3f}..{meas.max():.3f} N, max |step + F.d2| = "
              f"{err.max():.4f} N at sigma = {sig[k]:.3f} (allowed {0.05 * F:.3f} N)")
    check(worst[0.005] < 0.5 * worst[0.01],
          f"the difference falls with ds: {worst[0.01]:.4f} N -> {worst[0.005]:.4f} N (ratio "
          f"{worst[0.01] / worst[0.005]:.2f}, required > 2)")
    out = run(exe, scratch, os.path.join(ARCH, "deep_arch_v0.005.yaml"), "n2_deep",
              ["mesh.ds=0.01", "output.every=1", "output.fields=[n, R]"] + DAMPED)
    r = traverse_io.load(out)
    sig, meas, exp = arches.n2_step(r)
    F = np.linalg.norm(arches.scene_force(r))
    err = np.abs(meas - exp)
    check(len(sig) >= 90 and err.max() <= 0.05 * F,
          f"deep v = 0.005 (flop), ds = 0.01: {len(sig)} output steps, step {meas.min():.3f}..{meas.max():.3f} N, "
          f"max |step + F.d2| = {err.max():.4f} N (allowed {0.05 * F:.3f} N)")


if __name__ == "__main__":
    sys.exit(cli_checks.main("test_arch_dynamics", {"shallow": shallow, "deep": deep, "n2": n2}, sys.argv, __doc__))
