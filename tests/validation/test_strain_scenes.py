#!/usr/bin/env python3
"""The extensible and shearable reference scenes (inputs/rod/taut_span_robot.yaml,
elastic_catenary_load.yaml, rubber_cantilever_mass.yaml; docs/results.md) run through the
traverse executable on coarser meshes (--set), checked against closed forms and against each
other with postprocessing/plot_strained_rod.py (the code their figures use).

    test_strain_scenes.py TRAVERSE_EXE SCRATCH_DIR {taut,catenary,rubber,stiff}

taut      The static start's midspan sag is the taut elastic string's
          s^3 = 3 w L^4 / (64 E A) within 1 %; with E A x 8 it halves (within 1 %): the sag
          comes from the stretch alone. The robot crosses (the event left_rod_at_L) and its
          weight deepens the midspan sag by more than 20 %. The axial damping makes the
          step-to-step oscillation of the stretch decay: after 2 s it is below a tenth of the
          same run's without damping.
catenary  The static start is Irvine's elastic catenary: midspan sag within 1e-3, every node
          within 2e-3 of the sag of the catenary's point at its arclength (ds = 0.1; the error
          is of order 2 in ds), where the taut string's parabola misses the sag by more than
          2 %; the force crosses (the run completes at t = 10.5 s) and lowers the midspan by
          more than 0.4 m.
stiff     The hanging cable (inputs/default.yaml) and the coupled bead on it, as shearable rods
          with E A and k G A x 1e8: r and n within 1e-6 of the inextensible runs' largest
          values, the bead's position within 1e-6 m.
rubber    The tip height history of the shearable rubber cantilever against the same scene
          inextensible: E A, k G A x 1e6 differs from it by less than 1e-5 of the largest tip
          deflection, the rubber by more than 2 % (deflecting more).
Each prints what it measured. Exit status 0 when every check passes, 1 otherwise.
"""
import os
import sys

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.normpath(os.path.join(HERE, "..", ".."))
sys.path.insert(0, os.path.join(ROOT, "postprocessing"))
import plot_strained_rod as strained  # noqa: E402
import traverse_io  # noqa: E402

import cli_checks  # noqa: E402

import numpy as np  # noqa: E402

ROD = os.path.join(ROOT, "inputs", "rod")


def run(exe, scratch, scene, name, sets):
    return traverse_io.load(cli_checks.run(exe, scratch, os.path.join(ROD, scene), name, sets, "test_strain_scenes"))


def two_step_oscillation(field, t, after):
    """The largest |f(t + dt) - 2 f(t) + f(t - dt)| over the nodes and the steps after `after`."""
    d2 = np.abs(field[2:] - 2.0 * field[1:-1] + field[:-2]).max(axis=1)
    return float(d2[t[1:-1] > after].max())


