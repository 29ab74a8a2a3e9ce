"""What the PyElastica peer scenes share (pyelastica_cable.py, pyelastica_taut.py; not in CI).

A scene is a rod in one PyElastica simulator, run in two phases:
1. settle: the dead loads only, PyElastica's AnalyticalLinearDamper (uniform damping constant)
   on, until the rod is at rest (or --settle-time); then the damper is switched off and all
   velocities are set to zero (traverse starts from the static state, at rest);
2. crossing: a vertical force (downwards, along -j) moving from s = 0 at t = 0 to s = L at
   t = L / v, applied as external nodal forces on the two nodes around the load position with
   linear weights. Position Verlet, fixed dt.

run() writes a CSV of the midspan height y(L/2, t) over the crossing (every --record-every
steps, and at the end) and returns the JSON summary with the CPU times (time.process_time) of
the JIT warm-up, the settle phase and the crossing phase.
"""

import json
import math
import time as wallclock

import numpy as np

import elastica as ea


class Simulator(ea.BaseSystemCollection, ea.Constraints, ea.Forcing, ea.Damping):
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


def straight_rod(n_elem, length, radius, density, youngs, shear_modulus):
    """PyElastica's straight rod from the origin along k, normal j."""
    return ea.CosseratRod.straight_rod(n_elem, np.zeros(3), np.array([0.0, 0.0, 1.0]), np.array([0.0, 1.0, 0.0]),
                                       length, radius, density, youngs_modulus=youngs, shear_modulus=shear_modulus)


def add_loads(sim, rod, gravity, force, speed, length, n_elem, damping, dt):
    """Gravity along -j, the moving force and the switchable damper on `rod`; finalizes `sim`."""
    sim.add_forcing_to(rod).using(ea.GravityForces, acc_gravity=np.array([0.0, -gravity, 0.0]))
    sim.add_forcing_to(rod).using(MovingPointForce, force=force, speed=speed, length=length, n_elem=n_elem)
    sim.dampen(rod).using(SwitchableDamper, uniform_damping_constant=damping, time_step=dt)
    sim.finalize()


def add_arguments(p, damping, settle_time, csv):
    """The command-line options every scene has (defaults: the scene's)."""
    p.add_argument("--n-elem", type=int, default=200)
    p.add_argument(
        "--steps",
        type=int,
        default=0,
        help="time steps of the crossing (default: from --safety, rounded up to a multiple of "
        "50, of 200 for the taut span)",
    )
    p.add_argument(
        "--safety",
        type=float,
        default=0.9,
        help="dt = safety * 2 / omega_max unless --steps is given (see the scene's dt_limit)",
    )
    p.add_argument(
        "--damping",
        type=float,
        default=damping,
        help="uniform damping constant while settling [1/s]",
    )
    p.add_argument("--settle-time", type=float, default=settle_time, help="upper bound [s]")
    p.add_argument(
        "--settle-tol",
        type=float,
        default=1e-6,
        help="settled when max |u| < tol [m/s] (checked every 1000 steps)",
    )
    p.add_argument("--record-every", type=int, default=1)
    p.add_argument("--csv", default=csv)


def crossing_steps(args, t_end, dt_limit, multiple=50):
    """The crossing's step count: --steps, or from --safety rounded up to a multiple of
    `multiple` (so that the times k t_end / multiple are step times)."""
    if args.steps > 0:
        return args.steps
    return multiple * math.ceil(t_end / (args.safety * dt_limit) / multiple)


def run(build, args, t_end, steps, length):
    """Warm up, settle, cross; write args.csv; return the summary (a dict).

    build(n_elem, dt, damping) -> (simulator, rod): a fresh simulator, finalised, with a
    SwitchableDamper and a MovingPointForce."""
    n = args.n_elem
    dt = t_end / steps
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

    # Phase 1: settle under the dead loads with damping.
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
    slide_static = float(pos[2, -1] - length)

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
    return {
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


def report(summary):
    """Print the summary as one JSON line; the exit code (1 if the run blew up)."""
    print(json.dumps(summary))
    return 0 if summary["finite"] else 1
