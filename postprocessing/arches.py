#!/usr/bin/env python3
"""Hinged-arch figures of the scenes spec from the runs of inputs/arch/*.yaml, and the
analysis they share with postprocessing/collapse_speed.py and the arch-dynamics tests.

Shallow arch (F = 2 N):
  shallow_arch_hinge_spin.png   (a) omega(L) . i at the right hinge against sigma, a curve per v
  shallow_arch_end_rotation.png the right end's rotation against sigma, a curve per v, with the
                                collapse threshold (the collapse criterion, see collapse())
  shallow_arch_shapes_v0.5.png  (b) shapes at several sigma for v = 0.5 m/s, up to after collapse
  shallow_arch_n2_v0.5.png      (c) n2 = n . d2 against s at several times: the step travels with
                                the load; and the step against the load's component along d2
  shallow_arch_fast_shapes.png  (d) shapes at v = 2.6 and 20 m/s
Deep arch (F = 3.8 N, lateral trigger 1e-6 F):
  deep_arch_midpoint_slow.png   lateral x and vertical y of the midpoint against sigma for the
                                two slowest speeds, with the static out-of-plane branch
  deep_arch_lateral.png         lateral x against sigma for the faster speeds, and |x| of every
                                speed on a log scale
  deep_arch_shapes.png          3-D shapes (and plan views) at three sigma for the two slowest speeds

Usage: arches.py --traverse BUILD/traverse [--out DIR] [--plot-only] [--speeds-shallow ...]
                 [--speeds-deep ...] [--static-deep FILE.h5]
The static out-of-plane branch drawn with the deep arch comes from --static-deep (a
continuation output of inputs/statics/deep_arch_sigma.yaml); without it, and unless
--plot-only, the script runs that scene at mesh.ds = 0.005 into DIR/deep_static.h5.
"""
import argparse
import math
import os
import re
import subprocess
import sys

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import traverse_io  # noqa: E402

HERE = os.path.dirname(os.path.abspath(__file__))
INPUTS = os.path.join(HERE, "..", "inputs", "arch")
STATICS = os.path.join(HERE, "..", "inputs", "statics")
SHALLOW = [0.02, 0.5, 1.0, 2.0, 2.6, 5.0, 20.0]
DEEP = [0.005, 0.01, 0.05, 0.1]


# ---------------------------------------------------------------------------------------
# Analysis (used by the figures, collapse_speed.py and tests/validation/test_arch_dynamics.py)
# ---------------------------------------------------------------------------------------

def load_on(out):
    """True at the output steps at which the (first) moving load is on the rod, 0 <= sigma <= L."""
    sig = traverse_io.first_load_sigma(out)
    length = float(out.s[-1])
    return (sig >= -1e-12) & (sig <= length * (1.0 + 1e-12))


def right_end_rotation(out):
    """Rotation of the right end about i since t = 0 [rad], positive in the direction of the
    snap (the end tangent d3(L), which points down-and-out at the start, turns upwards; this
    is a rotation about -i, i.e. the integral of -omega(L) . i). Computed from the probe
    `end_tangent` (d3 at s = L, fixed frame): the pin keeps d3(L) in the (j, k) plane, so the
    rotation is the change of its angle atan2(d3 . j, d3 . k). Returns (theta, alpha0): theta
    per output step and the initial inclination alpha0 = -atan2(d3 . j, d3 . k) at t = 0 (> 0
    for an arch rising from its right support)."""
    if "end_tangent" not in out.probes:
        raise KeyError(f"{out.path}: no probe 'end_tangent' (d3 at s = L, fixed frame); "
                       "add `end_tangent: {type: point, at: 1.0, quantity: d3}` to output.probes")
    d3 = np.asarray(out.probes["end_tangent"], dtype=float)
    angle = np.arctan2(d3[:, 1], d3[:, 2])
    # Wrapped to (-pi, pi]: not unwrapped, because a coarse time step after a snap (the
    # damped slow runs, dt = 0.5 s) can alias the end's vibration into spurious full turns.
    return np.angle(np.exp(1j * (angle - angle[0]))), -angle[0]


