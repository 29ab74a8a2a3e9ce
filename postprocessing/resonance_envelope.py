#!/usr/bin/env python3
"""The resonance envelope of a `traverse sweep` over speeds: the peak response of each case (the
index's --summary column, e.g. deck:absmax for the peak deck acceleration) against the speed,
one curve per train, with horizontal limit lines of your choice.

The trains are either the values of a varied scene key (--train-key, e.g. the generator's
coach_length in one sweep that varies both) or the index files themselves (one sweep per scene
file, each labelled by --label or by its folder's name). With --f1 (the bridge's first
frequency, Hz) and a train key that is the spacing d of the train's loads, the first mode's
resonance speeds v = f1 d / i are marked on each curve.

Usage:
  resonance_envelope.py INDEX.csv [INDEX.csv ...] --speed-key loads.train.speed -o envelope.png
      [--summary deck:absmax] [--train-key KEY] [--label NAME ...] [--limit VALUE[:TEXT] ...]
      [--ylabel TEXT] [--f1 HZ] [--data OUT.csv]
--data also writes the plotted curves (train, speed, value) as CSV. Exit status 1 on bad input.
"""
import argparse
import csv
import os
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402


def fail(msg):
    print("resonance_envelope.py: " + msg, file=sys.stderr)
    sys.exit(1)


def read_index(path, speed_key, summary, train_key):
    """Rows of (train value or None, speed, summary value) of the completed cases."""
    with open(path, newline="") as fh:
        rows = list(csv.DictReader(fh))
    if not rows:
        fail(f"{path}: no cases")
    for key in [speed_key, summary] + ([train_key] if train_key else []):
        if key not in rows[0]:
            fail(f"{path}: expected a column '{key}', found {', '.join(rows[0].keys())}")
    out = []
    for r in rows:
        if r["status"] != "complete" or r[summary] == "":
            print(f"{path}: case {r['case']} not complete ({r['status']}): left out", file=sys.stderr)
            continue
        out.append((r[train_key] if train_key else None, float(r[speed_key]), float(r[summary])))
    return out


def curves(args):
    """{label: ([speeds], [values])}, each sorted by speed, in the order first seen."""
    result = {}
    for i, path in enumerate(args.index):
        default = args.label[i] if args.label and i < len(args.label) else os.path.basename(os.path.dirname(os.path.abspath(path)))
        for train, v, value in read_index(path, args.speed_key, args.summary, args.train_key):
            label = f"{args.train_key.split('.')[-1]} = {train}" if args.train_key else default
            result.setdefault(label, []).append((v, value, train))
    return {k: sorted(v) for k, v in result.items()}


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("index", nargs="+", help="index.csv of traverse sweep")
    ap.add_argument("--speed-key", required=True, help="the varied speed key, e.g. loads.train.speed")
    ap.add_argument("--summary", default=None, help="the summary column (default: the index's only one)")
    ap.add_argument("--train-key", default=None, help="a varied key whose values are the trains")
    ap.add_argument("--label", nargs="*", default=None, help="one label per index file")
    ap.add_argument("--limit", action="append", default=[], help="VALUE[:TEXT], a horizontal limit line")
    ap.add_argument("--ylabel", default=None)
    ap.add_argument("--title", default=None)
    ap.add_argument("--f1", type=float, default=None, help="first frequency [Hz]: mark v = f1 d / i (d: train key)")
    ap.add_argument("--data", default=None, help="write the plotted curves as CSV")
    ap.add_argument("-o", "--output", required=True)
    args = ap.parse_args()
    if args.summary is None:
        with open(args.index[0], newline="") as fh:
            header = next(csv.reader(fh))
        found = [h for h in header if ":" in h]
        if len(found) != 1:
            fail(f"{args.index[0]}: expected one summary column (or --summary), found {found}")
        args.summary = found[0]
    data = curves(args)
    fig, ax = plt.subplots(figsize=(9, 4.8))
    vmin = min(v for c in data.values() for v, _, _ in c)
    vmax = max(v for c in data.values() for v, _, _ in c)
    for label, c in data.items():
        (line,) = ax.plot([v for v, _, _ in c], [y for _, y, _ in c], "-", lw=1.5, label=label)
        if args.f1 and args.train_key:
            d = float(c[0][2])
            for i in range(1, 6):
                vr = args.f1 * d / i
                if vmin <= vr <= vmax:
                    ax.axvline(vr, color=line.get_color(), ls=":", lw=0.8)
    for spec in args.limit:
        value, _, text = spec.partition(":")
        ax.axhline(float(value), color="k", ls="--", lw=1.0)
        ax.annotate(text or f"limit {value}", (vmin, float(value)), xytext=(2, 3), textcoords="offset points",
                    fontsize=8)
    ax.set_xlabel(f"speed [m/s] ({args.speed_key})")
    ax.set_ylabel(args.ylabel or args.summary)
    ax.set_xlim(vmin, vmax)
    ax.set_ylim(bottom=0)
    if args.title:
        ax.set_title(args.title)
    ax.grid(alpha=0.3)
    ax.legend(fontsize=8, loc="upper left", bbox_to_anchor=(1.01, 1.0))  # beside the axes: never over a curve
    fig.tight_layout()
    fig.savefig(args.output, dpi=120)
    if args.data:
        with open(args.data, "w", newline="") as fh:
            w = csv.writer(fh)
            w.writerow(["train", "speed", "value"])
            for label, c in data.items():
                for v, y, _ in c:
                    w.writerow([label, v, y])
    print(f"wrote {args.output} ({len(data)} curve(s), {sum(len(c) for c in data.values())} cases)")


if __name__ == "__main__":
    main()
