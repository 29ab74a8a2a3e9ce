#!/usr/bin/env python3
"""Figures of the extensible and shearable rod scenes (docs/results.md, "Extensible and
shearable rods"), with the closed forms they are checked against:

  taut RUN.h5        a taut span whose unstretched length is the span (inputs/rod/
                     taut_span_robot.yaml): the shapes with the coupled mass marked, y
                     exaggerated; the midspan and the mass's height against the mass's
                     position, with the taut elastic string's static sag
                     s^3 = 3 w L^4 / (64 E A); the strain |r_s| - 1 along the span.
  catenary RUN.h5    an elastic catenary crossed by a load (inputs/rod/
                     elastic_catenary_load.yaml): the static shape against Irvine's elastic
                     catenary and the taut string's parabola, loaded shapes; the midspan height
                     against the load position; the stretch along the cable.
  cantilever RUN.h5 (INEXTENSIBLE.h5 STIFF.h5 | --traverse EXE)
                     a shearable cantilever under a moving mass (inputs/rod/
                     rubber_cantilever_mass.yaml) against the same scene run inextensible and
                     with E A and k G A x 1e6: shapes, the tip height against the load position,
                     the tip differences. With --traverse the two companions are run from the
                     scene stored in RUN.h5, next to it (RUN_inextensible.h5, RUN_stiff.h5).

Usage: plot_strained_rod.py {taut,catenary,cantilever} RUN.h5 [...] [-o FIGURE.png]
The titles give the values the runs used (their stored scenes). Exits with status 2 and a
message when a file is not a complete rod run with what the figure needs.
"""
import argparse
import math
import os
import subprocess
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import traverse_io  # noqa: E402

STIFF = 1e6  # the stiff limit: E A and k G A times this
STIFF_TEXT = "1e6"


# ---------------------------------------------------------------------------------------
# The rod's properties from the scene a run used, and the closed forms.
# ---------------------------------------------------------------------------------------
def rod_properties(run):
    """dict of the run's rod: length L, model, E, G, rho, A, I (bending in the (y, z) plane),
    EA, kGA (shearable; None otherwise), EI, w (weight per unstretched length, N/m), g."""
    sc = traverse_io.scene_values(run)
    rod, sec = sc["rod"], sc["rod"]["section"]
    E, nu = float(rod["youngs_modulus"]), rod.get("poisson_ratio")
    G = float(rod["shear_modulus"]) if "shear_modulus" in rod else E / (2.0 * (1.0 + float(nu)))
    nu = E / (2.0 * G) - 1.0
    kind = sec["type"]
    if kind == "solid_circle":
        r = float(sec["radius"])
        A, I, k = math.pi * r**2, math.pi * r**4 / 4.0, 6.0 * (1.0 + nu) / (7.0 + 6.0 * nu)
    elif kind == "hollow_circle":
        ro, ri = float(sec["outer_radius"]), float(sec["inner_radius"])
        A, I, m = math.pi * (ro**2 - ri**2), math.pi * (ro**4 - ri**4) / 4.0, ri / ro
        q = (1.0 + m * m) ** 2
        k = 6.0 * (1.0 + nu) * q / ((7.0 + 6.0 * nu) * q + (20.0 + 12.0 * nu) * m * m)
    elif kind == "rectangle":
        b, h = float(sec["width"]), float(sec["height"])
        A, I, k = b * h, b * h**3 / 12.0, 10.0 * (1.0 + nu) / (12.0 + 11.0 * nu)
    else:  # properties
        A, I, k = float(sec["area"]), float(sec["second_moment"]), None
    k = float(rod["shear_coefficient"]) if "shear_coefficient" in rod else k
    model = str(rod.get("model", "inextensible"))
    EA = float(rod.get("axial_stiffness", E * A))
    kGA = float(rod.get("shear_stiffness", k * G * A if k else float("nan"))) if model == "shearable" else None
    g = float(sc.get("gravity", 9.8))
    return dict(L=float(rod["length"]), model=model, E=E, G=G, rho=float(rod["density"]), A=A, I=I,
                EA=EA, kGA=kGA, EI=E * I, w=float(rod["density"]) * A * g, g=g)


def taut_string_sag(w, L, EA):
    """Midspan sag of a taut elastic string whose unstretched length is its span L, under its
    weight w per length: the parabola's extra length 8 s^2 / (3 L) equals the stretch
    H L / (E A) with H = w L^2 / (8 s), so s^3 = 3 w L^4 / (64 E A) (s << L, no bending)."""
    return (3.0 * w * L**4 / (64.0 * EA)) ** (1.0 / 3.0)


