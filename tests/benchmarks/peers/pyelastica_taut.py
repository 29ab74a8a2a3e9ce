#!/usr/bin/env python3
"""The taut span of inputs/rod/taut_span_robot.yaml in PyElastica (peer benchmark, not in CI).

Scene (traverse_taut.yaml): a steel wire rope, unstretched length L = 20 m equal to the span,
A = 3.14159265e-4 m^2 (PyElastica's solid circle of radius sqrt(A / pi) = 10 mm), E = 1e11 Pa,
nu = 0.3 (G = E / (2 (1 + nu))), rho = 7850 kg/m^3, gravity 9.8 m/s^2 along -j; both ends
pinned (position fixed, rotation free: PyElastica's GeneralConstraint on the end nodes'
positions only). It sags only by stretching: 0.179 m at midspan. Stiffnesses as in traverse's
shearable rod: E A, PyElastica's shear stiffness (27/28) G A, and the scene's bending stiffness
E I with I = 7.85398e-10 m^4 (a tenth of the solid bar's) and G J with J = 2 I: PyElastica's
bend matrix (E I_solid, E I_solid, G 2 I_solid) is scaled by I / I_solid after the rod is made.
The rotary inertia stays PyElastica's, that of the solid bar (ten times traverse's rho I; it
does not show in the midspan trace, see README.md, and keeps PyElastica's time step 3 times
larger; --rotary-inertia scene scales it to traverse's). No material damping.

Two phases in one simulator (pyelastica_common.py): settle under gravity with
PyElastica's AnalyticalLinearDamper, then the damper off, at rest, and the crossing of a
vertical force F = 294 N (the 30 kg robot's weight, downwards) from s = 0 at t = 0 to s = L at
t = L / v. The settle starts from the taut string's static shape (--start parabola, the
default): the parabola of sag (3 w L^4 / (64 E A))^(1/3) with the nodes placed at equal
stretch along it, which leaves only a small correction to damp out; --start straight starts
from the straight, unstretched rod.

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

# --- the scene (traverse_taut.yaml) --------------------------------------------------------
LENGTH = 20.0
AREA = 3.14159265e-4
RADIUS = math.sqrt(AREA / math.pi)
SECOND_MOMENT = 7.85398e-10  # the scene's I (bending); PyElastica's solid bar has A^2 / (4 pi)
YOUNGS = 1.0e11
POISSON = 0.3
SHEAR_MODULUS = YOUNGS / (2.0 * (1.0 + POISSON))
DENSITY = 7850.0
GRAVITY = 9.8
FORCE = 30.0 * GRAVITY
SPEED = 10.0  # default; --speed
I_SOLID = AREA * AREA / (4.0 * math.pi)


def dt_limit(ds, i_rot=I_SOLID):
    """Estimate of Position Verlet's stability limit 2 / omega_max for this rod: an element's
    rotation, held by shear (alpha_c G A / (rho i_rot), alpha_c = 27/28, i_rot the second
    moment in the rotary inertia: PyElastica's is the solid bar's) and by bending against its
    neighbours (4 E I / ds^2 / (rho i_rot)), and the axial vibration of the nodes (4 E / (rho
    ds^2)). The first dominates up to a few hundred elements, so dt hardly changes with ds
    there."""
    omega2 = ((27.0 / 28.0) * SHEAR_MODULUS * AREA / (DENSITY * i_rot)
              + 4.0 * YOUNGS * SECOND_MOMENT / (DENSITY * i_rot * ds * ds)
              + 4.0 * YOUNGS / (DENSITY * ds * ds))
    return 2.0 / math.sqrt(omega2)


def static_sag():
    """The taut elastic string's sag at midspan: s^3 = 3 w L^4 / (64 E A)."""
    w = DENSITY * AREA * GRAVITY
    return (3.0 * w * LENGTH**4 / (64.0 * YOUNGS * AREA)) ** (1.0 / 3.0)


