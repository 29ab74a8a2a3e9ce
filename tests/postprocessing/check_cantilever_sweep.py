#!/usr/bin/env python3
"""Checks postprocessing/cantilever_sweep.py on its real sweep (16 cantilever runs): for each of
its three figures
  - the PNG: ink, extent and colours (check_figure.png_checks);
  - the panels share one y scale (they are compared with each other);
  - the legends and titles name the mass fraction p (the sweep's loads.mass.mass_fraction),
    not an "M" that reads as the mass;
  - every curve is the probe of the case its panel and legend name (p and v read back from
    the labels, the case found in the sweep's index), in mm, point for point.

Usage: check_cantilever_sweep.py TRAVERSE SCRIPT OUT_DIR     (exit status 1 on any failure)
"""
import os
import re
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from check_figure import Checks, png_checks, run_figure_script  # noqa: E402


def main():
    exe, script, out = sys.argv[1:4]
    check = Checks()
    run_figure_script(script, ["--traverse", exe, "--out", out, "--keep-open"])
    import traverse_io

    sweep = os.path.join(out, "sweep")
    cases = {}
    for row in traverse_io.sweep_index(sweep):
        cases[(float(row["loads.mass.mass_fraction"]), float(row["loads.mass.speed"]))] = \
            traverse_io.load(os.path.join(sweep, row["output"]))

    def number(pattern, text):
        m = re.search(pattern, text)
        return float(m.group(1)) if m else None

    figures = {plt.figure(n).get_label(): plt.figure(n) for n in plt.get_fignums()}
    for name, probe in (("cantilever_tip_by_speed.png", "tip"), ("cantilever_tip_by_mass.png", "tip"),
                        ("cantilever_mass.png", "mass_deflection")):
        png_checks(os.path.join(out, name), check)
        fig = figures.get(name)
        check(fig is not None, f"{name}: the script builds the figure")
        if fig is None:
            continue
        limits = {ax.get_ylim() for ax in fig.axes}
        check(len(limits) == 1, f"{name}: the panels share one y scale ({sorted(limits)})")
        texts = [t.get_text() for t in fig.findobj(matplotlib.text.Text)]
        check(not any(re.search(r"\bM = ", t) for t in texts), f"{name}: no 'M = ...' label (the mass fraction is p)")
        check(any("mass fraction" in t for t in texts), f"{name}: a title or legend names the mass fraction p")
        curves = 0
        for ax in fig.axes:
            title = ax.get_title()
            for line in ax.get_lines():
                label = line.get_label()
                both = title + " " + label
                p, v = number(r"p = ([0-9.]+) %", both), number(r"v = ([0-9.]+) m/s", both)
                check(p is not None and v is not None, f"{name}: panel '{title}', curve '{label}' names p and v")
                if p is None or v is None:
                    continue
                run = cases.get((p / 100.0, v))
                check(run is not None, f"{name}: a case p = {p} %, v = {v} m/s in the sweep")
                if run is None:
                    continue
                x = run.probes["mass_position"]
                on = (x >= 0) & (x <= float(run.s[-1]))
                want = 1e3 * run.probes[probe][on]
                got = np.asarray(line.get_ydata(), float)
                check(got.shape == want.shape and np.array_equal(got, want),
                      f"{name}: '{label}' in '{title}' is {probe} of that case in mm")
                curves += 1
        check(curves == 16, f"{name}: 16 curves drawn from the cases ({curves})")
    check.finish()


if __name__ == "__main__":
    main()