class ElasticCatenary:
    """Irvine's elastic catenary: a cable of unstretched length L0 and weight W, ends at the
    same height a span l apart, horizontal tension H, end reactions V = W / 2. Along the
    unstretched arclength s0, x the horizontal distance and z the drop below the ends:
      x(s0) = H s0 / (E A) + (H L0 / W) [asinh(V / H) - asinh((V - W s0 / L0) / H)]
      z(s0) = (W s0 / (E A)) (V / W - s0 / (2 L0))
              + (H L0 / W) [sqrt(1 + (V / H)^2) - sqrt(1 + ((V - W s0 / L0) / H)^2)]
    with H from x(L0) = l (the formulas of tests/rod/test_rod_strain.cpp)."""

    def __init__(self, L0, span, EA, W):
        self.L0, self.l, self.EA, self.W = L0, span, EA, W
        lo, hi = 1e-6 * W, 1e6 * W
        for _ in range(200):  # x(L0) grows with H
            self.H = math.sqrt(lo * hi)
            if self.x(L0) < span:
                lo = self.H
            else:
                hi = self.H
        self.H = math.sqrt(lo * hi)

    def x(self, s0):
        V, W, H, L0 = 0.5 * self.W, self.W, self.H, self.L0
        return H * s0 / self.EA + H * L0 / W * (np.arcsinh(V / H) - np.arcsinh((V - W * s0 / L0) / H))

    def z(self, s0):
        V, W, H, L0 = 0.5 * self.W, self.W, self.H, self.L0
        a, b = V / H, (V - W * s0 / L0) / H
        return W * s0 / self.EA * (V / W - s0 / (2.0 * L0)) + H * L0 / W * (np.sqrt(1.0 + a * a) - np.sqrt(1.0 + b * b))

    def sag(self):
        return float(self.z(0.5 * self.L0))

    def stretch(self, s0):
        """|r_s| = 1 + T / (E A), T the tension at s0."""
        V, W = 0.5 * self.W, self.W
        return 1.0 + np.hypot(self.H, V - W * s0 / self.L0) / self.EA


def catenary_of(run):
    """The elastic catenary of a run's rod between its pinned ends (span = unstretched length)."""
    p = rod_properties(run)
    return ElasticCatenary(p["L"], p["L"], p["EA"], p["w"] * p["L"])


def static_midspan_sag(run, probe="midspan"):
    """The sag -y of the probe at the first output step (the static start)."""
    return -float(run.probes[probe][0, 1])


def stiffness_text(run, p):
    """The rod's model, stiffnesses, weight and damping, and what the run title leaves out of
    its coupled masses (drive, resistance)."""
    text = f"{p['model']}, E A = {p['EA']:.3g} N"
    if p["kGA"] is not None:
        text += f", k G A = {p['kGA']:.3g} N"
    text += f", E I = {p['EI']:.3g} N m^2, w = {p['w']:.3g} N/m"
    sc = traverse_io.scene_values(run)
    damping = sc["rod"].get("damping", {})
    units = {"axial": "N s", "shear": "N s", "bending": "N m^2 s", "torsion": "N m^2 s"}
    text += "".join(f", {k} damping {float(v):.3g} {units[k]}" for k, v in damping.items() if float(v) > 0.0)
    for name, load in sc.get("loads", {}).items():
        if load.get("type") == "coupled_mass":
            text += f"; '{name}': drive {float(load.get('drive', 0.0)):.3g} N, resistance {float(load.get('resistance', 0.0)):.3g} N s/m"
    return text


# ---------------------------------------------------------------------------------------
# Figures.
# ---------------------------------------------------------------------------------------
def _load(path, need_fields=("r",)):
    run = traverse_io.load_for_plot(path, "rod", "plot_strained_rod")
    for f in need_fields:
        if f not in run.field_names:
            traverse_io._exit_with(f"plot_strained_rod: {path} has no field '{f}' (output.fields)")
    return run


def _steps_at(sigma, targets):
    """Output steps where the load is nearest each target position, each step once (none
    without a load on the structure)."""
    out = []
    for target in targets:
        if np.any(np.isfinite(sigma)):
            j = int(np.nanargmin(np.abs(sigma - target)))
            if j not in out:
                out.append(j)
    return out


