#!/usr/bin/env python3
"""Figure of a sprung mass on the rod (inputs/rod/sprung_cabin_cable.yaml, docs/rod.md "Sprung
mass"), against the wheel's position along the rod: (a) the wheel's and the body's vertical
displacements and the midspan's (mm); (b) the body's acceleration; (c) the rod's contact force on
the vehicle with its weight (M_v + m_w) g.

Usage: plot_sprung_rod.py RUN.h5 [-o FIGURE.png] [--gravity G]
Exits with status 2 and a message when RUN.h5 is not a complete rod run with a sprung mass.
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


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("run")
    ap.add_argument("-o", "--output", default=None)
    args = ap.parse_args(argv)
    try:
        run = traverse_io.load(args.run)
    except (OSError, KeyError, traverse_io.IncompleteOutputError) as e:
        print(f"plot_sprung_rod: {args.run}: {e}", file=sys.stderr)
        return 2
    names = sorted(n[: -len("_body_displacement")] for n in run.probes if n.endswith("_body_displacement"))
    if str(run.attrs.get("model", "")) != "rod" or not names:
        print(f"plot_sprung_rod: {args.run}: expected a rod run with a sprung mass (a <name>_body_displacement probe)",
              file=sys.stderr)
        return 2
    name = names[0]
    sigma = run.probes[name + "_position"]
    wheel = run.probes[name + "_fixed_position"][:, 1]
    body = run.probes[name + "_body_displacement"]
    fig, ax = plt.subplots(1, 3, figsize=(15, 4.4))
    ax[0].plot(sigma, 1e3 * (wheel - wheel[0]), label="wheel (its height from the start)")
    ax[0].plot(sigma, 1e3 * (body - body[0]), label="body z - z(0)")
    if "midspan" in run.probes:
        mid = run.probes["midspan"][:, 1]
        ax[0].plot(sigma, 1e3 * (mid - mid[0]), label="midspan of the rod")
    ax[0].set_ylabel("vertical displacement [mm]")
    ax[1].plot(sigma, run.probes[name + "_body_acceleration"], color="C3", label="body z''")
    ax[1].set_ylabel("acceleration [m/s^2]")
    force = run.probes[name + "_contact_force"]
    ax[2].plot(sigma, force, color="C2", label="contact force along d2")
    sc = traverse_io.scene_values(run)
    load = sc.get("loads", {}).get(name, {})
    weight = (float(load.get("mass", 0.0)) + float(load.get("wheel_mass", 0.0))) * float(sc.get("gravity", 9.8))
    ax[2].axhline(weight, color="k", ls="--", lw=0.8, label=f"weight (M_v + m_w) g = {weight:.4g} N")
    ax[2].set_ylabel("contact force [N]")
    for a in ax:
        a.set_xlabel(f"position of '{name}' along the rod [m]")
        a.grid(alpha=0.3)
        a.legend(fontsize=8)
    fig.suptitle(traverse_io.wrapped(traverse_io.run_title(run), 120))
    fig.tight_layout()
    out = args.output or os.path.splitext(args.run)[0] + "_sprung.png"
    fig.savefig(out, dpi=110)
    print(out)
    return 0


if __name__ == "__main__":
    sys.exit(main())
