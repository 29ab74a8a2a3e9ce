#!/usr/bin/env python3
"""Side-by-side figure of a coupled-mass run and a prescribed-speed run of the same mass (docs/
results.md "Coupled mass"): (a) the mass's position against time, (b) its speed against its
position (the prescribed run's constant), (c) a probe component (e.g. the midspan height) and
(d) the mass's height against the mass's position, for both runs; the coupled run's event marked.

Usage: coupled_vs_prescribed.py COUPLED.h5 PRESCRIBED.h5 [--probe midspan] [--component 1]
                                [--title TEXT] [-o FIGURE.png]
Exits with status 2 and a message when a file is not a complete run, the first has no coupled
mass, or the probe is missing.
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
from plot_coupled import events, mass_name  # noqa: E402


def height_along(run, sigma):
    """The structure's height y at the load's position at each output step (field r, linear)."""
    r = run.field("r")
    return np.array([np.interp(sg, run.s, r[k, :, 1]) if np.isfinite(sg) else np.nan for k, sg in enumerate(sigma)])


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("coupled")
    ap.add_argument("prescribed")
    ap.add_argument("--probe", default="midspan")
    ap.add_argument("--component", type=int, default=1)
    ap.add_argument("--title", default=None)
    ap.add_argument("-o", "--output", default=None)
    args = ap.parse_args(argv)
    try:
        c, p = traverse_io.load(args.coupled), traverse_io.load(args.prescribed)
        name = mass_name(c)
        pc, pp = c.probes[args.probe][:, args.component], p.probes[args.probe][:, args.component]
        sp = p.sigma if p.sigma.ndim == 1 else p.sigma[:, 0]
        hc, hp = height_along(c, c.probes[name + "_position"]), height_along(p, sp)
    except (OSError, KeyError, IndexError, traverse_io.IncompleteOutputError) as e:
        print(f"coupled_vs_prescribed: {e}", file=sys.stderr)
        return 2
    sc, vc = c.probes[name + "_position"], c.probes[name + "_speed"]
    vp = np.gradient(sp, p.time)
    fig, ax = plt.subplots(2, 2, figsize=(11, 7.5))
    ax[0, 0].plot(c.time, sc, label="coupled")
    ax[0, 0].plot(p.time, sp, "--", label="prescribed speed")
    ax[0, 0].set_xlabel("t [s]")
    ax[0, 0].set_ylabel("mass position sigma [m]")
    ax[0, 1].plot(sc, vc, label="coupled")
    ax[0, 1].plot(sp, vp, "--", label="prescribed speed")
    ax[0, 1].set_xlabel("mass position sigma [m]")
    ax[0, 1].set_ylabel("speed [m/s]")
    comp = "xyz"[args.component]
    ax[1, 0].plot(sc, pc, label="coupled")
    ax[1, 0].plot(sp, pp, "--", label="prescribed speed")
    ax[1, 0].set_xlabel("mass position sigma [m]")
    ax[1, 0].set_ylabel(f"{args.probe} {comp} [{c.units(args.probe)}]")
    ax[1, 1].plot(sc, hc, label="coupled")
    ax[1, 1].plot(sp, hp, "--", label="prescribed speed")
    ax[1, 1].set_xlabel("mass position sigma [m]")
    ax[1, 1].set_ylabel("height of the structure under the mass [m]")
    for e_time, e_pos, reason in events(args.coupled):
        ax[0, 0].axvline(e_time, color="k", ls=":", lw=0.8)
        ax[0, 0].annotate(reason, (e_time, e_pos), fontsize=8, ha="right")
    for a in ax.flat:
        a.legend(fontsize=8)
    fig.suptitle(args.title or traverse_io.wrapped(traverse_io.run_title(c), 110))
    fig.tight_layout()
    out = args.output or os.path.splitext(args.coupled)[0] + "_vs_prescribed.png"
    fig.savefig(out, dpi=110)
    print(out)
    return 0


if __name__ == "__main__":
    sys.exit(main())