def collapse(out, threshold=None):
    """The shallow arch's collapse criterion.

    The arch has snapped when the right end has rotated, in the direction of the snap, by more
    than `threshold` [rad] at some output step while the load is on the arch (0 <= sigma <= L).
    Default threshold: the end's initial inclination alpha0 (42.6 degrees for the scene's
    shallow arch), i.e. the right end tangent has turned through the horizontal. Justification
    (docs/results.md): runs that snap rotate the end by 92-112 degrees (the inverted arch),
    runs that do not snap by at most 4.5 degrees, so alpha0 lies in a wide gap.

    Returns a dict: snapped (bool), sigma (load position at the first step over the threshold,
    None if there is none), max_rotation (largest theta while the load is on) [rad], threshold
    [rad], alpha0 [rad]."""
    theta, alpha0 = right_end_rotation(out)
    thr = alpha0 if threshold is None else float(threshold)
    on = load_on(out)
    sig = traverse_io.first_load_sigma(out)
    over = np.nonzero(on & (theta >= thr))[0]
    return {
        "snapped": bool(over.size),
        "sigma": float(sig[over[0]]) if over.size else None,
        "max_rotation": float(theta[on].max()),
        "threshold": thr,
        "alpha0": alpha0,
    }


def scene_force(out):
    """The moving load's force vector (fixed frame) [N] from the scene text stored in the
    output (`force_vector: [..]` or `force: F` along -j). Only one moving force is handled."""
    text = str(out.attrs.get("scene", ""))
    m = re.search(r"^\s+force_vector:\s*\[([^\]]*)\]", text, re.M)
    if m:
        return np.array([float(x) for x in m.group(1).split(",")])
    m = re.search(r"^\s+force:\s*([-+0-9.eE]+)\s*$", text, re.M)
    if m:
        return np.array([0.0, -float(m.group(1)), 0.0])
    raise ValueError(f"{out.path}: no moving force (force or force_vector) in the stored scene")


def n2_step(out, force=None):
    """The step of n2 = n . d2 at the load, at every output step with the load on a node j
    with 3 <= j <= N - 3 (dt = ds / v puts the load on a node at every step).

    Measured: n2 extrapolated linearly to s_j from the two nodes on its right (j+1, j+2),
    minus the same from the two nodes on its left (j-1, j-2): node j itself carries half the
    step (the load's weight is split between the cells on either side), and the linear
    extrapolation removes the smooth variation of n2 to O(ds^2). Expected: the point force
    gives n(s+) - n(s-) = -F, so the step in n2 is -F . d2 with d2 the director at the load
    (field R, row 2). Needs the fields n and R. Returns (sigma, measured, expected) arrays."""
    f = scene_force(out) if force is None else np.asarray(force, dtype=float)
    n = out.field("n")
    R = out.field("R")
    s = out.s
    ds = float(s[1] - s[0])
    N = len(s) - 1
    sig = traverse_io.first_load_sigma(out)
    rows = []
    for k in range(len(sig)):
        j = int(round(sig[k] / ds))
        if abs(sig[k] - j * ds) > 1e-6 * ds or j < 3 or j > N - 3:
            continue
        n2 = n[k, :, 1]
        right = 2.0 * n2[j + 1] - n2[j + 2]
        left = 2.0 * n2[j - 1] - n2[j - 2]
        d2 = R[k, j].reshape(3, 3)[1]
        rows.append((sig[k], right - left, -float(f @ d2)))
    a = np.array(rows).reshape(-1, 3)
    return a[:, 0], a[:, 1], a[:, 2]


def rho_inf(out):
    """scheme.rho_inf of the run (from the stored scene text)."""
    m = re.search(r"^\s+rho_inf:\s*([-+0-9.eE]+)\s*$", str(out.attrs.get("scene", "")), re.M)
    return float(m.group(1)) if m else 1.0


def lateral(out):
    """Deep arch: lateral midpoint position x(L/2) [m] (probe `midpoint`) and its largest
    magnitude. Returns dict: sigma, x, y, amplitude = max |x|, sigma_max (where it occurs)."""
    m = np.asarray(out.probes["midpoint"])
    sig = traverse_io.first_load_sigma(out)
    k = int(np.argmax(np.abs(m[:, 0])))
    return {"sigma": sig, "x": m[:, 0], "y": m[:, 1], "amplitude": float(abs(m[k, 0])),
            "sigma_max": float(sig[k])}


