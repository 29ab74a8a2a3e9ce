#!/usr/bin/env python3
"""Statics from Python: the pinned-roller rod of inputs/statics/euler_buckling.yaml under a
growing end load, followed by continuation through its first pitchfork onto the buckled
branch, against the elastica's closed form (elliptic integrals): with m = k^2 the parameter,
P / P_E = (2 K(m) / pi)^2 and the midspan deflection delta = L sqrt(m) / K(m), where
P_E = pi^2 EI / L^2 is Euler's load.

    PYTHONPATH=build/python /usr/bin/python3 examples/python/euler_buckling.py [-o FIGURE.png] [--set KEY=VALUE ...]

The run happens in this process (traverse.run); it needs scipy (Debian: python3-scipy) for
the complete elliptic integral K.
"""
import argparse
import math
import os

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
from scipy.special import ellipk  # noqa: E402

import traverse  # noqa: E402

HERE = os.path.dirname(os.path.abspath(__file__))
DEFAULT_SCENE = os.path.join(HERE, os.pardir, os.pardir, "inputs", "statics", "euler_buckling.yaml")


def bending_stiffness(rod):
    section = rod["section"]
    if section["type"] != "solid_circle":
        raise SystemExit("this example takes a solid circular section")
    return rod["youngs_modulus"] * math.pi * section["radius"] ** 4 / 4.0


def elastica(length, euler_load, m):
    """The pinned-pinned elastica at parameters m: (end load, midspan deflection)."""
    k = ellipk(m)
    return euler_load * (2.0 * k / math.pi) ** 2, length * np.sqrt(m) / k


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--scene", default=DEFAULT_SCENE, help="the scene file (default: inputs/statics/euler_buckling.yaml)")
    ap.add_argument("-o", "--output", default="euler_buckling.png", help="the figure (PNG)")
    ap.add_argument("--set", action="append", default=[], metavar="KEY=VALUE", help="as traverse run --set")
    args = ap.parse_args()

    scene = traverse.Scene.load(args.scene, overrides=args.set)  # as --set
    complete = scene.check()
    result = traverse.run(scene)
    length = complete["rod"]["length"]
    euler_load = math.pi ** 2 * bending_stiffness(complete["rod"]) / length ** 2
    c = result.continuation
    load, deflection, branch = c[result.parameter], c["mid_y"], c["branch"]
    pitchforks = [p for t, p in zip(result.bifurcations["type"], result.bifurcations[result.parameter]) if t == "pitchfork"]
    if not pitchforks:
        raise SystemExit("no pitchfork was found: raise continuation.stop above Euler's load")
    buckled = branch == 1
    exact_load, _ = elastica(length, euler_load, np.zeros(1))
    p_exact, d_exact = elastica(length, euler_load, np.linspace(0.0, 0.95, 20001))
    # Each computed point's distance from the closed-form curve in the plane (|y| / L, P / P_E):
    # neither the deflection at a given load (steep at the pitchfork) nor the load at a given
    # deflection (steep where the deflection is largest) alone is well conditioned everywhere.
    gap = np.hypot((np.abs(deflection[buckled])[:, None] - d_exact[None, :]) / length,
                   (load[buckled][:, None] - p_exact[None, :]) / euler_load)
    error = gap.min(axis=1).max()

    fig, ax = plt.subplots(figsize=(7, 4.5))
    shown = p_exact <= 1.15 * load.max()  # the closed form over the loads computed
    ax.plot(d_exact[shown], p_exact[shown] / euler_load, "-", color="0.6", lw=3, label="elastica (closed form)")
    ax.plot(np.abs(deflection[~buckled]), load[~buckled] / euler_load, "o", ms=3, label="traverse: straight branch")
    ax.plot(np.abs(deflection[buckled]), load[buckled] / euler_load, "o", ms=3, label="traverse: buckled branch")
    ax.axhline(pitchforks[0] / euler_load, color="C3", lw=0.8, ls="--",
               label=f"pitchfork located: P = {pitchforks[0]:.5f} N = {pitchforks[0] / euler_load:.5f} P_E")
    ax.set_xlabel("midspan deflection |y| [m]")
    ax.set_ylabel("end load P / P_E")
    ax.set_title(f"{complete.get('title', args.scene)}: P_E = pi^2 EI / L^2 = {euler_load:.5f} N\n"
                 f"ds = {complete['mesh']['ds']:g} m; buckled branch within {error:.1e} of the closed form (in |y| / L, P / P_E)",
                 fontsize=10)
    ax.legend(fontsize=8, loc="lower right")
    ax.grid(True, alpha=0.3)
    fig.tight_layout()
    fig.savefig(args.output, dpi=120)
    print(f"Euler load: {euler_load:.6f} N; pitchfork located at {pitchforks[0]:.6f} N "
          f"(relative difference {pitchforks[0] / exact_load[0] - 1:+.2e})")
    print(f"buckled branch: {int(buckled.sum())} points, largest distance from the closed form {error:.3e} (in |y| / L, P / P_E)")
    print(f"wrote {args.output}")


if __name__ == "__main__":
    main()