def figure_taut(path):
    run = _load(path, ("r", "stretch"))
    p = rod_properties(run)
    traverse_io.require_probe(run, "midspan", "plot_strained_rod")
    names = sorted(n[: -len("_fixed_position")] for n in run.probes if n.endswith("_fixed_position"))
    name = names[0] if names else None  # a coupled mass
    L, s0 = p["L"], taut_string_sag(p["w"], p["L"], p["EA"])
    t, r, st = run.time, run.field("r"), run.field("stretch")
    sigma = run.probes[name + "_position"] if name else traverse_io.first_load_sigma(run)
    steps = [0] + [j for j in _steps_at(sigma, [0.25 * L, 0.5 * L, 0.75 * L]) if j != 0]
    fig = plt.figure(figsize=(13, 8))
    gs = fig.add_gridspec(2, 2, height_ratios=[1.0, 1.15])
    ax0 = fig.add_subplot(gs[0, :])
    k = traverse_io.exaggeration(r[steps, :, 1], L)
    z = np.linspace(0.0, L, 201)
    for j in steps:
        what = "static start" if j == 0 else f"'{name}' at {sigma[j]:.1f} m" if name else f"load at {sigma[j]:.1f} m"
        line, = ax0.plot(r[j, :, 2], k * r[j, :, 1], label=f"t = {t[j]:.1f} s: {what}")
        if name:
            q = run.probes[name + "_fixed_position"][j]
            ax0.plot(q[2], k * q[1], "o", color=line.get_color())
    ax0.plot(z, -k * 4.0 * s0 * z * (L - z) / L**2, "k--", lw=1, zorder=3,
             label=f"taut string's parabola, static: sag {s0:.4f} m")
    ax0.axhline(0.0, color="0.6", lw=0.8)
    ax0.set_xlabel("z [m]")
    ax0.set_ylabel("y [m]" if k == 1.0 else f"y, exaggerated x {k:g} [m]")
    ax0.set_title("shapes" + ("" if name is None else f", '{name}' marked") + ("" if k == 1.0 else
                  f"; vertical displacement exaggerated {k:g} times (the straight line: the span)"), fontsize=10)
    ax0.legend(fontsize=8, ncol=3, loc="upper center")
    ax0.set_ylim(top=0.35 * k * float(np.abs(r[steps, :, 1]).max()))  # room for the legend
    ax1 = fig.add_subplot(gs[1, 0])
    ax1.plot(sigma, run.probes["midspan"][:, 1], label="midspan")
    if name:
        ax1.plot(sigma, run.probes[name + "_fixed_position"][:, 1], label=f"under '{name}'")
    ax1.axhline(-s0, color="k", ls="--", lw=1, label=f"taut string's static midspan: -{s0:.4f} m")
    ax1.plot([sigma[0]], [-static_midspan_sag(run)], "k+", ms=10,
             label=f"static start: -{static_midspan_sag(run):.4f} m")
    ax1.set_xlabel(f"'{name}' position sigma [m]" if name else "load position sigma [m]")
    ax1.set_ylabel("height y [m]")
    ax1.grid(True, alpha=0.3)
    ax1.legend(fontsize=8)
    ax2 = fig.add_subplot(gs[1, 1])
    for j in steps:
        ax2.plot(run.s, 1e4 * (st[j] - 1.0), label=f"t = {t[j]:.1f} s")
    H = p["w"] * L**2 / (8.0 * s0)
    ax2.axhline(1e4 * H / p["EA"], color="k", ls="--", lw=1, label=f"taut string, static: H / (E A), H = {H:.0f} N")
    ax2.set_title("the strain jumps at the robot by the tangential force it puts on the rope / (E A)", fontsize=10)
    ax2.set_xlabel("unstretched arclength s [m]")
    ax2.set_ylabel("strain |r_s| - 1 [1e-4]")
    ax2.grid(True, alpha=0.3)
    ax2.legend(fontsize=8)
    fig.suptitle(traverse_io.wrapped(f"{traverse_io.run_title(run)}; {stiffness_text(run, p)}; run to t = {t[-1]:.1f} s", 130),
                 fontsize=11)
    fig.tight_layout()
    return fig