def _text(v):
    return v.decode() if isinstance(v, bytes) else str(v)


def static_fold(path):
    """sigma of the fold of a load_position continuation file
    (inputs/statics/shallow_arch_sigma.yaml): the first fold on the primary branch in
    /bifurcations, else the turning point of the primary path (the largest sigma it reaches,
    provided the path turns back towards smaller sigma after it), else None. The fallback is
    there because a fold found only by the sign change of an eigenvalue may be recorded under
    another type when it is not located."""
    import h5py

    with h5py.File(path, "r") as f:
        if "bifurcations" in f:
            b = f["bifurcations"]
            kinds = [_text(t) for t in b["type"][...]]
            folds = [float(p) for t, br, p in zip(kinds, b["branch"][...], b["load_position"][...])
                     if t == "fold" and br == 0]
            if folds:
                return min(folds)
        c = f["continuation"]
        s = c["load_position"][...][c["branch"][...] == 0]
    k = int(np.argmax(s))
    return float(s[k]) if 0 < k < len(s) - 1 and s[-1] < s[k] else None


def static_out_of_plane(path):
    """The deep arch's static picture from a load_position continuation file
    (inputs/statics/deep_arch_sigma.yaml): the two pitchforks on the primary branch and the
    stable out-of-plane states between them. Returns dict: sigma1, sigma2, sigma (sorted),
    x (|x(L/2)| of the stable switched-branch states with sigma1 <= sigma <= sigma2, with 0
    added at both pitchforks), amplitude = the largest |x|."""
    import h5py

    with h5py.File(path, "r") as f:
        b = f["bifurcations"]
        kinds = [_text(t) for t in b["type"][...]]
        pf = sorted(float(p) for t, br, p in zip(kinds, b["branch"][...], b["load_position"][...])
                    if t == "pitchfork" and br == 0)
        if len(pf) < 2:
            raise ValueError(f"{path}: fewer than two pitchforks on the primary branch")
        c = f["continuation"]
        s = c["load_position"][...]
        x = c["mid_x"][...]
        keep = ((c["branch"][...] > 0) & (c["unstable_modes"][...] == 0) & (np.abs(x) > 1e-6)
                & (s >= pf[0]) & (s <= pf[-1]))
    s1, s2 = pf[0], pf[-1]
    o = np.argsort(s[keep])
    ss = np.concatenate([[s1], s[keep][o], [s2]])
    xs = np.concatenate([[0.0], np.abs(x[keep])[o], [0.0]])
    return {"sigma1": s1, "sigma2": s2, "sigma": ss, "x": xs, "amplitude": float(xs.max())}


# ---------------------------------------------------------------------------------------
# Runs and figures
# ---------------------------------------------------------------------------------------

def path(out, kind, v):
    return os.path.join(out, f"{kind}_v{v}.h5")


def run(exe, out, kind, v):
    scene = os.path.join(INPUTS, f"{kind}_arch_v{v}.yaml")
    subprocess.run([exe, "run", scene, "-o", path(out, kind, v), "--overwrite", "-q"], check=True)


def available(out, kind, speeds):
    return [v for v in speeds if os.path.exists(path(out, kind, v))]


def _plt():
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    return plt


def nearest(sig, target):
    return int(np.nanargmin(np.abs(sig - target)))


