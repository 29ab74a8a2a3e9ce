#!/usr/bin/env python3
"""A speed sweep of the default scene (a hanging cable crossed by a 2 N force) run from Python,
and its resonance curve: the cable's lowest and highest midspan height during each crossing
against the speed of the load.

    PYTHONPATH=build/python /usr/bin/python3 examples/python/speed_sweep.py [-o FIGURE.png]
        [--speeds 0.5:6:0.5] [--set KEY=VALUE ...] [--keep DIR]

The cases run in this process, one after the other (traverse.sweep, the cases of
`traverse sweep`); under `mpirun -n K` they spread over the K ranks. The sweep's files are
temporary unless --keep names a directory for them.
"""
import argparse
import os

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

import traverse  # noqa: E402

HERE = os.path.dirname(os.path.abspath(__file__))
DEFAULT_SCENE = os.path.join(HERE, os.pardir, os.pardir, "inputs", "default.yaml")
LOWEST, HIGHEST = "midspan.y:min", "midspan.y:max"


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--scene", default=DEFAULT_SCENE, help="the scene file (default: inputs/default.yaml)")
    ap.add_argument("-o", "--output", default="speed_sweep.png", help="the figure (PNG)")
    ap.add_argument("--speeds", default="0.5:6:0.5",
                    help="the load's speeds [m/s], as traverse sweep --vary takes them (default 0.5:6:0.5)")
    ap.add_argument("--set", action="append", default=[], metavar="KEY=VALUE", help="as traverse sweep --set")
    ap.add_argument("--keep", help="write the sweep's files (index.csv, case_NNNN.h5) into this directory")
    args = ap.parse_args()

    scene = traverse.Scene.load(args.scene, overrides=args.set)  # as --set
    load = next(iter(scene.check()["loads"]))  # the scene's first moving load
    table = traverse.sweep(scene, vary={f"loads.{load}.speed": args.speeds}, summary=[LOWEST, HIGHEST],
                           output=args.keep, quiet=False)
    done = [row for row in table if row["status"] == "complete"]
    if len(done) < len(table):
        print(f"{len(table) - len(done)} of {len(table)} cases did not complete:")
        for row in table:
            if row["status"] != "complete":
                print(f"  case {row['case']}: {row['status']}: {row['message']}")
    speed = np.array([row[f"loads.{load}.speed"] for row in done], dtype=float)
    low = 1e3 * np.array([row[LOWEST] for row in done])
    high = 1e3 * np.array([row[HIGHEST] for row in done])

    fig, ax = plt.subplots(figsize=(7, 4))
    ax.fill_between(speed, low, high, alpha=0.2, label="range of the midspan height")
    ax.plot(speed, low, "o-", lw=1.5, label="lowest (largest sag)")
    ax.plot(speed, high, "s-", lw=1, label="highest")
    worst = int(np.argmin(low))
    ax.annotate(f"{speed[worst]:g} m/s", (speed[worst], low[worst]), textcoords="offset points", xytext=(6, 8))
    ax.set_xlabel(f"speed of the load '{load}' [m/s]")
    ax.set_ylabel("midspan height y [mm]")
    ax.set_title(f"{scene.check().get('title', args.scene)}\n(traverse.sweep: {len(done)} of {len(table)} cases)",
                 fontsize=10)
    ax.grid(True, alpha=0.3)
    ax.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(args.output, dpi=120)
    print(f"wrote {args.output}: lowest midspan height {low[worst]:.3f} mm at {speed[worst]:g} m/s"
          + (f"; the sweep's files in {args.keep}" if args.keep else ""))


if __name__ == "__main__":
    main()
