#!/usr/bin/env python3
"""Checks what a figure script draws from real runs: runs the script's main() in this process
(matplotlib Agg), then
  - the PNG it saved: ink on 0.5 .. 60 % of the pixels, spread over at least half the width
    and a third of the height, and at least 3 distinct colours besides greys (the curves);
  - the figure it built: every axes draws at least one curve of 2 or more finite points, and
    the figure has a curve whose values are those of one of the runs' probes (a component,
    as stored or in mm: x 1e3), point for point (a masked part of it allowed).

Usage: check_figure.py SCRIPT PNG RUN.h5 [RUN2.h5] [-- SCRIPT_ARGS...]
Exit 0 when every check passes, 1 otherwise (each failure printed).
"""
import os
import runpy
import sys

import h5py
import matplotlib

matplotlib.use("Agg")
import matplotlib.image  # noqa: E402
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402


def probe_columns(path):
    """Every probe component of a run, up to steps_written."""
    cols = []
    with h5py.File(path, "r") as f:
        n = int(f.attrs["steps_written"])
        for name in f["probes"]:
            v = np.asarray(f["probes"][name][:n], dtype=float).reshape(n, -1)
            cols += [v[:, c] for c in range(v.shape[1])]
    return cols


def drawn_from(y, cols):
    """Whether the finite values y are, in order of appearance, values of one column (x 1 or
    x 1e3), each within 1e-9 of the column's largest magnitude."""
    y = y[np.isfinite(y)]
    if y.size < 2 or np.ptp(y) == 0.0:
        return False
    for col in cols:
        col = col[np.isfinite(col)]
        if col.size < y.size:
            continue
        for factor in (1.0, 1e3):
            scaled = factor * col
            tol = 1e-9 * max(np.abs(scaled).max(), 1e-300)
            if np.all(np.abs(scaled[:, None] - y[None, :]).min(axis=0) <= tol):
                return True
    return False


def png_checks(png, check):
    check(os.path.exists(png) and os.path.getsize(png) > 0, f"{png} is saved and not empty")
    if not os.path.exists(png):
        return
    img = matplotlib.image.imread(png)[..., :3]
    ink = np.abs(img - img[0, 0]).sum(axis=-1) > 0.1
    check(0.005 < ink.mean() < 0.6, f"{100 * ink.mean():.2f} % of the pixels drawn")
    rows, cols = np.nonzero(ink.any(axis=1))[0], np.nonzero(ink.any(axis=0))[0]
    check(cols.size > 0 and cols[-1] - cols[0] > 0.5 * img.shape[1], "the drawing spans half the width")
    check(rows.size > 0 and rows[-1] - rows[0] > 0.33 * img.shape[0], "the drawing spans a third of the height")
    pixels = img[ink]
    coloured = pixels[(pixels.max(axis=1) - pixels.min(axis=1)) > 0.2]
    hues = len(np.unique(np.round(coloured * 8).astype(int), axis=0))
    check(hues >= 3, f"{hues} colours besides greys: the curves are drawn in colour")


class Checks:
    """The checks of a test: call with (condition, what); a failed one prints FAILED: what.
    finish() prints the counts and exits non-zero when one failed."""

    def __init__(self):
        self.passed, self.failed = 0, 0

    def __call__(self, cond, what):
        self.passed, self.failed = self.passed + bool(cond), self.failed + (not cond)
        if not cond:
            print("FAILED: " + what)

    def finish(self):
        print(f"{self.passed} passed, {self.failed} failed")
        sys.exit(0 if self.failed == 0 else 1)


def run_figure_script(script, argv):
    """Runs a figure script's main(argv) in this process (its folder on the import path), so
    that its matplotlib figures stay open for the checks."""
    sys.path.insert(0, os.path.dirname(os.path.abspath(script)))
    module = runpy.run_path(script, run_name="figure_under_test")
    module["main"](argv)


def main():
    argv = sys.argv[1:]
    extra = argv[argv.index("--") + 1:] if "--" in argv else []
    argv = argv[:argv.index("--")] if "--" in argv else argv
    script, png, runs = argv[0], argv[1], argv[2:]
    check = Checks()
    run_figure_script(script, runs + extra + ["-o", png])
    png_checks(png, check)
    cols = [c for r in runs for c in probe_columns(r)]
    figures = [plt.figure(n) for n in plt.get_fignums()]
    check(len(figures) >= 1, "the script builds a figure")
    for fig in figures:
        lines = [ln for ax in fig.axes for ln in ax.get_lines()]
        for k, ax in enumerate(fig.axes):
            drawn = [ln for ln in ax.get_lines() if np.isfinite(np.asarray(ln.get_ydata(), float)).sum() >= 2]
            check(len(drawn) >= 1, f"axes {k} ('{ax.get_title() or ax.get_ylabel()}') draws a curve")
        check(any(drawn_from(np.asarray(ln.get_ydata(), float), cols) for ln in lines),
              "a curve shows a probe's values as the run stored them (or in mm)")
    check.finish()


if __name__ == "__main__":
    main()