def shallow_figures(out, speeds):
    plt = _plt()
    fig, ax = plt.subplots(figsize=(8, 4.8))
    for v in speeds:
        r = traverse_io.load(path(out, "shallow", v))
        ax.plot(traverse_io.first_load_sigma(r), r.probes["hinge_spin"][:, 0], label=f"v = {v} m/s")
    ax.set_xlabel("load position sigma [m]")
    ax.set_ylabel("omega(L) . i at the right hinge [rad/s]")
    ax.set_xlim(0, 1)
    ax.grid(True, alpha=0.3)
    ax.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(os.path.join(out, "shallow_arch_hinge_spin.png"), dpi=120)
    plt.close(fig)

    fig, ax = plt.subplots(figsize=(11, 4.8))
    alpha0 = None
    for v in speeds:
        r = traverse_io.load(path(out, "shallow", v))
        if "end_tangent" not in r.probes:
            continue
        theta, alpha0 = right_end_rotation(r)
        c = collapse(r)
        lab = f"v = {v} m/s: " + (f"snaps at sigma = {c['sigma']:.2f} m" if c["snapped"] else "no snap")
        ax.plot(traverse_io.first_load_sigma(r), np.degrees(theta), label=lab)
    if alpha0 is not None:
        ax.axhline(np.degrees(alpha0), color="k", ls="--", lw=1,
                   label=f"threshold alpha0 = {np.degrees(alpha0):.1f} deg (end tangent horizontal)")
    ax.set_xlabel("load position sigma [m]")
    ax.set_ylabel("rotation of the right end towards the snap [deg]")
    ax.set_xlim(0, 1)
    ax.grid(True, alpha=0.3)
    ax.legend(fontsize=7, loc="upper left", bbox_to_anchor=(1.01, 1.0))
    ax.set_title("shallow arch, F = 2 N: collapse criterion")
    fig.tight_layout()
    fig.savefig(os.path.join(out, "shallow_arch_end_rotation.png"), dpi=120)
    plt.close(fig)

    if 0.5 in speeds:
        r = traverse_io.load(path(out, "shallow", 0.5))
        sig = traverse_io.first_load_sigma(r)
        fig, ax = plt.subplots(figsize=(8, 4.5))
        for target in [0.0, 0.2, 0.4, 0.6, 0.65, 0.7, 0.8, 1.0]:
            k = nearest(sig, target)
            xyz = r.field("r", k)
            ax.plot(xyz[:, 2], xyz[:, 1], label=f"sigma = {sig[k]:.2f} m")
        ax.set_xlabel("z [m]")
        ax.set_ylabel("y [m]")
        ax.set_aspect("equal", adjustable="datalim")
        ax.grid(True, alpha=0.3)
        ax.legend(fontsize=7, ncol=2)
        ax.set_title("shallow arch, F = 2 N, v = 0.5 m/s")
        fig.tight_layout()
        fig.savefig(os.path.join(out, "shallow_arch_shapes_v0.5.png"), dpi=120)
        plt.close(fig)

        fig, (ax, bx) = plt.subplots(1, 2, figsize=(13, 4.5))
        s = r.s
        for target in [0.1, 0.3, 0.5]:
            k = nearest(sig, target)
            n = r.field("n", k)
            ax.plot(s, n[:, 1], label=f"t = {r.time[k]:.3f} s (sigma = {sig[k]:.2f} m)")
        ax.set_xlabel("s [m]")
        ax.set_ylabel("n2 = n . d2 [N]")
        ax.grid(True, alpha=0.3)
        ax.legend(fontsize=8)
        ax.set_title("v = 0.5 m/s: the step in n2 travels with the load")
        if "R" in r.field_names:
            ss, measured, expected = n2_step(r)
            bx.plot(ss, expected, "k-", lw=1, label="-F . d2 at the load")
            bx.plot(ss, measured, ".", ms=4, label="step of n2 at the load")
            bx.set_xlabel("load position sigma [m]")
            bx.set_ylabel("[N]")
            bx.grid(True, alpha=0.3)
            bx.legend(fontsize=8)
            bx.set_title(f"step vs load component: max difference {np.abs(measured - expected).max():.3f} N")
        fig.tight_layout()
        fig.savefig(os.path.join(out, "shallow_arch_n2_v0.5.png"), dpi=120)
        plt.close(fig)

    fast = [v for v in (2.6, 20.0) if v in speeds]
    if fast:
        fig, axes = plt.subplots(1, len(fast), figsize=(6 * len(fast), 4.2), squeeze=False)
        for ax, v in zip(axes[0], fast):
            r = traverse_io.load(path(out, "shallow", v))
            sig = traverse_io.first_load_sigma(r)
            for target in [0.0, 0.25, 0.5, 0.75, 1.0]:
                k = nearest(sig, target)
                xyz = r.field("r", k)
                ax.plot(xyz[:, 2], xyz[:, 1], label=f"sigma = {sig[k]:.2f} m")
            ax.set_title(f"shallow arch, v = {v} m/s")
            ax.set_xlabel("z [m]")
            ax.set_ylabel("y [m]")
            ax.set_aspect("equal", adjustable="datalim")
            ax.grid(True, alpha=0.3)
            ax.legend(fontsize=7)
        fig.tight_layout()
        fig.savefig(os.path.join(out, "shallow_arch_fast_shapes.png"), dpi=120)
        plt.close(fig)


