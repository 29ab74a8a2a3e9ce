#!/usr/bin/python3
"""Compare the numbers of two traverse output files, dataset by dataset.

    /usr/bin/python3 scripts/compare-runs.py A.h5 B.h5 [--tolerance 1e-10] [--atol 1e-12] [-v]

For every numeric dataset present in both files (time, probes, fields, continuation
branches), prints the largest difference relative to the dataset's largest magnitude in A
(an absolute difference where A is all zeros); a dataset agrees when that is at most the
tolerance or its largest absolute difference is at most --atol. A value that is not a
number must be so in both files. Exit code 1 when a dataset disagrees, or when a dataset or
the shape of one exists in only one file; 0 else.
Timings and the file's own bookkeeping (wall times, counters of work done) are skipped, and
so is the /xdmf group (views of the same fields for ParaView). -v prints every dataset.
"""
import argparse
import sys

import h5py
import numpy as np

SKIPPED = ("wall", "seconds", "timing", "restart")


def datasets(f):
    out = {}

    def visit(name, obj):
        if name.startswith("xdmf/"):
            return
        if isinstance(obj, h5py.Dataset) and obj.dtype.kind in "fiu" and not any(s in name for s in SKIPPED):
            out[name] = obj

    f.visititems(visit)
    return out


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("a")
    ap.add_argument("b")
    ap.add_argument("--tolerance", type=float, default=1e-10)
    ap.add_argument("--atol", type=float, default=1e-12,
                    help="a dataset also agrees when its largest absolute difference is below this (for "
                    "quantities that are round-off, e.g. a frictionless contact's tangential force)")
    ap.add_argument("-v", action="store_true", help="print every dataset")
    args = ap.parse_args()
    worst, bad = 0.0, []
    with h5py.File(args.a, "r") as fa, h5py.File(args.b, "r") as fb:
        da, db = datasets(fa), datasets(fb)
        for name in sorted(set(da) | set(db)):
            if name not in da or name not in db:
                bad.append(f"{name}: only in {'A' if name in da else 'B'}")
                continue
            x, y = np.asarray(da[name][()], dtype=float), np.asarray(db[name][()], dtype=float)
            if x.shape != y.shape:
                bad.append(f"{name}: shape {x.shape} against {y.shape}")
                continue
            nan_x, nan_y = np.isnan(x), np.isnan(y)
            if not np.array_equal(nan_x, nan_y):
                bad.append(f"{name}: not-a-number at different places")
                continue
            x, y = x[~nan_x], y[~nan_y]  # a probe undefined at some steps (NaN) in both files
            if x.size == 0:
                continue
            scale = np.max(np.abs(x))
            diff = np.max(np.abs(x - y))
            rel = diff / scale if scale > 0 else diff
            worst = max(worst, rel)
            if args.v:
                print(f"{name:40s} max |A - B| = {diff:.3e}  relative {rel:.3e}")
            if not (rel <= args.tolerance or diff <= args.atol):
                bad.append(f"{name}: relative difference {rel:.3e} > {args.tolerance:g}")
    print(f"largest relative difference: {worst:.3e} ({len(da)} datasets)")
    for b in bad:
        print("DIFFERS:", b)
    return 1 if bad else 0


if __name__ == "__main__":
    sys.exit(main())
