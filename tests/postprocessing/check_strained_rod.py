#!/usr/bin/env python3
"""Checks the figures of postprocessing/plot_strained_rod.py on real runs of the three
extensible and shearable scenes (coarse meshes, a stiffness changed with --set):
  - each PNG has ink, extent and colours (check_figure.png_checks) and a curve that is a probe
    as the run stored it (or in mm);
  - taut: the title gives the E A the run used (not the scene's), the dashed parabola's sag is
    the taut string's for that E A, the shapes are drawn exaggerated by the factor the axis
    names (k times the stored y);
  - catenary: the dashed shape is Irvine's elastic catenary of the run's E A and weight;
  - cantilever (--traverse: the companions run from the stored scene): the tip curves are the
    three runs' tip heights in mm; a companion that is not inextensible is refused (status 2).

Usage: check_strained_rod.py TRAVERSE POSTPROCESSING_DIR INPUTS_ROD_DIR OUT_DIR
(exit status 1 on any failure)
"""
import os
import subprocess
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from check_figure import Checks, drawn_from, png_checks, probe_columns, run_figure_script  # noqa: E402

check = Checks()


def run(exe, scene, out, *sets):
    cmd = [exe, "run", scene, "-o", out, "--overwrite", "-q"]
    for s in sets:
        cmd += ["--set", s]
    subprocess.run(cmd, check=True)
    return out


def figure_of(script, argv):
    plt.close("all")
    run_figure_script(script, argv)
    return plt.figure(plt.get_fignums()[-1])


def lines_of(fig):
    return [ln for ax in fig.axes for ln in ax.get_lines()]


def shows_a_probe(fig, runs, what):
    cols = [c for r in runs for c in probe_columns(r)]
    check(any(drawn_from(np.asarray(ln.get_ydata(), float), cols) for ln in lines_of(fig)),
          f"{what}: a curve shows a probe's values as the run stored them (or in mm)")


def main():
    exe, pp, rod, out = sys.argv[1:5]
    os.makedirs(out, exist_ok=True)
    script = os.path.join(pp, "plot_strained_rod.py")
    sys.path.insert(0, pp)
    import plot_strained_rod as strained  # noqa: E402
    import traverse_io  # noqa: E402

    # Taut span: E A changed to 8 x the scene's (2.513e8 N), a coarse mesh, a short run.
    h5 = run(exe, os.path.join(rod, "taut_span_robot.yaml"), os.path.join(out, "taut.h5"),
             "mesh.ds=0.5", "time.end=6", "output.every=10", "rod.axial_stiffness=2.513274e8")
    png = os.path.join(out, "taut.png")
    fig = figure_of(script, ["taut", h5, "-o", png])
    png_checks(png, check)
    shows_a_probe(fig, [h5], "taut")
    title = fig._suptitle.get_text().replace("\n", " ")
    check("E A = 2.51e+08 N" in title and "drive 60 N" in title, f"taut: the title gives the run's E A and drive: {title}")
    p = strained.rod_properties(traverse_io.load(h5))
    s0 = strained.taut_string_sag(p["w"], p["L"], p["EA"])
    shapes = fig.axes[0]
    label = shapes.get_ylabel()
    k = float(label.split("exaggerated x")[1].split()[0]) if "exaggerated x" in label else 1.0
    dashed = [ln for ln in shapes.get_lines() if ln.get_linestyle() == "--"]
    check(len(dashed) == 1 and abs(-np.min(dashed[0].get_ydata()) / k - s0) < 1e-9 * s0,
          f"taut: the dashed parabola's sag is the taut string's {s0:.5f} m for the run's E A (y x {k:g})")
    r = traverse_io.load(h5).field("r", 0)
    first = [ln for ln in shapes.get_lines() if ln.get_label().startswith("t = 0.0 s")]
    check(k > 1.0 and len(first) == 1 and np.allclose(first[0].get_ydata(), k * r[:, 1]),
          f"taut: the static shape drawn is {k:g} x the stored y, as the axis says ('{label}')")

    # Elastic catenary: coarse mesh, the force's speed doubled.
    h5 = run(exe, os.path.join(rod, "elastic_catenary_load.yaml"), os.path.join(out, "catenary.h5"),
             "mesh.ds=0.2", "loads.F.speed=2.0")
    png = os.path.join(out, "catenary.png")
    fig = figure_of(script, ["catenary", h5, "-o", png])
    png_checks(png, check)
    shows_a_probe(fig, [h5], "catenary")
    title = fig._suptitle.get_text().replace("\n", " ")
    check("at 2 m/s" in title, f"catenary: the title gives the speed the run used: {title}")
    cat = strained.catenary_of(traverse_io.load(h5))
    irvine = [ln for ln in fig.axes[0].get_lines() if ln.get_label().startswith("Irvine")]
    s0 = np.linspace(0.0, cat.L0, 401)
    check(len(irvine) == 1 and np.allclose(irvine[0].get_xdata(), cat.x(s0)) and np.allclose(irvine[0].get_ydata(), -cat.z(s0)),
          f"catenary: the dashed shape is Irvine's catenary (H = {cat.H:.4g} N, sag {cat.sag():.4f} m)")

    # Rubber cantilever: coarse mesh; the companions run by the script.
    h5 = run(exe, os.path.join(rod, "rubber_cantilever_mass.yaml"), os.path.join(out, "rubber.h5"), "mesh.ds=0.0125")
    png = os.path.join(out, "rubber.png")
    fig = figure_of(script, ["cantilever", h5, "--traverse", exe, "-o", png])
    png_checks(png, check)
    companions = [os.path.join(out, f"rubber_{t}.h5") for t in ("inextensible", "stiff")]
    shows_a_probe(fig, [h5] + companions, "cantilever")
    tips = fig.axes[1].get_lines()
    ok = len(tips) == 3
    for ln, path in zip(tips, [h5] + companions):
        ok = ok and np.allclose(ln.get_ydata(), 1e3 * traverse_io.load(path).probes["tip"][:, 1])
    check(ok, "cantilever: the three tip curves are the shearable, inextensible and stiff runs' tip heights in mm")
    p = subprocess.run([sys.executable, script, "cantilever", h5, h5, companions[1], "-o", os.path.join(out, "refused.png")],
                       stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    check(p.returncode == 2 and "is not inextensible" in p.stderr,
          f"cantilever: a companion that is not inextensible is refused (exit {p.returncode}: {p.stderr.strip()})")
    check.finish()


if __name__ == "__main__":
    main()
