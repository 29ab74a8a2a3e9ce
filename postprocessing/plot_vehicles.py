#!/usr/bin/env python3
"""Figures of the vehicle scenes of inputs/beam (docs/beam.md "Vehicles" and "Axle trains"):
  vehicles_sprung_mass.png  sprung_mass.yaml: midspan deflection against the load's position for
                            the sprung mass, the moving mass and the moving force of the same
                            weight; body and deck accelerations; the contact force
  vehicles_two_axle_car.png two_axle_car.yaml: midspan deflection, body bounce and pitch, the
                            two axles' contact forces
  vehicles_axle_train.png   axle_train.yaml at its first resonance (73.6 m/s) and off it (60 m/s):
                            deck acceleration and midspan deflection against time
  vehicles_envelope.png     the resonance envelope of axle_train.yaml for coach lengths 14, 16.67 (2 L / 3), 18
                            and 22 m over 30-100 m/s (a sweep, resonance_envelope.py)
Usage: plot_vehicles.py --traverse BUILD/traverse [--out DIR] [--plot-only] [--ranks K]
"""
import argparse
import os
import subprocess
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, HERE)
import traverse_io  # noqa: E402

INPUTS = os.path.join(HERE, "..", "inputs", "beam")
F1 = 4.0916  # first frequency of the 25 m bridge [Hz]


def run(args, scene, out, *sets):
    cmd = [args.traverse, "run", os.path.join(INPUTS, scene), "-o", out, "--overwrite", "-q"]
    for s in sets:
        cmd += ["--set", s]
    subprocess.run(cmd, check=True)


def outputs(args):
    o = lambda name: os.path.join(args.out, name)  # noqa: E731
    if args.plot_only:
        return o
    run(args, "sprung_mass.yaml", o("sprung_mass.h5"))
    run(args, "sprung_mass.yaml", o("moving_mass.h5"), "loads.car={type: moving_mass, mass: 5750, speed: 25}")
    run(args, "sprung_mass.yaml", o("moving_force.h5"), "loads.car={type: moving_force, mass: 5750, speed: 25}")
    run(args, "two_axle_car.yaml", o("two_axle_car.h5"))
    for v in ("60", "73.6"):
        run(args, "axle_train.yaml", o(f"axle_train_{v}.h5"), f"loads.train.speed={v}")
    sweep = traverse_io.command(args.traverse, "sweep", args.ranks) + [
        os.path.join(INPUTS, "axle_train.yaml"), "-o", o("envelope"), "--overwrite", "-q",
        "--vary", "loads.train.generator.coach_length=14,16.6667,18,22", "--vary", "loads.train.speed=30:100:0.5",
        "--summary", "deck:absmax"]
    subprocess.run(sweep, check=True)
    return o


def sprung_mass_figure(o, path):
    runs = {k: traverse_io.load_for_plot(o(f"{k}.h5"), "beam", "plot_vehicles.py")
            for k in ("sprung_mass", "moving_mass", "moving_force")}
    fig, ax = plt.subplots(1, 3, figsize=(15, 4.2))
    for k, r in runs.items():
        x = traverse_io.first_load_sigma(r)
        ax[0].plot(x, 1e3 * r.probes["midspan"], label=k.replace("_", " "))
    s = runs["sprung_mass"]
    x = traverse_io.first_load_sigma(s)
    ax[1].plot(x, s.probes["car_body_acceleration"], label="body z''")
    ax[1].plot(x, s.probes["midspan_acceleration"], label="deck w_tt(L/2)")
    ax[2].plot(x, 1e-3 * s.probes["car_contact_force"], label="contact force")
    ax[2].axhline(5750 * 9.81e-3, color="k", ls="--", lw=0.8, label="static weight")
    labels = ("midspan deflection w(L/2) [mm]", "acceleration [m/s^2]", "contact force [kN]")
    for a, yl in zip(ax, labels):
        a.set_xlabel("position of the load x(t) [m]")
        a.set_ylabel(yl)
        a.grid(alpha=0.3)
        a.legend(fontsize=8)
    fig.suptitle("sprung mass (5750 kg on 1595 kN/m) at 25 m/s on the 25 m bridge")
    fig.tight_layout()
    fig.savefig(path, dpi=110)