def figure_catenary(path):
    run = _load(path, ("r", "stretch"))
    traverse_io.require_probe(run, "midspan", "plot_strained_rod")
    p = rod_properties(run)
    cat = catenary_of(run)
    L, sag = p["L"], cat.sag()
    s_parab = taut_string_sag(p["w"], L, p["EA"])
    t, r, st = run.time, run.field("r"), run.field("stretch")
    sigma = traverse_io.first_load_sigma(run)
    steps = [0] + [j for j in _steps_at(sigma, [0.25 * L, 0.5 * L, 0.75 * L]) if j != 0]
    fig, ax = plt.subplots(1, 3, figsize=(16, 5.2), gridspec_kw={"width_ratios": [1.4, 1.0, 1.0]})
    s0 = np.linspace(0.0, L, 401)
    ax[0].plot(cat.x(s0), -cat.z(s0), "k--", lw=1.2, label=f"Irvine's elastic catenary: sag {sag:.4f} m", zorder=3)
    ax[0].plot(s0, -4.0 * s_parab * s0 * (L - s0) / L**2, ":", color="0.4",
               label=f"taut string's parabola: sag {s_parab:.4f} m")
    for j in steps:
        what = "static start" if j == 0 else f"load at {sigma[j]:.2f} m"
        line, = ax[0].plot(r[j, :, 2], r[j, :, 1], label=what)
        if np.isfinite(sigma[j]):
            i = int(np.argmin(np.abs(run.s - sigma[j])))
            ax[0].plot(r[j, i, 2], r[j, i, 1], "v", color=line.get_color(), ms=8)
    ax[0].set_aspect("equal")
    ax[0].set_ylim(-1.45 * float(np.abs(r[steps, :, 1]).max()), 0.9 * float(np.abs(r[steps, :, 1]).max()))
    ax[0].set_xlabel("z [m]")
    ax[0].set_ylabel("y [m]")
    ax[0].set_title("shapes (true scale), the load marked", fontsize=10)
    ax[0].legend(fontsize=8, loc="upper center")
    ax[0].grid(True, alpha=0.3)
    on = np.isfinite(sigma)
    ax[1].plot(sigma[on], run.probes["midspan"][on, 1], label="midspan, load on the cable")
    ax[1].axhline(-sag, color="k", ls="--", lw=1, label=f"Irvine, static: -{sag:.4f} m")
    ax[1].plot([0.0], [-static_midspan_sag(run)], "k+", ms=10, label=f"static start: -{static_midspan_sag(run):.4f} m")
    ax[1].set_xlabel("load position sigma [m]")
    ax[1].set_ylabel("midspan height y [m]")
    ax[1].grid(True, alpha=0.3)
    ax[1].legend(fontsize=8)
    for j in steps:
        ax[2].plot(run.s, 100.0 * (st[j] - 1.0), label="static start" if j == 0 else f"load at {sigma[j]:.2f} m")
    ax[2].plot(s0, 100.0 * (cat.stretch(s0) - 1.0), "k--", lw=1.2, zorder=3, label="Irvine, static: T / (E A)")
    ax[2].set_xlabel("unstretched arclength s [m]")
    ax[2].set_ylabel("strain |r_s| - 1 [%]")
    ax[2].grid(True, alpha=0.3)
    ax[2].legend(fontsize=8)
    fig.suptitle(traverse_io.wrapped(f"{traverse_io.run_title(run)}; {stiffness_text(run, p)}, weight {p['w'] * L:.3g} N; "
                                     f"H = {cat.H:.3g} N", 140), fontsize=11)
    fig.tight_layout()
    return fig


def companions(path, exe, folder):
    """Runs the scene stored in `path` inextensible and with E A, k G A x STIFF; their files."""
    run = traverse_io.load(path)
    p = rod_properties(run)
    scene = os.path.join(folder, os.path.splitext(os.path.basename(path))[0] + "_scene.yaml")
    with open(scene, "w") as f:
        f.write(traverse_io._text(run.attrs["scene"]))
    out = []
    for tag, sets in (("inextensible", ["rod.model=inextensible"]),
                      ("stiff", [f"rod.axial_stiffness={STIFF * p['EA']!r}", f"rod.shear_stiffness={STIFF * p['kGA']!r}"])):
        o = os.path.join(folder, os.path.splitext(os.path.basename(path))[0] + f"_{tag}.h5")
        cmd = [exe, "run", scene, "-o", o, "--overwrite", "-q"] + [a for s in sets for a in ("--set", s)]
        subprocess.run(cmd, check=True)
        out.append(o)
    return out