def _static_overlay(ax, st, vertical=False):
    if st is None:
        return
    for x in (st["sigma1"], st["sigma2"]):
        ax.axvline(x, color="0.5", lw=0.8, ls=":")
    if not vertical:
        ax.plot(st["sigma"], st["x"], "k--", lw=1.2, label="static out-of-plane branch (stable, +/-)")
        ax.plot(st["sigma"], -st["x"], "k--", lw=1.2)


def deep_figures(out, speeds, static=None):
    plt = _plt()
    st = static_out_of_plane(static) if static and os.path.exists(static) else None
    runs = {v: traverse_io.load(path(out, "deep", v)) for v in speeds}
    slow = speeds[:2]
    fast = speeds[2:]

    fig, (ax, bx) = plt.subplots(2, 1, figsize=(9, 7.5), sharex=True)
    for v in slow:
        d = lateral(runs[v])
        lab = f"v = {v} m/s (ds = {runs[v].s[1]:g} m, rho_inf = {rho_inf(runs[v]):g})"
        ax.plot(d["sigma"], d["x"], lw=1, label=lab)
        bx.plot(d["sigma"], d["y"], lw=1, label=lab)
    _static_overlay(ax, st)
    _static_overlay(bx, st, vertical=True)
    ax.set_ylabel("lateral midpoint position x [m]")
    bx.set_ylabel("vertical midpoint position y [m]")
    bx.set_xlabel("load position sigma [m]")
    for a in (ax, bx):
        a.set_xlim(0.3, 0.8)
        a.grid(True, alpha=0.3)
        a.legend(fontsize=8)
    ax.set_title("deep arch, F = 3.8 N, lateral trigger 1e-6 F (dotted: static pitchforks)")
    fig.tight_layout()
    fig.savefig(os.path.join(out, "deep_arch_midpoint_slow.png"), dpi=120)
    plt.close(fig)

    fig, (ax, bx) = plt.subplots(1, 2, figsize=(13, 4.5))
    for v in fast:
        d = lateral(runs[v])
        ax.plot(d["sigma"], d["x"], lw=1, label=f"v = {v} m/s, ds = {runs[v].s[1]:g} m, rho_inf = "
                f"{rho_inf(runs[v]):g} (max |x| = {1e3 * d['amplitude']:.2g} mm)")
    for v in speeds:
        d = lateral(runs[v])
        bx.semilogy(d["sigma"], np.maximum(np.abs(d["x"]), 1e-9), lw=1, label=f"v = {v} m/s")
    if st is not None:
        bx.semilogy(st["sigma"][1:-1], st["x"][1:-1], "k--", lw=1.2, label="static out-of-plane branch")
    for a in (ax, bx):
        if st is not None:
            for x in (st["sigma1"], st["sigma2"]):
                a.axvline(x, color="0.5", lw=0.8, ls=":")
        a.set_xlabel("load position sigma [m]")
        a.set_xlim(0, 1)
        a.grid(True, alpha=0.3)
        a.legend(fontsize=8)
    ax.set_ylabel("lateral midpoint position x [m]")
    ax.set_title("deep arch, faster loads")
    bx.set_ylabel("|x(L/2)| [m]")
    bx.set_ylim(1e-7, 0.3)
    bx.set_title("all speeds (log scale)")
    fig.tight_layout()
    fig.savefig(os.path.join(out, "deep_arch_lateral.png"), dpi=120)
    plt.close(fig)

    if slow:
        # A column per speed: the 3-D shapes large (two thirds of the height, the box in the
        # data's proportions, few ticks), the plan view below with the one legend.
        from matplotlib.ticker import MaxNLocator

        fig = plt.figure(figsize=(7.5 * len(slow), 11))
        grid = fig.add_gridspec(2, len(slow), height_ratios=[2, 1])
        for i, v in enumerate(slow):
            r = runs[v]
            sig = traverse_io.first_load_sigma(r)
            d = lateral(r)
            targets = [0.40, d["sigma_max"], 0.65]
            ax = fig.add_subplot(grid[0, i], projection="3d")
            bx = fig.add_subplot(grid[1, i])
            for target in targets:
                k = nearest(sig, target)
                xyz = r.field("r", k)
                lab = f"sigma = {sig[k]:.3f} m"
                ax.plot(xyz[:, 0], xyz[:, 2], xyz[:, 1], label=lab)
                ax.plot([xyz[nearest(r.s, sig[k]), 0]], [xyz[nearest(r.s, sig[k]), 2]],
                        [xyz[nearest(r.s, sig[k]), 1]], "kv", ms=6)
                bx.plot(xyz[:, 2], xyz[:, 0], label=lab)
            ax.set_xlim(-0.25, 0.25)
            ax.set_ylim(0, 0.53)
            ax.set_zlim(0, 0.45)
            ax.set_box_aspect((0.5, 0.53, 0.45))
            ax.view_init(elev=20, azim=-60)
            for axis in (ax.xaxis, ax.yaxis, ax.zaxis):
                axis.set_major_locator(MaxNLocator(4))
            ax.set_xlabel("lateral x [m]")
            ax.set_ylabel("z [m]")
            ax.set_zlabel("y [m]")
            ax.set_title(f"deep arch, v = {v} m/s (triangle: load)")
            bx.set_xlabel("z [m]")
            bx.set_ylabel("lateral x [m]")
            bx.set_title("plan view")
            bx.grid(True, alpha=0.3)
            bx.legend(fontsize=8)
        fig.tight_layout()
        fig.savefig(os.path.join(out, "deep_arch_shapes.png"), dpi=120)
        plt.close(fig)


