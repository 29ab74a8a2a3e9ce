"""Checks postprocessing/resonance_envelope.py on index files made here with known values: the
curves it writes (--data) are the index's completed cases, per train, sorted by speed; in the
picture, each curve's highest ink lies at the column of its known peak speed, and the two limit
lines lie at heights in the ratio of their values (the axis starts at 0).
Usage: check_resonance_envelope.py PYTHON SCRIPT OUT_DIR     (exit status 1 on any failure)
"""
import csv
import os
import subprocess
import sys

import matplotlib.image
import numpy as np

failed = 0


def check(cond, what):
    global failed
    print(("ok    " if cond else "FAIL  ") + what)
    failed += not cond


def write_index(path, rows, train_key=None):
    with open(path, "w", newline="") as fh:
        w = csv.writer(fh)
        w.writerow(["case"] + ([train_key] if train_key else []) +
                   ["loads.train.speed", "output", "status", "exit_code", "wall_s", "deck:absmax", "message"])
        for i, (train, v, y, status) in enumerate(rows):
            w.writerow([i] + ([train] if train_key else []) + [v, f"case_{i:04d}.h5", status, 0, 0.1,
                                                               "" if status != "complete" else y, ""])


def peak_curve(v, vp, height):
    return height / (1.0 + ((v - vp) / 1.5) ** 2)


def axes_box(img):
    """(left, right, top, bottom) pixel indices of the axes frame: the long dark spines."""
    dark = img[:, :, :3].sum(axis=2) < 0.6
    rows = np.where(dark.sum(axis=1) > 0.5 * img.shape[1])[0]
    cols = np.where(dark.sum(axis=0) > 0.5 * img.shape[0])[0]
    return cols.min(), cols.max(), rows.min(), rows.max()


def main():
    python, script, out = sys.argv[1:4]
    os.makedirs(out, exist_ok=True)
    speeds = np.arange(40.0, 100.5, 1.0)
    # One sweep with two trains (a varied key), one case failed; the peaks at 55 and 80 m/s.
    rows = [(d, v, peak_curve(v, vp, h), "complete") for d, vp, h in ((14, 55.0, 2.0), (20, 80.0, 4.0)) for v in speeds]
    rows[7] = (rows[7][0], rows[7][1], 0.0, "failed")
    index = os.path.join(out, "index.csv")
    write_index(index, rows, "loads.train.generator.coach_length")
    png, data = os.path.join(out, "envelope.png"), os.path.join(out, "envelope.csv")
    r = subprocess.run([python, script, index, "--speed-key", "loads.train.speed", "--train-key",
                        "loads.train.generator.coach_length", "--limit", "1.0:lower", "--limit", "3.0:upper",
                        "-o", png, "--data", data], capture_output=True, text=True)
    print(r.stdout + r.stderr)
    check(r.returncode == 0, "the script runs")
    with open(data, newline="") as fh:
        plotted = list(csv.DictReader(fh))
    for d in (14, 20):
        mine = [(float(p["speed"]), float(p["value"])) for p in plotted if p["train"] == f"coach_length = {d}"]
        expected = sorted((v, y) for t, v, y, s in rows if t == d and s == "complete")
        check(mine == expected, f"train {d}: the plotted curve is the index's {len(expected)} completed cases")
    check("case 7 not complete" in r.stderr, "the failed case is reported and left out")
    img = matplotlib.image.imread(png)
    left, right, top, bottom = axes_box(img)
    rgb = img[:, :, :3]
    for color, vp in (((0.12, 0.47, 0.71), 55.0), ((1.0, 0.5, 0.05), 80.0)):  # matplotlib's C0, C1
        ink = np.abs(rgb - np.array(color)).sum(axis=2) < 0.25
        ink[:, : left + 2] = False
        ink[:, right - 1:] = False
        ys, xs = np.nonzero(ink[top + 2: bottom - 1])
        col = xs[ys == ys.min()].mean()
        expected = left + (vp - speeds[0]) / (speeds[-1] - speeds[0]) * (right - left)
        check(abs(col - expected) < 3, f"the curve peaking at {vp} m/s peaks at column {col:.1f} (expected {expected:.1f})")
    # The dashed limit lines: rows (between the spines) where dark ink covers a good part of the width.
    dark = rgb.sum(axis=2) < 0.6
    frac = dark[top + 3: bottom - 2, left + 3: right - 2].mean(axis=1)
    lines = [top + 3 + i for i in np.where(frac > 0.3)[0]]
    groups = []
    for y in lines:
        if groups and y - groups[-1][-1] <= 1:
            groups[-1].append(y)
        else:
            groups.append([y])
    heights = sorted(bottom - np.mean(g) for g in groups)
    check(len(heights) == 2, f"two limit lines drawn (found {len(heights)})")
    if len(heights) == 2:
        check(abs(heights[1] / heights[0] - 3.0) < 0.05, f"limit lines at heights in the ratio {heights[1] / heights[0]:.3f} (3.0)")
    # Two index files: one curve each, labelled.
    a, b = os.path.join(out, "a", "index.csv"), os.path.join(out, "b", "index.csv")
    for path, vp in ((a, 60.0), (b, 70.0)):
        os.makedirs(os.path.dirname(path), exist_ok=True)
        write_index(path, [(None, v, peak_curve(v, vp, 1.0), "complete") for v in speeds])
    r = subprocess.run([python, script, a, b, "--speed-key", "loads.train.speed", "--label", "A", "B", "-o",
                        os.path.join(out, "two.png"), "--data", os.path.join(out, "two.csv")], capture_output=True,
                       text=True)
    check(r.returncode == 0, "two index files")
    with open(os.path.join(out, "two.csv"), newline="") as fh:
        labels = sorted({p["train"] for p in csv.DictReader(fh)})
    check(labels == ["A", "B"], f"one curve per index file, labelled {labels}")
    r = subprocess.run([python, script, a, "--speed-key", "loads.train.nospeed", "-o", os.path.join(out, "x.png")],
                       capture_output=True, text=True)
    check(r.returncode == 1 and "expected a column 'loads.train.nospeed'" in r.stderr, "a missing column is refused")
    print(f"{failed} failure(s)")
    sys.exit(1 if failed else 0)


if __name__ == "__main__":
    main()