def taut(exe, scratch, check):
    # The static start on the scene's mesh (ds = 0.1), the crossing on a coarser one.
    coarse = ["mesh.ds=0.5"]
    start = run(exe, scratch, "taut_span_robot.yaml", "taut_static", ["time.end=0.02"])
    p = strained.rod_properties(start)
    s_cf = strained.taut_string_sag(p["w"], p["L"], p["EA"])
    s = strained.static_midspan_sag(start)
    print(f"  E A = {p['EA']:.4g} N, w = {p['w']:.4g} N/m, L = {p['L']:g} m, E I = {p['EI']:.3g} N m^2; "
          f"bending's share of the sag about 8 E I / (H L^2) = {8 * p['EI'] * 8 * s_cf / (p['w'] * p['L'] ** 4):.1e}")
    # Tolerance 1 %: the closed form drops terms of order (s / L)^2 = 1e-4 and the bending
    # stiffness (2e-4); the robot's weight at the pinned left end enters the first cell's
    # balance, an error of order ds (6e-4 at ds = 0.1, 3e-3 at 0.25, 9e-3 at 0.5).
    check(abs(s / s_cf - 1.0) < 0.01, f"static midspan sag {s:.5f} m, taut string {s_cf:.5f} m "
          f"(relative {s / s_cf - 1.0:+.2e}, allowed 1e-2)")
    stiff = run(exe, scratch, "taut_span_robot.yaml", "taut_static_EAx8",
                ["time.end=0.02", f"rod.axial_stiffness={8.0 * p['EA']!r}"])
    ratio = strained.static_midspan_sag(stiff) / s
    check(abs(ratio - 0.5) < 0.005, f"E A x 8: sag ratio {ratio:.5f} (s ~ (E A)^(-1/3): 0.5, allowed +- 0.005)")
    full = run(exe, scratch, "taut_span_robot.yaml", "taut_run", coarse + ["output.every=1"])
    nodamp = run(exe, scratch, "taut_span_robot.yaml", "taut_run_undamped",
                 coarse + ["output.every=1", "rod.damping.axial=0", "time.end=3"])
    reason = traverse_io._text(full.attrs.get("end_reason", ""))
    sigma = full.probes["robot_position"]
    check("left_rod_at_L" in reason and sigma[-1] >= p["L"] - 1e-9,
          f"the robot crosses: end reason '{reason}', last position {sigma[-1]:.4f} m at t = {full.time[-1]:.2f} s")
    deepest = -float(full.probes["midspan"][:, 1].min())
    check(deepest > 1.2 * s, f"deepest midspan sag with the robot {deepest:.4f} m (static {s:.4f} m; more than 1.2 x)")
    n = len(nodamp.time)
    damped = two_step_oscillation(full.field("stretch")[:n], full.time[:n], 2.0)
    undamped = two_step_oscillation(nodamp.field("stretch"), nodamp.time, 2.0)
    first = two_step_oscillation(full.field("stretch")[:4], full.time[:4], -1.0)
    print(f"  two-step oscillation of the stretch: first steps {first:.2e}; after t = 2 s {damped:.2e} "
          f"with rod.damping.axial, {undamped:.2e} without")
    check(damped < 0.1 * undamped, "after 2 s the damped rope's stretch oscillates less than a tenth of the undamped's")


def catenary(exe, scratch, check):
    ds = 0.1
    out = run(exe, scratch, "elastic_catenary_load.yaml", "catenary", [f"mesh.ds={ds}"])
    p = strained.rod_properties(out)
    cat = strained.catenary_of(out)
    sag, s = cat.sag(), strained.static_midspan_sag(out)
    parab = strained.taut_string_sag(p["w"], p["L"], p["EA"])
    print(f"  E A = {p['EA']:.4g} N, weight {p['w'] * p['L']:.4g} N, H = {cat.H:.4g} N (strain {cat.H / p['EA']:.3f}), "
          f"sag / span {sag / p['L']:.3f}")
    # Tolerances from the mesh: the static error is of order 2 in ds; measured 8e-5 of the
    # sag at ds = 0.1 (2e-5 at 0.05), everywhere largest at midspan.
    check(abs(s / sag - 1.0) < 1e-3, f"static midspan sag {s:.5f} m, Irvine {sag:.5f} m "
          f"(relative {s / sag - 1.0:+.2e}, allowed 1e-3)")
    r = out.field("r", 0)
    err = np.hypot(r[:, 2] - cat.x(out.s), r[:, 1] + cat.z(out.s)).max() / sag
    check(err < 2e-3, f"every node within {err:.2e} of the sag of Irvine's point at its arclength (allowed 2e-3)")
    check(abs(parab / sag - 1.0) > 0.02, f"the taut string's parabola misses: sag {parab:.4f} m "
          f"({parab / sag - 1.0:+.3f}): the check tells the elastic catenary from it")
    status = traverse_io._text(out.attrs.get("status", ""))
    check(status == "complete" and abs(out.time[-1] - 10.5) < 1e-9,
          f"the run completes: status '{status}', t = {out.time[-1]:.3f} s (the force leaves at 10.5 s)")
    low = -float(out.probes["midspan"][:, 1].min())
    check(low > sag + 0.4, f"the force lowers the midspan to {low:.3f} m (static {sag:.3f} m; by more than 0.4 m)")