def figure_cantilever(path, inext_path, stiff_path, probe="tip"):
    run, inext, stiff = (_load(x) for x in (path, inext_path, stiff_path))
    for x, o in ((path, run), (inext_path, inext), (stiff_path, stiff)):
        traverse_io.require_probe(o, probe, "plot_strained_rod")
    p, pi, ps = rod_properties(run), rod_properties(inext), rod_properties(stiff)
    if pi["model"] != "inextensible":
        traverse_io._exit_with(f"plot_strained_rod: {inext_path} is not inextensible (rod.model: {pi['model']})")
    L = p["L"]
    sigma = traverse_io.first_load_sigma(run)
    y = {k: o.probes[probe][:, 1] for k, o in (("run", run), ("inext", inext), ("stiff", stiff))}
    n = min(len(v) for v in y.values())
    ref = np.abs(y["inext"][:n]).max()
    fig, ax = plt.subplots(1, 3, figsize=(16, 5.0))
    for j in _steps_at(sigma, [0.0, 0.25 * L, 0.5 * L, 0.75 * L, L]):
        rr, ri = run.field("r", j), inext.field("r", j)
        line, = ax[0].plot(rr[:, 2], rr[:, 1], label=f"mass at {sigma[j]:.3f} m")
        ax[0].plot(ri[:, 2], ri[:, 1], "--", color=line.get_color())
        i = int(np.argmin(np.abs(run.s - sigma[j])))
        ax[0].plot(rr[i, 2], rr[i, 1], "o", color=line.get_color())
    ax[0].plot([], [], "k--", label="inextensible")
    ax[0].set_aspect("equal", adjustable="datalim")
    ax[0].set_xlabel("z [m]")
    ax[0].set_ylabel("y [m]")
    ax[0].set_title(f"shapes (true scale): {p['model']} solid, inextensible dashed", fontsize=10)
    ax[0].legend(fontsize=8)
    ax[0].grid(True, alpha=0.3)
    ax[1].plot(sigma[:n], 1e3 * y["run"][:n], label=p["model"])
    ax[1].plot(sigma[:n], 1e3 * y["inext"][:n], "--", label="inextensible")
    ax[1].plot(sigma[:n], 1e3 * y["stiff"][:n], ":", lw=2, label=f"E A, k G A x {STIFF_TEXT}")
    ax[1].set_xlabel("mass position sigma [m]")
    ax[1].set_ylabel(f"{probe} height y [mm]")
    ax[1].grid(True, alpha=0.3)
    ax[1].legend(fontsize=8)
    d_run = np.abs(y["run"][:n] - y["inext"][:n]) / ref
    d_stiff = np.abs(y["stiff"][:n] - y["inext"][:n]) / ref
    ax[2].semilogy(sigma[:n], d_run, label=f"{p['model']}: largest {d_run.max():.3g}")
    ax[2].semilogy(sigma[:n], d_stiff, label=f"E A, k G A x {STIFF_TEXT}: largest {d_stiff.max():.2g}")
    ax[2].set_xlabel("mass position sigma [m]")
    ax[2].set_ylabel("difference from the inextensible rod [1]")
    ax[2].set_title(f"|y - y_inextensible| at the {probe} / largest |y_inextensible| ({1e3 * ref:.1f} mm)", fontsize=10)
    ax[2].grid(True, alpha=0.3, which="both")
    ax[2].legend(fontsize=8)
    fig.suptitle(traverse_io.wrapped(f"{traverse_io.run_title(run)}; {stiffness_text(run, p)}; against the same run "
                                     f"inextensible and with E A = {ps['EA']:.3g} N, k G A = {ps['kGA']:.3g} N", 140),
                 fontsize=11)
    fig.tight_layout()
    return fig


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("kind", choices=["taut", "catenary", "cantilever"])
    ap.add_argument("runs", nargs="+")
    ap.add_argument("--traverse", help="cantilever: run the two companions with this executable")
    ap.add_argument("-o", "--output")
    a = ap.parse_args(argv)
    out = a.output or os.path.splitext(a.runs[0])[0] + f"_{a.kind}.png"
    if a.kind == "cantilever":
        if a.traverse:
            if len(a.runs) != 1:
                ap.error("cantilever with --traverse takes one run")
            others = companions(a.runs[0], a.traverse, os.path.dirname(os.path.abspath(a.runs[0])))
        elif len(a.runs) == 3:
            others = a.runs[1:]
        else:
            ap.error("cantilever takes RUN.h5 INEXTENSIBLE.h5 STIFF.h5, or RUN.h5 --traverse EXE")
        fig = figure_cantilever(a.runs[0], *others)
    else:
        if len(a.runs) != 1:
            ap.error(f"{a.kind} takes one run")
        fig = (figure_taut if a.kind == "taut" else figure_catenary)(a.runs[0])
    fig.savefig(out, dpi=110)
    print(f"plot_strained_rod: wrote {out}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
