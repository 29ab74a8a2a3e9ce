#!/usr/bin/env python3
"""The default scene (a hanging cable crossed by a 2 N force) run from Python, and a figure of
the cable's midspan height against the position of the load.

    PYTHONPATH=build/python /usr/bin/python3 examples/python/default_cable.py [-o FIGURE.png] [--set KEY=VALUE ...]

The run happens in this process (traverse.run); its output file is temporary unless --keep
names a path for it.
"""
import argparse
import os

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

import traverse  # noqa: E402

HERE = os.path.dirname(os.path.abspath(__file__))
DEFAULT_SCENE = os.path.join(HERE, os.pardir, os.pardir, "inputs", "default.yaml")


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--scene", default=DEFAULT_SCENE, help="the scene file (default: inputs/default.yaml)")
    ap.add_argument("-o", "--output", default="default_cable.png", help="the figure (PNG)")
    ap.add_argument("--set", action="append", default=[], metavar="KEY=VALUE", help="as traverse run --set")
    ap.add_argument("--keep", help="keep the run's HDF5 file at this path")
    args = ap.parse_args()

    scene = traverse.Scene.load(args.scene, overrides=args.set)  # as --set
    result = traverse.run(scene, output=args.keep)

    complete = scene.check()  # the scene as run, defaults filled in
    load = next(iter(complete["loads"]))  # the scene's first moving load
    sigma = result.sigma if result.sigma.ndim == 1 else result.sigma[:, 0]
    height = result.probes["midspan"][:, 1]  # the position's y component: up
    fig, ax = plt.subplots(figsize=(7, 4))
    ax.plot(sigma, 1e3 * height, lw=1.5)
    ax.set_xlabel(f"position of the load '{load}' along the cable, sigma [{result.output.units('sigma')}]")
    ax.set_ylabel("midspan height y [mm]")
    ax.set_title(f"{complete.get('title', args.scene)}\n(run in Python: {result.steps} output steps, {result.status})",
                 fontsize=10)
    ax.grid(True, alpha=0.3)
    fig.tight_layout()
    fig.savefig(args.output, dpi=120)
    print(f"wrote {args.output} ({result.steps} output steps"
          + (f", run kept in {args.keep})" if args.keep else ")"))


if __name__ == "__main__":
    main()
