#!/usr/bin/env python3
"""The hanging cable of inputs/default.yaml in PyElastica (peer benchmark, not in CI).

Scene (traverse's default scene, the hanging cable of the scenes spec): L = 1 m, solid circle
r = 5 mm, E = 2.5e8 Pa, nu = 0.25 (G = E / (2 (1 + nu))), rho = 1500 kg/m^3, gravity 9.8 m/s^2
along -j. The cable lies along k. Left end: position and directors fixed. Right end: position
fixed in i and j, free along k; rotation prevented (PyElastica's GeneralConstraint with the
translational selector (True, True, False) and all rotations constrained).

Two phases in one simulator:
1. settle: gravity only, PyElastica's AnalyticalLinearDamper (uniform damping constant) on,
   until the rod is at rest (or --settle-time); then the damper is switched off and all
   velocities are set to zero (traverse starts from the static state, at rest);
2. crossing: a vertical force F = 2 N (downwards) moving from s = 0 at t = 0 to s = L at
   t = L / v, v = 3.63418 m/s, applied as external nodal forces on the two nodes around the
   load position with linear weights. Position Verlet, fixed dt.

Writes a CSV of the midspan height y(L/2, t) over the crossing (every --record-every steps,
and at the end) and prints a JSON summary with the CPU times (time.process_time) of the
JIT warm-up, the settle phase and the crossing phase.
"""

import argparse
import json
import math
import sys
import time as wallclock

import numpy as np

import elastica as ea

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


class CableSimulator(ea.BaseSystemCollection, ea.Constraints, ea.Forcing, ea.Damping):
    pass


class SwitchableDamper(ea.AnalyticalLinearDamper):
    """PyElastica's analytical linear damper with an on/off switch (on while settling)."""

    active = True

    def dampen_rates(self, system, time):
        if SwitchableDamper.active:
            super().dampen_rates(system, time)


class MovingPointForce(ea.NoForces):
    """A vertical force moving at constant speed along the rod, shared by the two nodes
    around the load position with linear weights. Off while `active` is False."""

    active = False

    def __init__(self, force, speed, length, n_elem):
        super().__init__()
        self.force = force
        self.speed = speed
        self.length = length
        self.n_elem = n_elem

    def apply_forces(self, system, time=np.float64(0.0)):
        if not MovingPointForce.active:
            return
        s = self.speed * time
        if s < 0.0 or s > self.length:
            return
        x = s / self.length * self.n_elem
        i = min(int(math.floor(x)), self.n_elem - 1)
        w = x - i
        system.external_forces[1, i] -= (1.0 - w) * self.force
        system.external_forces[1, i + 1] -= w * self.force


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
    sim = CableSimulator()
    rod = ea.CosseratRod.straight_rod(
        n_elem,
        np.zeros(3),
        np.array([0.0, 0.0, 1.0]),  # direction (k)
        np.array([0.0, 1.0, 0.0]),  # normal (j)
        LENGTH,
        RADIUS,
        DENSITY,
        youngs_modulus=YOUNGS,
        shear_modulus=YOUNGS / (2.0 * (1.0 + POISSON)),
    )
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
    sim.add_forcing_to(rod).using(
        ea.GravityForces, acc_gravity=np.array([0.0, -GRAVITY, 0.0])
    )
    sim.add_forcing_to(rod).using(
        MovingPointForce, force=FORCE, speed=SPEED, length=LENGTH, n_elem=n_elem
    )
    sim.dampen(rod).using(
        SwitchableDamper, uniform_damping_constant=damping, time_step=dt
    )
    sim.finalize()
    return sim, rod


