#!/usr/bin/env python3
"""Checks what the single-run figures say about the run they draw (real runs of traverse):
  - plot_beam.py on a beam with two loads and two probes, declared out of alphabetical order,
    one load's speed changed with --set: the solid curve is the scene's first probe and the
    x axis the position of its first load (not the alphabetically first of either); the title
    gives the speed the run used and not the scene's `title:`;
  - plot_rod.py on a cable too stiff to sag visibly (steel, a sag of well under a thousandth of
    its length): the shapes are drawn exaggerated, the axis and the panel say by what factor
    k, each drawn shape is k times the stored centreline's y, and the drawn shapes reach at
    least a twentieth of the length; on the default cable (a visible sag) nothing is
    exaggerated.

Usage: check_titles_and_shapes.py TRAVERSE POSTPROCESSING_DIR DEFAULT_SCENE OUT_DIR
(exit status 1 on any failure)
"""
import os
import re
import subprocess
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from check_figure import Checks, png_checks, run_figure_script  # noqa: E402

BEAM = """model: beam
title: a title that the run does not follow, v = 1 m/s
beam:
  length: 10.0
  youngs_modulus: 2.0e11
  density: 7850
  section: {type: rectangle, width: 0.2, height: 0.3}
  supports: simply-supported
  modes: 3
loads:
  zeta: {type: moving_force, force: 1000, speed: 10}
  alpha: {type: moving_force, force: 500, speed: 10, entry_time: 0.3}
output:
  probes:
    quarter: {type: deflection, at: 2.5}
    mid: {type: deflection, at: 5.0}
"""

check = Checks()


def run(exe, scene, out, *args):
    subprocess.run([exe, "run", scene, "-o", out, "--overwrite", "-q", *args], check=True)


def figure_of(pp, script, argv):
    plt.close("all")
    run_figure_script(os.path.join(pp, script), argv)
    return plt.figure(plt.get_fignums()[-1])


def main():
    exe, pp, default_scene, out = sys.argv[1:5]
    os.makedirs(out, exist_ok=True)
    sys.path.insert(0, pp)
    import traverse_io

    # plot_beam: the probe and the load from the file, the title from the values used.
    scene = os.path.join(out, "two_loads.yaml")
    with open(scene, "w") as fh:
        fh.write(BEAM)
    h5, png = os.path.join(out, "beam.h5"), os.path.join(out, "beam.png")
    speed = 7.27
    run(exe, scene, h5, "--set", f"loads.zeta.speed={speed}")
    fig = figure_of(pp, "plot_beam.py", [h5, "-o", png])
    png_checks(png, check)
    r = traverse_io.load(h5)
    ax = fig.axes[0]
    title = ax.get_title().replace("\n", " ")
    check(f"{speed:g} m/s" in title, f"plot_beam: the title gives the speed the run used ({title!r})")
    check("a title that the run does not follow" not in title, "plot_beam: the title is not the scene's title:")
    solid = [ln for ln in ax.get_lines() if ln.get_linestyle() == "-"]
    x = r.probes["zeta_position"]
    on = (x >= 0) & (x <= float(r.s[-1]))
    check(len(solid) == 1 and np.array_equal(solid[0].get_ydata(), 1e3 * r.probes["quarter"][on]),
          "plot_beam: the solid curve is the scene's first probe 'quarter' in mm")
    check(len(solid) == 1 and np.array_equal(solid[0].get_xdata(), x[on]),
          "plot_beam: against the position of the scene's first load 'zeta'")
    check("zeta" in ax.get_xlabel(), f"plot_beam: the x label names the load ({ax.get_xlabel()!r})")

    # plot_rod: a stiff cable's shapes exaggerated and labelled, the default cable's not.
    for label, args, small in (("stiff", ["--set", "rod.youngs_modulus=2e11", "--set", "mesh.ds=0.02"], True),
                               ("default", ["--set", "mesh.ds=0.02"], False)):
        h5, png = os.path.join(out, label + ".h5"), os.path.join(out, label + ".png")
        run(exe, default_scene, h5, *args)
        fig = figure_of(pp, "plot_rod.py", [h5, "-o", png])
        png_checks(png, check)
        r = traverse_io.load(h5)
        length = float(r.s[-1] - r.s[0])
        ys = np.concatenate([r.field("r")[:, :, 1].ravel()])
        sag = np.abs(ys).max()
        check((sag < length / 1000.0) == small, f"plot_rod {label}: the stored sag {sag:.3g} m is as the case means")
        shapes = fig.axes[1]
        m = re.search(r"exaggerated x ([0-9.e+]+)", shapes.get_ylabel())
        k = float(m.group(1)) if m else 1.0
        if small:
            check(m is not None and k > 1.0, f"plot_rod {label}: the y axis says the factor ({shapes.get_ylabel()!r})")
            check(f"{k:g}" in shapes.get_title(), f"plot_rod {label}: the panel says the factor ({shapes.get_title()!r})")
        else:
            check(m is None and shapes.get_ylabel() == "y [m]", f"plot_rod {label}: not exaggerated")
        sigma = traverse_io.first_load_sigma(r)
        field = r.field("r")
        lines = [ln for ln in shapes.get_lines() if len(ln.get_xdata()) == len(r.s)]
        check(len(lines) == 5, f"plot_rod {label}: five shapes drawn ({len(lines)})")
        reach = 0.0
        for ln in lines:
            step = int(np.nanargmin(np.abs(sigma - float(re.search(r"sigma = ([0-9.]+)", ln.get_label()).group(1)))))
            drawn = np.asarray(ln.get_ydata(), float)
            check(np.allclose(drawn, k * field[step, :, 1], rtol=0, atol=1e-12 * k),
                  f"plot_rod {label}: '{ln.get_label()}' is {k:g} x the stored y of its step")
            reach = max(reach, np.abs(drawn).max())
        check(reach >= length / 20.0, f"plot_rod {label}: the drawn shapes reach {reach:.3g} m of {length:g} m")
    check.finish()


if __name__ == "__main__":
    main()
