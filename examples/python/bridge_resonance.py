#!/usr/bin/env python3
"""The beam model from Python: a 25 m simply supported bridge crossed by a train of ten 18 m
coaches (inputs/beam/axle_train.yaml), swept over the train's speed, and the resonance curve
of the bridge: the largest midspan deflection and deck acceleration against the speed, with
the resonance speeds v_i = f_1 d / i of the first mode (f_1 from the beam's properties, d the
coach length) marked.

    PYTHONPATH=build/python /usr/bin/python3 examples/python/bridge_resonance.py [-o FIGURE.png]
        [--speeds 30:110:2] [--set KEY=VALUE ...] [--keep DIR]

The cases run in this process (traverse.sweep); under `mpirun -n K` they spread over the K
ranks. The files are temporary unless --keep names a directory for them.
"""
import argparse
import math
import os

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

import traverse  # noqa: E402

HERE = os.path.dirname(os.path.abspath(__file__))
DEFAULT_SCENE = os.path.join(HERE, os.pardir, os.pardir, "inputs", "beam", "axle_train.yaml")
DEFLECTION, ACCELERATION = "midspan:absmax", "deck:absmax"


def first_frequency(beam):
    """f_1 [Hz] of a simply supported Euler-Bernoulli beam: (pi / 2 L^2) sqrt(EI / rho A)."""
    section = beam["section"]
    ei = beam["youngs_modulus"] * section["second_moment"]
    mass = beam["density"] * section["area"]
    return math.pi / (2.0 * beam["length"] ** 2) * math.sqrt(ei / mass)


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--scene", default=DEFAULT_SCENE, help="the scene file (default: inputs/beam/axle_train.yaml)")
    ap.add_argument("-o", "--output", default="bridge_resonance.png", help="the figure (PNG)")
    ap.add_argument("--speeds", default="30:110:2", help="the train's speeds [m/s], as --vary takes them")
    ap.add_argument("--set", action="append", default=[], metavar="KEY=VALUE", help="as traverse sweep --set")
    ap.add_argument("--keep", help="write the sweep's files (index.csv, case_NNNN.h5) into this directory")
    args = ap.parse_args()

    scene = traverse.Scene.load(args.scene, overrides=args.set)  # as --set
    complete = scene.check()
    if complete["beam"]["supports"] != "simply-supported":
        ap.error("the resonance speeds marked are those of a simply supported beam")
    load = next(iter(complete["loads"]))
    coach = complete["loads"][load]["generator"]["coach_length"]
    table = traverse.sweep(scene, vary={f"loads.{load}.speed": args.speeds}, summary=[DEFLECTION, ACCELERATION],
                           output=args.keep)
    failed = [row for row in table if row["status"] != "complete"]
    if failed:
        raise SystemExit(f"{len(failed)} cases did not complete, e.g. case {failed[0]['case']}: {failed[0]['message']}")

    speed = table.column(f"loads.{load}.speed")
    f1 = first_frequency(complete["beam"])
    fig, (top, bottom) = plt.subplots(2, 1, figsize=(7, 6), sharex=True)
    top.plot(speed, 1e3 * table.column(DEFLECTION), "o-", ms=3, lw=1.2)
    bottom.plot(speed, table.column(ACCELERATION), "o-", ms=3, lw=1.2, color="C1")
    top.set_ylabel("largest midspan deflection [mm]")
    bottom.set_ylabel("largest deck acceleration [m/s$^2$]")
    bottom.set_xlabel("train speed [m/s]")
    for i in range(1, 4):
        v = f1 * coach / i
        if speed.min() <= v <= speed.max():
            for ax in (top, bottom):
                ax.axvline(v, color="0.5", lw=0.8, ls="--")
            top.annotate(f"$v_{i} = f_1 d / {i}$" if i > 1 else "$v_1 = f_1 d$", (v, top.get_ylim()[1]),
                         textcoords="offset points", xytext=(-3, -12), ha="right", fontsize=8, color="0.3")
    for ax in (top, bottom):
        ax.grid(True, alpha=0.3)
    top.set_title(f"{complete.get('title', args.scene)}\n"
                  f"f_1 = {f1:.2f} Hz, coach length d = {coach:g} m, {len(table)} speeds", fontsize=10)
    fig.tight_layout()
    fig.savefig(args.output, dpi=120)
    k = int(table.column(DEFLECTION).argmax())
    print(f"first mode {f1:.4f} Hz; resonance speed f1 d = {f1 * coach:.2f} m/s; largest deflection "
          f"{1e3 * table[k][DEFLECTION]:.3f} mm at {speed[k]:g} m/s")
    print(f"wrote {args.output}" + (f"; cases kept in {args.keep}" if args.keep else ""))


if __name__ == "__main__":
    main()