def rubber(exe, scratch, check):
    coarse = ["mesh.ds=0.00625"]
    sh = run(exe, scratch, "rubber_cantilever_mass.yaml", "rubber_shearable", coarse)
    p = strained.rod_properties(sh)
    ie = run(exe, scratch, "rubber_cantilever_mass.yaml", "rubber_inextensible", coarse + ["rod.model=inextensible"])
    st = run(exe, scratch, "rubber_cantilever_mass.yaml", "rubber_stiff",
             coarse + [f"rod.axial_stiffness={1e6 * p['EA']!r}", f"rod.shear_stiffness={1e6 * p['kGA']!r}"])
    y = {k: o.probes["tip"][:, 1] for k, o in (("sh", sh), ("ie", ie), ("st", st))}
    check(len(y["sh"]) == len(y["ie"]) == len(y["st"]), f"the three runs have {len(y['sh'])} output steps each")
    ref = float(np.abs(y["ie"]).max())
    d_st = float(np.abs(y["st"] - y["ie"]).max()) / ref
    d_sh = float(np.abs(y["sh"] - y["ie"]).max()) / ref
    final = y["sh"][-1] / y["ie"][-1] - 1.0
    print(f"  E A = {p['EA']:.4g} N, k G A = {p['kGA']:.4g} N, E I = {p['EI']:.4g} N m^2; largest tip deflection "
          f"{1e3 * ref:.2f} mm inextensible, {-1e3 * y['sh'].min():.2f} mm shearable")
    check(d_st < 1e-5, f"E A, k G A x 1e6: largest tip difference {d_st:.2e} of the largest deflection (allowed 1e-5)")
    check(d_sh > 0.02 and final > 0.02, f"shearable rubber: largest tip difference {d_sh:.4f} of the largest deflection, "
          f"{final:+.4f} when the mass reaches the tip (more than 0.02, deflecting more)")


def stiff(exe, scratch, check):
    # The shipped inextensible scenes as shearable rods with E A and k G A x 1e8: the hanging
    # cable (a moving force) and the bead on it (a coupled mass, its position an unknown).
    for scene, name, sets in ((os.path.join(ROOT, "inputs", "default.yaml"), "cable", ["mesh.ds=0.02"]),
                              (os.path.join(ROD, "coupled_bead_cable.yaml"), "bead", ["time.end=0.3"])):
        fields = ["output.fields=[r,n]"]
        ie = traverse_io.load(cli_checks.run(exe, scratch, scene, name + "_inextensible", sets + fields,
                                             "test_strain_scenes"))
        p = strained.rod_properties(ie)
        EA, kGA = p["EA"], 0.4 * p["EA"]
        st = traverse_io.load(cli_checks.run(
            exe, scratch, scene, name + "_stiff",
            sets + fields + ["rod.model=shearable", f"rod.axial_stiffness={1e8 * EA!r}",
                             f"rod.shear_stiffness={1e8 * kGA!r}"], "test_strain_scenes"))
        check(len(ie.time) == len(st.time), f"{name}: {len(ie.time)} and {len(st.time)} output steps")
        for f in ("r", "n"):
            a, b = ie.field(f), st.field(f)
            d = float(np.abs(a - b).max() / np.abs(a).max())
            check(d < 1e-6, f"{name}: E A, k G A x 1e8 against the inextensible rod: {f} {d:.2e} of its largest "
                  "(allowed 1e-6)")
        if name == "bead":
            a, b = ie.sigma, st.sigma
            d = float(np.abs(a - b).max())
            check(d < 1e-6, f"bead: its position differs by {d:.2e} m (allowed 1e-6)")


if __name__ == "__main__":
    sys.exit(cli_checks.main("test_strain_scenes", {"taut": taut, "catenary": catenary, "rubber": rubber,
                                                    "stiff": stiff}, sys.argv, __doc__))
