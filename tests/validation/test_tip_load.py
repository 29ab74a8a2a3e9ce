#!/usr/bin/env python3
"""A cantilever under a load at its free tip, through the traverse executable, against the
elastica computed here by shooting (an independent solution of the same continuum problem).

    test_tip_load.py TRAVERSE_EXE SCRATCH_DIR {elastica,extensible,dynamic}

The scene rod (L = 1 m, E I = 0.1227 N m^2), clamped at s = 0 along k, free at s = L, carries
a force P along -j at sigma = L (a moving force entering at the right end, at 1e-12 m/s: it
stays there), raised from 0 by
continuation in the load magnitude to P L^2 / (E I) = 2.4 (tip rotation about 50 degrees).

elastica    Inextensible: the tip's deflection and its end shortening at ds = 0.04, 0.02, 0.01
            converge to the elastica at order 2 (within 0.3). The load's share of the end node
            acts in the free end's force rows, n(L) = F; put into the end cell instead it would
            act at L - ds/2, an error of order 1.
extensible  The same with E A = 10 P and k G A = 20 P (rod.axial_stiffness, shear_stiffness):
            stretch and shear change the tip deflection by several per cent, and the
            extensible-shearable elastica is met at order 2 (within 0.3).
dynamic     The static start under the tip load (initial_state static), run dynamically with
            the load held there, stays at rest: the dynamic end rows carry the end share as the
            static ones do (largest speed below 1e-9 m/s over 0.05 s, where the same run from
            the straight rod moves at more than 0.1 m/s).
Each prints what it measured. Exit status 0 when every check passes, 1 otherwise.
"""
import math
import os
import sys

import h5py
import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, HERE)
import cli_checks  # noqa: E402

E, RADIUS, L = 2.5e8, 0.005, 1.0
EI = E * math.pi * RADIUS ** 4 / 4.0
P = 2.4 * EI / L ** 2
MESHES = (0.04, 0.02, 0.01)

SCENE = """model: rod
title: cantilever under a tip load
gravity: 0.0
rod:
  length: {L}
  youngs_modulus: {E}
  poisson_ratio: 0.25
  density: 1500
  section: {{type: solid_circle, radius: {r}}}
{model}ends:
  left: {{type: clamped}}
  right: {{type: free}}
mesh:
  ds: 0.02
{analysis}
loads:
  F:
    type: moving_force
    force: {P!r}
    entry: right
    speed: 1.0e-12
output:
  file: tip_load.h5
"""

CONTINUATION = """initial_state:
  type: rest
continuation:
  parameter: load_magnitude
  start: 0.0
  stop: {P!r}
  step: {step!r}
  max_step: {step!r}
  method: natural
  stability: false
  switch_branches: false
  probes:
    tip_y: {{type: point, at: {L}, quantity: position, component: y}}
    tip_z: {{type: point, at: {L}, quantity: position, component: z}}"""

DYNAMIC = """initial_state:
  type: {start}
time:
  dt: 0.001
  end: 0.05"""


def elastica_tip(EA=math.inf, kGA=math.inf, steps=2000):
    """Tip (y, z) of the clamped rod under F = (0, -P) at s = L, by shooting on m(0).

    In the plane (z, y): tangent t = (cos phi, sin phi), normal d = (-sin phi, cos phi). The
    contact force is F all along (no distributed load), in body components n_t = F . t,
    n_d = F . d; the strain r' = (1 + n_t / EA) t + (n_d / kGA) d; m = E I phi' and
    m' = -(r' x F) = P r'_z; m(L) = 0 fixes m(0). RK4 in s."""
    def rhs(x):
        phi, m = x[0], x[1]
        c, s = math.cos(phi), math.sin(phi)
        nt, nd = -P * s, -P * c
        a, b = 1.0 + nt / EA, nd / kGA
        rz, ry = a * c - b * s, a * s + b * c
        return np.array([m / EI, P * rz, rz, ry])

    def shoot(m0):
        x = np.array([0.0, m0, 0.0, 0.0])
        h = L / steps
        for _ in range(steps):
            k1 = rhs(x)
            k2 = rhs(x + 0.5 * h * k1)
            k3 = rhs(x + 0.5 * h * k2)
            k4 = rhs(x + h * k3)
            x = x + h / 6.0 * (k1 + 2 * k2 + 2 * k3 + k4)
        return x

    m0, m1 = -P * L, -0.9 * P * L  # secant on m(L) = 0
    f0, f1 = shoot(m0)[1], shoot(m1)[1]
    for _ in range(60):
        if f1 == f0:
            break
        m0, m1, f0 = m1, m1 - f1 * (m1 - m0) / (f1 - f0), f1
        f1 = shoot(m1)[1]
        if abs(f1) < 1e-14 * P * L:
            break
    x = shoot(m1)
    return x[3], x[2]


