#!/usr/bin/env python3
"""Figure of a driven coupled mass on the rod (the inspection robot, docs/results.md): (a) its
speed against its position, with the rigid level line's terminal speed D / c and the speed
(D + M g sin theta) / c a rigid line at the cable's local slope under the robot would give
(theta the downward slope of the cell of the cable that holds the robot); (b) the cable's shape at a few times with
the robot marked; (c) the robot's height and the midspan height against time.

Usage: plot_robot.py RUN.h5 --drive D --resistance C --mass M [-o FIGURE.png]
Exits with status 2 and a message when RUN.h5 is not a complete rod run with a coupled mass and
the field r.
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


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("run")
    ap.add_argument("--drive", type=float, required=True)
    ap.add_argument("--resistance", type=float, required=True)
    ap.add_argument("--mass", type=float, required=True)
    ap.add_argument("--gravity", type=float, default=9.8)
    ap.add_argument("-o", "--output", default=None)
    args = ap.parse_args(argv)
    try:
        run = traverse_io.load(args.run)
        name = mass_name(run)
        r = run.field("r")
    except (OSError, KeyError, traverse_io.IncompleteOutputError) as e:
        print(f"plot_robot: {args.run}: {e}", file=sys.stderr)
        return 2
    t = run.time
    sigma, v = run.probes[name + "_position"], run.probes[name + "_speed"]
    pv, pos = run.probes[name + "_fixed_velocity"], run.probes[name + "_fixed_position"]
    s_nodes = run.s
    cell = np.clip(np.searchsorted(s_nodes, sigma, side="right") - 1, 0, len(s_nodes) - 2)
    steps = np.arange(len(t))
    chord = r[steps, cell + 1, :] - r[steps, cell, :]
    sin_down = -chord[:, 1] / np.linalg.norm(chord, axis=1)  # sin of the downward slope along +s
    local = (args.drive + args.mass * args.gravity * sin_down) / args.resistance
    fig, ax = plt.subplots(1, 3, figsize=(15, 4.6))
    ax[0].plot(sigma, v, label="coupled robot sigma'")
    ax[0].plot(sigma[1:], local[1:], "--", label="(D + M g sin theta) / c, local slope")
    ax[0].axhline(args.drive / args.resistance, color="k", ls=":", label="D / c (rigid level line)")
    ax[0].set_xlabel("robot position sigma [m]")
    ax[0].set_ylabel("speed along the cable [m/s]")
    ax[0].legend(fontsize=8)
    picks = np.unique(np.linspace(0, len(t) - 1, 6).astype(int))
    # The cable starts straight along z: y is its vertical displacement, exaggerated when small.
    scale = traverse_io.exaggeration(r[picks, :, 1], float(s_nodes[-1] - s_nodes[0]))
    for k in picks:
        line, = ax[1].plot(r[k, :, 2], scale * r[k, :, 1], label=f"t = {t[k]:.2f} s")
        ax[1].plot(pos[k, 2], scale * pos[k, 1], "o", color=line.get_color())
    ax[1].set_aspect("equal")
    ax[1].set_xlabel("z [m]")
    ax[1].set_ylabel("y [m]" if scale == 1.0 else f"y, exaggerated x {scale:g} [m]")
    ax[1].legend(fontsize=7, loc="upper center", ncol=3, bbox_to_anchor=(0.5, 0.28), bbox_transform=fig.transFigure)  # below the flat panel
    ax[1].set_title("cable shapes, robot marked" + ("" if scale == 1.0 else f" (y x {scale:g})"))
    ax[2].plot(t, pos[:, 1], label="robot height")
    ax[2].plot(t, run.probes["midspan"][:, 1], label="midspan height")
    ax[2].set_xlabel("t [s]")
    ax[2].set_ylabel("y [m]")
    ax[2].legend(fontsize=8)
    for e_time, _, reason in events(args.run):
        ax[2].axvline(e_time, color="k", ls=":", lw=0.8)
        ax[2].annotate(reason, (e_time, ax[2].get_ylim()[0]), fontsize=8, ha="right", va="bottom")
    fig.suptitle(traverse_io.wrapped(traverse_io.run_title(run), 140))
    fig.tight_layout()
    out = args.output or os.path.splitext(args.run)[0] + "_robot.png"
    fig.savefig(out, dpi=110)
    print(out)
    return 0


if __name__ == "__main__":
    sys.exit(main())
