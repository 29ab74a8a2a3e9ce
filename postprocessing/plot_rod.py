#!/usr/bin/env python3
"""Figure of one rod run: the vertical position of a probe (default: midspan) against the
load position sigma, and the shapes y(z) of the centreline at a few sigma (needs the field r).

Usage: plot_rod.py RUN.h5 [-o FIGURE.png] [--probe midspan]
"""
import argparse
import os
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import traverse_io  # noqa: E402


def shapes_at(run, sigmas):
    """[(sigma, r (nodes x 3))] for the output steps nearest the given load positions."""
    sig = traverse_io.first_load_sigma(run)
    out = []
    for target in sigmas:
        k = int(np.nanargmin(np.abs(sig - target)))
        out.append((sig[k], run.field("r", k)))
    return out


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("run")
    ap.add_argument("-o", "--output")
    ap.add_argument("--probe", default="midspan")
    a = ap.parse_args(argv)
    run = traverse_io.load(a.run)
    has_r = "r" in run.field_names
    fig, axes = plt.subplots(1, 2 if has_r else 1, figsize=(12 if has_r else 7, 4.2), squeeze=False)
    ax = axes[0, 0]
    sig = traverse_io.first_load_sigma(run)
    if a.probe in run.probes:
        ax.plot(sig, run.probes[a.probe][:, 1], label=f"{a.probe} y")
    ax.set_xlabel("load position sigma [m]")
    ax.set_ylabel("vertical position y [m]")
    ax.grid(True, alpha=0.3)
    ax.legend()
    if has_r:
        ax2 = axes[0, 1]
        for s, r in shapes_at(run, np.linspace(0.0, float(run.s[-1]), 5)):
            ax2.plot(r[:, 2], r[:, 1], label=f"sigma = {s:.2f} m")
        ax2.set_xlabel("z [m]")
        ax2.set_ylabel("y [m]")
        ax2.set_aspect("equal", adjustable="datalim")
        ax2.grid(True, alpha=0.3)
        ax2.legend(fontsize=8)
    fig.suptitle(traverse_io.scene_title(run) or os.path.basename(a.run))
    fig.tight_layout()
    out = a.output or os.path.splitext(a.run)[0] + ".png"
    fig.savefig(out, dpi=130)
    print(f"plot_rod: wrote {out}")


if __name__ == "__main__":
    main()