def summary(out, shallow, deep, static):
    for v in shallow:
        r = traverse_io.load(path(out, "shallow", v))
        if "end_tangent" in r.probes:
            c = collapse(r)
            print(f"shallow v = {v}: " + (f"snaps at sigma = {c['sigma']:.3f} m" if c["snapped"] else "no snap")
                  + f" (largest end rotation {math.degrees(c['max_rotation']):.1f} deg, threshold "
                  f"{math.degrees(c['threshold']):.1f} deg)")
    st = static_out_of_plane(static) if static and os.path.exists(static) else None
    if st is not None:
        print(f"deep static: pitchforks at sigma = {st['sigma1']:.4f}, {st['sigma2']:.4f} m, "
              f"largest |x(L/2)| on the stable out-of-plane branch {st['amplitude']:.4f} m")
    for v in deep:
        d = lateral(traverse_io.load(path(out, "deep", v)))
        print(f"deep v = {v}: max |x(L/2)| = {d['amplitude']:.4g} m at sigma = {d['sigma_max']:.3f} m")


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--traverse")
    ap.add_argument("--out", default="out/arches")
    ap.add_argument("--plot-only", action="store_true")
    ap.add_argument("--speeds-shallow", type=float, nargs="*", default=SHALLOW)
    ap.add_argument("--speeds-deep", type=float, nargs="*", default=DEEP)
    ap.add_argument("--static-deep", help="continuation output of inputs/statics/deep_arch_sigma.yaml")
    a = ap.parse_args(argv)
    os.makedirs(a.out, exist_ok=True)
    static = a.static_deep or os.path.join(a.out, "deep_static.h5")
    if not a.plot_only:
        if not a.traverse:
            ap.error("--traverse is required unless --plot-only")
        for v in a.speeds_shallow:
            run(a.traverse, a.out, "shallow", v)
        for v in a.speeds_deep:
            run(a.traverse, a.out, "deep", v)
        if not a.static_deep and a.speeds_deep:
            subprocess.run([a.traverse, "run", os.path.join(STATICS, "deep_arch_sigma.yaml"), "-o", static,
                            "--overwrite", "-q", "--set", "mesh.ds=0.005"], check=True)
    s = available(a.out, "shallow", a.speeds_shallow)
    d = available(a.out, "deep", a.speeds_deep)
    if s:
        shallow_figures(a.out, s)
    if d:
        deep_figures(a.out, d, static)
    summary(a.out, s, d, static)
    print(f"arches: figures in {a.out} (shallow speeds {s}, deep speeds {d})")


if __name__ == "__main__":
    main()
