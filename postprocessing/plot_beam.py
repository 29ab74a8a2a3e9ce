#!/usr/bin/env python3
"""Figure of one beam run: a probe's deflection and the deflection under each load against
the position x(t) of a load on the beam (the "beam coordinate").

The probe and the load come from the file: by default the first probe and the first load the
scene declares (--probe, --load choose others). The title gives the values the run used (its
stored scene, after any --set), not the scene's `title:`.

Usage: plot_beam.py RUN.h5 [-o FIGURE.png] [--probe NAME] [--load NAME]
Exits with status 2 and a message when RUN.h5 is not a complete beam run or has no such probe
or load.
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


def load_names(run):
    """Names of the moving loads of a beam run, in the scene's order (each has a
    NAME_position probe)."""
    declared = traverse_io.scene_values(run).get("loads", {})
    names = [n for n in declared if n + "_position" in run.probes] if isinstance(declared, dict) else []
    return names or sorted(n[: -len("_position")] for n in run.probes if n.endswith("_position"))


def probe_names(run):
    """The scene's own probes (output.probes), in its order, without the loads' probes."""
    declared = traverse_io.scene_values(run).get("output", {}).get("probes", {})
    return [n for n in declared if n in run.probes] if isinstance(declared, dict) else []


def draw(run, ax, probe=None, load=None, label_prefix=""):
    """Plots probe `probe` (None: none) and every load's deflection against the position of
    load `load` (None: the scene's first load), in mm against m."""
    loads = load_names(run)
    if not loads:
        raise SystemExit("plot_beam: the run has no moving load to plot against")
    load = load or loads[0]
    x = run.probes[load + "_position"]
    on = (x >= 0) & (x <= float(run.s[-1]))
    if probe is not None:
        ax.plot(x[on], 1e3 * run.probes[probe][on], label=label_prefix + f"{probe} deflection")
    for name in loads:
        xl = run.probes[name + "_position"]
        w = run.probes[name + "_deflection"]
        ok = np.isfinite(w)
        ax.plot(xl[ok], 1e3 * w[ok], "--", label=label_prefix + f"under '{name}'")
    ax.set_xlabel(f"position of '{load}' on the beam x(t) [m]")
    ax.set_ylabel("deflection w [mm]")
    ax.grid(True, alpha=0.3)


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("run")
    ap.add_argument("-o", "--output", help="PNG file (default: RUN with .png)")
    ap.add_argument("--probe", help="probe to draw besides the loads (default: the scene's first probe)")
    ap.add_argument("--load", help="load whose position is the x axis (default: the scene's first load)")
    a = ap.parse_args(argv)
    run = traverse_io.load_for_plot(a.run, "beam", "plot_beam")
    probe = a.probe
    if probe is None:
        own = probe_names(run)
        probe = own[0] if own else None
    else:
        traverse_io.require_probe(run, probe, "plot_beam")
    if a.load is not None and a.load not in load_names(run):
        traverse_io._exit_with(f"plot_beam: {a.run} has no load '{a.load}' (its loads: "
                               f"{', '.join(load_names(run)) or 'none'}); choose one with --load")
    fig, ax = plt.subplots(figsize=(8, 4.6))
    draw(run, ax, probe, a.load)
    ax.set_title(traverse_io.wrapped(traverse_io.run_title(run)), fontsize=10)
    ax.legend()
    fig.tight_layout()
    out = a.output or os.path.splitext(a.run)[0] + ".png"
    fig.savefig(out, dpi=130)
    print(f"plot_beam: wrote {out}")


if __name__ == "__main__":
    main()
