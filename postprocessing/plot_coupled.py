#!/usr/bin/env python3
"""Figure of one run with a coupled mass (beam or rod; docs/beam.md, docs/rod.md "Coupled
mass"): the mass's position and speed, the contact forces and the energies against time, with
the event that ended the run marked.

Usage: plot_coupled.py RUN.h5 [-o FIGURE.png]
Exits with status 2 and a message when RUN.h5 is not a complete run with a coupled mass.
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

ENERGIES_BEAM = ["energy_beam_kinetic", "energy_beam_elastic", "energy_beam_gravity"]
ENERGIES_ROD = ["energy_rod", "energy_rod_gravity"]
ENERGIES_MASS = ["energy_mass_kinetic", "energy_mass_gravity", "work_drive", "work_dissipated", "work_friction"]


def mass_name(run):
    """The coupled mass's name (from its *_normal_force probe)."""
    names = sorted(n[: -len("_normal_force")] for n in run.probes if n.endswith("_normal_force"))
    if not names:
        raise SystemExit("plot_coupled: the run has no coupled mass (no <name>_normal_force probe)")
    return names[0]


def events(path):
    """(time, position, reason) of the events table, empty without one."""
    import h5py

    with h5py.File(path, "r") as f:
        if "events" not in f or int(f["events"].attrs["count"]) == 0:
            return []
        g = f["events"]
        reasons = traverse_io._text(g.attrs["reasons"]).split(",")
        return list(zip(g["time"][()], g["position"][()], reasons))


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("run")
    ap.add_argument("-o", "--output", default=None)
    args = ap.parse_args(argv)
    try:
        run = traverse_io.load(args.run)
    except (OSError, traverse_io.IncompleteOutputError) as e:
        print(f"plot_coupled: {args.run}: {e}", file=sys.stderr)
        return 2
    try:
        name = mass_name(run)
    except SystemExit as e:
        print(f"{e} ({args.run})", file=sys.stderr)
        return 2
    t = run.time
    fig, ax = plt.subplots(2, 2, figsize=(11, 7), sharex=True)
    ax[0, 0].plot(t, run.probes[name + "_position"])
    ax[0, 0].set_ylabel("position along the structure [m]")
    ax[0, 1].plot(t, run.probes[name + "_speed"])
    ax[0, 1].set_ylabel("speed along the structure [m/s]")
    normal = np.atleast_2d(run.probes[name + "_normal_force"].T).T
    nmag = normal[:, 0] if normal.shape[1] == 1 else np.linalg.norm(normal, axis=1)
    ax[1, 0].plot(t, nmag, label="normal")
    ax[1, 0].plot(t, run.probes[name + "_tangential_force"], label="tangential")
    ax[1, 0].set_ylabel("contact force on the mass [N]")
    ax[1, 0].legend()
    for e in ENERGIES_BEAM + ENERGIES_ROD + ENERGIES_MASS + ["energy_balance"]:
        if e in run.probes:
            v = run.probes[e]
            ax[1, 1].plot(t, v - v[0], label=e.replace("energy_", ""))
    ax[1, 1].set_ylabel("change since t = 0 [J]")
    ax[1, 1].legend(fontsize=7)
    for e_time, e_pos, reason in events(args.run):
        for a in ax.flat:
            a.axvline(e_time, color="k", ls=":", lw=0.8)
        ax[0, 0].annotate(f"{reason} at {e_pos:.4g} m", (e_time, e_pos), fontsize=8, ha="right")
    for a in ax[1]:
        a.set_xlabel("t [s]")
    fig.suptitle(traverse_io.wrapped(f"{traverse_io.run_title(run)}: coupled mass '{name}'", 110))
    fig.tight_layout()
    out = args.output or os.path.splitext(args.run)[0] + "_coupled.png"
    fig.savefig(out, dpi=110)
    print(out)
    return 0


if __name__ == "__main__":
    sys.exit(main())