def write_scene(scratch, name, model, analysis):
    path = os.path.join(scratch, name + ".yaml")
    with open(path, "w") as f:
        f.write(SCENE.format(L=L, E=E, r=RADIUS, P=P, model=model, analysis=analysis))
    return path


def tip(out):
    """The tip (y, z) at the continuation's last point (the full load)."""
    with h5py.File(out, "r") as f:
        par = f["/continuation/load_magnitude"][()]
        k = int(np.argmax(par))
        assert abs(par[k] - P) < 1e-9 * P, par
        return float(f["/continuation/tip_y"][k]), float(f["/continuation/tip_z"][k])


def orders(exe, scratch, check, name, model, reference):
    scene = write_scene(scratch, name, model, CONTINUATION.format(P=P, step=P / 8.0, L=L))
    y_ref, z_ref = reference
    print(f"  elastica: tip y = {y_ref:.9f} m, z = {z_ref:.9f} m (P = {P:.5g} N)")
    ey, ez = [], []
    for ds in MESHES:
        y, z = tip(cli_checks.run(exe, scratch, scene, f"{name}_{ds}", [f"mesh.ds={ds}"], "test_tip_load"))
        ey.append(abs(y - y_ref))
        ez.append(abs(z - z_ref))
        print(f"  ds = {ds}: tip y {y:.9f} (error {ey[-1]:.2e} = {ey[-1] / abs(y_ref):.2e} of it), "
              f"z {z:.9f} (error {ez[-1]:.2e})")
    for label, e in (("deflection", ey), ("end shortening", ez)):
        p = [math.log(e[i] / e[i + 1], 2.0) for i in range(len(e) - 1)]
        check(all(abs(q - 2.0) < 0.3 for q in p), f"{label}: orders {', '.join(f'{q:.2f}' for q in p)} (2 +- 0.3)")
    return ey


def elastica(exe, scratch, check):
    ey = orders(exe, scratch, check, "inextensible", "", elastica_tip())
    check(ey[-1] < 1e-4, f"tip deflection error at ds = 0.01: {ey[-1]:.2e} m (< 1e-4 m)")


def extensible(exe, scratch, check):
    EA, kGA = 10.0 * P, 20.0 * P
    model = f"  model: shearable\n  axial_stiffness: {EA!r}\n  shear_stiffness: {kGA!r}\n"
    ref = elastica_tip(EA, kGA)
    rigid = elastica_tip()
    change = abs(ref[0] - rigid[0]) / abs(rigid[0])
    check(change > 0.03, f"stretch and shear change the tip deflection by {100 * change:.1f} % (> 3 %)")
    orders(exe, scratch, check, "shearable", model, ref)


def dynamic(exe, scratch, check):
    for start, bound, held in (("static", 1e-9, True), ("rest", 0.1, False)):
        scene = write_scene(scratch, "dynamic_" + start, "", DYNAMIC.format(start=start))
        out = cli_checks.run(exe, scratch, scene, "dynamic_" + start, ["output.fields=[u]"], "test_tip_load")
        with h5py.File(out, "r") as f:
            speed = float(np.abs(f["/fields/u"][()]).max())
        if held:
            check(speed < bound, f"static start with the load at the tip: largest speed {speed:.2e} m/s (< {bound})")
        else:
            check(speed > bound, f"the same from the straight rod: largest speed {speed:.2e} m/s (> {bound})")


if __name__ == "__main__":
    sys.exit(cli_checks.main("test_tip_load", {"elastica": elastica, "extensible": extensible, "dynamic": dynamic},
                             sys.argv, __doc__))