def two_axle_figure(o, path):
    r = traverse_io.load_for_plot(o("two_axle_car.h5"), "beam", "plot_vehicles.py")
    x = traverse_io.first_load_sigma(r)
    fig, ax = plt.subplots(1, 3, figsize=(15, 4.2))
    ax[0].plot(x, 1e3 * r.probes["midspan"])
    ax[0].set_ylabel("midspan deflection w(L/2) [mm]")
    ax[1].plot(x, 1e3 * (r.probes["car_body_displacement"] - r.probes["car_body_displacement"][0]), label="bounce z - z(0) [mm]")
    ax[1].plot(x, 1e3 * r.probes["car_pitch"], label="pitch theta [mrad]")
    ax[1].set_ylabel("body motion")
    f = r.probes["car_contact_force"]
    ax[2].plot(x, 1e-3 * f[:, 0], label="front axle")
    ax[2].plot(x, 1e-3 * f[:, 1], label="rear axle")
    ax[2].set_ylabel("contact force [kN]")
    for a in ax:
        a.set_xlabel("position of the front axle [m]")
        a.axvline(0.0, color="grey", lw=0.6)
        a.axvline(25.0, color="grey", lw=0.6)
        a.grid(alpha=0.3)
        if a.get_legend_handles_labels()[0]:
            a.legend(fontsize=8)
    fig.suptitle("two-axle car (bounce and pitch) at 25 m/s on the damped 25 m bridge")
    fig.tight_layout()
    fig.savefig(path, dpi=110)


def train_figure(o, path):
    fig, ax = plt.subplots(2, 1, figsize=(10, 6), sharex=True)
    for v in ("60", "73.6"):
        r = traverse_io.load_for_plot(o(f"axle_train_{v}.h5"), "beam", "plot_vehicles.py")
        ax[0].plot(r.time, r.probes["deck"], lw=0.8, label=f"v = {v} m/s")
        ax[1].plot(r.time, 1e3 * r.probes["midspan"], lw=0.8, label=f"v = {v} m/s")
    ax[0].set_ylabel("deck acceleration w_tt(L/2) [m/s^2]")
    ax[1].set_ylabel("midspan deflection [mm]")
    ax[1].set_xlabel("time [s]")
    for a in ax:
        a.grid(alpha=0.3)
        a.legend(fontsize=8)
    fig.suptitle(f"generic articulated train (D = 18 m): resonance at v = f1 D = {F1 * 18:.1f} m/s")
    fig.tight_layout()
    fig.savefig(path, dpi=110)


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--traverse", default="traverse")
    ap.add_argument("--out", default=".")
    ap.add_argument("--plot-only", action="store_true")
    ap.add_argument("--ranks", type=int, default=1, help="MPI ranks of the envelope's sweep")
    args = ap.parse_args()
    os.makedirs(args.out, exist_ok=True)
    o = outputs(args)
    sprung_mass_figure(o, o("vehicles_sprung_mass.png"))
    two_axle_figure(o, o("vehicles_two_axle_car.png"))
    train_figure(o, o("vehicles_axle_train.png"))
    subprocess.run([sys.executable, os.path.join(HERE, "resonance_envelope.py"), o(os.path.join("envelope", "index.csv")),
                    "--speed-key", "loads.train.speed", "--train-key", "loads.train.generator.coach_length",
                    "--f1", str(F1), "--limit", "3.5:limit 3.5 m/s^2", "--ylabel", "peak deck acceleration [m/s^2]",
                    "--title", "generic articulated trains on the 25 m bridge (2 % damping)",
                    "-o", o("vehicles_envelope.png")], check=True)


if __name__ == "__main__":
    main()