def parabola_start(n_elem):
    """Nodes on the parabola y = -4 sag z (L - z) / L^2 at equal arclength (equal stretch of
    every element), and directors with d3 along each element, d1 in the (j, k) plane."""
    sag = static_sag()
    z = np.linspace(0.0, LENGTH, 200001)
    slope = -4.0 * sag * (LENGTH - 2.0 * z) / LENGTH**2
    ds_arc = np.sqrt(1.0 + slope**2)
    arc = np.concatenate(([0.0], np.cumsum(0.5 * (ds_arc[1:] + ds_arc[:-1]) * np.diff(z))))
    zn = np.interp(np.linspace(0.0, arc[-1], n_elem + 1), arc, z)
    zn[0], zn[-1] = 0.0, LENGTH
    yn = -4.0 * sag * zn * (LENGTH - zn) / LENGTH**2
    pos = np.zeros((3, n_elem + 1))
    pos[1], pos[2] = yn, zn
    t = np.diff(pos, axis=1)
    t /= np.linalg.norm(t, axis=0)
    d = np.zeros((3, 3, n_elem))
    d[0, 1], d[0, 2] = t[2], -t[1]  # d1 = (0, t_z, -t_y): j on the straight rod
    d[1, 0] = -1.0                  # d2 = d3 x d1 = -i
    d[2] = t                        # d3 = t
    return pos, d


def build(n_elem, dt, damping, start="parabola", speed=SPEED, i_rot=I_SOLID):
    sim = Simulator()
    rod = straight_rod(n_elem, LENGTH, RADIUS, DENSITY, YOUNGS, SHEAR_MODULUS)
    # E I and G J of the scene: a tenth of the solid bar's (rotary inertia left as it is)
    rod.bend_matrix[...] *= SECOND_MOMENT / I_SOLID
    rod.mass_second_moment_of_inertia[...] *= i_rot / I_SOLID
    rod.inv_mass_second_moment_of_inertia[...] *= I_SOLID / i_rot
    if start == "parabola":
        pos, d = parabola_start(n_elem)
        rod.position_collection[...] = pos
        rod.director_collection[...] = d
    sim.append(rod)
    # pinned: both end nodes' positions fixed, their elements free to rotate
    sim.constrain(rod).using(ea.GeneralConstraint, constrained_position_idx=(0, -1))
    add_loads(sim, rod, GRAVITY, FORCE, speed, LENGTH, n_elem, damping, dt)
    return sim, rod


def main():
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    # damping while settling: 32 1/s settles fastest from the parabola (40 elements: 0.82 s
    # of simulated time against 0.93 s with 16 1/s, 1.7 s with 64 1/s, 1.8 s with 8 1/s)
    add_arguments(p, damping=32.0, settle_time=30.0, csv="pyelastica_taut.csv")
    p.add_argument("--speed", type=float, default=SPEED, help="speed of the force [m/s]")
    p.add_argument("--start", choices=["parabola", "straight"], default="parabola",
                   help="the settle's initial shape")
    p.add_argument("--rotary-inertia", choices=["solid", "scene"], default="solid",
                   help="rho times the solid bar's second moments (PyElastica's) or the scene's "
                        "(traverse's)")
    args = p.parse_args()
    i_rot = I_SOLID if args.rotary_inertia == "solid" else SECOND_MOMENT
    t_end = LENGTH / args.speed
    steps = crossing_steps(args, t_end, dt_limit(LENGTH / args.n_elem, i_rot), multiple=200)

    def scene(n, dt, damping):
        return build(n, dt, damping, args.start, args.speed, i_rot)

    summary = run(scene, args, t_end, steps, LENGTH)
    summary.update(speed=args.speed, start=args.start, rotary_inertia=args.rotary_inertia,
                   sag_string=static_sag())
    return report(summary)


if __name__ == "__main__":
    sys.exit(main())