def main():
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--n-elem", type=int, default=200)
    p.add_argument(
        "--steps",
        type=int,
        default=0,
        help="time steps of the crossing (default: from --safety, rounded up to a multiple of 50)",
    )
    p.add_argument(
        "--safety",
        type=float,
        default=0.9,
        help="dt = safety * 2 / omega_max unless --steps is given (see dt_limit)",
    )
    p.add_argument(
        "--damping",
        type=float,
        default=2.0 * 22.834,
        help="uniform damping constant while settling [1/s] (default: 2 omega1)",
    )
    p.add_argument("--settle-time", type=float, default=2.0, help="upper bound [s]")
    p.add_argument(
        "--settle-tol",
        type=float,
        default=1e-6,
        help="settled when max |u| < tol [m/s] (checked every 1000 steps)",
    )
    p.add_argument("--record-every", type=int, default=1)
    p.add_argument("--csv", default="pyelastica_cable.csv")
    args = p.parse_args()

    n = args.n_elem
    ds = LENGTH / n
    if args.steps > 0:
        steps = args.steps
    else:
        steps = 50 * math.ceil(T_END / (args.safety * dt_limit(ds)) / 50)
    dt = T_END / steps
    mid = n // 2
    assert n % 2 == 0, "need a node at midspan"

    # JIT warm-up (numba compiles, or loads its cache, on the first calls): a throw-away
    # copy of the scene, a few steps in both phases.
    stepper = ea.PositionVerlet()
    c0 = wallclock.process_time()
    w0 = wallclock.perf_counter()
    sim, rod = build(n, dt, args.damping)
    t = 0.0
    for _ in range(5):
        t = stepper.step(sim, t, dt)
    MovingPointForce.active, SwitchableDamper.active = True, False
    for _ in range(5):
        t = stepper.step(sim, t, dt)
    MovingPointForce.active, SwitchableDamper.active = False, True
    jit_cpu = wallclock.process_time() - c0
    jit_wall = wallclock.perf_counter() - w0

    # The real run (set-up outside the timed loops).
    sim, rod = build(n, dt, args.damping)
    pos = rod.position_collection
    vel = rod.velocity_collection

    # Phase 1: settle under gravity with damping.
    c0 = wallclock.process_time()
    t = 0.0
    settle_steps = 0
    max_settle = int(math.ceil(args.settle_time / dt))
    umax = float("nan")
    while settle_steps < max_settle:
        t = stepper.step(sim, t, dt)
        settle_steps += 1
        if settle_steps % 1000 == 0:
            umax = float(np.abs(vel).max())
            if umax < args.settle_tol:
                break
    settle_cpu = wallclock.process_time() - c0
    umax = float(np.abs(vel).max())
    y_static = float(pos[1, mid])
    slide_static = float(pos[2, -1] - LENGTH)

    # Switch: damper off, at rest, load on, clock at 0.
    SwitchableDamper.active = False
    MovingPointForce.active = True
    rod.velocity_collection[...] = 0.0
    rod.omega_collection[...] = 0.0

    # Phase 2: the crossing.
    times = [0.0]
    ys = [y_static]
    c0 = wallclock.process_time()
    t = 0.0
    rec = args.record_every
    for k in range(1, steps + 1):
        t = stepper.step(sim, t, dt)
        if k % rec == 0 or k == steps:
            times.append(t)
            ys.append(pos[1, mid])
    cross_cpu = wallclock.process_time() - c0
    ok = bool(np.all(np.isfinite(pos)))

    with open(args.csv, "w") as f:
        f.write("t,y_mid\n")
        for a, b in zip(times, ys):
            f.write(f"{a:.17g},{float(b):.17g}\n")

    ys_arr = np.array(ys, dtype=float)
    summary = {
        "code": "PyElastica",
        "n_elem": n,
        "dt": dt,
        "steps_crossing": steps,
        "steps_settle": settle_steps,
        "settle_time": settle_steps * dt,
        "settle_umax": umax,
        "damping": args.damping,
        "y_static": y_static,
        "slide_static": slide_static,
        "y_min": float(ys_arr.min()) if ok else None,
        "finite": ok,
        "cpu_jit_warmup": jit_cpu,
        "wall_jit_warmup": jit_wall,
        "cpu_settle": settle_cpu,
        "cpu_crossing": cross_cpu,
        "cpu_computing": settle_cpu + cross_cpu,
        "csv": args.csv,
    }
    print(json.dumps(summary))
    return 0 if ok else 1


if __name__ == "__main__":
    sys.exit(main())
