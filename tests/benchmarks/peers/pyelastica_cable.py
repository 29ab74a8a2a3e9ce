#!/usr/bin/env python3
"""The hanging cable of inputs/default.yaml in PyElastica (peer benchmark, not in CI).

Scene (traverse's default scene, the hanging cable of the scenes spec): L = 1 m, solid circle
r = 5 mm, E = 2.5e8 Pa, nu = 0.25 (G = E / (2 (1 + nu))), rho = 1500 kg/m^3, gravity 9.8 m/s^2
along -j. The cable lies along k. Left end: position and directors fixed. Right end: position
fixed in i and j, free along k; rotation prevented (PyElastica's GeneralConstraint with the
translational selector (True, True, False) and all rotations constrained).

Two phases in one simulator (pyelastica_common.py): settle under gravity with
PyElastica's AnalyticalLinearDamper, then the damper off, at rest, and the crossing of a
vertical force F = 2 N (downwards) from s = 0 at t = 0 to s = L at t = L / v, v = 3.63418 m/s.

Writes a CSV of the midspan height y(L/2, t) over the crossing and prints a JSON summary with
the CPU times (time.process_time) of the JIT warm-up, the settle phase and the crossing phase.
"""

import argparse
import math
import sys

import numpy as np

import elastica as ea

from pyelastica_common import (Simulator, add_arguments, add_loads, straight_rod,
                               crossing_steps, report, run)

# --- the scene (inputs/default.yaml) ---------------------------------------------------
LENGTH = 1.0
RADIUS = 0.005
YOUNGS = 2.5e8
POISSON = 0.25
DENSITY = 1500.0
GRAVITY = 9.8
FORCE = 2.0
SPEED = 3.63418
T_END = LENGTH / SPEED


def dt_limit(ds):
    """Estimate of Position Verlet's stability limit 2 / omega_max for this rod: the fastest
    mode is an element's rotation, held by shear (alpha_c G A / (rho I), alpha_c = 27/28 in
    PyElastica) and by bending against its neighbours (about 4 E I / ds^2 / (rho I)).
    Measured (crossing + settle): 200 elements stable at dt = 0.94 x this, unstable at
    1.0 x; 100 elements stable at 0.90 x, unstable at 0.955 x."""
    G = YOUNGS / (2.0 * (1.0 + POISSON))
    area = math.pi * RADIUS**2
    inertia = area * RADIUS**2 / 4.0
    omega2 = (27.0 / 28.0) * G * area / (DENSITY * inertia) + 4.0 * YOUNGS / (DENSITY * ds * ds)
    return 2.0 / math.sqrt(omega2)


def build(n_elem, dt, damping):
    sim = Simulator()
    rod = straight_rod(n_elem, LENGTH, RADIUS, DENSITY, YOUNGS, YOUNGS / (2.0 * (1.0 + POISSON)))
    sim.append(rod)
    sim.constrain(rod).using(
        ea.GeneralConstraint,
        constrained_position_idx=(0,),
        constrained_director_idx=(0,),
    )
    sim.constrain(rod).using(
        ea.GeneralConstraint,
        constrained_position_idx=(-1,),
        constrained_director_idx=(-1,),
        translational_constraint_selector=np.array([True, True, False]),
        rotational_constraint_selector=np.array([True, True, True]),
    )
    add_loads(sim, rod, GRAVITY, FORCE, SPEED, LENGTH, n_elem, damping, dt)
    return sim, rod


def main():
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    # damping while settling: 2 omega1 (about critical for the first mode)
    add_arguments(p, damping=2.0 * 22.834, settle_time=2.0, csv="pyelastica_cable.csv")
    args = p.parse_args()
    steps = crossing_steps(args, T_END, dt_limit(LENGTH / args.n_elem))
    return report(run(build, args, T_END, steps, LENGTH))


if __name__ == "__main__":
    sys.exit(main())
