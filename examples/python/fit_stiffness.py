#!/usr/bin/env python3
"""A parameter fit with traverse in the loop: the Young's modulus of the default cable (a
hanging cable crossed by a 2 N force) recovered from a "measured" midspan trace.

    PYTHONPATH=build/python /usr/bin/python3 examples/python/fit_stiffness.py [-o FIGURE.png]
        [--true-modulus 3e8] [--bounds 1e8 6e8] [--xatol 1e5] [--set KEY=VALUE ...]

The measurement is the midspan height y(t) of a run at the true modulus (synthetic, without
noise). scipy.optimize.minimize_scalar (bounded Brent) then searches the modulus between the
bounds that minimises the mean squared difference between that trace and the trace of a run
at the trial modulus; every evaluation is a traverse.run in this process. The search stops
when the modulus is known to within --xatol [Pa] (Brent's bracket: the minimiser of a misfit
with one minimum in the bounds lies within xatol + 2 sqrt(eps) |E| of the answer), which is
the accuracy the script reports.

The figure shows the measured trace with the fitted one, and the misfit at every trial.
"""
import argparse
import math
import os
import sys
import time

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
from scipy.optimize import minimize_scalar  # noqa: E402

import traverse  # noqa: E402

HERE = os.path.dirname(os.path.abspath(__file__))
DEFAULT_SCENE = os.path.join(HERE, os.pardir, os.pardir, "inputs", "default.yaml")
KEY = "rod.youngs_modulus"
PROBE = "midspan"


def midspan_trace(scene, modulus):
    """(t, y): the output times [s] and the midspan height [m] of a run at `modulus` [Pa]."""
    trial = scene.copy().set(KEY, float(modulus))
    result = traverse.run(trial)  # a temporary output file, removed by close()
    try:
        return result.time.copy(), result.probes[PROBE][:, 1].copy()
    finally:
        result.close()


def fit_tolerance(modulus, xatol):
    """How far from the misfit's minimiser minimize_scalar(method="bounded") may stop: its
    final bracket is at most 2 (sqrt(eps) |x| + xatol / 3) wide around its answer."""
    return xatol + 2.0 * math.sqrt(np.finfo(float).eps) * abs(modulus)


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--scene", default=DEFAULT_SCENE, help="the scene file (default: inputs/default.yaml)")
    ap.add_argument("-o", "--output", default="fit_stiffness.png", help="the figure (PNG)")
    ap.add_argument("--true-modulus", type=float, default=3.0e8,
                    help="the Young's modulus [Pa] of the measurement (default 3e8; the scene has 2.5e8)")
    ap.add_argument("--bounds", type=float, nargs=2, default=(1.0e8, 6.0e8), metavar=("LOW", "HIGH"),
                    help="the range [Pa] searched (default 1e8 6e8)")
    ap.add_argument("--xatol", type=float, default=1.0e5,
                    help="the search stops when the modulus is known to within this [Pa] (default 1e5)")
    ap.add_argument("--set", action="append", default=[], metavar="KEY=VALUE",
                    help="as traverse run --set, for the measurement and every trial "
                         "(default: mesh.ds=0.02, a coarse mesh for a fit of seconds)")
    args = ap.parse_args()

    scene = traverse.Scene.load(args.scene, overrides=args.set or ["mesh.ds=0.02"])  # as --set

    start = time.perf_counter()
    t_meas, y_meas = midspan_trace(scene, args.true_modulus)
    trials = []  # (modulus, misfit) of every evaluation, in order

    def misfit(modulus):
        t, y = midspan_trace(scene, modulus)
        # The output times do not depend on the modulus (dt from the mesh and the load's
        # speed); interpolating keeps the misfit meaningful should they differ.
        model = y if np.array_equal(t, t_meas) else np.interp(t_meas, t, y)
        value = float(np.mean((model - y_meas) ** 2))
        trials.append((modulus, value))
        return value

    res = minimize_scalar(misfit, bounds=tuple(args.bounds), method="bounded",
                          options={"xatol": args.xatol, "maxiter": 200})
    seconds = time.perf_counter() - start
    if not res.success:
        sys.exit(f"fit_stiffness: the search did not converge: {res.message}")
    fitted = float(res.x)
    error = fitted - args.true_modulus
    tolerance = fit_tolerance(fitted, args.xatol)
    print(f"true modulus:      {args.true_modulus!r} Pa")
    print(f"recovered modulus: {fitted!r} Pa")  # every digit: the tests compare it
    print(f"error:             {error:+.3e} Pa ({error / args.true_modulus:+.2e} relative); "
          f"the fit's tolerance {tolerance:.3e} Pa")
    print(f"runs:              {len(trials) + 1} ({res.nfev} trials and the measurement) in {seconds:.1f} s")

    t_fit, y_fit = midspan_trace(scene, fitted)
    fig, (top, bottom) = plt.subplots(2, 1, figsize=(7, 6.5))
    top.plot(t_meas, 1e3 * y_meas, "o", ms=3, color="0.3", label=f"measured (E = {args.true_modulus:.4g} Pa)")
    top.plot(t_fit, 1e3 * y_fit, "-", lw=1.5, label=f"fitted (E = {fitted:.6g} Pa)")
    for bound in args.bounds:
        t_b, y_b = midspan_trace(scene, bound)
        top.plot(t_b, 1e3 * y_b, ":", lw=1, label=f"bound E = {bound:.3g} Pa")
    top.set_xlabel("time t [s]")
    top.set_ylabel("midspan height y [mm]")
    top.legend(fontsize=8)
    top.grid(True, alpha=0.3)
    moduli, values = np.array(trials).T
    bottom.semilogy(moduli, np.maximum(values, np.finfo(float).tiny), "o", ms=4)
    for k, (m, v) in enumerate(trials, start=1):
        bottom.annotate(str(k), (m, max(v, np.finfo(float).tiny)), fontsize=7, xytext=(3, 3),
                        textcoords="offset points")
    bottom.axvline(args.true_modulus, color="0.5", lw=1, ls="--", label="true modulus")
    bottom.set_xlabel("trial Young's modulus E [Pa] (numbers: order of evaluation)")
    bottom.set_ylabel("misfit: mean (y - y_measured)^2 [m^2]")
    bottom.legend(fontsize=8)
    bottom.grid(True, alpha=0.3)
    fig.suptitle(f"Young's modulus from the midspan trace: {fitted:.6g} Pa "
                 f"(true {args.true_modulus:.6g} Pa, {res.nfev} runs)", fontsize=10)
    fig.tight_layout()
    fig.savefig(args.output, dpi=120)
    print(f"wrote {args.output}")


if __name__ == "__main__":
    main()
