#!/usr/bin/env python3
"""Hinged-arch figures of the scenes spec from the runs of inputs/arch/*.yaml.

Shallow arch (F = 2 N):
  shallow_arch_hinge_spin.png  (a) omega(L) . i at the right hinge against sigma, a curve per v
  shallow_arch_shapes_v0.5.png (b) shapes at several sigma for v = 0.5 m/s, up to after collapse
  shallow_arch_n2_v0.5.png     (c) n2 = n . d2 against s at several times: the step travels with the load
  shallow_arch_fast_shapes.png (d) shapes at v = 2.6 and 20 m/s
Deep arch (F = 3.8 N, lateral trigger 1e-6 F):
  deep_arch_midpoint.png       lateral x and vertical y of the midpoint against sigma, a curve per v
  deep_arch_shapes.png         3-D shapes at three sigma for the slowest runs available

Usage: arches.py --traverse BUILD/traverse [--out DIR] [--plot-only] [--speeds-shallow ...] [--speeds-deep ...]
"""
import argparse
import os
import subprocess
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import traverse_io  # noqa: E402

HERE = os.path.dirname(os.path.abspath(__file__))
INPUTS = os.path.join(HERE, "..", "inputs", "arch")
SHALLOW = [0.02, 0.5, 1.0, 2.0, 2.6, 5.0, 20.0]
DEEP = [0.005, 0.01, 0.05, 0.1]


def path(out, kind, v):
    return os.path.join(out, f"{kind}_v{v}.h5")


def run(exe, out, kind, v):
    scene = os.path.join(INPUTS, f"{kind}_arch_v{v}.yaml")
    subprocess.run([exe, "run", scene, "-o", path(out, kind, v), "--overwrite", "-q"], check=True)


def available(out, kind, speeds):
    return [v for v in speeds if os.path.exists(path(out, kind, v))]


def shallow_figures(out, speeds):
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

    if 0.5 in speeds:
        r = traverse_io.load(path(out, "shallow", 0.5))
        sig = traverse_io.first_load_sigma(r)
        fig, ax = plt.subplots(figsize=(8, 4.5))
        for target in [0.0, 0.2, 0.4, 0.6, 0.65, 0.7, 0.8, 1.0]:
            k = int(np.nanargmin(np.abs(sig - target)))
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

        fig, ax = plt.subplots(figsize=(8, 4.5))
        s = r.s
        for target in [0.1, 0.3, 0.5]:
            k = int(np.nanargmin(np.abs(sig - target)))
            n = r.field("n", k)
            ax.plot(s, n[:, 1], label=f"t = {r.time[k]:.3f} s (sigma = {sig[k]:.2f} m)")
        ax.set_xlabel("s [m]")
        ax.set_ylabel("n2 = n . d2 [N]")
        ax.grid(True, alpha=0.3)
        ax.legend(fontsize=8)
        ax.set_title("shallow arch, v = 0.5 m/s: the step in n2 travels with the load")
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
                k = int(np.nanargmin(np.abs(sig - target)))
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


def deep_figures(out, speeds):
    fig, (ax, bx) = plt.subplots(1, 2, figsize=(12, 4.5))
    for v in speeds:
        r = traverse_io.load(path(out, "deep", v))
        sig = traverse_io.first_load_sigma(r)
        m = r.probes["midpoint"]
        ax.plot(sig, m[:, 0], label=f"v = {v} m/s")
        bx.plot(sig, m[:, 1], label=f"v = {v} m/s")
    ax.set_ylabel("lateral midpoint position x [m]")
    bx.set_ylabel("vertical midpoint position y [m]")
    for x in (ax, bx):
        x.set_xlabel("load position sigma [m]")
        x.set_xlim(0, 1)
        x.grid(True, alpha=0.3)
        x.legend(fontsize=8)
    fig.suptitle("deep arch, F = 3.8 N, lateral trigger 1e-6 F")
    fig.tight_layout()
    fig.savefig(os.path.join(out, "deep_arch_midpoint.png"), dpi=120)
    plt.close(fig)

    slow = speeds[:2]
    if slow:
        fig = plt.figure(figsize=(6 * len(slow), 5))
        for i, v in enumerate(slow):
            r = traverse_io.load(path(out, "deep", v))
            sig = traverse_io.first_load_sigma(r)
            ax = fig.add_subplot(1, len(slow), i + 1, projection="3d")
            for target in [0.3, 0.5, 0.7]:
                k = int(np.nanargmin(np.abs(sig - target)))
                xyz = r.field("r", k)
                ax.plot(xyz[:, 0], xyz[:, 2], xyz[:, 1], label=f"sigma = {sig[k]:.2f} m")
            ax.set_xlabel("x [m]")
            ax.set_ylabel("z [m]")
            ax.set_zlabel("y [m]")
            ax.set_title(f"deep arch, v = {v} m/s")
            ax.legend(fontsize=7)
        fig.tight_layout()
        fig.savefig(os.path.join(out, "deep_arch_shapes.png"), dpi=120)
        plt.close(fig)


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--traverse")
    ap.add_argument("--out", default="out/arches")
    ap.add_argument("--plot-only", action="store_true")
    ap.add_argument("--speeds-shallow", type=float, nargs="*", default=SHALLOW)
    ap.add_argument("--speeds-deep", type=float, nargs="*", default=DEEP)
    a = ap.parse_args(argv)
    os.makedirs(a.out, exist_ok=True)
    if not a.plot_only:
        if not a.traverse:
            ap.error("--traverse is required unless --plot-only")
        for v in a.speeds_shallow:
            run(a.traverse, a.out, "shallow", v)
        for v in a.speeds_deep:
            run(a.traverse, a.out, "deep", v)
    s = available(a.out, "shallow", a.speeds_shallow)
    d = available(a.out, "deep", a.speeds_deep)
    if s:
        shallow_figures(a.out, s)
    if d:
        deep_figures(a.out, d)
    print(f"arches: figures in {a.out} (shallow speeds {s}, deep speeds {d})")


if __name__ == "__main__":
    main()
