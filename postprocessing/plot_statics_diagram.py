#!/usr/bin/python3
"""Static diagrams of a continuation run (docs/statics.md, "HDF5 layout").

Reads, for each continuation group /continuation[/<branch>] in the file:
  /continuation/<parameter>       (n,) the continued parameter (e.g. load_position [m])
  /continuation/<probe>           (n,) probe values (e.g. end_compression [N], mid_x [m])
  /continuation/unstable_modes    (n,) int, -1 = unknown
and the table /bifurcations with datasets type (strings "fold"/"pitchfork"), parameter,
and one dataset per probe name. Stable stretches are drawn solid, unstable dashed (red),
bifurcations as markers.

Usage: plot_statics_diagram.py FILE.h5 --parameter load_position --probe end_compression [-o out.png]
       (shallow arch: --probe end_compression; deep arch: --probe mid_x)
"""
import argparse

import h5py
import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt
import numpy as np


def groups(f):
    c = f["continuation"]
    if "unstable_modes" in c:
        yield "main", c
    for name, g in c.items():
        if isinstance(g, h5py.Group) and "unstable_modes" in g:
            yield name, g


def draw(ax, p, y, u, label):
    first = True
    start = 0
    for i in range(1, len(p) + 1):
        if i == len(p) or (u[i] > 0) != (u[start] > 0):
            seg = slice(start, min(i + 1, len(p)))
            unstable = u[start] > 0
            ax.plot(p[seg], y[seg], "--" if unstable else "-", color="tab:red" if unstable else "tab:blue",
                    label=(label if first else None))
            first = False
            start = i


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("file")
    ap.add_argument("--parameter", default="load_position")
    ap.add_argument("--probe", default="end_compression")
    ap.add_argument("--absolute", action="store_true", help="plot |probe|")
    ap.add_argument("-o", "--output", default=None)
    a = ap.parse_args()
    with h5py.File(a.file, "r") as f:
        fig, ax = plt.subplots(figsize=(6, 4))
        for name, g in groups(f):
            p = np.asarray(g[a.parameter])
            y = np.asarray(g[a.probe])
            u = np.asarray(g["unstable_modes"])
            draw(ax, p, np.abs(y) if a.absolute else y, u, name)
        if "bifurcations" in f and a.probe in f["bifurcations"]:
            b = f["bifurcations"]
            types = [t.decode() if isinstance(t, bytes) else str(t) for t in b["type"][()]]
            bp = np.asarray(b["parameter"])
            by = np.asarray(b[a.probe])
            for t, x, y in zip(types, bp, by):
                ax.plot([x], [abs(y) if a.absolute else y], "o" if t == "fold" else "s", color="k", ms=6)
                ax.annotate(t, (x, abs(y) if a.absolute else y), textcoords="offset points", xytext=(5, 5))
        ax.set_xlabel(a.parameter)
        ax.set_ylabel(a.probe)
        ax.set_title("solid: stable, dashed: unstable")
        ax.legend()
        fig.tight_layout()
        fig.savefig(a.output or a.file.rsplit(".", 1)[0] + "_" + a.probe + ".png", dpi=150)


if __name__ == "__main__":
    main()
