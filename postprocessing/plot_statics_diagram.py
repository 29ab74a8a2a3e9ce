#!/usr/bin/env python3
"""Static diagram of a continuation run (layout: docs/output.md, "Continuation files"):
a probe against the continued parameter, one colour per branch (/continuation/branch),
stable stretches solid, unstable ones dashed (from /continuation/unstable_modes, the count
written on each stretch), and the bifurcations of /bifurcations marked (filled: located,
open: bracketed) and labelled with their parameter value (folds also with the probe value).

Usage: plot_statics_diagram.py RUN.h5 --probe end_compression [--abs] [-o FIGURE.png]
       (shallow arch: --probe end_compression --abs; deep arch: --probe mid_x)
"""
import argparse
import os
import sys

import h5py
import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import traverse_io  # noqa: E402


def parameter_name(f):
    reserved = {"unstable_modes", "critical_eigenvalue", "branch"}
    names = [n for n in f["continuation"] if n not in reserved]
    # The parameter is the dataset described as such.
    for n in names:
        if f["continuation"][n].attrs.get("description", b"") in (b"the continued parameter", "the continued parameter"):
            return n
    raise SystemExit("plot_statics_diagram: no continued parameter in the file")


def text(v):
    return v.decode() if isinstance(v, bytes) else str(v)


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("run")
    ap.add_argument("--probe", required=True)
    ap.add_argument("--abs", action="store_true", help="plot the absolute value of the probe")
    ap.add_argument("-o", "--output")
    a = ap.parse_args(argv)
    f = h5py.File(a.run, "r")
    c = f["continuation"]
    par = parameter_name(f)
    n = int(f.attrs["points_written"])
    p = c[par][:n]
    q = c[a.probe][:n]
    if a.abs:
        q = np.abs(q)
    u = c["unstable_modes"][:n]
    b = c["branch"][:n]
    fig, ax = plt.subplots(figsize=(7.5, 4.8))
    for k in np.unique(b):
        idx = np.where(b == k)[0]
        idx = idx[np.argsort(idx)]
        color = "C0" if k == 0 else f"C{int(k) + 1}"
        # Stable stretches solid, unstable dashed (a segment is unstable when either end is);
        # the number of unstable modes is written where it changes.
        for i0, i1 in zip(idx[:-1], idx[1:]):
            unstable = u[i0] > 0 or u[i1] > 0
            ax.plot(p[[i0, i1]], q[[i0, i1]], "--" if unstable else "-", color=color, lw=1.6)
        span_p = max(np.ptp(p), 1e-300)
        span_q = max(np.ptp(q), 1e-300)
        start = 0
        for j in range(1, len(idx) + 1):  # label each stretch of constant count at its middle
            if j == len(idx) or u[idx[j]] != u[idx[start]]:
                run = idx[start:j]
                d = np.concatenate([[0.0], np.cumsum(np.hypot(np.diff(p[run]) / span_p, np.diff(q[run]) / span_q))])
                m = run[int(np.argmin(np.abs(d - 0.5 * d[-1])))]
                if u[m] >= 0 and d[-1] > 0.05:
                    ax.annotate(f"{u[m]} unstable", (p[m], q[m]), textcoords="offset points", xytext=(4, -12),
                                fontsize=7, color=color)
                start = j
        ax.plot([], [], "-", color=color, label="primary branch" if k == 0 else f"switched branch {int(k)}")
    ax.plot([], [], "-", color="0.4", label="stable")
    ax.plot([], [], "--", color="0.4", label="unstable")
    if "bifurcations" in f and len(f["bifurcations/type"]) > 0:
        for i, (t, pv, qv, ok) in enumerate(zip(f["bifurcations/type"][:], f["bifurcations"][par][:],
                                                f["bifurcations"][a.probe][:], f["bifurcations/located"][:])):
            qv = abs(qv) if a.abs else qv
            kind = text(t)
            ax.plot(pv, qv, "ko" if kind == "fold" else "ks", ms=7, mfc="none" if not ok else "k")
            label = f"{kind} {pv:.4g}" + (f", {qv:.4g}" if kind == "fold" else "") + ("" if ok else " (bracketed)")
            ax.annotate(label, (pv, qv), textcoords="offset points", xytext=(6, 6 + 12 * (i % 3)), fontsize=8)
    units_p = text(c[par].attrs.get("units", ""))
    units_q = text(c[a.probe].attrs.get("units", ""))
    ax.set_xlabel(f"{par} [{units_p}]")
    ax.set_ylabel(f"{'|' + a.probe + '|' if a.abs else a.probe} [{units_q}]")
    ax.grid(True, alpha=0.3)
    ax.legend(fontsize=8)
    ax.set_title(traverse_io.wrapped(traverse_io.run_title(f), 90), fontsize=10)  # the values the run used
    fig.tight_layout()
    out = a.output or os.path.splitext(a.run)[0] + ".png"
    fig.savefig(out, dpi=130)
    print(f"plot_statics_diagram: wrote {out}")


if __name__ == "__main__":
    main()
